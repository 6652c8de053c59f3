"""The grasp strategy: mapping tables, approach selection, robot-aware goals, whole-hand
table clearance, collision-checked arm paths, execution and runs that hold."""

from __future__ import annotations

import dataclasses
import functools
import json
import math
from pathlib import Path

import numpy as np
import pytest

from graspframe.cli.commands import main
from graspframe.common.defaults import MOUNTS, SCENE_OBJECT_XY
from graspframe.common.grasps import HumanGrasp
from graspframe.common.json_files import jsonable
from graspframe.common.transforms import R_from_rpy, inv_T, make_T, rotation_angle
from graspframe.hal import AdapterShape
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.mounting import mount
from graspframe.run.request import RunRequest
from graspframe.run.runner import run_grasp
from graspframe.strategy import method
from graspframe.strategy.arm_path import choose_plan, path_problem
from graspframe.strategy.hand_geometry import closing_configurations, lowest_points
from graspframe.strategy.method import ExecutorParams
from graspframe.strategy.planner import (
    PlannerParams,
    PlanningError,
    PlanningTarget,
    approach_direction,
    object_in_palm,
    plan_grasp,
)
from graspframe.strategy.reference_poses import R_OBJECT_PALM_TOP, reference_placement

REGISTRY = default_registry()
G = HumanGrasp
ROBOT_HANDS = ("barrett", "karlsruhe")

# The method's mapping table, verbatim.
MAPPING = {
    "barrett": {
        G.LARGE_DIAMETER: "wrap",
        G.SMALL_DIAMETER: "wrap",
        G.ABDUCTED_THUMB: "precision",
        G.PINCH: "precision",
        G.POWER_SPHERE: "precision_disc",
        G.PRECISION_DISC: "precision_disc",
    },
    "karlsruhe": {
        G.LARGE_DIAMETER: "power",
        G.SMALL_DIAMETER: "wrap",
        G.ABDUCTED_THUMB: "power",
        G.PINCH: "power",
        G.POWER_SPHERE: "sphere",
        G.PRECISION_DISC: "disc",
    },
}


@pytest.mark.parametrize("hand_name", sorted(MAPPING))
def test_mapping_tables_are_the_methods(hand_name):
    hand = REGISTRY.get_hand(hand_name)
    assert {g: str(p) for g, p in hand.grasp_map.items()} == MAPPING[hand_name]


def _R_palm(z_palm, y_palm):
    z, y = np.asarray(z_palm, float), np.asarray(y_palm, float)
    return np.column_stack([np.cross(y, z), y, z])


@pytest.mark.parametrize(
    ("label", "R_world_palm", "expected"),
    [
        ("upright, palm facing +x", _R_palm([1, 0, 0], [0, 0, -1]), "side"),
        ("upright, palm facing -y, thumb down", _R_palm([0, -1, 0], [0, 0, 1]), "side"),
        # The choice follows the palm normal only: an abducted thumb (palm y tilted) with
        # a horizontal palm normal is a side grasp.
        ("palm sideways, hand lying flat", _R_palm([1, 0, 0], [0, 1, 0]), "side"),
        ("palm down", _R_palm([0, 0, -1], [0, -1, 0]), "top"),
        (
            "palm tilted 20 deg down",
            R_from_rpy(0, math.radians(20), 0) @ _R_palm([1, 0, 0], [0, 0, -1]),
            "side",
        ),
        (
            "palm tilted 40 deg down",
            R_from_rpy(0, math.radians(40), 0) @ _R_palm([1, 0, 0], [0, 0, -1]),
            "top",
        ),
    ],
)
def test_approach_selection_follows_the_palm_normal(label, R_world_palm, expected):
    approach, a = approach_direction(R_world_palm, PlannerParams())
    assert approach == expected, label
    if expected == "top":
        np.testing.assert_allclose(a, [0, 0, -1])
    else:  # along the palm normal, in the table plane
        assert a[2] == 0.0
        assert a @ R_world_palm[:, 2] > 0.9


