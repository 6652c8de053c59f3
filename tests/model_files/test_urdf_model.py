"""Robot models read as shipped (graspframe/model_files/urdf_model.py): vendor files untouched, mesh
paths resolved, visuals kept for pictures, collision meshes as convex pieces that the
simulator and the collision checker share, frames added, arms cut at the flange, name
clashes between hand and arm resolved."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from conftest import folder_state
from graspframe_sapien.articulation import (
    active_joints,
    configure_drives,
    create_scene,
    load_articulation,
)
from scipy.spatial import ConvexHull

from graspframe.common.cache import ENTRY_FILE
from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import R_from_rpy, make_T
from graspframe.hal.descriptions import DriveGains
from graspframe.model_files.convex import MAX_PIECE_VERTICES, convex_pieces
from graspframe.model_files.urdf_model import FrameOffset, read_model
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, load_pinocchio_model, summarize_urdf
from graspframe.robot_models.mounting import mount
from graspframe.robot_models.shapes import convex_points

PANDA_PACKAGE = "example-robot-data"


def test_the_leap_hand_loads_as_shipped_and_stays_untouched(leap_hand_dir):
    before = folder_state(leap_hand_dir)
    model = read_model(leap_hand_dir / "leap_hand_right.urdf")
    assert folder_state(leap_hand_dir) == before  # nothing edited, nothing written beside it

    assert len(summarize_urdf(model).joints) == 16
    assert "<visual" not in model.text  # a physics-only scene cannot load visuals
    assert len(model.visuals) == 17  # 8 meshes, used by 17 links
    assert all(v.mesh_path is not None and v.mesh_path.is_file() for v in model.visuals)
    # Every collision mesh is now convex pieces from the cache, none from the vendor folder.
    meshes = [line for line in model.text.splitlines() if "<mesh" in line]
    assert len(meshes) == 4
    assert not any(str(leap_hand_dir) in line for line in meshes)


def test_a_collision_mesh_is_the_same_convex_piece_in_the_simulator_and_the_checker(
    leap_hand_dir,
):
    model = read_model(leap_hand_dir / "leap_hand_right.urdf")
    checker_points = [
        convex_points(shape)
        for link, shape, _ in CollisionModel(model).shapes()
        if link == "fingertip" and type(shape).__name__ == "Convex"
    ]
    assert len(checker_points) == 1 and len(checker_points[0]) <= MAX_PIECE_VERTICES

    scene = create_scene(1 / 500)  # the articulation lives as long as its scene
    articulation = load_articulation(scene, model, fix_root=True)
    link = next(lk for lk in articulation.get_links() if lk.name == "fingertip")
    convex = [s for s in link.get_collision_shapes() if "ConvexMesh" in type(s).__name__]
    assert len(convex) == 1
    simulated = np.asarray(convex[0].get_vertices()) * np.asarray(convex[0].get_scale())
    # PhysX cooks the piece again and may drop vertices that lie within a fraction of a
    # millimetre of a face: every vertex it keeps is one of the piece's, and the piece's
    # other vertices lie within 1 mm of the simulated solid.
    assert all(np.min(np.linalg.norm(checker_points[0] - v, axis=1)) < 1e-6 for v in simulated)
    planes = ConvexHull(simulated).equations
    outside = (checker_points[0] @ planes[:, :3].T + planes[:, 3]).max(axis=1)
    assert outside.max() < 0.001


def test_package_paths_resolve_and_the_arm_is_cut_at_its_flange(panda_description_dir):
    packages = {PANDA_PACKAGE: panda_description_dir.parents[1]}
    model = read_model(panda_description_dir / "urdf/panda.urdf", packages, cut_below="panda_link8")
    assert "panda_link8" in model.link_names
    # The vendor's own gripper beyond the flange is gone, with its joints and visuals.
    assert not {"panda_hand", "panda_leftfinger", "panda_hand_tcp"} & model.link_names
    assert "panda_finger_joint1" not in model.joint_names
    assert {v.link for v in model.visuals} == {f"panda_link{i}" for i in range(8)}
    assert all(v.mesh_path.suffix == ".dae" for v in model.visuals if v.mesh_path)
    assert len(summarize_urdf(model).joints) == 7


def test_an_unknown_package_is_named(panda_description_dir):
    with pytest.raises(DescriptionError, match=r"package 'example-robot-data'.*packages: none"):
        read_model(panda_description_dir / "urdf/panda.urdf")


def _write_box_mesh(path: Path, extents=(0.04, 0.02, 0.06)) -> None:
    trimesh.creation.box(extents=extents).export(path)


QUIRKY_URDF = """<?xml version="1.0"?>
<robot name="quirky">
  <material name="grey "><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base ">
    <visual><geometry><mesh filename="meshes/palm.stl"/></geometry>
      <material name="grey "/></visual>
    <collision>
      <origin xyz="0 0 0.03 "/><geometry><mesh filename="meshes/palm.stl"/></geometry>
    </collision>
  </link>
  <link name="finger">
    <inertial>
      <mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <collision><geometry><box size="0.01 0.01 0.05"/></geometry></collision>
  </link>
  <link name="follower">
    <inertial>
      <mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <collision><geometry><box size="0.01 0.01 0.05"/></geometry></collision>
  </link>
  <joint name="finger_joint " type="revolute">
    <parent link="base "/><child link="finger"/><origin xyz="0.02 0 0.07"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="1.5" effort="1" velocity="2"/>
  </joint>
  <joint name="follower_joint" type="revolute">
    <parent link="base "/><child link="follower"/><origin xyz="-0.02 0 0.07"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="1.5" effort="1" velocity="2"/>
    <mimic joint="finger_joint " multiplier="1" offset="0"/>
  </joint>
