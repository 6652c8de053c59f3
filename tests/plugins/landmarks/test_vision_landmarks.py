"""The landmark classifier (plugin graspframe_landmarks): joint-angle features on
landmarks built from the human model's own forward kinematics, the palm frame, the
refusals, and registration. Tests that run MediaPipe skip without the `hands` extra;
those that need /work/shared/real_photos skip when it is absent (never copied here)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from graspframe_landmarks.classifier import LandmarkClassifier, estimate_from_landmarks
from graspframe_landmarks.features import FEATURE_NAMES, MIRROR_X, angle_features, palm_frame
from graspframe_landmarks.postures import GRASP_ORDER, HumanModelLandmarks, posture_table
from scipy.spatial.transform import Rotation

from graspframe.cli.vision import classify_command
from graspframe.common.errors import NotAvailableError, UnknownNameError
from graspframe.plugin_system.registry import default_registry
from graspframe.vision import hands
from graspframe.vision.common import NoHandFoundError

REAL_PHOTOS = Path("/work/shared/real_photos")
FRAME_TOL_DEG = 10.0  # the landmark palm plane is tilted ~7 deg from the model's palm frame


@pytest.fixture(scope="module")
def kinematics() -> HumanModelLandmarks:
    return HumanModelLandmarks()


def _rotation_angle_deg(R_a, R_b) -> float:
    return float(np.degrees(Rotation.from_matrix(R_a.T @ R_b).magnitude()))


def _camera_view(points_wrist, seed: int):
    """The points seen from a random camera: rotated, scaled to millimetres, shifted."""
    R_camera_wrist = Rotation.random(random_state=seed).as_matrix()
    shift = np.random.default_rng(seed).normal(size=3)
    return 1000.0 * points_wrist @ R_camera_wrist.T + shift, R_camera_wrist


def test_a_straight_hand_has_no_flexion(kinematics):
    features = dict(zip(FEATURE_NAMES, angle_features(kinematics.points({})), strict=True))
    for finger in ("index", "middle", "ring", "little"):
        assert features[f"{finger}_pip"] < 1e-6
        assert features[f"{finger}_dip"] < 1e-6
        # wrist -> knuckle is not along the finger: the metacarpals fan out in the palm
        assert features[f"{finger}_mcp"] < np.radians(25)


def test_features_ignore_pose_scale_and_mirroring(kinematics):
    points = kinematics.points(kinematics.posture(GRASP_ORDER[0], 0.5))
    moved, _ = _camera_view(points, seed=3)
    reference = angle_features(points)
    np.testing.assert_allclose(angle_features(moved), reference, atol=1e-9)
    np.testing.assert_allclose(angle_features(moved @ MIRROR_X), reference, atol=1e-9)


def test_pip_flexion_is_the_model_joint_angle(kinematics):
    q = kinematics.posture(GRASP_ORDER[1], 1.0)  # small diameter, closed
    features = dict(zip(FEATURE_NAMES, angle_features(kinematics.points(q)), strict=True))
    for finger in ("index", "middle", "ring", "little"):
        assert features[f"{finger}_pip"] == pytest.approx(q[f"hh_{finger}_pip"], abs=1e-6)
        assert features[f"{finger}_dip"] == pytest.approx(2 / 3 * q[f"hh_{finger}_pip"], abs=1e-6)


@pytest.mark.parametrize("grasp", GRASP_ORDER, ids=lambda g: g.value)
@pytest.mark.parametrize("closure", [0.0, 0.33, 0.5, 0.77, 1.0])
def test_model_postures_classify_as_their_grasp(kinematics, grasp, closure):
    points = kinematics.points(kinematics.posture(grasp, closure))
    points_camera, _ = _camera_view(points, seed=int(100 * closure))
    estimate = estimate_from_landmarks(points_camera, left=False, table=posture_table())
    assert estimate.grasp is grasp
    assert 0.5 < estimate.confidence <= 1.0


def test_palm_frame_follows_the_model_palm(kinematics):
    points = kinematics.points(kinematics.posture(GRASP_ORDER[0], 0.0))
    R_wrist_palm = posture_table().R_wrist_palm
    assert _rotation_angle_deg(palm_frame(points), R_wrist_palm) < FRAME_TOL_DEG
    points_camera, R_camera_wrist = _camera_view(points, seed=7)
    R_camera_palm = estimate_from_landmarks(points_camera, False, posture_table()).R_camera_palm
    assert _rotation_angle_deg(R_camera_palm, R_camera_wrist @ R_wrist_palm) < FRAME_TOL_DEG


def test_a_left_hand_is_mirrored_back(kinematics):
    points = kinematics.points(kinematics.posture(GRASP_ORDER[3], 0.5))
    points_camera, _ = _camera_view(points, seed=11)
    R_right = palm_frame(points_camera)
    R_left = palm_frame(points_camera @ MIRROR_X, left=True)  # the mirror image of this hand
    # Its fingertip axis and palm normal are this hand's, reflected.
    np.testing.assert_allclose(R_left[:, 0], MIRROR_X @ R_right[:, 0], atol=1e-12)
    np.testing.assert_allclose(R_left[:, 2], MIRROR_X @ R_right[:, 2], atol=1e-12)
    assert np.linalg.det(R_left) == pytest.approx(1.0)


def test_registered_next_to_the_default():
    registry = default_registry()
    assert registry.get_classifier("landmarks") is LandmarkClassifier
    assert "hog_knn" in registry.names("classifier")


def test_unknown_classifier_lists_the_names(tmp_path):
    with pytest.raises(UnknownNameError, match="hog_knn, landmarks"):
        classify_command(tmp_path / "none.png", classifier="nope")


@pytest.fixture
def fresh_detector():
    hands._detector.cache_clear()
    yield
    hands._detector.cache_clear()


def _colour_image() -> np.ndarray:
    image = np.zeros((64, 64, 3), np.uint8)
    image[:, :, 2] = np.arange(64, dtype=np.uint8)[None, :] * 4
    return image


def test_missing_extra_is_named(monkeypatch, fresh_detector):
    monkeypatch.setitem(sys.modules, "mediapipe", None)  # import mediapipe -> ImportError
    monkeypatch.delenv("GRASPFRAME_HAND_DETECTOR", raising=False)
    with pytest.raises(NotAvailableError, match=r"pip install \"\.\[hands\]\"") as info:
        LandmarkClassifier().classify(_colour_image())
    assert "\n" not in str(info.value)


def test_no_hand_is_refused(fresh_detector):
    pytest.importorskip("mediapipe")
    with pytest.raises(NoHandFoundError, match="no hand"):
        LandmarkClassifier().classify(_colour_image())


@pytest.mark.skipif(not REAL_PHOTOS.is_dir(), reason="the real photographs are not here")
def test_a_real_photo_is_classified(fresh_detector):
    pytest.importorskip("mediapipe")
    from graspframe.vision.images import read_image

    estimate = LandmarkClassifier().classify(read_image(REAL_PHOTOS / "rp_002.jpg"))
    assert estimate.grasp in GRASP_ORDER
    np.testing.assert_allclose(
        estimate.R_camera_palm @ estimate.R_camera_palm.T, np.eye(3), atol=1e-9
    )
    assert np.linalg.det(estimate.R_camera_palm) == pytest.approx(1.0)