def test_a_palm_facing_up_is_refused():
    R_up = R_from_rpy(0, math.radians(-50), 0) @ _R_palm([1, 0, 0], [0, 0, -1])
    with pytest.raises(PlanningError, match="palm faces up"):
        approach_direction(R_up, PlannerParams())


def _reference_plan(hand_name: str, grasp: HumanGrasp, **kwargs):
    hand, obj = REGISTRY.get_hand(hand_name), REGISTRY.default_object_for(grasp)
    T_world_object = make_T(p=[*SCENE_OBJECT_XY, obj.half_height])
    placement = reference_placement(obj, REGISTRY.get_hand("human").preshape_for(grasp))
    table = {"table_height": kwargs.pop("table_height")} if "table_height" in kwargs else {}
    target = PlanningTarget(grasp, placement.T_object_palm, T_world_object, hand, obj, **table)
    plan = plan_grasp(target, **kwargs)
    return hand, obj, placement, plan


@pytest.mark.parametrize("grasp", list(HumanGrasp))
@pytest.mark.parametrize("hand_name", ROBOT_HANDS)
def test_the_object_goes_where_the_robot_hand_holds_it(hand_name, grasp):
    hand, obj, placement, plan = _reference_plan(hand_name, grasp)
    preshape = hand.preshape(plan.preshape)
    assert plan.volar == (grasp in (G.LARGE_DIAMETER, G.SMALL_DIAMETER))
    assert plan.preshape == MAPPING[hand_name][grasp]
    # Orientation: the human palm's, turned by the preshape's roll about the normal.
    roll = rotation_angle(placement.T_object_palm[:3, :3], plan.T_object_palm[:3, :3])
    assert roll == pytest.approx(abs(preshape.roll), abs=1e-9)
    # Position: the object's centroid at the hand's own grasp centre (x, y) ...
    p_palm_object = inv_T(plan.T_object_palm)[:3, 3]
    if plan.table_raise == 0.0:
        np.testing.assert_allclose(p_palm_object[:2], preshape.grasp_center_palm[:2], atol=1e-9)
    # ... resting on the palm in a volar grasp, or, thinner than the preshape's volar
    # centre height, held there after the hand backs off by the volar gap.
    extent = obj.extent_along(plan.T_object_palm[:3, 2])
    if plan.volar:
        height = max(extent, preshape.volar_centre_height or 0.0)
        assert p_palm_object[2] == pytest.approx(height, abs=1e-9)
        assert plan.volar_gap == pytest.approx(height - extent, abs=1e-9)
    else:
        assert p_palm_object[2] >= extent
    # The pre-approach pose lies back along the approach, orientation unchanged.
    offset = plan.T_world_palm_goal[:3, 3] - plan.T_world_palm_pre[:3, 3]
    np.testing.assert_allclose(offset / np.linalg.norm(offset), plan.a_world, atol=1e-9)
    np.testing.assert_allclose(plan.T_world_palm_goal[:3, :3], plan.T_world_palm_pre[:3, :3])
    json.dumps(jsonable(plan))  # plain and serialisable


@pytest.mark.parametrize("grasp", list(HumanGrasp))
@pytest.mark.parametrize("hand_name", ROBOT_HANDS)
def test_the_whole_hand_clears_the_table_at_the_goal(hand_name, grasp):
    hand, obj, _, plan = _reference_plan(hand_name, grasp)
    preshape = hand.preshape(plan.preshape)
    configurations = closing_configurations(hand, preshape, obj, inv_T(plan.T_object_palm))
    lowest = min(lowest_points(hand, configurations, plan.T_world_palm_goal[:3, :3]).values())
    assert plan.T_world_palm_goal[2, 3] + lowest >= PlannerParams().table_clearance - 1e-9
    assert plan.min_goal_height == pytest.approx(PlannerParams().table_clearance - lowest, abs=1e-6)


