"""The landmark classifier: MediaPipe hand landmarks -> joint angles -> weighted kNN
over the human hand model's grasp postures.

classify(image): check the image, detect the hand (graspframe.vision.hands, needs the
`hands` extra), take its 3-D world landmarks [m] (camera axes: x right, y down, z
forward), compute the 19 joint angles (features.py), find the k nearest sampled model
postures (postures.py) and vote by 1 / distance; R_camera_palm is the palm frame of the
landmarks (features.palm_frame). p_camera_palm is not estimated (None): the world
landmarks are relative to the hand.
"""

from __future__ import annotations

from typing import ClassVar, Self

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import InputError, NotAvailableError
from graspframe.hal.classifier import (
    Classifier,
    ClassifierOptions,
    HumanGraspEstimate,
    Neighbour,
)
from graspframe.vision import hands
from graspframe.vision.common import NoHandFoundError, weighted_vote
from graspframe.vision.images import check_image
from graspframe_landmarks.features import angle_features, palm_frame
from graspframe_landmarks.postures import GRASP_ORDER, PostureTable, posture_table

DEFAULT_K = 8


def require_detector() -> None:
    """NotAvailableError (one line) when the hand detector cannot run."""
    if hands.detector_enabled():
        return
    if hands.detector_switched_off():
        raise NotAvailableError(
            "the landmarks classifier needs the hand detector, switched off by "
            "GRASPFRAME_HAND_DETECTOR; unset it"
        )
    raise NotAvailableError(
        "the landmarks classifier needs MediaPipe, which is not installed: "
        'pip install ".[hands]" in the graspframe folder (the `hands` extra; '
        "Python 3.11 or 3.12: MediaPipe 0.10.14 has no wheel for 3.13)"
    )


def estimate_from_landmarks(
    points_camera: NDArray[np.float64], left: bool, table: PostureTable, k: int = DEFAULT_K
) -> HumanGraspEstimate:
    """The estimate for (21, 3) landmarks in the camera frame (any unit)."""
    query = angle_features(points_camera)
    distances = np.linalg.norm(table.features - query, axis=1)  # [rad]
    ids = np.argsort(distances)[: min(k, len(distances))]
    _, votes = weighted_vote(table.grasps[ids], distances[ids], len(GRASP_ORDER))
    winner = int(np.argmax(votes))
    R_camera_palm = palm_frame(points_camera, left=left)
    neighbours = tuple(
        Neighbour(int(i), GRASP_ORDER[int(table.grasps[i])], R_camera_palm, float(distances[i]))
        for i in ids
    )
    return HumanGraspEstimate(
        grasp=GRASP_ORDER[winner],
        confidence=float(votes[winner] / votes.sum()),
        R_camera_palm=R_camera_palm,
        p_camera_palm=None,
        neighbours=neighbours,
    )


class LandmarkClassifier(Classifier):
    """MediaPipe hand landmarks, joint angles, k nearest human-model postures.

    k: postures that vote (neighbour view_id = index of the sampled posture).
    """

    name: ClassVar[str] = "landmarks"
    summary: ClassVar[str] = (
        "MediaPipe hand landmarks + joint angles + weighted kNN over the human model's "
        "postures (needs the `hands` extra)"
    )

    def __init__(self, k: int = DEFAULT_K):
        if k < 1:
            raise InputError(f"k must be >= 1, got {k}")
        self.k = k

    @classmethod
    def with_options(cls, options: ClassifierOptions) -> Self:
        """The classifier with the user's `options.k` (its default when None)."""
        return cls() if options.k is None else cls(k=options.k)

    def classify(self, image_bgr: NDArray[np.uint8]) -> HumanGraspEstimate:
        """Estimate the grasp in a BGR uint8 image; raises InputError, NotAvailableError
        (no `hands` extra) or NoHandFoundError."""
        image = check_image(image_bgr)
        require_detector()
        hand = hands.detect_hand(image)
        if hand is None or hand.world_landmarks is None:
            raise NoHandFoundError("no hand found: the hand detector finds no hand landmarks")
        return estimate_from_landmarks(hand.world_landmarks, hand.left, posture_table(), self.k)
