"""Perception of the object during a grasp: a depth sensor's noise model, the robot
filtered out of its image, and the object localised in what is left."""