def test_a_stop_direction_keeps_the_objects_rim_at_the_stopping_fingers():
    """Karlsruhe disc: index and middle take the far rim (palm +x) where they stand, so a
    smaller or larger disc keeps its far rim where the design disc's is; its near face
    (the top) keeps the design's distance from the palm as before."""
    hand = REGISTRY.get_hand("karlsruhe")
    preshape = hand.preshape_for(HumanGrasp.PRECISION_DISC)
    design = preshape.design_object
    assert preshape.stop_direction == (1.0, 0.0, 0.0)
    R_object_palm = R_OBJECT_PALM_TOP
    for name in ("disc_075", "disc", "disc_125"):
        obj = REGISTRY.get_object(name)
        radius, half = obj.dimensions["radius"], obj.dimensions["length"] / 2
        centre = object_in_palm(preshape, obj, R_object_palm, volar=False)
        assert centre[0] + radius == pytest.approx(design.centre[0] + design.radius, abs=1e-9)
        assert centre[1] == pytest.approx(design.centre[1], abs=1e-9)
        assert centre[2] - half == pytest.approx(design.centre[2] - design.length / 2, abs=1e-9)
    # Without a stop direction only the height follows the object.
    plain = dataclasses.replace(preshape, stop_direction=None)
    centre = object_in_palm(plain, REGISTRY.get_object("disc_125"), R_object_palm, volar=False)
    np.testing.assert_allclose(centre[:2], design.centre[:2], atol=1e-9)


def test_a_goal_that_would_put_the_hand_into_the_table_is_raised():
    hand, obj = REGISTRY.get_hand("barrett"), REGISTRY.get_object("ball_075")
    T_world_object = make_T(p=[0.55, 0.2, obj.half_height])
    # A 6.75 cm ball held from the top where the precision disc preshape holds balls
    # (near face 30 mm from the palm) leaves the deepest fingertips about 4 mm above the
    # table: less than the clearance, so the goal is raised.
    T_object_palm = make_T(R_OBJECT_PALM_TOP, [0.0, 0.0, -0.05])
    plan = plan_grasp(PlanningTarget(G.POWER_SPHERE, T_object_palm, T_world_object, hand, obj))
    assert plan.table_raise > 0.005
    assert plan.T_world_palm_goal[2, 3] == pytest.approx(plan.min_goal_height)


def _barrett_large_diameter_on_kuka():
    """(the checked plan, its planning target) of the Barrett's large diameter grasp of
    the can on the KUKA arm."""
    hand, arm = REGISTRY.get_hand("barrett"), REGISTRY.get_arm("kuka")
    obj = REGISTRY.get_object("large_cylinder")
    placement = reference_placement(obj, REGISTRY.get_hand("human").preshape_for(G.LARGE_DIAMETER))
    T_world_object = make_T(p=[*SCENE_OBJECT_XY, obj.half_height])
    target = PlanningTarget(G.LARGE_DIAMETER, placement.T_object_palm, T_world_object, hand, obj)
    return choose_plan(target, arm, np.eye(4)), target


def test_the_chosen_arm_path_is_collision_free_and_refusals_say_why():
    checked, target = _barrett_large_diameter_on_kuka()
    assert path_problem(checked.plan, target, checked.robot, checked.T_world_base) is None
    for reason in checked.refused:  # each refused variant names the part of the path
        assert any(part in reason for part in ("transfer", "descent", "approach", "unreachable"))


def test_the_path_check_checks_the_segments_the_executor_drives(monkeypatch):
    """The executor and the path check take their segments from one builder
    (method.planned_path): an approach changed there, sunk 8 cm into the table, is
    what the check then refuses."""
    checked, target = _barrett_large_diameter_on_kuka()
    args = (checked.plan, target, checked.robot, checked.T_world_base)
    assert path_problem(*args) is None
    built = method.palm_path

    def sunk_approach(*path_args, **path_kwargs):
        path = built(*path_args, **path_kwargs)
        T_start = path.approach.T_world_palm_start.copy()
        T_start[2, 3] -= 0.08
        return dataclasses.replace(
            path, approach=dataclasses.replace(path.approach, T_world_palm_start=T_start)
        )

    monkeypatch.setattr(method, "palm_path", sunk_approach)
    problem = path_problem(*args)
    assert problem is not None and "approach" in problem and "table" in problem


