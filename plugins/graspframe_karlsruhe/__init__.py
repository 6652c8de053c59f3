"""graspframe plugin: the Karlsruhe humanoid hand (fluidic, 5 fingers, 8 DOF, right hand)."""
