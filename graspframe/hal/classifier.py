"""Image -> human grasp estimate."""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar, Self

import numpy as np
from numpy.typing import NDArray

from graspframe.common.grasps import HumanGrasp


@dataclass(frozen=True)
class Neighbour:
    """One database view used for an estimate: its label, its hand-vs-camera rotation
    R_camera_palm, and its descriptor distance to the query [-]."""

    view_id: int
    grasp: HumanGrasp
    R_camera_palm: NDArray[np.float64]
    distance: float


PICTURE_KINDS = ("mask", "image")


@dataclass(frozen=True)
class ClassifierPicture:
    """A picture a classifier shows of its work on one image (a run's recording shows it
    beside the image).

    name: one word, unique within an estimate (e.g. "mask", "crop"); kind: "mask" (H x W
    uint8 in the image's own pixels, nonzero where the classifier found the hand) or
    "image" (H x W grey or H x W x 3 BGR uint8, any size); pixels: the array.
    """

    name: str
    kind: str
    pixels: NDArray[np.uint8]


@dataclass(frozen=True)
class HumanGraspEstimate:
    """What a classifier says about one image.

    grasp: the estimated human grasp; confidence: its vote share in [0, 1].
    R_camera_palm: rotation of the human palm frame in the camera frame.
    p_camera_palm: palm position in the camera frame [m], None when not estimated.
    neighbours: the database views behind the estimate, nearest first.
    pictures: what the classifier shows of its work on the image (its hand mask, the
    crop it described, ...); none when it has nothing to show.
    """

    grasp: HumanGrasp
    confidence: float
    R_camera_palm: NDArray[np.float64]
    p_camera_palm: NDArray[np.float64] | None
    neighbours: tuple[Neighbour, ...] = ()
    pictures: tuple[ClassifierPicture, ...] = ()


@dataclass(frozen=True)
class ClassifierOptions:
    """The settings a user may give any classifier (`graspframe classify --k`).

    k: how many nearest neighbours vote (>= 1); None: the classifier's own default. A
    classifier without such a setting ignores it.
    """

    k: int | None = None


class Classifier(ABC):
    """Turns a colour image (H x W x 3, uint8, BGR as OpenCV reads it) into an estimate.

    Registered as a class; `name` is what users select. It builds with no arguments
    (its defaults), and `with_options` builds it with a user's `ClassifierOptions`.
    Raises a GraspframeError (never guesses) when the image holds no hand or cannot be
    used. The pictures a classifier can show of its work come with its estimate
    (`HumanGraspEstimate.pictures`).
    """

    name: ClassVar[str]
    summary: ClassVar[str] = ""

    @classmethod
    def with_options(cls, options: ClassifierOptions) -> Self:
        """The classifier with the user's `options`. This default ignores them (built
        with no arguments); a classifier with such settings overrides it."""
        return cls()

    @abstractmethod
    def classify(self, image_bgr: NDArray[np.uint8]) -> HumanGraspEstimate: ...