def test_when_no_straight_mounted_path_exists_an_adapter_of_the_hand_is_tried():
    """The Karlsruhe hand holds the short abducted-thumb cylinder with its fingers tilted
    up: straight on the flange, the KR 5's wrist would be in the table in every variant;
    its dorsal plate lifts the wrist above the palm, and the plate is checked too."""
    hand, arm = REGISTRY.get_hand("karlsruhe"), REGISTRY.get_arm("kuka")
    obj = REGISTRY.get_object("thumb_cylinder")
    placement = reference_placement(obj, REGISTRY.get_hand("human").preshape_for(G.ABDUCTED_THUMB))
    T_world_object = make_T(p=[*SCENE_OBJECT_XY, obj.half_height])
    target = PlanningTarget(G.ABDUCTED_THUMB, placement.T_object_palm, T_world_object, hand, obj)
    checked = choose_plan(target, arm, np.eye(4))
    assert checked.plan.variant.mounting == checked.robot.mounting == "dorsal_plate"
    assert checked.refused and not any("mounting" in reason for reason in checked.refused)
    assert path_problem(checked.plan, target, checked.robot, checked.T_world_base) is None
    # The adapter is checked like an arm link: a plate grown to 40 cm hits the table.
    plate = hand.mounting("dorsal_plate")
    (shape,) = plate.adapter
    grown = AdapterShape("box", {"size_x": 0.4, "size_y": 0.4, "size_z": 0.4}, shape.T_root_shape)
    big_hand = dataclasses.replace(
        hand, mountings={"big": dataclasses.replace(plate, adapter=(grown,))}
    )
    big = mount(arm, big_hand, mounting="big")
    big_target = dataclasses.replace(target, hand=big_hand)
    problem = path_problem(checked.plan, big_target, big, checked.T_world_base)
    assert problem is not None and f"{hand.root_link}_adapter" in problem


def test_a_plan_without_a_collision_free_path_is_refused():
    hand, arm = REGISTRY.get_hand("barrett"), REGISTRY.get_arm("kuka")
    obj = REGISTRY.get_object("large_cylinder")
    placement = reference_placement(obj, REGISTRY.get_hand("human").preshape_for(G.LARGE_DIAMETER))
    # The can right beside the arm's foot: every variant puts the arm through the table
    # or the can, or out of reach.
    T_world_object = make_T(p=[0.12, 0.0, obj.half_height])
    with pytest.raises(PlanningError, match="no collision-free path"):
        choose_plan(
            PlanningTarget(G.LARGE_DIAMETER, placement.T_object_palm, T_world_object, hand, obj),
            arm,
            np.eye(4),
        )


@functools.cache
def _run(out_root: str, **fields) -> dict:
    """One run per distinct request (shared by the tests of this module)."""
    return run_grasp(RunRequest(out_root=out_root, record=False, **fields), REGISTRY).to_json()


@pytest.fixture(scope="module")
def runs_dir(tmp_path_factory) -> str:
    return str(tmp_path_factory.mktemp("runs"))


# (hand, grasp, object size, mount) -> why it is not held (docs/experiments.md, Known
# limits). Strict: a case that starts to hold fails the suite until it is taken off.
NOT_HELD = {
    ("barrett", G.SMALL_DIAMETER, "075", "arm"): (
        "the 19 mm handle sits loose in the wedge under the crossing fingers (the arm's "
        "path takes the grasp turned by 30 deg)"
    ),
    ("barrett", G.PRECISION_DISC, "075", "arm"): (
        "refused: the fingertips pass over the 19 mm disc once the hand is off the table"
    ),
    ("karlsruhe", G.PRECISION_DISC, "125", "arm"): (
        "the 11 cm disc does not fit between the thumb and the little finger's post"
    ),
}

