"""The YCB objects (plugins/graspframe_ycb) on the scans themselves, read in place: each
loads with its published mass, a centroid inside its mesh and the rest pose a person
finds it in; PhysX cooks its pieces as the planner sees them; each is held.

The scans are looked for in GRASPFRAME_TEST_YCB_DIR, else under objects/ycb of the
third-party folder conftest.py finds (beside the repository, where CI keeps it); without
them these tests are skipped."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import sapien
from conftest import THIRD_PARTY, folder_state
from graspframe_sapien.backend import SapienBackend
from graspframe_sapien.scene_objects import MAX_COOKING_CHANGE, cooking_change
from graspframe_ycb.plugin import YCB_DIR_ENV, YCB_OBJECTS, ycb_objects

from graspframe.checks.grasps import hand_alone_setup
from graspframe.common.cache import CACHE_ENV
from graspframe.common.defaults import SCENE_OBJECT_XY
from graspframe.model_files import mesh_geometry as mesh_geometry_module
from graspframe.model_files.mesh_geometry import display_mesh
from graspframe.motion.arm_motion import ArmMotion
from graspframe.plugin_system.registry import Registry, default_registry
from graspframe.strategy.execution import run_policy
from graspframe.strategy.held_check import HeldTest
from graspframe.strategy.method import MethodStrategy
from graspframe.strategy.reference_poses import reference_placement

YCB_DIR = Path(os.environ.get("GRASPFRAME_TEST_YCB_DIR", THIRD_PARTY / "objects" / "ycb"))
pytestmark = pytest.mark.skipif(
    not (YCB_DIR / "005_tomato_soup_can" / "google_16k" / "textured.obj").is_file(),
    reason=f"the YCB scans are not at {YCB_DIR} (set GRASPFRAME_TEST_YCB_DIR)",
)
REGISTRY = default_registry()
# The hand of the held test below, for each object (the quicker of the two where both
# hold; the 24 runs of both hands on both mounts are in docs/objects.md).
HELD_BY = {
    "005_tomato_soup_can": "karlsruhe",
    "006_mustard_bottle": "barrett",
    "011_banana": "karlsruhe",
    "025_mug": "karlsruhe",
    "056_tennis_ball": "barrett",
    "061_foam_brick": "barrett",
}
# Strict: an object that starts to hold fails the suite until it is taken off the list.
NOT_HELD = {
    "011_banana": (
        "the pinch takes the 36 mm banana about 10 mm above its widest section: the whole "
        "hand must stay 10 mm above the table over the closing motion (docs/objects.md)"
    ),
}


@pytest.fixture(scope="module")
def scans_as_shipped() -> dict[str, str]:
    """The scans' folder before this module loads anything from it."""
    return folder_state(YCB_DIR)


@pytest.fixture(scope="module")
def objects(scans_as_shipped):
    found = {obj.name.removeprefix("ycb_"): obj for obj in ycb_objects(YCB_DIR)}
    assert set(found) == set(HELD_BY)
    return found


def test_the_plugin_registers_every_object_of_the_folder(monkeypatch):
    monkeypatch.setenv(YCB_DIR_ENV, str(YCB_DIR))
    registry = Registry.from_entry_points()
    names = [n for n in registry.names("object") if n.startswith("ycb_")]
    assert names == [f"ycb_{folder}" for folder in sorted(HELD_BY)]
    mug = registry.get_object("ycb_025_mug")
    assert mug.collision_path == YCB_DIR / "025_mug" / "google_16k" / "textured_vhacd.stl"
    assert mug.grasps and not mug.default_for  # nobody's default object


@pytest.mark.parametrize("folder", sorted(HELD_BY))
def test_each_object_loads_with_its_mass_and_its_centroid_inside_it(objects, folder):
    obj = objects[folder]
    geometry = obj.mesh_geometry()
    assert obj.mass == YCB_OBJECTS[folder].mass
    assert geometry.convex.method == "given pieces"
    assert 40 <= len(geometry.pieces) <= 80
    # The centroid (the object frame's origin, in the scan's frame) is inside the scan's
    # bounding box, and the object's volume is of the object's size (a mug's walls, ...).
    scan = display_mesh(geometry, obj.mesh_path, obj.scale)
    low, high = scan.bounds + geometry.T_mesh_object[:3, 3]
    p_centroid = geometry.T_mesh_object[:3, 3]
    assert np.all(low < p_centroid) and np.all(p_centroid < high)
    density = obj.mass / obj.volume
    assert 100 < density < 2000, density  # foam 160 kg/m^3 ... soup 1140 kg/m^3
    # It stands as scanned (z up), on the table: the scan's lowest point is at the
    # centroid's height below it, within the 2 mm between the scan and its pieces.
    assert geometry.upright_as_scanned
    assert np.allclose(geometry.T_mesh_object[:3, :3], np.eye(3))
    assert scan.bounds[0, 2] == pytest.approx(-obj.half_height, abs=0.002)


def test_loading_writes_nothing_beside_the_scans(monkeypatch, tmp_path):
    # A cold cache (on disk and in this process): the tennis ball's pieces, volume and
    # rest pose are computed now, and written to the cache, not beside the scan.
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    mesh_geometry_module._geometry.cache_clear()
    before = folder_state(YCB_DIR)
    ball = {obj.name: obj for obj in ycb_objects(YCB_DIR)}["ycb_056_tennis_ball"]
    display_mesh(ball.mesh_geometry(), ball.mesh_path, ball.scale)
    assert any(tmp_path.rglob("*.obj"))  # the pieces were built, not read from a cache
    assert folder_state(YCB_DIR) == before


