"""Mesh objects (ObjectDescription shape "mesh", graspframe/model_files/mesh_geometry.py) on meshes
made here with trimesh: the object frame, rest pose, mass properties, bad input, and one
geometry for the simulator, the collision checker and the pictures."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import trimesh
from graspframe_sapien.backend import SapienBackend
from graspframe_sapien.scene_objects import MAX_COOKING_CHANGE, cooking_change

from graspframe.common.errors import DescriptionError, GraspframeError
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import make_T, transform_points
from graspframe.hal import ObjectDescription, WorldConfig
from graspframe.model_files.mesh_geometry import SUPPORT_TOLERANCE, union_mass_properties
from graspframe.model_files.urdf_model import read_model
from graspframe.motion.collision import Obstacle, RobotCollisionChecker, object_obstacle
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.shapes import object_collision_meshes, object_mesh, primitive_mesh
from graspframe.strategy import human_reference
from graspframe.strategy.held_check import HeldTest

REGISTRY = default_registry()
BOX_SIZE = (0.04, 0.06, 0.10)  # [m]
# Where the box mesh's centroid is in its file: off the origin, standing on z = 0, as a
# scanner would leave it.
BOX_CENTRE_IN_FILE = (0.10, -0.05, 0.05)


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))


def _box_file(folder: Path, name: str = "box.obj") -> Path:
    box = trimesh.creation.box(extents=BOX_SIZE)
    box.apply_translation(BOX_CENTRE_IN_FILE)
    path = folder / name
    box.export(path)
    return path


def _l_shape(folder: Path) -> tuple[Path, Path]:
    """(visual mesh, convex pieces) of an L made of two overlapping boxes standing on
    z = 0: a 10 x 2 x 2 cm foot along x and a 2 x 2 x 10 cm post at its -x end."""
    foot = trimesh.creation.box(extents=(0.10, 0.02, 0.02))
    foot.apply_translation((0.05, 0.0, 0.01))
    post = trimesh.creation.box(extents=(0.02, 0.02, 0.10))
    post.apply_translation((0.01, 0.0, 0.05))
    pieces = folder / "l_pieces.stl"
    trimesh.util.concatenate([foot, post]).export(pieces)
    visual = folder / "l_visual.stl"
    trimesh.util.concatenate([foot, post]).export(visual)
    return visual, pieces


def test_a_mesh_object_is_recentred_at_its_centroid(tmp_path):
    box = ObjectDescription("box_mesh", "mesh", mesh_path=_box_file(tmp_path), mass=0.2)
    geometry = box.mesh_geometry()
    # The centroid of the grid of cells (1 mm across a 10 cm box) is the box centre.
    np.testing.assert_allclose(geometry.T_mesh_object[:3, 3], BOX_CENTRE_IN_FILE, atol=1e-6)
    np.testing.assert_allclose(geometry.T_mesh_object[:3, :3], np.eye(3))
    assert geometry.upright_as_scanned and geometry.convex.method == "hull"
    assert box.half_extents == pytest.approx(np.divide(BOX_SIZE, 2), abs=1e-7)
    assert box.half_height == pytest.approx(0.05, abs=1e-7)
    assert box.largest_dimension == pytest.approx(0.10, abs=1e-7)
    assert box.volume == pytest.approx(math.prod(BOX_SIZE), rel=1e-6)
    assert not box.symmetric_about_z


def test_a_mesh_box_measures_like_the_primitive_box(tmp_path):
    mesh = ObjectDescription("box_mesh", "mesh", mesh_path=_box_file(tmp_path), mass=0.2)
    sizes = dict(zip(("size_x", "size_y", "size_z"), BOX_SIZE, strict=True))
    primitive = ObjectDescription("box", "box", sizes, mass=0.2)
    rng = np.random.default_rng(3)
    for n in rng.normal(size=(20, 3)):
        assert mesh.extent_along(n) == pytest.approx(primitive.extent_along(n), abs=1e-7)
    # Inertia of the cells (each a cube) against the exact box: within 0.1 %.
    np.testing.assert_allclose(mesh.inertia, primitive.inertia, rtol=1e-3, atol=1e-12)


def test_a_mesh_given_its_density_gets_its_mass_from_its_volume(tmp_path):
    box = ObjectDescription("box_mesh", "mesh", mesh_path=_box_file(tmp_path), density=500.0)
    assert box.mass == pytest.approx(500.0 * math.prod(BOX_SIZE), rel=1e-6)
    assert replace(box, name="copy").mass == box.mass  # the resolved mass and density agree
    with pytest.raises(DescriptionError, match="give its mass or its density, not both"):
        replace(box, mass=1.0)


def test_an_object_that_cannot_stand_as_its_file_has_it_rests_on_a_face(tmp_path):
    box = trimesh.creation.box(extents=BOX_SIZE)
    box.apply_transform(make_T(R=trimesh.transformations.euler_matrix(0.5, 0.3, 0)[:3, :3]))
    box.apply_translation((0.0, 0.0, -box.bounds[0, 2]))  # standing on a corner
    path = tmp_path / "tilted_box.stl"
    box.export(path)
    tilted = ObjectDescription("tilted", "mesh", mesh_path=path, mass=0.2)
    geometry = tilted.mesh_geometry()
    assert not geometry.upright_as_scanned
    # In the object frame it lies on a face: four corners share the lowest height...
    corners = geometry.points
    low = corners[:, 2] <= corners[:, 2].min() + SUPPORT_TOLERANCE
    assert low.sum() == 4
    # ...and the most probable face of a 4 x 6 x 10 cm box is its largest (6 x 10 cm).
    assert tilted.half_height == pytest.approx(0.02, abs=1e-6)


def test_a_cylinder_mesh_is_symmetric_about_its_axis_and_a_box_is_not(tmp_path):
    can = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=64)
    can.apply_translation((0.0, 0.0, 0.05))
    path = tmp_path / "can.ply"
    can.export(path)
    assert ObjectDescription("can", "mesh", mesh_path=path, mass=0.3).symmetric_about_z
    box = ObjectDescription("box", "mesh", mesh_path=_box_file(tmp_path), mass=0.2)
    assert not box.symmetric_about_z


def test_overlapping_pieces_are_counted_once():
    a = trimesh.creation.box(extents=(0.02, 0.02, 0.02))
    b = trimesh.creation.box(extents=(0.02, 0.02, 0.02))
    b.apply_translation((0.01, 0.0, 0.0))  # half inside a
    solid = union_mass_properties([a, b])
    # Cells of 0.3 mm (3 cm / 100), a cell counted when its centre is inside: within one
    # cell on each face, 2 % here (the sum of the two volumes would be 33 % too much).
    assert solid.volume == pytest.approx(0.03 * 0.02 * 0.02, rel=0.02)
    np.testing.assert_allclose(solid.centroid, (0.005, 0.0, 0.0), atol=3e-4)


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"mesh_path": "missing.obj", "mass": 0.1}, r"mesh_path .*missing\.obj does not exist"),
        (
            {"mesh_path": "texture.jpg", "mass": 0.1},
            r"unknown format '\.jpg'; mesh files are \.obj, \.stl, \.dae, \.glb, \.gltf, \.ply",
        ),
        ({"mesh_path": "box.obj"}, r"needs its mass \[kg\] or its density \[kg/m\^3\]"),
        ({"mass": 0.1}, r"needs mesh_path, a \.obj/\.stl/\.dae/\.glb/\.gltf/\.ply file"),
        ({"mesh_path": "box.obj", "mass": -1.0}, r"must be > 0"),
        ({"mesh_path": "box.obj", "mass": 0.1, "scale": (1.0, 0.0, 1.0)}, r"scale must be"),
        ({"mesh_path": "box.obj", "mass": 0.1, "dimensions": {"radius": 0.1}}, "no dimensions"),
    ],
)
def test_bad_mesh_objects_are_refused_in_one_line(tmp_path, fields, message):
    _box_file(tmp_path)
    (tmp_path / "texture.jpg").write_bytes(b"\xff\xd8")
    if "mesh_path" in fields:
        fields = {**fields, "mesh_path": tmp_path / fields["mesh_path"]}
    with pytest.raises(DescriptionError, match=message) as raised:
        ObjectDescription("bad", "mesh", **fields)
    assert "\n" not in str(raised.value) and "'bad'" in str(raised.value)


def test_a_primitive_takes_no_mesh_file(tmp_path):
    with pytest.raises(DescriptionError, match="for shape 'mesh', not a box"):
        ObjectDescription(
            "b", "box", {"size_x": 1, "size_y": 1, "size_z": 1}, 1.0, mesh_path=tmp_path
        )


def test_display_and_collision_meshes_are_in_the_object_frame(tmp_path):
    box = ObjectDescription("box_mesh", "mesh", mesh_path=_box_file(tmp_path), mass=0.2)
    display = object_mesh(box)
    np.testing.assert_allclose(display.bounds, [np.divide(BOX_SIZE, -2), np.divide(BOX_SIZE, 2)])
    (piece,) = object_collision_meshes(box)
    np.testing.assert_allclose(piece.bounds, display.bounds, atol=1e-7)
    can = REGISTRY.get_object("large_cylinder")
    np.testing.assert_array_equal(
        object_mesh(can).vertices, primitive_mesh(can.shape, can.dimensions).vertices
    )


PROBE_URDF = """<robot name="probe">
  <link name="probe"><collision><geometry><sphere radius="0.005"/></geometry></collision></link>