# Cases whose outcome changes from one machine to the next at the same commit and the
# same package versions (PhysX on the CPU; a grasp on the edge): not strict.
MARGINAL = {
    ("karlsruhe", G.LARGE_DIAMETER, "125", "arm"): (
        "the thumb touches the 10 cm cylinder first on every approach and the four "
        "corrections do not clear it (on 2026-12-03, at a commit whose CI had held it)"
    ),
}


def _cases(sizes, mounts):
    """(hand, grasp, size, mount) parameters, the known failures marked strict xfail."""
    cases = []
    for hand_name in ROBOT_HANDS:
        for grasp in HumanGrasp:
            for size in sizes:
                for mount_name in mounts:
                    key = (hand_name, grasp, size, mount_name)
                    marks = ()
                    if key in NOT_HELD:
                        marks = pytest.mark.xfail(reason=NOT_HELD[key], strict=True)
                    elif key in MARGINAL:
                        marks = pytest.mark.xfail(reason=MARGINAL[key], strict=False)
                    label = f"{hand_name}-{grasp.value}-{size}-{mount_name}"
                    cases.append(pytest.param(*key, marks=marks, id=label))
    return cases


@pytest.mark.slow
@pytest.mark.parametrize(("hand_name", "grasp", "size", "mount"), _cases(["100"], MOUNTS))
def test_every_grasp_holds_under_perfect_perception(hand_name, grasp, size, mount, runs_dir):
    result = _run(runs_dir, hand=hand_name, grasp=grasp, mount=mount)
    outcome = result["outcome"]
    assert result["status"] == "ok"
    assert outcome["held_after_lift"], outcome["failure_reason"]
    assert outcome["held_under_disturbance"], outcome["failure_reason"]
    assert len(outcome["touching_fingers"]) >= 2
    assert set(outcome["disturbance"]) == {"+x", "-x", "+y", "-y", "+z", "-z"}
    assert Path(result["snapshots"]).stat().st_size > 10_000


@pytest.mark.slow
@pytest.mark.parametrize(("hand_name", "grasp", "size", "mount"), _cases(["075", "125"], ["arm"]))
def test_every_grasp_holds_a_smaller_and_a_larger_object(hand_name, grasp, size, mount, runs_dir):
    obj = f"{REGISTRY.default_object_for(grasp).name}_{size}"
    result = _run(runs_dir, hand=hand_name, grasp=grasp, object=obj, mount=mount)
    assert result["outcome"]["success"], result["outcome"]["failure_reason"]


@pytest.mark.slow
@pytest.mark.parametrize("grasp", [G.LARGE_DIAMETER, G.SMALL_DIAMETER])
@pytest.mark.parametrize("hand_name", ROBOT_HANDS)
def test_volar_grasps_hold_with_a_5_cm_object_error_in_5_of_6_directions(
    hand_name, grasp, runs_dir
):
    """Experiment B on the arm: the robot believes the object 5 cm off in each of six
    directions; the volar loop (finger-first corrections, centring on the palm) finds it."""
    held = []
    for k in range(6):
        beta = k * math.pi / 3
        error = (0.05 * math.cos(beta), 0.05 * math.sin(beta))
        result = _run(runs_dir, hand=hand_name, grasp=grasp, object_error=error)
        held.append(result["outcome"]["success"])
    assert sum(held) >= 5, held


