"""Vision pieces every classifier may use; the classifiers themselves are plugins.

Modules, one job each: `images` (reading an image file, checking an image array),
`common` (the no-hand refusal, the distance-weighted kNN vote, a left hand's palm frame
mapped back from the mirrored image), `hands` (the optional MediaPipe hand detector of
the `hands` extra). The HOG + kNN classifier and its view database are the plugin
graspframe_hog_knn, the landmark classifier the plugin graspframe_landmarks
(docs/vision.md). The CPU rasteriser is graspframe/pictures/rasteriser.py.
"""
