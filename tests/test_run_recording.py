"""The main job from one image, and its rerun recording."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import cv2
import numpy as np
import pytest
from graspframe_rerun.recording import RunRecording

import graspframe.runner as runner
from graspframe.cli import main
from graspframe.errors import GraspframeError
from graspframe.events import MOTION_CYCLE, WORLD_BUILT, RunInfo
from graspframe.hal import ObjectDescription
from graspframe.transforms import make_T

EXPECTED_ENTITIES = (
    "/world/table",
    "/world/object",
    "/world/robot/",
    "/world/plan/path",
    "/world/palm_path",
    "/world/contacts/",
    "/vf/robot/",
    "/vf/human/",
    "/plots/joints/",
    "/plots/palm_sensor",
    "/plots/distance_to_goal",
    "/vision/input",
    "/vision/mask",
    "/log",
)
CHUNK = re.compile(r"with (\d+) rows .* - (/\S+) - ")


def rrd_rows(path: Path) -> dict[str, int]:
    """entity path -> rows, read back with rerun's own `rerun rrd print`."""
    rerun = shutil.which("rerun") or str(Path(__import__("sys").executable).parent / "rerun")
    out = subprocess.run(
        [rerun, "rrd", "print", str(path)],
        capture_output=True,
        text=True,
        check=True,
        stdin=subprocess.DEVNULL,
    ).stdout
    rows: dict[str, int] = {}
    for count, entity in CHUNK.findall(out):
        rows[entity] = rows.get(entity, 0) + int(count)
    return rows


def _only_run(out: Path) -> Path:
    (run_dir,) = out.iterdir()
    return run_dir


@pytest.mark.slow
@pytest.mark.parametrize("hand", ["karlsruhe", "barrett"])
def test_the_demo_runs_and_is_recorded(hand, tmp_path):
    assert main(["run", "--hand", hand, "--out", str(tmp_path)]) == 0
    run_dir = _only_run(tmp_path)
    result = json.loads((run_dir / "result.json").read_text())
    assert result["status"] == "ok"
    assert result["classification"]["grasp"] == "large_diameter"
    assert result["recording"] == str(run_dir / "recording.rrd")
    # No --grasp and no --image: the command itself repeats the demo.
    assert result["reproduce"] == f"graspframe run --hand {hand} --arm kuka --mount arm --seed 0"
    # The main job holds the can, and shows it.
    assert result["outcome"]["success"], result["outcome"]["failure_reason"]
    assert (run_dir / "snapshots.png").stat().st_size > 10_000

    rows = rrd_rows(run_dir / "recording.rrd")
    for expected in EXPECTED_ENTITIES:
        assert any(entity.startswith(expected) for entity in rows), expected
    approach_cycles = sum(
        e.get("cycles", 0) for e in result["events"] if e["kind"] == "execute.approach"
    )
    assert approach_cycles > 0
    assert rows["/plots/distance_to_goal"] >= approach_cycles  # a frame per control cycle


def test_no_record_writes_no_recording(tmp_path):
    assert (
        main(
            ["run", "--hand", "barrett", "--grasp", "pinch", "--no-record", "--out", str(tmp_path)]
        )
        == 0
    )
    run_dir = _only_run(tmp_path)
    assert not (run_dir / "recording.rrd").exists()
    assert "recording" not in json.loads((run_dir / "result.json").read_text())


def test_a_run_that_raises_midway_leaves_a_readable_recording(tmp_path, monkeypatch):
    def broken(plan, world, motion, hand, obj, params=None, emit=None):
        motion.move_palm_to(plan.T_world_palm_via)  # some motion gets recorded
        raise RuntimeError("hand controller lost")

    monkeypatch.setattr(runner, "execute_plan", broken)
    assert (
        main(["run", "--hand", "barrett", "--grasp", "precision_disc", "--out", str(tmp_path)]) == 1
    )
    run_dir = _only_run(tmp_path)
    result = json.loads((run_dir / "result.json").read_text())
    assert result["status"] == "failed"
    assert result["error"] == "RuntimeError: hand controller lost"
    rows = rrd_rows(run_dir / "recording.rrd")
    assert rows.get("/plots/distance_to_goal", 0) > 0
    assert any(entity.startswith("/world/robot/") for entity in rows)