</robot>
"""


def test_the_collision_checker_sees_the_pieces_not_their_hull(tmp_path):
    """A 5 mm ball in the L's notch is inside the L's hull but 3 cm from its pieces."""
    visual, pieces = _l_shape(tmp_path)
    l_object = ObjectDescription("l", "mesh", mesh_path=visual, collision_path=pieces, mass=0.1)
    geometry = l_object.mesh_geometry()
    assert geometry.convex.method == "given pieces" and len(geometry.pieces) == 2
    T_world_object = make_T(p=[0.5, 0.0, l_object.half_height])
    obstacle = object_obstacle(l_object, T_world_object)
    assert obstacle.shape == "mesh" and len(obstacle.collision_geometries()) == 2
    with pytest.raises(GraspframeError, match="use collision_geometries"):
        obstacle.collision_geometry()
    assert obstacle.moved(make_T(p=[0.1, 0.0, 0.0])).pieces is obstacle.pieces

    probe = tmp_path / "probe.urdf"
    probe.write_text(PROBE_URDF)
    T_world_mesh = T_world_object @ np.linalg.inv(geometry.T_mesh_object)
    p_world_notch = transform_points(T_world_mesh, [0.05, 0.0, 0.05]).reshape(3)
    checker = RobotCollisionChecker(read_model(probe), make_T(p=p_world_notch), [obstacle])
    assert checker.collisions({}) == []
    hull_piece = trimesh.util.concatenate(list(geometry.pieces)).convex_hull
    hull = Obstacle("hull", "mesh", {}, T_world_object, (hull_piece,))
    (hit,) = RobotCollisionChecker(read_model(probe), make_T(p=p_world_notch), [hull]).collisions(
        {}
    )
    assert hit.obstacle == "hull" and hit.distance < 0
    # Moved onto the foot's top face, the probe touches the L.
    p_world_foot = transform_points(T_world_mesh, [0.05, 0.0, 0.022]).reshape(3)
    (touch,) = RobotCollisionChecker(
        read_model(probe), make_T(p=p_world_foot), [obstacle]
    ).collisions({})
    assert touch.obstacle == "object" and touch.distance < 0.005


def test_the_simulator_builds_the_pieces_with_the_objects_mass_and_inertia(tmp_path):
    import sapien

    visual, pieces = _l_shape(tmp_path)
    l_object = ObjectDescription("l", "mesh", mesh_path=visual, collision_path=pieces, mass=0.1)
    T_world_object = make_T(p=[0.5, 0.0, l_object.half_height])
    hand = REGISTRY.get_hand("barrett")
    config = WorldConfig(hand=hand, object=l_object, T_world_object=T_world_object)
    with SapienBackend().create_world(config) as world:
        body = world.object._body
        assert body.mass == pytest.approx(0.1, rel=1e-6)
        moments = np.linalg.eigvalsh(l_object.inertia)
        np.testing.assert_allclose(sorted(body.inertia), moments, rtol=1e-5)
        shapes = body.get_collision_shapes()
        assert len(shapes) == 2
        for shape, piece in zip(shapes, l_object.mesh_geometry().pieces, strict=True):
            assert isinstance(shape, sapien.physx.PhysxCollisionShapeConvexMesh)
            assert cooking_change(piece.vertices, shape.get_vertices()) <= MAX_COOKING_CHANGE
        world.step(round(1.0 / world.timestep))  # it stands still on its foot
        T = world.object.T_world_object()
        assert np.linalg.norm(T[:3, 3] - T_world_object[:3, 3]) < 0.001


def test_the_human_reference_key_follows_the_mesh_content(tmp_path):
    human = REGISTRY.get_hand("human")
    first = ObjectDescription("box_mesh", "mesh", mesh_path=_box_file(tmp_path), mass=0.2)
    backend, held = SapienBackend(), HeldTest()
    key = human_reference._cache_key(HumanGrasp.PINCH, first, human, backend, held)
    larger = trimesh.creation.box(extents=(0.05, 0.06, 0.10))
    larger.export(tmp_path / "box.obj")  # the same path, another mesh
    second = ObjectDescription("box_mesh", "mesh", mesh_path=tmp_path / "box.obj", mass=0.2)
    assert human_reference._cache_key(HumanGrasp.PINCH, second, human, backend, held) != key
