"""graspframe.snapshots: the 3-view picture of a grasp, drawn from the real robot models.

Scenes: the Barrett hand alone, palm facing down over a cylinder on the table, and the
Barrett on the KUKA arm at its home pose. Pixel checks look for colours that only one
kind of element has (pure red: contact dots; the arm's slate blended at alpha 0.9).
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest
from graspframe_barrett.description import BARRETT, hand_q
from matplotlib.colors import to_rgb

from graspframe import snapshots as snap
from graspframe.errors import InputError
from graspframe.grasps import PALM
from graspframe.mounting import mount
from graspframe.registry import default_registry
from graspframe.robot_model import CollisionModel
from graspframe.snapshots import Snapshot, SnapshotScene, draw_snapshots
from graspframe.transforms import inv_T, make_T

PALM_HEIGHT = 0.20  # [m] palm origin above the table (Barrett scene)
RADIUS, LENGTH = 0.03, 0.10  # [m] the cylinder
# Palm facing down (palm z = -world z), fingertips along world +x.
R_WORLD_PALM_DOWN = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])


def _count_colour(image: np.ndarray, rgb, tol: float = 0.03) -> int:
    return int(np.count_nonzero(np.all(np.abs(image[..., :3] - np.asarray(rgb)) < tol, axis=-1)))


def _has_colour(image: np.ndarray, rgb, tol: float = 0.03) -> bool:
    return _count_colour(image, rgb, tol) > 0


def _arm_pixel_rgb():
    """The arm's face colour as painted: alpha 0.9 over the white background."""
    return 0.9 * np.asarray(to_rgb(snap.ARM_COLOUR)) + 0.1


@pytest.fixture(scope="module")
def barrett_scene() -> tuple[SnapshotScene, list[Snapshot]]:
    """Barrett alone: palm 20 cm above the table, a cylinder standing under it."""
    model = CollisionModel(BARRETT.urdf())
    model.place(BARRETT.with_model_followers(hand_q(0, 10)))
    T_world_palm = make_T(R_WORLD_PALM_DOWN, [0.5, 0.1, PALM_HEIGHT])
    T_world_root = T_world_palm @ inv_T(model.T_root_frame(BARRETT.palm_frame))
    scene = SnapshotScene(
        model=BARRETT.urdf(),
        T_world_root=T_world_root,
        palm_frame=BARRETT.palm_frame,
        finger_of_link=BARRETT.finger_of_link(),
        joint_followers=BARRETT.with_model_followers,
        object_shape="cylinder",
        object_dimensions={"radius": RADIUS, "length": LENGTH},
        table_height=0.0,
    )
    T_world_object = make_T(p=[0.5, 0.1, LENGTH / 2])
    p_contact = np.array([[0.5 + RADIUS, 0.1, 0.08], [0.5 - RADIUS, 0.1, 0.08], [0.5, 0.1, 0.1]])
    moments = [
        Snapshot("first contact", hand_q(0, 90), T_world_object, p_contact[:1], ["finger_1"]),
        Snapshot("hold", hand_q(0, 120), T_world_object, p_contact, ["finger_1", "finger_2", PALM]),
        Snapshot(
            "after lift",
            hand_q(0, 120),
            make_T(p=[0.5, 0.1, LENGTH / 2 + 0.05]),
            p_contact + np.array([0.0, 0.0, 0.05]),
            ["finger_1", "finger_2", PALM],
        ),
    ]
    return scene, moments


def _without_contacts(moments: list[Snapshot]) -> list[Snapshot]:
    # An empty list is accepted as well as an empty (0, 3) array.
    return [Snapshot(m.label, m.q_by_joint, m.T_world_object, [], []) for m in moments]


def _assert_layout(image: np.ndarray, n_columns: int) -> None:
    """The image has the figure size for n_columns moments (matplotlib truncates to pixels)."""
    width, height = snap.figure_size(n_columns, len(BARRETT.real_fingers))
    assert abs(image.shape[0] - height * snap.DPI) < 1
    assert abs(image.shape[1] - width * snap.DPI) < 1


