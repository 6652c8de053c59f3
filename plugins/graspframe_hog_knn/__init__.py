"""Built-in graspframe plugin: the HOG + weighted-kNN grasp classifier (METHOD.md section 2)."""
