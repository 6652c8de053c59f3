"""Built-in graspframe plugin: scanned YCB objects from a folder named by GRASPFRAME_YCB_DIR."""
