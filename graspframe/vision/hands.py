"""Optional hand detector: MediaPipe Hands (the legacy `mp.solutions.hands` API).

Installed by the `hands` extra (`pip install ".[hands]"` in the graspframe folder;
Python 3.11 and 3.12 only: MediaPipe 0.10.14 has no wheel for 3.13); the hand models ship
inside the mediapipe wheel, so nothing is downloaded at run time. Imported lazily on
first use; without mediapipe (or with GRASPFRAME_HAND_DETECTOR=none) `detect_hand`
returns None (the hog_knn plugin's segmentation then keeps its colour method; the
landmarks plugin refuses).
"""

from __future__ import annotations

import functools
import os
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

MIN_DETECTION_CONFIDENCE = 0.3  # [-] MediaPipe palm-detector threshold
MODEL_COMPLEXITY = 1  # MediaPipe landmark model (0 lite, 1 full)
WRIST, MIDDLE_MCP = 0, 9  # landmark indices
# Landmark chains of the hand skeleton (wrist -> fingertip), for drawing the sure hand.
CHAINS = (
    (0, 1, 2, 3, 4),
    (0, 5, 6, 7, 8),
    (0, 9, 10, 11, 12),
    (0, 13, 14, 15, 16),
    (0, 17, 18, 19, 20),
)
PALM = (0, 1, 5, 9, 13, 17)


@dataclass(frozen=True)
class DetectedHand:
    """One detected hand: `landmarks` (21, 2) [px] in the image; `left` True for a
    left hand (MediaPipe's label swapped back, since it assumes a mirrored selfie
    image); `score` the handedness confidence; `world_landmarks` (21, 3) [m]
    MediaPipe's metric 3-D estimate, origin near the hand's centre, axes along the
    camera's (x right, y down, z away from the camera), None when not given."""

    landmarks: NDArray[np.float64]
    left: bool
    score: float
    world_landmarks: NDArray[np.float64] | None = None

    @property
    def size(self) -> float:
        """[px] the larger side of the landmarks' bounding box."""
        extent = self.landmarks.max(axis=0) - self.landmarks.min(axis=0)
        return float(max(extent.max(), 1.0))


def detector_enabled() -> bool:
    """True when mediapipe is installed and not switched off by the environment."""
    return _detector() is not None


def detector_switched_off() -> bool:
    """True when GRASPFRAME_HAND_DETECTOR switches the detector off."""
    return os.environ.get("GRASPFRAME_HAND_DETECTOR", "").lower() in {"none", "off", "0"}


@functools.cache
def _detector():
    if detector_switched_off():
        return None
    os.environ.setdefault("GLOG_minloglevel", "2")
    os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "3")
    try:
        import mediapipe as mp
    except ImportError:
        return None
    return mp.solutions.hands.Hands(
        static_image_mode=True,
        max_num_hands=2,
        model_complexity=MODEL_COMPLEXITY,
        min_detection_confidence=MIN_DETECTION_CONFIDENCE,
    )


def detect_hand(image_bgr: NDArray[np.uint8]) -> DetectedHand | None:
    """The largest hand MediaPipe finds in the image, or None (none found, or no
    detector)."""
    detector = _detector()
    if detector is None:
        return None
    import cv2

    with warnings.catch_warnings():  # protobuf's deprecation notice inside mediapipe
        warnings.simplefilter("ignore", UserWarning)
        result = detector.process(cv2.cvtColor(image_bgr, cv2.COLOR_BGR2RGB))
    if not result.multi_hand_landmarks:
        return None
    h, w = image_bgr.shape[:2]
    world = result.multi_hand_world_landmarks or [None] * len(result.multi_hand_landmarks)
    hands = []
    for landmarks, handedness, world_landmarks in zip(
        result.multi_hand_landmarks, result.multi_handedness, world, strict=True
    ):
        points = np.array([(p.x * w, p.y * h) for p in landmarks.landmark], np.float64)
        points_m = (
            None
            if world_landmarks is None
            else np.array([(p.x, p.y, p.z) for p in world_landmarks.landmark], np.float64)
        )
        label = handedness.classification[0]
        hands.append(
            DetectedHand(
                points, left=label.label == "Right", score=label.score, world_landmarks=points_m
            )
        )
    return max(hands, key=lambda hand: hand.size)
