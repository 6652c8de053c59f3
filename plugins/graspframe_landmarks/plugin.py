"""Registers the hand-landmark classifier (needs the `hands` extra at classify time)."""

from __future__ import annotations

from graspframe.plugin_system import hookimpl
from graspframe_landmarks.classifier import LandmarkClassifier


@hookimpl
def graspframe_register_classifiers(register):
    register(LandmarkClassifier)
