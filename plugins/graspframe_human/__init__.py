"""Built-in graspframe plugin: human."""
