"""Built-in graspframe plugin: barrett."""
