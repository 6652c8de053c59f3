"""Built-in graspframe plugin: the default graspable objects, one per human grasp."""
