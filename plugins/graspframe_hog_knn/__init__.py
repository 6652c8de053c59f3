"""Built-in graspframe plugin: the HOG + weighted-kNN grasp classifier (docs/vision.md)."""
