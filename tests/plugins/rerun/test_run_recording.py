"""The main job from one image, and its rerun recording."""

from __future__ import annotations

import json
from collections import defaultdict
from pathlib import Path

import cv2
import numpy as np
import pytest
from conftest import THIRD_PARTY
from graspframe_rerun.recording import RunRecording
from rerun.chunk import RrdReader
from scipy.spatial.transform import Rotation

import graspframe.run.stages as run_stages
from graspframe.cli.commands import main
from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import make_T
from graspframe.hal import ObjectDescription
from graspframe.model_files.urdf_model import read_model
from graspframe.plugin_system.events import EXECUTE_PRESHAPE, MOTION_CYCLE, WORLD_BUILT, RunInfo
from graspframe.robot_models.model import CollisionModel
from graspframe.run.request import demo_paths

LEAP_URDF = THIRD_PARTY / "hands" / "leap_hand" / "leap_hand_right.urdf"
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
    "/vision/crop",
    "/log",
)
# Entities with one sample per motion cycle (besides each /world/robot/<link>).
PER_CYCLE_ENTITIES = (
    "/world/object",
    "/world/palm_path",
    "/plots/palm_sensor",
    "/plots/distance_to_goal",
)


def rrd_rows(path: Path) -> dict[str, int]:
    """entity path -> rows (static and on the timeline), read back with rerun's reader."""
    rows: dict[str, int] = defaultdict(int)
    for chunk in RrdReader(path).stream():
        rows[chunk.entity_path] += chunk.num_rows
    return dict(rows)


def rrd_samples(path: Path) -> dict[str, list[tuple[int, dict]]]:
    """entity path -> (sim_time [ns], {component: value}) of every row on the sim_time
    timeline, in time order."""
    samples: dict[str, list[tuple[int, dict]]] = defaultdict(list)
    for chunk in RrdReader(path).stream():
        if "sim_time" not in chunk.timeline_names:
            continue
        batch = chunk.to_record_batch()
        sim_time_ns = batch.column("sim_time").to_numpy().astype(np.int64)
        components = {
            name: batch.column(name).to_pylist()
            for name in batch.schema.names
            if ":" in name  # Archetype:component
        }
        for row, t in enumerate(sim_time_ns):
            values = {name: column[row] for name, column in components.items()}
            samples[chunk.entity_path].append((int(t), values))
    for rows in samples.values():
        rows.sort(key=lambda sample: sample[0])
    return dict(samples)


def _count_motion_cycles(monkeypatch) -> list[float]:
    """Collects the sim_time [s] of every motion.cycle the recorder receives."""
    cycle_times: list[float] = []
    handle = RunRecording.handle

    def counting_handle(self, kind, sim_time, data):
        if kind == MOTION_CYCLE.name:
            cycle_times.append(sim_time)
        handle(self, kind, sim_time, data)

    monkeypatch.setattr(RunRecording, "handle", counting_handle)
    return cycle_times


def _only_run(out: Path) -> Path:
    (run_dir,) = out.iterdir()
    return run_dir


@pytest.mark.slow
@pytest.mark.parametrize("hand", ["karlsruhe", "barrett"])
def test_the_demo_runs_and_is_recorded(hand, tmp_path, monkeypatch):
    cycle_times = _count_motion_cycles(monkeypatch)
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
    assert len(cycle_times) >= approach_cycles > 0
    # A sample per control cycle, at its simulation time, on every per-cycle entity.
    samples = rrd_samples(run_dir / "recording.rrd")
    cycle_time_ns = [round(1e9 * t) for t in cycle_times]
    robot_links = [entity for entity in samples if entity.startswith("/world/robot/")]
    joints = [entity for entity in samples if entity.startswith("/plots/joints/")]
    assert robot_links and joints
    assert all(entity.count("/") == 3 for entity in robot_links)  # /world/robot/<link>
    for entity in [*PER_CYCLE_ENTITIES, *robot_links, *joints]:
        times = [t for t, _ in samples[entity]]
        if entity == "/world/object":
            times = times[1:]  # its pose when the world was built comes first
        assert times == cycle_time_ns, entity


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
    def broken(self, world, motion, log):
        motion.move_palm_to(self.plan.T_world_palm_via)  # some motion gets recorded
        raise RuntimeError("hand controller lost")

    monkeypatch.setattr(run_stages.MethodStrategy, "grasp", broken)
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
    scene = json.loads((Path(demo_paths()[1])).read_text())
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
    demo_image, _ = demo_paths()
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
            "model": read_model(fake_hand_urdf),
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
    recording.finish("ok")
    rows = rrd_rows(recording.path)
    assert "/world/object" in rows and "/plots/joints/fk_finger_joint" in rows
    assert any(entity.startswith("/world/robot/fk_finger/collision/") for entity in rows)


def _world_built(hand_urdf, T_world_object) -> dict:
    return {
        "hand": "fake_hand",
        "arm": "none",
        "arm_joint_names": [],
        "object": "unregistered_can",
        "model": read_model(hand_urdf),
        "T_world_arm_base": make_T(p=[0.0, 0.0, 0.2]),
        "T_world_object": T_world_object,
        "T_world_object_est": T_world_object,
        "table_height": 0.0,
    }


def _cycle(i: int) -> dict:
    """The i-th motion cycle of a made-up motion: fingers closing, palm and object moving."""
    q = 0.1 * i
    return {
        "q_arm": [],
        "q_hand": {"fk_finger_joint": q, "fk_thumb_joint": 0.5 * q},
        "T_world_palm": make_T(p=[0.01 * i, 0.0, 0.3]),
        "T_world_object": make_T(R=Rotation.from_rotvec([0.0, 0.0, q]).as_matrix(), p=[q, 0, 0]),
        "palm_touched": i >= 4,
        "distance_to_goal": 0.5 - q,
    }