@pytest.fixture(scope="module")
def barrett_png(barrett_scene, tmp_path_factory) -> Path:
    scene, moments = barrett_scene
    path = tmp_path_factory.mktemp("barrett") / "run" / "snapshots.png"
    assert draw_snapshots(path, scene, moments, "barrett · wrap · cylinder — HELD") == path
    return path


def test_png_written_with_one_panel_per_view_and_moment(barrett_png: Path):
    image = matplotlib.image.imread(barrett_png)
    _assert_layout(image, 3)
    assert barrett_png.stat().st_size < 400_000
    assert [p.name for p in barrett_png.parent.iterdir()] == ["snapshots.png"]  # no temp file
    assert _has_colour(image, to_rgb(snap.OBJECT_COLOUR), tol=0.12)
    assert not _has_colour(image, _arm_pixel_rgb(), tol=0.01)  # a hand alone has no arm


def test_drawing_is_deterministic_and_one_column_per_moment(
    tmp_path: Path, barrett_scene, barrett_png: Path
):
    scene, moments = barrett_scene
    again = draw_snapshots(
        tmp_path / "again.png", scene, moments, "barrett · wrap · cylinder — HELD"
    )
    assert again.read_bytes() == barrett_png.read_bytes()
    one = draw_snapshots(tmp_path / "one.png", scene, moments[:1], "one moment")
    _assert_layout(matplotlib.image.imread(one), 1)


def test_contacts_are_drawn_as_red_dots(tmp_path: Path, barrett_scene, barrett_png: Path):
    scene, moments = barrett_scene
    with_contacts = matplotlib.image.imread(barrett_png)
    without = matplotlib.image.imread(
        draw_snapshots(tmp_path / "n.png", scene, _without_contacts(moments), "t")
    )
    # Both have the legend's contact marker; only the first has dots in the panels (7 contacts
    # in 3 views, ~30 pure red pixels each).
    red = to_rgb(snap.CONTACT_COLOUR)
    assert _count_colour(with_contacts, red) > _count_colour(without, red) + 7 * 3 * 10


def test_hand_on_arm_draws_the_arm_links_near_the_hand(tmp_path: Path):
    registry = default_registry()
    arm, hand = registry.get_arm("kuka"), registry.get_hand("barrett")
    robot = mount(arm, hand)
    q = dict(zip(arm.joint_names, arm.home_q, strict=True)) | hand_q(0, 100)
    model = CollisionModel(robot.model)
    model.place(hand.with_model_followers(q))
    T_world_palm = model.T_root_frame(hand.palm_frame)  # root = arm base = world
    assert T_world_palm[2, 2] < -0.9  # home: the palm faces down
    p_world_object = T_world_palm[:3, 3] + 0.06 * T_world_palm[:3, 2]
    scene = SnapshotScene(
        model=robot.model,
        T_world_root=np.eye(4),
        palm_frame=hand.palm_frame,
        finger_of_link=hand.finger_of_link(),
        joint_followers=hand.with_model_followers,
        object_shape="box",
        object_dimensions={"size_x": 0.05, "size_y": 0.05, "size_z": 0.08},
        table_height=float(p_world_object[2] - 0.04),
    )
    moment = Snapshot("hold", q, make_T(p=p_world_object), np.zeros((0, 3)), [])
    image = matplotlib.image.imread(draw_snapshots(tmp_path / "arm.png", scene, [moment], "t"))
    _assert_layout(image, 1)
    assert _has_colour(image, _arm_pixel_rgb(), tol=0.01)


