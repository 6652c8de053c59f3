"""Registers the HOG + weighted-kNN classifier (classifier.py) and the command that
builds its view database, `graspframe db build` (commands.py)."""

from __future__ import annotations

from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe_hog_knn.classifier import HogKnnClassifier
from graspframe_hog_knn.commands import DB_COMMAND


@hookimpl
def graspframe_register_classifiers(register: Register) -> None:
    register(HogKnnClassifier)


@hookimpl
def graspframe_register_commands(register: Register) -> None:
    register(DB_COMMAND)
