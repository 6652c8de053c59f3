"""The bundled demo: a rendered image of a human grasp and its scene description."""
