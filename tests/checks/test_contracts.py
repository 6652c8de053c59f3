"""The contract checks themselves, on a fake hand built to pass and then broken one way
at a time; each breakage must be named in plain words."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from graspframe.common.errors import DescriptionError, GraspframeError
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.hal import (
    Classifier,
    ClassifierPicture,
    HandPreshape,
    HumanGraspEstimate,
    JointSpec,
)
from graspframe.hal.descriptions import FINGERTIP_FRAMES_KEY
from graspframe.testing import (
    assert_classifier_contract,
    assert_hand_contract,
    assert_hand_free_of_self_collision,
    classifier_problems,
    estimate_problems,
    hand_problems,
    self_collision_problems,
)

from fakes import make_fake_hand


def test_fake_hand_passes(fake_hand):
    assert hand_problems(fake_hand) == []
    assert_hand_contract(fake_hand)


def test_an_open_preshape_that_crosses_its_fingers_is_named(fake_hand):
    assert_hand_free_of_self_collision(fake_hand)
    # Both fingers tilt towards each other by 1.2 rad: their 6 cm cylinders cross.
    crossed = {"fk_finger_joint": 1.2, "fk_thumb_joint": 1.2}
    preshape = HandPreshape("pinch", crossed, crossed, 0.06)
    hand = dataclasses.replace(fake_hand, preshapes={"pinch": preshape})
    (problem,) = self_collision_problems(hand)
    assert "preshape 'pinch' open: links 'fk_finger' and 'fk_thumb' collide" in problem
    assert "signed distance -" in problem
    with pytest.raises(AssertionError, match="fk_finger"):
        assert_hand_free_of_self_collision(hand)


def _broken_cases(urdf):
    ok = make_fake_hand(urdf)
    bad_open = HandPreshape("pinch", {"fk_finger_joint": 2.0, "fk_thumb_joint": 0.1}, {}, 0.06)
    return {
        "joint not in model": (
            {"joints": (*ok.joints, JointSpec("fk_ghost", 0, 1, 1, 1))},
            "'fk_ghost' is not a movable joint of the model",
        ),
        "limits differ from model": (
            {"joints": (JointSpec("fk_finger_joint", 0, 1.0, 2, 2), ok.joints[1])},
            "differ from the model's",
        ),
        "preshape outside limits": ({"preshapes": {"pinch": bad_open}}, "outside [0.0000, 1.5000]"),
        "finger without links": (
            {"real_fingers": {**ok.real_fingers, "ring": ()}},
            "real finger 'ring' has no links",
        ),
        "no palm": (
            {"real_fingers": {"finger": ("fk_finger",), "thumb": ("fk_thumb",)}},
            "real fingers must include 'palm'",
        ),
        "missing mapping": (
            {"grasp_map": {HumanGrasp.PINCH: "pinch"}},
            "mapping table has no entry for: large_diameter",
        ),
        "mapping to undefined preshape": (
            {"grasp_map": {g: "wrap" for g in HumanGrasp}},
            "undefined preshape 'wrap'",
        ),
        "palm frame not a link": ({"palm_frame": "nowhere"}, "palm frame 'nowhere' is not a link"),
        "bad name": ({"name": "Fake Hand"}, "must be lowercase"),
        "delta in mm": (
            {"preshapes": {"pinch": dataclasses.replace(ok.preshapes["pinch"], delta=60.0)}},
            "is it in metres?",
        ),
        "sensor off the palm": ({"palm_sensor_link": "fk_finger"}, "is not a link of the palm"),
        "missing model": ({"model_path": urdf.parent / "missing.urdf"}, "model file not found"),
        "palm frame pointing into the palm": (
            {"palm_frame": "fk_base"},
            "not on the palm surface",
        ),
        "fingertip frame not in the model": (
            {"fingertip_frames": {"finger": "fk_nowhere"}},
            "fingertip frame of 'finger' 'fk_nowhere' is not a link of the model",
        ),
        "fingertip frame of no finger": (
            {"fingertip_frames": {"index": "fk_finger"}},
            "'index', which is not a real finger",
        ),
    }


@pytest.mark.parametrize(
    "case",
    [
        "joint not in model",
        "limits differ from model",
        "preshape outside limits",
        "finger without links",
        "no palm",
        "missing mapping",
        "mapping to undefined preshape",
        "palm frame not a link",
        "bad name",
        "delta in mm",
        "sensor off the palm",
        "missing model",
        "palm frame pointing into the palm",
        "fingertip frame not in the model",
        "fingertip frame of no finger",
    ],
)
def test_each_defect_is_named(case, fake_hand_urdf):
    overrides, expected = _broken_cases(fake_hand_urdf)[case]
    hand = dataclasses.replace(make_fake_hand(fake_hand_urdf), **overrides)
    problems = hand_problems(hand)
    assert any(expected in p for p in problems), problems
    with pytest.raises(AssertionError, match="breaks the contract"):
        assert_hand_contract(hand)


def test_fingertip_frames_that_are_not_a_mapping_are_refused_when_made(fake_hand_urdf):
    with pytest.raises(DescriptionError, match="must map real finger names to frame names"):
        dataclasses.replace(make_fake_hand(fake_hand_urdf), fingertip_frames=("fk_finger",))


def test_fingertip_frames_in_extras_are_still_read_with_a_warning(fake_hand_urdf):
    """The key that named them before `fingertip_frames` did."""
    hand = make_fake_hand(fake_hand_urdf)
    with pytest.warns(DeprecationWarning, match="fingertip_frames=..."):
        old = dataclasses.replace(
            hand, fingertip_frames={}, extras={FINGERTIP_FRAMES_KEY: {"finger": "fk_finger"}}
        )
    assert old.fingertip_frames == {"finger": "fk_finger"}


def test_palm_group_check_uses_the_palm_name(fake_hand_urdf):
    hand = make_fake_hand(fake_hand_urdf)
    assert PALM in hand.real_fingers


class _RefusingClassifier(Classifier):
    """Refuses anything that is not a colour image, and every image without skin."""

    name = "refusing"

    def classify(self, image_bgr):
        image = np.asarray(image_bgr)
        if image.ndim != 3 or image.dtype != np.uint8 or image.size == 0:
            raise GraspframeError("expected an H x W x 3 uint8 colour image")
        raise GraspframeError("no hand found in the image")


class _GuessingClassifier(Classifier):
    """Always answers: the behaviour the contract must catch."""

    name = "guessing"

    def classify(self, image_bgr):
        return HumanGraspEstimate(HumanGrasp.PINCH, 0.5, np.eye(3), None)


def test_estimate_pictures_must_be_masks_or_images():
    mask = ClassifierPicture("mask", "mask", np.zeros((48, 64), np.uint8))
    crop = ClassifierPicture("crop", "image", np.zeros((8, 8, 3), np.uint8))
    estimate = HumanGraspEstimate(HumanGrasp.PINCH, 0.5, np.eye(3), None, pictures=(mask, crop))
    assert estimate_problems(estimate, (48, 64, 3)) == []
    bad = (
        ClassifierPicture("mask", "mask", np.zeros((48, 64, 3), np.uint8)),
        ClassifierPicture("depth", "depth", np.zeros((48, 64), np.uint8)),
        ClassifierPicture("float", "image", np.zeros((8, 8), np.float32)),
        ClassifierPicture("mask", "mask", np.zeros((10, 10), np.uint8)),
    )
    problems = estimate_problems(dataclasses.replace(estimate, pictures=bad), (48, 64, 3))
    assert problems == [
        "picture names repeat: ['mask', 'depth', 'float', 'mask']",
        "picture 'mask': a mask is H x W, got shape (48, 64, 3)",
        "picture 'depth': kind 'depth' is not one of mask, image",
        "picture 'float': pixels are not a uint8 array",
        "picture 'mask': mask (10, 10) is not the image's size (48, 64)",
    ]


def test_classifier_contract_accepts_a_refusing_classifier():
    assert classifier_problems(_RefusingClassifier) == []
    assert_classifier_contract(_RefusingClassifier)


def test_classifier_contract_catches_guessing():
    problems = classifier_problems(_GuessingClassifier)
    assert "a uniform grey image gave an estimate (pinch) instead of an error" in problems
    assert "an empty array gave an estimate (pinch) instead of an error" in problems


def test_a_classifier_without_settings_ignores_the_options():
    """The user's options (classify --k) reach any classifier through `with_options`;
    one that has no such setting is built with no arguments."""
    from graspframe.hal import ClassifierOptions

    built = _RefusingClassifier.with_options(ClassifierOptions(k=3))
    assert type(built) is _RefusingClassifier
