"""The core hand controller, without a simulator: setpoints, couplings, breakaway."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from graspframe.common.errors import GraspframeError, UnknownNameError
from graspframe.hal import Coupling, DriveGains
from graspframe.hal.hand_control import HOLD_STIFFNESS_FACTOR, HandController, holding_drive

from fakes import make_fake_hand

FINGER, THUMB = "fk_finger_joint", "fk_thumb_joint"  # both [0, 1.5] rad, 2 rad/s
DT = 0.01  # [s]
BREAKAWAY = 0.5  # [N m]; the fake hand's drive: 5 N m/rad, 0.5 N m s/rad


def _controller(tmp_path, **coupling) -> HandController:
    couplings = (Coupling(THUMB, FINGER, 0.5, in_model=False, **coupling),) if coupling else ()
    return HandController(make_fake_hand(tmp_path / "fake.urdf", couplings=couplings))


def test_setpoints_move_at_the_joint_velocity_limit(tmp_path):
    controller = _controller(tmp_path)
    controller.command({FINGER: 1.0})
    still = {FINGER: 0.0, THUMB: 0.0}
    targets = [controller.update(DT, still, still)[FINGER] for _ in range(3)]
    assert targets == pytest.approx([0.02, 0.04, 0.06])  # 2 rad/s x 10 ms per update
    for _ in range(100):
        targets = controller.update(DT, still, still)
    assert targets == pytest.approx({FINGER: 1.0, THUMB: 0.0})


def test_independent_joints_arrive_one_after_the_other(tmp_path):
    controller = _controller(tmp_path)
    controller.command({FINGER: 1.2, THUMB: 0.4})
    still = {FINGER: 0.0, THUMB: 0.0}
    targets = [controller.update(DT, still, still) for _ in range(30)]
    assert targets[19] == pytest.approx({FINGER: 0.4, THUMB: 0.4})  # the thumb is there
    assert targets[29][FINGER] == pytest.approx(0.6)


def test_a_synchronised_hand_moves_every_joint_in_step(tmp_path):
    hand = make_fake_hand(tmp_path / "fake.urdf")
    controller = HandController(replace(hand, synchronised_closing=True))
    controller.command({FINGER: 1.2, THUMB: 0.4})  # 0.6 s for the finger at 2 rad/s
    still = {FINGER: 0.0, THUMB: 0.0}
    targets = [controller.update(DT, still, still) for _ in range(60)]
    assert targets[29] == pytest.approx({FINGER: 0.6, THUMB: 0.2})  # half way, both
    assert targets[59] == pytest.approx({FINGER: 1.2, THUMB: 0.4})  # there together
    # A new command from where the setpoints are: only the thumb moves, at its limit.
    controller.command({THUMB: 0.0})
    assert controller.update(DT, still, still) == pytest.approx({FINGER: 1.2, THUMB: 0.38})


def test_targets_stay_within_the_joint_limits(tmp_path):
    controller = _controller(tmp_path)
    controller.command({FINGER: 3.0, THUMB: -1.0})
    still = {FINGER: 0.0, THUMB: 0.0}
    for _ in range(300):
        targets = controller.update(DT, still, still)
    assert targets == {FINGER: 1.5, THUMB: 0.0}


def test_a_controller_coupling_drives_the_follower_from_the_leader(tmp_path):
    controller = _controller(tmp_path, breakaway_torque=None)
    controller.command({FINGER: 1.0, THUMB: 1.4})  # the follower's own value is ignored
    still = {FINGER: 0.0, THUMB: 0.0}
    for _ in range(100):
        targets = controller.update(DT, still, still)
    assert targets == pytest.approx({FINGER: 1.0, THUMB: 0.5})
    assert controller.held_leaders == {}


def test_breakaway_holds_a_blocked_leader_and_the_follower_keeps_closing(tmp_path):
    controller = _controller(tmp_path, breakaway_torque=BREAKAWAY)
    controller.command({FINGER: 1.2})
    blocked = {FINGER: 0.3, THUMB: 0.1}  # the leader stopped on an object at 0.3 rad
    still = {FINGER: 0.0, THUMB: 0.0}
    targets = {}
    for _ in range(100):
        targets = controller.update(DT, blocked, still)
    # Held once 5 N m/rad x (motor - 0.3 rad) exceeded 0.5 N m, i.e. at motor 0.4 rad.
    assert controller.held_leaders == {FINGER: 0.3}
    assert targets[FINGER] == 0.3
    assert targets[THUMB] == pytest.approx(0.5 * 1.2)  # the motor reached its command


def test_a_moving_leader_does_not_break_away(tmp_path):
    controller = _controller(tmp_path, breakaway_torque=BREAKAWAY)
    controller.command({FINGER: 1.2})
    q = {FINGER: 0.0, THUMB: 0.0}
    for _ in range(100):
        targets = controller.update(DT, q, {FINGER: 2.0, THUMB: 1.0})
        q = {FINGER: targets[FINGER], THUMB: targets[THUMB]}  # tracking perfectly
    assert controller.held_leaders == {}
    assert q[FINGER] == pytest.approx(1.2)


def test_opening_below_the_held_angle_releases_the_leader(tmp_path):
    controller = _controller(tmp_path, breakaway_torque=BREAKAWAY)
    controller.command({FINGER: 1.2})
    blocked, still = {FINGER: 0.3, THUMB: 0.1}, {FINGER: 0.0, THUMB: 0.0}
    for _ in range(100):
        controller.update(DT, blocked, still)
    controller.command({FINGER: 0.1})
    for _ in range(100):
        targets = controller.update(DT, blocked, still)
    assert controller.held_leaders == {}
    assert targets == pytest.approx({FINGER: 0.1, THUMB: 0.05})


def test_reset_takes_the_measured_positions_and_releases_holds(tmp_path):
    controller = _controller(tmp_path, breakaway_torque=BREAKAWAY)
    controller.command({FINGER: 1.2})
    for _ in range(100):
        controller.update(DT, {FINGER: 0.3, THUMB: 0.1}, {FINGER: 0.0, THUMB: 0.0})
    controller.reset({FINGER: 0.7, THUMB: 0.35})
    assert controller.held_leaders == {}
    targets = controller.update(DT, {FINGER: 0.7, THUMB: 0.35}, {FINGER: 0.0, THUMB: 0.0})
    assert targets == pytest.approx({FINGER: 0.7, THUMB: 0.35})


def test_commands_are_checked(tmp_path):
    controller = _controller(tmp_path)
    with pytest.raises(UnknownNameError):
        controller.command({"no_such_joint": 0.1})
    with pytest.raises(GraspframeError, match="not finite"):
        controller.command({FINGER: math.nan})


def test_the_holding_drive_is_stiffer_and_unlimited():
    held = holding_drive(DriveGains(stiffness=4.0, damping=0.3, force_limit=2.0))
    assert held == DriveGains(4.0 * HOLD_STIFFNESS_FACTOR, 0.3, math.inf)
