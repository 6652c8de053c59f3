"""Registers the HOG + weighted-kNN classifier (graspframe.vision.classifier)."""

from __future__ import annotations

from graspframe.plugins import hookimpl
from graspframe.vision.classifier import HogKnnClassifier


@hookimpl
def graspframe_register_classifiers(register):
    register(HogKnnClassifier)
