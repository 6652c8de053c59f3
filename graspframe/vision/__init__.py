"""Vision: the synthetic human-hand view database and the HOG + weighted-kNN classifier.

Modules, one job each: `scene` (hand + object triangles in the palm frame), `views`
(random view parameters), `render` (moderngl CPU rendering), `segmentation` (skin mask,
crop), `features` (HOG), `index` (PCA + nearest-neighbour search), `rotations`
(rotation averaging), `database` (build, save, load), `classifier` (the Classifier
plugin class), `demo` (the bundled demo image), `commands` (CLI functions).
"""
