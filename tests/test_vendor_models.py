"""The real vendor models, as a user brings them (read where they lie, never copied):
the LEAP hand spec passes check-hand and grasps on the floating base, the Franka Panda
carries the built-in hands through a held grasp, and the vendor files stay byte for byte
as shipped."""

from __future__ import annotations

import pytest
from conftest import LEAP_HAND_SPEC, PANDA_SPEC, folder_state

from graspframe.commands.check_hand import check_hand_command
from graspframe.grasps import HumanGrasp
from graspframe.registry import default_registry
from graspframe.run_request import RunRequest
from graspframe.runner import run_grasp

pytestmark = pytest.mark.slow


def _held(result: dict) -> bool:
    outcome = result["outcome"]
    return bool(outcome["held_after_lift"] and outcome["held_under_disturbance"])


def test_the_leap_hand_spec_passes_check_hand(leap_hand_dir, tmp_path, capsys):
    before = folder_state(leap_hand_dir)
    assert check_hand_command(str(LEAP_HAND_SPEC), pictures=tmp_path) == 0
    printed = capsys.readouterr().out
    assert "3 of 3 checks ran, all passed" in printed and "4 of 4 held" in printed
    # One picture per preshape closed without physics, one per hold trial (held or not).
    assert len(list(tmp_path.glob("*_closing.png"))) == 4
    assert len(list(tmp_path.glob("*.png"))) == 8
    assert folder_state(leap_hand_dir) == before


def test_the_leap_hand_grasps_on_the_floating_base(leap_hand_dir, tmp_path):
    before = folder_state(leap_hand_dir)
    result = run_grasp(
        RunRequest(
            hand=str(LEAP_HAND_SPEC),
            grasp=HumanGrasp.LARGE_DIAMETER,
            mount="floating",
            out_root=str(tmp_path),
            record=False,
        ),
        default_registry(),
    ).to_json()
    assert result["status"] == "ok" and _held(result), result["outcome"]["failure_reason"]
    assert "index" in result["outcome"]["touching_fingers"]
    assert folder_state(leap_hand_dir) == before  # the run read the vendor files in place


@pytest.mark.parametrize("hand", ["barrett", "karlsruhe"])
def test_the_panda_carries_a_hand_through_a_held_grasp(panda_description_dir, tmp_path, hand):
    before = folder_state(panda_description_dir)
    result = run_grasp(
        RunRequest(hand=hand, arm=str(PANDA_SPEC), out_root=str(tmp_path), record=False),
        default_registry(),
    ).to_json()
    assert result["status"] == "ok" and _held(result), result["outcome"]["failure_reason"]
    assert result["plan"]["approach"] == "side"
    assert folder_state(panda_description_dir) == before