def test_projection_of_primitives_is_their_outline():
    world_xz, world_yz, _ = snap.VIEWS
    cylinder = snap.object_solid("cylinder", {"radius": 0.03, "length": 0.1})
    polygon, _ = snap.project(cylinder.moved(make_T(p=[1.0, 2.0, 3.0])), world_xz)
    np.testing.assert_allclose(polygon.min(axis=0), [0.97, 2.95], atol=1e-9)
    np.testing.assert_allclose(polygon.max(axis=0), [1.03, 3.05], atol=1e-9)

    sphere = snap.object_solid("sphere", {"radius": 0.02})
    polygon, _ = snap.project(sphere, world_yz)
    np.testing.assert_allclose(np.linalg.norm(polygon, axis=1), 0.02, atol=1e-12)

    # A box turned 90 deg about world z shows its y size along world x.
    box = snap.object_solid("box", {"size_x": 0.1, "size_y": 0.2, "size_z": 0.3})
    R_z90 = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    polygon, _ = snap.project(box.moved(make_T(R_z90)), world_xz)
    np.testing.assert_allclose(np.ptp(polygon, axis=0), [0.2, 0.3], atol=1e-9)

    # Painter's depth: in the x-z view the viewer is at -y, so smaller y is nearer.
    _, near = snap.project(sphere.moved(make_T(p=[0, -1.0, 0])), world_xz)
    _, far = snap.project(sphere.moved(make_T(p=[0, 1.0, 0])), world_xz)
    assert near > far


def test_table_line_in_the_palm_view():
    palm_view = snap.VIEWS[2]
    # Palm facing down 0.2 m above the table: the table is the line palm z = +0.2.
    T_world_palm = make_T(R_WORLD_PALM_DOWN, [0.5, 0.1, PALM_HEIGHT])
    point, direction, towards_table = snap.table_line(palm_view, inv_T(T_world_palm), 0.0)
    assert point[1] == pytest.approx(PALM_HEIGHT)
    assert abs(direction[1]) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(towards_table, [0.0, 1.0], atol=1e-12)
    # Palm tilted 30 deg about its y axis: the line through (x, z) with world z = 0.
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    R_tilt = R_WORLD_PALM_DOWN @ np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    T_world_palm = make_T(R_tilt, [0.5, 0.1, PALM_HEIGHT])
    point, direction, _ = snap.table_line(palm_view, inv_T(T_world_palm), 0.0)
    for t in (-0.3, 0.0, 0.4):
        p_palm = np.array([point[0] + t * direction[0], 0.0, point[1] + t * direction[1]])
        assert (T_world_palm[:3, :3] @ p_palm + T_world_palm[:3, 3])[2] == pytest.approx(0.0)
    # Palm x-z plane parallel to the table (palm y vertical): no line.
    R_side = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])
    assert snap.table_line(palm_view, inv_T(make_T(R_side, [0, 0, 0.3])), 0.0) is None


def _one_line_input_error(path: Path, scene, moments, match: str) -> None:
    with pytest.raises(InputError, match=match) as info:
        draw_snapshots(path, scene, moments, "t")
    assert "\n" not in str(info.value)
    assert not path.exists()


def test_bad_input_raises_one_line_input_errors(tmp_path: Path, barrett_scene):
    scene, moments = barrett_scene
    path = tmp_path / "bad.png"
    good = moments[1]
    _one_line_input_error(path, scene, [], "no snapshots to draw")
    mismatched = Snapshot(
        "hold", good.q_by_joint, good.T_world_object, good.contact_points_world, ["finger_1"]
    )
    _one_line_input_error(path, scene, [mismatched], "3 contact points but 1 contact fingers")
    flat = Snapshot("hold", good.q_by_joint, good.T_world_object, np.zeros((2, 2)), ["a", "b"])
    _one_line_input_error(path, scene, [flat], r"\(n, 3\) array")
    cone = SnapshotScene(**{**scene.__dict__, "object_shape": "cone"})
    _one_line_input_error(path, cone, moments, "unknown object shape 'cone'; known shapes: box")
    no_length = SnapshotScene(**{**scene.__dict__, "object_dimensions": {"radius": 0.03}})
    _one_line_input_error(path, no_length, moments, "dimension 'length' missing")
    bad_palm = SnapshotScene(**{**scene.__dict__, "palm_frame": "no_such_frame"})
    _one_line_input_error(path, bad_palm, moments, "palm frame 'no_such_frame' is not in")
    unknown_joint = Snapshot("hold", {"no_such_joint": 0.1}, good.T_world_object)
    _one_line_input_error(path, scene, [unknown_joint], "'hold'.*no_such_joint")
    bad_pose = Snapshot("hold", good.q_by_joint, np.eye(3))
    _one_line_input_error(path, scene, [bad_pose], "T_world_object must be a finite 4x4")
    assert list(tmp_path.iterdir()) == []
