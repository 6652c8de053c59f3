"""Registers the HOG + weighted-kNN classifier (classifier.py)."""

from __future__ import annotations

from graspframe.plugins import hookimpl
from graspframe_hog_knn.classifier import HogKnnClassifier


@hookimpl
def graspframe_register_classifiers(register):
    register(HogKnnClassifier)
