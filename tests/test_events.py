"""The run event catalogue (graspframe/events.py) and what observers receive."""

from __future__ import annotations

import pytest

import graspframe.runner as runner
from graspframe import events
from graspframe.errors import GraspframeError
from graspframe.grasps import HumanGrasp
from graspframe.plugins import hookimpl
from graspframe.registry import Registry


def test_every_kind_is_declared_once_with_distinct_fields():
    names = [kind.name for kind in events.EVENT_KINDS]
    assert len(set(names)) == len(names)
    for kind in events.EVENT_KINDS:
        assert "." in kind.name and kind.when and kind.fields, kind.name
        assert len(set(kind.field_names)) == len(kind.field_names), kind.name


def test_a_payload_must_match_its_declaration():
    kind = events.EXECUTE_BACK_OFF
    kind.check({"gap": 0.01, "travel": -0.01})
    with pytest.raises(GraspframeError, match=r"undeclared payload fields \['speed'\]"):
        kind.check({"gap": 0.01, "travel": -0.01, "speed": 0.05})
    with pytest.raises(GraspframeError, match=r"missing \['travel'\]"):
        kind.check({"gap": 0.01})
    events.EXECUTE_DISTURBANCE.check({"skipped": "this probe cannot push"})  # optional fields


@pytest.mark.parametrize("mount", runner.MOUNTS)
def test_observers_get_the_descriptions_of_the_run_and_declared_events(
    mount, tmp_path, monkeypatch
):
    started, received = [], []

    class Observer:
        @hookimpl
        def graspframe_run_started(self, run):
            started.append(run)

        @hookimpl
        def graspframe_run_event(self, run, event):
            received.append((run, event))

    def stops_after_the_world_is_built(self, world, motion, emit):
        raise RuntimeError("stop here")

    monkeypatch.setattr(runner.MethodStrategy, "grasp", stops_after_the_world_is_built)
    registry = Registry.from_entry_points(strict=False)
    registry.add_plugin("observer", Observer())
    request = runner.RunRequest(
        hand="barrett", grasp=HumanGrasp.PINCH, mount=mount, out_root=str(tmp_path), record=False
    )
    with pytest.raises(RuntimeError, match="stop here"):
        runner.run_grasp(request, registry)

    (run,) = started
    assert run.hand is registry.get_hand("barrett")
    # The hand on the floating base is on no arm.
    assert run.arm is (registry.get_arm("kuka") if mount == runner.MOUNT_ARM else None)
    assert run.object is registry.default_object_for(HumanGrasp.PINCH)
    assert all(seen is run for seen, _ in received)
    kinds = [event.kind for _, event in received]
    assert kinds[:2] == [events.PLAN_DONE.name, events.WORLD_BUILT.name]
    declared = {kind.name for kind in events.EVENT_KINDS}
    assert set(kinds) <= declared
    world_built = received[1][1]
    assert world_built.data["hand"] == run.hand.name
    assert world_built.data["object"] == run.object.name