def test_every_cycle_is_recorded_at_its_time_with_its_values(fake_hand, fake_hand_urdf, tmp_path):
    can = ObjectDescription("unregistered_can", "cylinder", {"radius": 0.03, "length": 0.1}, 0.2)
    recording = RunRecording(RunInfo("r1", str(tmp_path), {"record": True}, fake_hand, None, can))
    recording.handle(WORLD_BUILT.name, 0.0, _world_built(fake_hand_urdf, make_T()))
    cycle_times = [0.001 * (i + 1) for i in range(7)]
    cycles = [_cycle(i) for i in range(7)]
    for i, (sim_time, data) in enumerate(zip(cycle_times, cycles, strict=True)):
        if i == 3:  # another event between cycles: those before it are sent first
            recording.handle(EXECUTE_PRESHAPE.name, sim_time, {"preshape": "pinch"})
        recording.handle(MOTION_CYCLE.name, sim_time, data)
    recording.finish("ok")

    samples = rrd_samples(recording.path)
    cycle_time_ns = [round(1e9 * t) for t in cycle_times]

    def per_cycle(entity: str, component: str) -> list:
        rows = samples[entity][1:] if entity == "/world/object" else samples[entity]
        assert [t for t, _ in rows] == cycle_time_ns, entity
        return [values[component] for _, values in rows]

    distances = per_cycle("/plots/distance_to_goal", "Scalars:scalars")
    assert distances == [[data["distance_to_goal"]] for data in cycles]
    touched = per_cycle("/plots/palm_sensor", "Scalars:scalars")
    assert touched == [[float(data["palm_touched"])] for data in cycles]
    for joint in ("fk_finger_joint", "fk_thumb_joint"):
        values = per_cycle(f"/plots/joints/{joint}", "Scalars:scalars")
        assert values == [[data["q_hand"][joint]] for data in cycles]
    # The palm path grows by one point a cycle, over the whole motion.
    strips = per_cycle("/world/palm_path", "LineStrips3D:strips")
    for i, (strip,) in enumerate(strips):
        expected = [data["T_world_palm"][:3, 3] for data in cycles[: i + 1]]
        np.testing.assert_allclose(strip, expected, atol=1e-6)

    def poses(entity: str) -> list[np.ndarray]:
        translations = per_cycle(entity, "Transform3D:translation")
        quaternions = per_cycle(entity, "Transform3D:quaternion")
        return [
            make_T(R=Rotation.from_quat(quat_xyzw).as_matrix(), p=p)
            for (p,), (quat_xyzw,) in zip(translations, quaternions, strict=True)
        ]

    for T, data in zip(poses("/world/object"), cycles, strict=True):
        np.testing.assert_allclose(T, data["T_world_object"], atol=1e-6)
    # Each link where forward kinematics puts it, on the arm base; its meshes below it.
    model = CollisionModel(read_model(fake_hand_urdf))
    T_world_base = _world_built(fake_hand_urdf, make_T())["T_world_arm_base"]
    links = sorted({link for link, _, _ in model.shapes()})
    for link in links:
        expected = []
        for data in cycles:
            model.place(fake_hand.with_model_followers(data["q_hand"]))
            expected.append(T_world_base @ model.T_root_frame(link))
        np.testing.assert_allclose(poses(f"/world/robot/{link}"), expected, atol=1e-6)
        assert f"/world/robot/{link}/collision/0" not in samples  # static, moved by its link
    # The geometry is logged once, not per cycle.
    static = {chunk.entity_path for chunk in RrdReader(recording.path).stream() if chunk.is_static}
    assert "/world/object" in static and "/world/table" in static
    assert {f"/world/robot/{link}/collision/0" for link in links} <= static


def test_a_recording_needs_the_descriptions_of_its_run(tmp_path):
    with pytest.raises(GraspframeError, match="needs its hand and object"):
        RunRecording(RunInfo("r1", str(tmp_path), {"record": True}))


def _albedo_alpha(path: Path) -> dict[str, int]:
    """Mesh entity -> alpha [0, 255] of its albedo factor."""
    alphas = {}
    for chunk in RrdReader(path).stream():
        batch = chunk.to_record_batch()
        if "Mesh3D:albedo_factor" in batch.schema.names:
            (rgba,) = batch.column("Mesh3D:albedo_factor").to_pylist()[0]
            alphas[chunk.entity_path] = rgba & 0xFF
    return alphas


@pytest.mark.skipif(not LEAP_URDF.is_file(), reason="the third-party models are not here")
def test_visual_meshes_are_recorded_with_the_collision_shapes_as_an_overlay(fake_hand, tmp_path):
    can = ObjectDescription("unregistered_can", "cylinder", {"radius": 0.03, "length": 0.1}, 0.2)
    recording = RunRecording(RunInfo("r1", str(tmp_path), {"record": True}, fake_hand, None, can))
    T_world_object = make_T(p=[0.1, 0.0, 0.05])
    world_built = _world_built(LEAP_URDF, T_world_object)
    recording.handle(WORLD_BUILT.name, 0.0, world_built)
    recording.finish("ok")
    alphas = _albedo_alpha(recording.path)
    # The palm: its vendor mesh, opaque, and its collision boxes, see-through.
    assert alphas["/world/robot/palm_lower/visual/0"] == 255
    collision = [a for e, a in alphas.items() if e.startswith("/world/robot/palm_lower/collision/")]
    assert collision and all(a < 128 for a in collision)
    # Every link with a vendor mesh has it logged.
    visual_links = {v.link for v in world_built["model"].visuals}
    logged = {e.split("/")[3] for e in alphas if "/visual/" in e}
    assert logged == visual_links