def test_the_soup_cans_centroid_is_its_centre(objects):
    """A can is symmetric: its centroid is the centre of its bounding box (measured
    0.5 mm, 0.4 mm, 0.3 mm apart: the scan is not perfectly round)."""
    geometry = objects["005_tomato_soup_can"].mesh_geometry()
    scan = display_mesh(geometry, objects["005_tomato_soup_can"].mesh_path, (1.0, 1.0, 1.0))
    np.testing.assert_allclose(scan.bounds.mean(axis=0), 0.0, atol=0.001)
    assert objects["005_tomato_soup_can"].symmetric_about_z
    assert objects["056_tennis_ball"].symmetric_about_z
    assert not objects["006_mustard_bottle"].symmetric_about_z
    assert not objects["025_mug"].symmetric_about_z


def test_the_mustard_bottle_stands_upright(objects):
    bottle = objects["006_mustard_bottle"]
    low, high = bottle.mesh_geometry().bounds
    assert (high - low)[2] > 0.18  # 19 cm tall, as it stands on a shelf
    assert bottle.half_height == pytest.approx(0.077, abs=0.002)


def test_physx_cooks_the_pieces_the_planner_uses(objects):
    material = sapien.physx.PhysxMaterial(0.8, 0.6, 0.0)
    changes = []
    for obj in objects.values():
        for piece in obj.mesh_geometry().pieces:
            shape = sapien.physx.PhysxCollisionShapeConvexMesh(
                vertices=np.asarray(piece.vertices, dtype=np.float32),
                scale=np.ones(3, dtype=np.float32),
                material=material,
            )
            changes.append(cooking_change(piece.vertices, shape.get_vertices()))
    changed = [c for c in changes if c > 0]
    # Measured: 5 of 359 pieces lose a vertex, by at most 1.9 mm (graspframe/model_files/convex.py).
    assert len(changed) <= 0.02 * len(changes)
    assert max(changes) <= MAX_COOKING_CHANGE


def _held(obj, hand_name: str):
    """The object's first documented grasp by the hand alone (floating mount), with the
    executor's held test (lift, then pushes)."""
    hand, human = REGISTRY.get_hand(hand_name), REGISTRY.get_hand("human")
    grasp = obj.documented_grasps()[0]
    placement = reference_placement(obj, human.preshape_for(grasp))
    setup = hand_alone_setup(hand, grasp, obj, placement.T_object_palm, xy=SCENE_OBJECT_XY)
    checked = setup.checked
    with SapienBackend().create_world(setup.config) as world:
        motion = ArmMotion(world, checked.robot, checked.T_world_base)
        return run_policy(world, motion, MethodStrategy(checked.plan, hand, obj), obj, HeldTest())


@pytest.mark.slow
@pytest.mark.parametrize(
    "folder",
    [
        pytest.param(f, marks=pytest.mark.xfail(reason=NOT_HELD[f], strict=True))
        if f in NOT_HELD
        else f
        for f in sorted(HELD_BY)
    ],
)
def test_each_object_is_held_in_its_documented_grasp(objects, folder, scans_as_shipped):
    outcome = _held(objects[folder], HELD_BY[folder])
    # Loaded and grasped, the scans are byte for byte as shipped, with nothing beside them.
    assert folder_state(YCB_DIR) == scans_as_shipped
    assert outcome.held_after_lift, outcome.failure_reason
    assert outcome.held_under_disturbance, outcome.failure_reason
    assert len(outcome.touching_fingers) >= 2


# The six scans of this folder under six other objects' ids of the set: what a user's
# folder of other YCB objects looks like to the plugin.
OTHER_IDS = {
    "005_tomato_soup_can": "002_master_chef_can",
    "006_mustard_bottle": "021_bleach_cleanser",
    "011_banana": "043_phillips_screwdriver",
    "025_mug": "065-h_cups",
    "056_tennis_ball": "055_baseball",
    "061_foam_brick": "077_rubiks_cube",
}


def test_a_folder_of_other_ycb_objects_registers_every_one(tmp_path, monkeypatch):
    for scanned, other in OTHER_IDS.items():
        folder = tmp_path / other / "google_16k"
        folder.mkdir(parents=True)
        for name in ("textured.obj", "textured.mtl", "texture_map.jpg", "textured_vhacd.stl"):
            (folder / name).symlink_to(YCB_DIR / scanned / "google_16k" / name)
    before = folder_state(YCB_DIR)
    monkeypatch.setenv(YCB_DIR_ENV, str(tmp_path))
    registry = Registry.from_entry_points()
    info = next(p for p in registry.plugins if p.name == "ycb")
    assert info.status == "loaded" and info.not_registered == []
    assert sorted(name for _kind, name in info.provides) == sorted(
        f"ycb_{other}" for other in OTHER_IDS.values()
    )
    for other in OTHER_IDS.values():
        obj = registry.get_object(f"ycb_{other}")
        assert obj.mass == YCB_OBJECTS[other].mass  # the set's table, Calli et al. 2015
        assert obj.documented_grasps() == (YCB_OBJECTS[other].grasp,)
        assert obj.collision_path == tmp_path / other / "google_16k" / "textured_vhacd.stl"
    assert folder_state(YCB_DIR) == before