def _scene(tmp_path: Path, **changes) -> Path:
    scene = json.loads((Path(runner.demo_paths()[1])).read_text())
    scene.update(changes)
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    return path


@pytest.mark.parametrize(
    ("case", "expected"),
    [
        ("no hand in the image", "skin"),
        ("malformed scene", "not readable JSON"),
        ("scene pose not 4x4", "T_camera_object must be a 4x4"),
        ("unknown object", "unknown object 'mug'; known objects: ball"),
        ("image without scene", "--image needs --scene"),
    ],
)
def test_bad_user_inputs_give_their_error_and_exit_code(case, expected, tmp_path, capsys):
    demo_image, _ = runner.demo_paths()
    image = demo_image
    scene = _scene(tmp_path)
    if case == "no hand in the image":
        image = tmp_path / "wall.png"
        rng = np.random.default_rng(0)
        cv2.imwrite(str(image), rng.integers(0, 60, (240, 320, 3), dtype=np.uint8))
    elif case == "malformed scene":
        scene.write_text('{"format": "graspframe.scene/1", ')
    elif case == "scene pose not 4x4":
        scene = _scene(tmp_path, T_camera_object=[[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    elif case == "unknown object":
        scene = _scene(tmp_path, object="mug")
    args = ["run", "--hand", "barrett", "--image", str(image), "--out", str(tmp_path / "runs")]
    if case != "image without scene":
        args += ["--scene", str(scene)]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert expected in err, err
    assert len(err.strip().splitlines()) <= 2  # one message (rich may wrap a long line)
    if case == "no hand in the image":  # found while running: the run records why
        (result_file,) = (tmp_path / "runs").glob("*/result.json")
        saved = json.loads(result_file.read_text())
        assert saved["status"] == "failed" and "NoHandFoundError" in saved["error"]
    else:  # found before anything ran
        assert not (tmp_path / "runs").exists()


def test_the_recording_takes_the_hand_and_object_from_the_run(fake_hand, fake_hand_urdf, tmp_path):
    # Neither the fake hand nor this can is registered: the recorder must not look them up.
    can = ObjectDescription("unregistered_can", "cylinder", {"radius": 0.03, "length": 0.1}, 0.2)
    run = RunInfo("r1", str(tmp_path), {"record": True}, hand=fake_hand, object=can)
    recording = RunRecording(run)
    T_world_object = make_T(p=[0.1, 0.0, 0.05])
    recording.handle(
        WORLD_BUILT.name,
        0.0,
        {
            "hand": fake_hand.name,
            "arm": "none",
            "arm_joint_names": [],
            "object": can.name,
            "model_path": str(fake_hand_urdf),
            "T_world_arm_base": np.eye(4),
            "T_world_object": T_world_object,
            "T_world_object_est": T_world_object,
            "table_height": 0.0,
        },
    )
    recording.handle(
        MOTION_CYCLE.name,
        0.01,
        {
            "q_arm": [],
            "q_hand": {"fk_finger_joint": 0.3, "fk_thumb_joint": 0.3},
            "T_world_palm": np.eye(4),
            "T_world_object": T_world_object,
            "palm_touched": False,
            "distance_to_goal": 0.1,
        },
    )
    recording.finish({"status": "ok"})
    rows = rrd_rows(recording.path)
    assert "/world/object" in rows and "/plots/joints/fk_finger_joint" in rows
    assert any(entity.startswith("/world/robot/fk_finger/") for entity in rows)


def test_a_recording_needs_the_descriptions_of_its_run(tmp_path):
    with pytest.raises(GraspframeError, match="needs its hand and object"):
        RunRecording(RunInfo("r1", str(tmp_path), {"record": True}))
