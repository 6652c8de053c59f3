"""graspframe plugin: the Barrett BH8-280 hand (description and URDF model)."""
