"""graspframe plugin: a two-finger parallel gripper (URDF model and hand description)."""
