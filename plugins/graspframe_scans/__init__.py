"""Scans as objects: mesh files with their sidecars (GRASPFRAME_OBJECTS)."""