def test_volar_grasp_with_object_error_corrects_towards_the_true_object(runs_dir):
    """The robot believes the can 5 cm off to +y: the first touch is a finger, the goal
    moves so that the hand's grasp centre comes towards the true can (across the
    approach, in the table plane), never below the lowest goal that keeps the hand off
    the table, the palm touches in the end and the can is held."""
    result = _run(runs_dir, hand="barrett", grasp=G.LARGE_DIAMETER, object_error=(0.0, 0.05))
    events, plan = result["events"], result["plan"]
    corrections = [e for e in events if e["kind"] == "execute.correction"]
    assert corrections, [e["kind"] for e in events]
    first_contacts = [e for e in events if e["kind"] == "execute.first_contact"]
    assert not first_contacts[0]["on_palm"] and first_contacts[-1]["on_palm"]
    assert corrections[0]["reason"] == "finger first"
    for c in corrections:
        assert c["goal_after"][2] == pytest.approx(c["goal_before"][2])  # height kept
        assert c["goal_after"][2] >= plan["min_goal_height"] - 1e-9

    # Where the grasp centre is at each goal, against the true can, across the approach.
    R_world_palm = np.asarray(plan["T_world_palm_goal"])[:3, :3]
    a = np.asarray(plan["a_world"])
    p_true = np.array([*SCENE_OBJECT_XY, 0.0])

    def miss(p_goal) -> float:
        d = np.asarray(p_goal) + R_world_palm @ np.asarray(plan["p_palm_object"]) - p_true
        d[2] = 0.0
        return float(np.linalg.norm(d - (d @ a) * a))

    goals = result["outcome"]["goals"]
    assert miss(goals[0]) > 0.03  # the believed can is well off across the approach
    assert miss(goals[-1]) < ExecutorParams().centring_tolerance + 0.005
    assert result["outcome"]["palm_contact"] and result["outcome"]["success"]


def test_non_volar_grasp_runs_without_corrections(runs_dir):
    result = _run(runs_dir, hand="barrett", grasp=G.POWER_SPHERE, object_error=(0.05, 0.0))
    kinds = [e["kind"] for e in result["events"]]
    assert "execute.correction" not in kinds and "execute.first_contact" not in kinds
    assert result["outcome"]["corrections"] == 0


def test_result_json_holds_everything_to_reproduce_the_run(tmp_path):
    result = run_grasp(
        RunRequest(
            hand="barrett", grasp=G.PRECISION_DISC, seed=5, out_root=str(tmp_path), record=False
        ),
        REGISTRY,
    ).to_json()
    saved = json.loads(Path(result["result_path"]).read_text())
    assert saved["status"] == "ok"
    assert saved["seed"] == 5
    assert saved["reproduce"].startswith(
        "graspframe run --hand barrett --grasp precision_disc --arm kuka --mount arm"
    )
    assert {"graspframe", "sapien", "pin", "placo", "ruckig"} <= set(saved["versions"])
    assert {"plan", "outcome", "events", "score", "request", "snapshots"} <= set(saved)
    assert saved["outcome"]["contacts_object"]
    assert {"held_after_lift", "held_under_disturbance", "disturbance"} <= set(saved["outcome"])
    assert (
        saved["outcome"]["held_test"]
        == saved["score"]["human_held_test"]["held_test"]
        == ("graspframe")
    )
    assert (Path(result["result_path"]).parent / "snapshots.png").is_file()
    assert Path(saved["human_reference_picture"]).is_file()  # the human grasp, drawn
    # Grasp quality of robot and human, from their contacts with the object's friction.
    quality = saved["score"]["quality"]
    assert quality["robot"]["n_contacts"] == len(saved["outcome"]["contacts_object"])
    assert quality["robot"]["friction"] == REGISTRY.get_object("disc").static_friction
    assert quality["human"]["n_contacts"] > 0
    # The simulated human reference went through the same held test.
    assert set(saved["score"]["human_held_test"]) == {
        "held",
        "held_test",
        "held_after_lift",
        "held_under_disturbance",
        "failure",
    }
    # Which real fingers (and contacts) formed each virtual finger, on each side of
    # every matched pair.
    for side in ("robot", "human"):
        for vf in saved["score"][side]["virtual_fingers"]:
            fingers = {c["real_finger"] for c in vf["contacts"]}
            assert vf["contacts"] and fingers == set(vf["members"])
            assert len(vf["contacts"]) == vf["contact_count"]
    for pair in saved["score"]["comparison"]["pairs"]:
        robot_vf = saved["score"]["robot"]["virtual_fingers"][pair["robot_index"]]
        assert pair["robot_members"] == robot_vf["members"]
        assert pair["human_members"]
    # The held disc is in force closure (three fingers round it, with friction).
    assert quality["robot"]["force_closure"] and quality["robot"]["epsilon_l1"] > 0