</robot>
"""


@pytest.fixture
def quirky_urdf(tmp_path: Path) -> Path:
    (tmp_path / "meshes").mkdir()
    _write_box_mesh(tmp_path / "meshes" / "palm.stl")
    path = tmp_path / "quirky.urdf"
    path.write_text(QUIRKY_URDF)
    return path


def test_stray_spaces_relative_stl_meshes_and_mimic_joints(quirky_urdf):
    model = read_model(quirky_urdf)
    assert {"base", "finger", "follower"} <= model.link_names
    assert model.mimic_followers == {"follower_joint": ("finger_joint", 1.0, 0.0)}
    assert model.visuals[0].rgba == (0.5, 0.5, 0.5, 1.0)
    # Pinocchio reads the follower as part of its leader; SAPIEN enforces the coupling.
    assert load_pinocchio_model(model, mimic=True).nq == 1
    scene = create_scene(1 / 500)
    articulation = load_articulation(scene, model, fix_root=True)
    assert set(active_joints(articulation)) == {"finger_joint", "follower_joint"}
    # The box-shaped STL stays a box: its convex piece has the box's volume.
    piece = next(s for link, s, _ in CollisionModel(model).shapes() if link == "base")
    assert trimesh.convex.convex_hull(convex_points(piece)).volume == pytest.approx(
        0.04 * 0.02 * 0.06, rel=1e-6
    )


@pytest.mark.parametrize("topology", ["siblings", "chain"])
def test_a_mimic_coupling_holds_the_urdf_relation_from_the_first_step(quirky_urdf, topology):
    """q_follower = multiplier * q_leader + offset, for a follower on its leader's link
    (the Ability hand's distal joints) and one beside it on the same link (SAPIEN's own
    loader inverts that one). The all-zero posture a model loads in breaks a coupling with
    an offset (the Ability's: 0.72 rad at a leader's 0): PhysX corrected it in one step
    and the articulation's poses went NaN."""
    text = QUIRKY_URDF.replace('multiplier="1" offset="0"', 'multiplier="0.5" offset="0.7"')
    if topology == "chain":
        text = text.replace(
            '<parent link="base "/><child link="follower"/>',
            '<parent link="finger"/><child link="follower"/>',
        )
    quirky_urdf.write_text(text)
    model = read_model(quirky_urdf)
    scene = create_scene(1 / 500)
    articulation = load_articulation(scene, model, fix_root=True)
    followers = model.mimic_followers
    configure_drives(articulation, {"finger_joint": DriveGains(10.0, 0.3, 5.0)}, followers)
    joints = list(active_joints(articulation))
    leader, follower = joints.index("finger_joint"), joints.index("follower_joint")
    assert articulation.get_qpos()[follower] == pytest.approx(0.7)
    active_joints(articulation)["finger_joint"].set_drive_target(0.5)
    for _ in range(500):
        scene.step()
    qpos = articulation.get_qpos()
    assert np.all(np.isfinite(qpos))
    assert qpos[leader] == pytest.approx(0.5, abs=0.01)
    assert qpos[follower] == pytest.approx(0.5 * qpos[leader] + 0.7, abs=0.01)


