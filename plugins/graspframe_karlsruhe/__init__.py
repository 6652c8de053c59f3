"""Built-in graspframe plugin: karlsruhe."""