def test_a_backend_that_cannot_push_reports_the_disturbance_test_as_not_run(tmp_path, monkeypatch):
    from graspframe_sapien.drivers import SapienObjectProbe

    def cannot_push(self, f_world):
        raise NotImplementedError("this probe cannot push the object")

    monkeypatch.setattr(SapienObjectProbe, "apply_force", cannot_push)
    result = run_grasp(
        RunRequest(hand="barrett", grasp=G.POWER_SPHERE, out_root=str(tmp_path), record=False),
        REGISTRY,
    ).to_json()
    outcome = result["outcome"]
    assert outcome["held_after_lift"] and outcome["held_under_disturbance"] is None
    assert "cannot push" in outcome["disturbance_skipped"]
    assert outcome["success"]  # a lift that held is a grasp when nothing could push


def test_measured_human_contacts_file_replaces_the_simulation(tmp_path):
    from graspframe.common.errors import InputError
    from graspframe.strategy.human_reference import load_reference_file

    path = tmp_path / "pinch.json"
    contact = {"real_finger": "thumb", "p": [0.0125, 0, 0.01], "n": [1, 0, 0], "f": [-2, 0, 0]}
    opposite = {"real_finger": "index", "p": [-0.0125, 0, 0.01], "n": [-1, 0, 0], "f": [2, 0, 0]}
    path.write_text(
        json.dumps(
            {
                "format": "graspframe.human_contacts/1",
                "grasp": "pinch",
                "object": "pinch_block",
                "frame": "object",
                "contacts": [contact, opposite],
            }
        )
    )
    reference = load_reference_file(path)
    assert reference.touching_fingers == ["index", "thumb"]
    result = run_grasp(
        RunRequest(
            hand="barrett",
            grasp=G.PINCH,
            human_contacts=str(path),
            out_root=str(tmp_path),
            record=False,
        ),
        REGISTRY,
    ).to_json()
    assert result["score"]["human_source"] == str(path)
    assert result["score"]["human_held_test"] is None  # measured contacts: taken as given
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "graspframe.human_contacts/1", "frame": "world"}')
    with pytest.raises(InputError, match="frame"):
        load_reference_file(bad)


def test_a_run_that_fails_midway_leaves_a_failed_result(tmp_path, monkeypatch):
    import graspframe.run.stages as run_stages

    def broken(*args, **kwargs):
        raise RuntimeError("actuator fault")

    monkeypatch.setattr(run_stages, "execute", broken)
    with pytest.raises(RuntimeError):
        run_grasp(
            RunRequest(hand="barrett", grasp=G.PINCH, out_root=str(tmp_path), record=False),
            REGISTRY,
        )
    (result_file,) = tmp_path.glob("*/result.json")
    saved = json.loads(result_file.read_text())
    assert saved["status"] == "failed"
    assert saved["error"] == "RuntimeError: actuator fault"
    assert "plan" in saved


@pytest.mark.parametrize(
    ("args", "listed"),
    [
        (["--hand", "allegro", "--grasp", "pinch"], "known hands: barrett"),
        (["--hand", "barrett", "--grasp", "tripod"], "known grasps: abducted_thumb"),
        (["--hand", "barrett", "--grasp", "pinch", "--object", "mug"], "known objects: ball"),
        (["--hand", "barrett", "--grasp", "pinch", "--object-error-mm", "5"], "DX,DY"),
        (["--hand", "barrett", "--grasp", "pinch", "--mount", "wall"], "mounts: arm, floating"),
    ],
)
def test_run_with_a_bad_name_exits_non_zero_listing_valid_names(args, listed, capsys, tmp_path):
    assert main(["run", *args, "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert listed in " ".join(err.split())
    assert not list(tmp_path.iterdir())  # nothing ran, no run folder
