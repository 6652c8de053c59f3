"""Objects from mesh files with sidecars (GRASPFRAME_OBJECTS)."""
