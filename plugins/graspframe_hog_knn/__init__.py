"""Built-in graspframe plugin: the HOG + weighted-kNN grasp classifier and everything it
needs (docs/vision.md).

Modules, one job each: `classifier` (the `HogKnnClassifier`), `segmentation` (skin mask,
crop), `features` (HOG), `index` (PCA + nearest-neighbour search), `rotations`
(rotation averaging), `hand_scene` (hand + object triangles in the palm frame), `views`
(random view parameters, one rendered view), `database` (build, save, load; the shipped
one is `data/views.npz`), `commands` (`graspframe db build`), `demo` (renders the
bundled demo image), `plugin` (registers the classifier).
"""