def test_a_missing_mesh_names_the_link_and_the_path(quirky_urdf):
    (quirky_urdf.parent / "meshes" / "palm.stl").unlink()
    with pytest.raises(DescriptionError, match=r"link 'base'.*meshes/palm.stl.*looked at"):
        read_model(quirky_urdf)


def test_frames_are_added_at_their_offsets_with_an_optional_pad(quirky_urdf):
    T_base_palm = make_T(R_from_rpy(0.0, -np.pi / 2, 0.0), [0.0, 0.0, 0.06])  # 9 digits in the text
    frames = {
        "palm": FrameOffset("base", T_base_palm),
        "pad": FrameOffset("palm", make_T(p=[0.0, 0.0, 0.001]), pad=(0.03, 0.02, 0.002)),
    }
    model = CollisionModel(read_model(quirky_urdf, frames=frames))
    np.testing.assert_allclose(model.T_root_frame("palm"), T_base_palm, atol=1e-8)
    pads = [s for link, s, _ in model.shapes() if link == "pad"]
    assert len(pads) == 1 and np.allclose(2 * np.asarray(pads[0].halfSide), (0.03, 0.02, 0.002))


@pytest.mark.parametrize(
    ("frames", "message"),
    [
        ({"palm": FrameOffset("wrist")}, "hangs from 'wrist', which is not a link"),
        ({"finger": FrameOffset("base")}, "'finger' is already a link"),
    ],
)
def test_bad_frames_are_refused(quirky_urdf, frames, message):
    with pytest.raises(DescriptionError, match=message):
        read_model(quirky_urdf, frames=frames)


def test_a_pad_needs_three_positive_sizes():
    with pytest.raises(DescriptionError, match="three sizes > 0"):
        FrameOffset("base", pad=(0.03, 0.0, 0.002))


def test_an_arm_whose_names_clash_with_the_hand_gets_a_prefix(quirky_urdf, tmp_path):
    """A hand and an arm that both call a link "base" (as vendor collections do)."""
    from dataclasses import replace

    kuka = default_registry().get_arm("kuka")
    hand_text = quirky_urdf.read_text().replace('name="finger"', 'name="kr5_base"')
    hand_text = hand_text.replace('link="finger"', 'link="kr5_base"')
    clashing = tmp_path / "clashing.urdf"
    clashing.write_text(hand_text)
    barrett = default_registry().get_hand("barrett")
    hand = replace(
        barrett,
        name="clashing",
        model_path=clashing,
        root_link="base",
        palm_frame="base",
        palm_sensor_link="base",
        joints=(),
        couplings=(),
        real_fingers={"palm": ("base",)},
    )
    robot = mount(kuka, hand)
    assert robot.arm.base_link == "kuka_kr5_base" and robot.arm.flange_link == "kuka_kr5_flange"
    assert robot.arm.joint_names[0] == "kuka_kr5_a1"
    assert {"kuka_kr5_base", "kr5_base", "base"} <= robot.model.link_names
    # The prefixed arm is a whole model: Pinocchio and SAPIEN load it, joints by their new names.
    scene = create_scene(1 / 500)
    articulation = load_articulation(scene, robot.model, fix_root=True)
    assert set(robot.arm.joint_names) <= set(active_joints(articulation))


def test_convex_pieces_are_cached_and_a_damaged_entry_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))
    mesh = tmp_path / "ball.obj"
    trimesh.creation.icosphere(subdivisions=3, radius=0.02).export(mesh)
    first = convex_pieces(mesh)
    assert len(first.pieces) == 1 and len(first.pieces[0].vertices) <= MAX_PIECE_VERTICES
    assert convex_pieces(mesh).files == first.files  # the same entry, read back
    (first.files[0].parent / ENTRY_FILE).write_text("{ cut short")
    again = convex_pieces(mesh)
    assert again.files == first.files and len(again.pieces[0].vertices) <= MAX_PIECE_VERTICES
