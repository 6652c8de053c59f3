"""What the classifiers share: the refusal of an image without a hand, the
distance-weighted kNN vote, and the mapping of a left hand's palm frame back from the
mirrored image.

Both built-in classifiers (plugins graspframe_hog_knn and graspframe_landmarks) use
these, and a third-party classifier may. They live in the core rather than in one
plugin so that no classifier plugin depends on another: each one can be installed,
disabled (GRASPFRAME_DISABLE_PLUGINS) or replaced on its own, and the core's commands
and tests can name `NoHandFoundError` without importing a plugin. The optional MediaPipe
hand detector, shared the same way, is `graspframe.vision.hands`.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError

DISTANCE_FLOOR = 1e-6  # keeps the 1 / distance weight finite for an exact match
# Reflection of the camera x axis: a left hand is classified in the mirrored image.
MIRROR_X = np.diag([-1.0, 1.0, 1.0])
FLIP_Y = np.diag([1.0, -1.0, 1.0])


class NoHandFoundError(GraspframeError):
    """No hand in the image (no skin region large enough, no hand landmarks found)."""


def weighted_vote(
    labels: NDArray[np.int64], distances: NDArray[np.float64], n_classes: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The distance-weighted kNN vote: (weights 1 / distance of the neighbours, votes per
    class = the sum of their weights)."""
    weights = 1.0 / np.maximum(distances, DISTANCE_FLOOR)
    # With weights, bincount sums them as float64.
    votes = cast(NDArray[np.float64], np.bincount(labels, weights=weights, minlength=n_classes))
    return weights, votes


def unmirror(R_camera_palm_mirrored: NDArray[np.float64]) -> NDArray[np.float64]:
    """The palm frame of a left hand from the right-hand frame estimated in the mirrored
    image: its fingertip axis x and palm normal z are the mirrored estimate's, reflected
    back (S x, S z, with S = MIRROR_X), and y = z x x keeps it a right-handed rotation
    (= -S y: a left hand's thumb is on its palm frame's +y side):
    R = S R_mirrored diag(1, -1, 1)."""
    return MIRROR_X @ R_camera_palm_mirrored @ FLIP_Y
