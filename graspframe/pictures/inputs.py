"""Checks of what picture functions are given: each problem is one line of InputError."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError, InputError
from graspframe.hal.objects import ObjectDescription
from graspframe.pictures.render3d import Soup


def contact_points(points, fingers: Sequence[str], what: str) -> NDArray[np.float64]:
    """Contact points as a finite (n, 3) array [m] (empty input: (0, 3)), one real finger
    each; InputError naming `what` otherwise."""
    try:
        array = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be an (n, 3) array [m]") from None
    if array.size == 0:
        array = np.zeros((0, 3))
    if array.ndim != 2 or array.shape[1] != 3 or not np.all(np.isfinite(array)):
        raise InputError(f"{what} must be a finite (n, 3) array [m], got shape {array.shape}")
    if len(fingers) != len(array):
        raise InputError(
            f"{what}: {len(array)} contact points but {len(fingers)} contact fingers; "
            "give one finger per point"
        )
    return array


def checked_object_soup(obj, what: str, simulated: bool = False) -> Soup:
    """The object's soup (robot_scene.object_soup, its collision shapes with
    `simulated`); InputError when `obj` is not an ObjectDescription or its mesh cannot be
    made."""
    from graspframe.pictures.robot_scene import object_soup

    if not isinstance(obj, ObjectDescription):
        raise InputError(
            f"{what}: the object must be an ObjectDescription, got {type(obj).__name__}"
        )
    try:
        return object_soup(obj, simulated)
    except (GraspframeError, OSError, ValueError) as exc:
        raise InputError(f"{what}: cannot draw object {obj.name!r}: {exc}") from None


def checked_figure(
    model, finger_of_link, colours, palm_frame: str, what: str, simulated: bool = False
):
    """A RobotFigure of `model` (robot_scene.py; its collision shapes with `simulated`)
    that has the frame `palm_frame` and some hand link to draw; InputError naming `what`
    otherwise."""
    from graspframe.pictures.robot_scene import RobotFigure

    try:
        figure = RobotFigure(model, finger_of_link, colours, simulated)
    except GraspframeError as exc:
        raise InputError(f"{what}: {exc}") from None
    if not figure.has_frame(palm_frame):
        raise InputError(f"palm frame {palm_frame!r} is not in {model.describe()}")
    if not any(figure.is_hand_link(link) for link in figure.soups):
        raise InputError(
            f"{what}: no link of the hand's real fingers is a link of {model.describe()} "
            "with a shape to draw"
        )
    return figure
