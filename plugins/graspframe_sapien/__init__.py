"""Built-in graspframe plugin: the SAPIEN physics backend (CPU physics, no renderer)."""
