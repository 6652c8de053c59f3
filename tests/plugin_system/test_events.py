"""The run event catalogue (graspframe/plugin_system/events.py) and what observers receive."""

from __future__ import annotations

from pathlib import Path

import pytest

import graspframe.run.runner as runner
import graspframe.run.stages as run_stages
from graspframe.common.defaults import MOUNT_ARM, MOUNTS
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import HumanGrasp
from graspframe.plugin_system import events, hookimpl
from graspframe.plugin_system.registry import Registry
from graspframe.run.request import demo_paths


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


@pytest.mark.parametrize("mount", MOUNTS)
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

    def stops_after_the_world_is_built(self, world, motion, log):
        raise RuntimeError("stop here")

    monkeypatch.setattr(run_stages.MethodStrategy, "grasp", stops_after_the_world_is_built)
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
    assert run.arm is (registry.get_arm("kuka") if mount == MOUNT_ARM else None)
    assert run.object is registry.default_object_for(HumanGrasp.PINCH)
    assert all(seen is run for seen, _ in received)
    kinds = [event.kind for _, event in received]
    assert kinds[:2] == [events.PLAN_DONE.name, events.WORLD_BUILT.name]
    declared = {kind.name for kind in events.EVENT_KINDS}
    assert set(kinds) <= declared
    world_built = received[1][1]
    assert world_built.data["hand"] == run.hand.name
    assert world_built.data["object"] == run.object.name


@pytest.mark.parametrize("shows_pictures", [True, False], ids=["pictures", "none"])
def test_the_run_shows_the_pictures_the_classifier_gives(shows_pictures, tmp_path, monkeypatch):
    """classify.images carries the classifier's own pictures, whatever they are, and none
    for a classifier that shows none (the run computes no mask of its own)."""
    import json

    import numpy as np

    from graspframe.hal import Classifier, ClassifierPicture, HumanGraspEstimate

    _, demo_scene = demo_paths()
    truth = json.loads(Path(demo_scene).read_text())["truth"]
    R_camera_palm = np.asarray(truth["T_camera_palm"])[:3, :3]
    given = (ClassifierPicture("edges", "image", np.zeros((4, 6), np.uint8)),)

    class Stated(Classifier):
        name = "stated"

        def classify(self, image_bgr):
            pictures = given if shows_pictures else ()
            return HumanGraspEstimate(
                HumanGrasp(truth["grasp"]), 1.0, R_camera_palm, None, pictures=pictures
            )

    class Plugin:
        @hookimpl
        def graspframe_register_classifiers(self, register):
            register(Stated)

        @hookimpl
        def graspframe_run_event(self, run, event):
            if event.kind == events.CLASSIFY_IMAGES.name:
                received.append(event.data)

    received: list[dict] = []

    def stop(*args, **kwargs):
        raise RuntimeError("stop here")

    monkeypatch.setattr(run_stages, "execute", stop)
    registry = Registry.from_entry_points(strict=False)
    registry.add_plugin("stated", Plugin())
    request = runner.RunRequest(
        hand="barrett", classifier="stated", out_root=str(tmp_path), record=False
    )
    with pytest.raises(RuntimeError, match="stop here"):
        runner.run_grasp(request, registry)
    (data,) = received
    assert data["image_bgr"].shape == (480, 640, 3)
    if shows_pictures:
        assert data["pictures"] is given  # forwarded as the classifier gave them
    else:
        assert data["pictures"] == ()
