"""`check_hand_command`: a registered hand checked in plain words, every defect named."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from graspframe.checks import grasps as grasp_checks
from graspframe.checks import hand as checks
from graspframe.checks.grasps import HoldTrial, design_object
from graspframe.cli.check_hand import check_hand_command
from graspframe.common.errors import UnknownNameError
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.hal import DesignObject, DriveGains, HandDescription, HandPreshape, JointSpec
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system import registry as registry_module
from graspframe.plugin_system.registry import Registry
from graspframe.strategy.execution import GraspOutcome, Grip
from graspframe.strategy.planner import PlanningError
from graspframe.testing import hand_problems

from fakes import FAKE_HAND_URDF, make_fake_hand

PALM_FRAME_JOINT_ORIGIN = '<origin xyz="0 0 0.04" rpy="0 0 0"/>'


class _HandPlugin:
    """A plugin object registering one hand."""

    def __init__(self, hand: HandDescription):
        self.hand = hand

    @hookimpl
    def graspframe_register_hands(self, register):
        register(self.hand)


def _registry_with(hand: HandDescription) -> Registry:
    registry = Registry(strict=True)
    registry.add_plugin("test_hand", _HandPlugin(hand))
    return registry


def _flipped_palm_urdf(tmp_path: Path) -> Path:
    """The fake hand with its palm frame turned over: +z points into the palm."""
    assert FAKE_HAND_URDF.count(PALM_FRAME_JOINT_ORIGIN) == 1
    path = tmp_path / "flipped_palm.urdf"
    path.write_text(
        FAKE_HAND_URDF.replace(
            PALM_FRAME_JOINT_ORIGIN, '<origin xyz="0 0 0.04" rpy="3.14159 0 0"/>'
        )
    )
    return path


def _broken_hand(tmp_path: Path) -> HandDescription:
    """Five defects at once, each of a different kind."""
    ok = make_fake_hand(_flipped_palm_urdf(tmp_path), name="broken_hand")
    too_far = HandPreshape(
        "pinch",
        open_q={"fk_finger_joint": 0.1, "fk_thumb_joint": 0.1},
        closed_q={"fk_finger_joint": 2.0, "fk_thumb_joint": 1.2},  # limit 1.5 rad
        delta=0.06,
    )
    return make_fake_hand(
        ok.model_path,
        name="broken_hand",
        joints=(*ok.joints, JointSpec("fk_index_joint", 0.0, 1.5, 2.0, 2.0)),
        preshapes={"pinch": too_far},
        real_fingers={PALM: ("fk_base",), "finger": ("fk_finger",), "thumb": ()},
        grasp_map={HumanGrasp.PINCH: "pinch"},
    )


EXPECTED_DEFECTS = {
    "joint not in the model": "joint 'fk_index_joint' is not a movable joint of the model",
    "palm frame pointing into the palm": "palm frame +z points into the hand",
    "preshape outside limits": "preshape 'pinch' (closed) puts 'fk_finger_joint' at 2.0000",
    "real finger with no links": "real finger 'thumb' has no links",
    "missing mapping entries": "mapping table has no entry for: large_diameter, small_diameter",
}


def test_a_broken_hand_has_every_defect_named(tmp_path, capsys):
    registry = _registry_with(_broken_hand(tmp_path))

    assert check_hand_command("broken_hand", registry=registry, hold=False) == 1

    out = capsys.readouterr().out
    assert out.startswith("hand broken_hand: 1 of 3 checks ran, FAILED")
    problems = [line.strip() for line in out.splitlines() if "problem: " in line]
    for defect, words in EXPECTED_DEFECTS.items():
        assert any(words in line for line in problems), f"{defect} not named:\n{out}"
    # The checks that need a sound description say why they did not run.
    assert "2. closing in free space: not run (the description check failed)" in out


def test_the_palm_direction_is_checked_even_when_joints_are_wrong(tmp_path):
    # A wrong joint must not hide a palm frame that points into the palm.
    hand = make_fake_hand(
        _flipped_palm_urdf(tmp_path),
        joints=(JointSpec("fk_index_joint", 0.0, 1.5, 2.0, 2.0),),
        preshapes={},
        grasp_map={},
    )
    problems = hand_problems(hand)
    assert any("'fk_index_joint' is not a movable joint" in p for p in problems), problems
    assert any("palm frame +z points into the hand" in p for p in problems), problems


def test_a_good_hand_passes_with_a_summary(fake_hand, capsys):
    assert check_hand_command("fake_hand", registry=_registry_with(fake_hand), hold=False) == 0

    out = capsys.readouterr().out
    assert out.splitlines()[0] == "hand fake_hand: 2 of 3 checks ran, all passed"
    for words in (
        "1. the description against its model",
        "joints (2): fk_finger_joint [0, 1.5], fk_thumb_joint [0, 1.5]",
        "real fingers (3): palm (1 link), finger (1 link), thumb (1 link)",
        "2. closing in free space brings opposed fingers within 15 mm: passed",
        "3. holding the design objects: not run (--no-hold)",
        "preshapes (1): pinch",
        "mapping: large_diameter -> pinch",
    ):
        assert words in out, out


def test_the_default_registry_is_used_when_none_is_given(fake_hand, monkeypatch, capsys):
    registry = _registry_with(fake_hand)
    monkeypatch.setattr(registry_module, "default_registry", lambda: registry)

    assert check_hand_command("fake_hand", hold=False) == 0
    assert "hand fake_hand: 2 of 3 checks ran, all passed" in capsys.readouterr().out


def test_an_unknown_hand_is_the_registrys_error(fake_hand):
    with pytest.raises(UnknownNameError, match="fake_hand"):
        check_hand_command("no_such_hand", registry=_registry_with(fake_hand))


def test_one_problem_is_counted_in_the_singular(fake_hand_urdf, capsys):
    fingers = {PALM: ("fk_base",), "finger": ("fk_finger",), "thumb": ()}  # one defect
    hand = make_fake_hand(fake_hand_urdf, name="thumbless_hand", real_fingers=fingers)
    assert check_hand_command("thumbless_hand", registry=_registry_with(hand), hold=False) == 1
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].startswith("1. the description against its model")
    assert lines[1].endswith(": FAILED (1 problem)"), lines[1]


def test_an_open_preshape_whose_fingers_cross_fails_the_description(fake_hand, capsys):
    """check-hand fails what the contract test fails: links that overlap when open."""
    crossed = {"fk_finger_joint": 1.2, "fk_thumb_joint": 1.2}  # the two cylinders cross
    preshape = HandPreshape("pinch", crossed, crossed, 0.06)
    hand = dataclasses.replace(fake_hand, name="crossed_hand", preshapes={"pinch": preshape})
    assert check_hand_command("crossed_hand", registry=_registry_with(hand), hold=False) == 1
    out = capsys.readouterr().out
    assert "open preshapes free of self-collision: none" in out
    assert "problem: preshape 'pinch' open: links 'fk_finger' and 'fk_thumb' collide" in out


# A rod lying across the fake hand's palm, between its finger and its thumb (which close
# about palm x): the fake hand, at full strength, holds it in both of its trials.
ROD = DesignObject("cylinder", (0.0, 0.0, 0.035), 0.015, (1.0, 0.0, 0.0), 0.1)
WEAK_DRIVE = DriveGains(stiffness=5.0, damping=0.5, force_limit=0.002)  # [N m]: no squeeze


def _hand_with_a_rod(model_path: Path, name: str, **overrides) -> HandDescription:
    """The fake hand whose pinch is shaped for ROD (one trial per volar/non-volar use)."""
    plain = make_fake_hand(model_path).preshapes["pinch"]
    pinch = dataclasses.replace(plain, design_object=ROD, opposed=(("finger", "thumb"),))
    return make_fake_hand(model_path, name=name, preshapes={"pinch": pinch}, **overrides)


def test_a_hand_too_weak_to_hold_fails_saying_what_limited_it(fake_hand_urdf, tmp_path, capsys):
    import graspframe_sapien.plugin

    hand = _hand_with_a_rod(fake_hand_urdf, "weak_hand", drive=WEAK_DRIVE)
    registry = _registry_with(hand)
    registry.add_plugin("sapien", graspframe_sapien.plugin)  # real physics
    pictures = tmp_path / "pictures"

    assert check_hand_command("weak_hand", registry, pictures=pictures) == 1

    out = capsys.readouterr().out
    assert "3. the hand alone holds each preshape's design object" in out, out
    assert "0 of 2 held" in out, out
    problems = [line.strip() for line in out.splitlines() if "problem: " in line]
    assert len(problems) == 2, out
    for line in problems:  # the squeeze, times the friction, is below the weight
        assert "limited by: squeeze" in line and "x friction 0.8" in line, line
        assert "N weight" in line, line
    # The closed preshape and a picture of each failed trial.
    drawn = sorted(p.name for p in pictures.glob("*.png"))
    assert drawn == ["pinch_abducted_thumb.png", "pinch_closing.png", "pinch_large_diameter.png"]


def test_a_failed_description_still_draws_each_preshape(tmp_path, capsys):
    # The mistake the docs warn about: the palm frame's +z points into the hand.
    hand = _hand_with_a_rod(_flipped_palm_urdf(tmp_path), "flipped_hand")
    pictures = tmp_path / "pictures"

    registry = _registry_with(hand)
    assert check_hand_command("flipped_hand", registry, hold=False, pictures=pictures) == 1

    out = capsys.readouterr().out
    assert "palm frame +z points into the hand" in out, out
    picture = pictures / "pinch_closing.png"
    assert picture.is_file()
    assert f"pinch: posed closed around its design object (no physics), picture: {picture}" in out
    assert "2. closing in free space: not run (the description check failed)" in out


def test_a_model_that_does_not_load_is_said_in_one_line(tmp_path, capsys):
    hand = _hand_with_a_rod(tmp_path / "missing.urdf", "lost_hand")
    pictures = tmp_path / "pictures"

    assert check_hand_command("lost_hand", _registry_with(hand), hold=False, pictures=pictures) == 1

    no_pictures = [line for line in capsys.readouterr().out.splitlines() if "no pictures" in line]
    assert len(no_pictures) == 1 and "the model does not load" in no_pictures[0], no_pictures
    assert not list(pictures.glob("*.png"))


class _NamedBackend:
    name = "no-physics"


def test_a_trial_that_recorded_nothing_is_drawn_posed(fake_hand_urdf, tmp_path, monkeypatch):
    hand = _hand_with_a_rod(fake_hand_urdf, "rod_hand")
    aborted = GraspOutcome(
        contacts=[],
        T_world_object_at_hold=np.eye(4),
        grip=Grip(),
        held=None,
        aborted="the arm cannot carry out the plan: the approach left the workspace",
    )
    trial = HoldTrial(
        HumanGrasp.PINCH,
        "pinch",
        design_object(hand.preshapes["pinch"]),
        ("finger", "thumb"),
        aborted,
        moments=(),
        checked=None,  # type: ignore[arg-type]  # not drawn: nothing was recorded
    )
    monkeypatch.setattr(checks, "hold_trials", lambda *_args, **_kwargs: [trial])

    passed, lines = checks.check_hand_report(hand, _NamedBackend(), tmp_path)  # type: ignore[arg-type]

    assert not passed
    picture = tmp_path / "pinch_pinch.png"
    assert picture.is_file()
    assert f"  picture (posed, nothing was recorded): {picture}" in "\n".join(lines)
    problem = next(line for line in lines if "problem: preshape 'pinch'" in line)
    assert "the approach left the workspace" in problem
    assert problem.endswith("; limited by: the trial stopped before the hold"), problem


def test_a_grasp_with_no_plan_is_a_failed_trial_drawn_posed(fake_hand_urdf, tmp_path, monkeypatch):
    hand = _hand_with_a_rod(fake_hand_urdf, "rod_hand")

    def no_plan(*_args, **_kwargs):
        raise PlanningError("no collision-free path for the free rod_hand hand: the table")

    monkeypatch.setattr(grasp_checks, "_hand_alone", no_plan)

    passed, lines = checks.check_hand_report(hand, _NamedBackend(), tmp_path)  # type: ignore[arg-type]

    assert not passed
    assert "     0 of 2 held" in lines, lines
    problems = [line for line in lines if "problem: preshape 'pinch'" in line]
    assert len(problems) == 2 and all("no plan: no collision-free path" in p for p in problems)
    assert {p.name for p in tmp_path.glob("*.png")} == {
        "pinch_closing.png",
        "pinch_large_diameter.png",
        "pinch_abducted_thumb.png",
    }
    # Without asking, the planner's error is raised as before (hold_problems, the tests).
    with pytest.raises(PlanningError):
        grasp_checks.hold_trials(hand, _NamedBackend())  # type: ignore[arg-type]
