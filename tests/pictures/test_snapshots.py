"""graspframe.pictures.snapshots: the rendered 3-view picture of a grasp, drawn from the real robot
models with the CPU rasteriser.

Scenes: the Barrett hand alone, palm facing down over a cylinder on the table; the
Barrett on the KUKA arm at its home pose; the LEAP hand from its vendor files (visual
meshes; skipped when the third-party models are not beside the project). Pixel checks
look for hues only one kind of element has (a finger's colour, the object's yellow) and
for the pure red of the contact markers (the PNG's palette rounds colours a little).
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
from conftest import THIRD_PARTY
from graspframe_barrett.description import BARRETT, hand_q

from graspframe.common.errors import InputError
from graspframe.common.grasps import PALM
from graspframe.common.transforms import R_from_rpy, inv_T, make_T
from graspframe.hal.objects import ObjectDescription
from graspframe.model_files.urdf_model import FrameOffset, read_model
from graspframe.pictures import sheet, style
from graspframe.pictures import snapshots as snap
from graspframe.pictures.robot_scene import RobotFigure
from graspframe.pictures.snapshots import Snapshot, SnapshotScene, draw_snapshots
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.robot_models.mounting import mount

PALM_HEIGHT = 0.20  # [m] palm origin above the table (Barrett scene)
RADIUS, LENGTH = 0.03, 0.10  # [m] the cylinder
CAN = ObjectDescription("can", "cylinder", {"radius": RADIUS, "length": LENGTH}, 0.2)
# Palm facing down (palm z = -world z), fingertips along world +x.
R_WORLD_PALM_DOWN = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])
LEAP_URDF = THIRD_PARTY / "hands" / "leap_hand" / "leap_hand_right.urdf"
CONTACT_RED = np.array([255, 0, 0])


def read_rgb(path: Path) -> np.ndarray:
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    assert image is not None, path
    return image[..., ::-1]


def hue_mask(image_rgb: np.ndarray, colour: str, tol_deg: float = 8.0) -> np.ndarray:
    """Pixels of the hue of `colour` (any brightness, saturated enough to be no grey)."""
    hsv = cv2.cvtColor(np.ascontiguousarray(image_rgb[..., ::-1]), cv2.COLOR_BGR2HSV)
    target = cv2.cvtColor(np.uint8([[style.bgr255(colour)]]), cv2.COLOR_BGR2HSV)[0, 0]
    difference = np.abs(hsv[..., 0].astype(int) - int(target[0]))
    difference = np.minimum(difference, 180 - difference) * 2  # OpenCV hue: 2 deg a step
    return (difference <= tol_deg) & (hsv[..., 1] > 90) & (hsv[..., 2] > 40)


def red_pixels(image_rgb: np.ndarray) -> int:
    """Pixels of the contact markers' pure red (within the written palette's rounding)."""
    near = np.abs(image_rgb.astype(int) - CONTACT_RED) <= 24
    return int(np.count_nonzero(np.all(near, axis=-1)))


def sheet_width(n_columns: int) -> int:
    grid = n_columns * snap.PANEL_PX + (n_columns - 1) * sheet.GAP
    return 2 * sheet.MARGIN + sheet.ROW_LABEL_WIDTH + grid


@pytest.fixture(scope="module")
def barrett_scene() -> tuple[SnapshotScene, list[Snapshot]]:
    """Barrett alone: palm 20 cm above the table, a cylinder standing under it."""
    model = CollisionModel(model_of(BARRETT))
    model.place(BARRETT.with_model_followers(hand_q(0, 10)))
    T_world_palm = make_T(R_WORLD_PALM_DOWN, [0.5, 0.1, PALM_HEIGHT])
    T_world_root = T_world_palm @ inv_T(model.T_root_frame(BARRETT.palm_frame))
    scene = SnapshotScene(
        model=model_of(BARRETT),
        T_world_root=T_world_root,
        palm_frame=BARRETT.palm_frame,
        finger_of_link=BARRETT.finger_of_link(),
        joint_followers=BARRETT.with_model_followers,
        obj=CAN,
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


TITLE = "barrett · wrap · cylinder — HELD"


@pytest.fixture(scope="module")
def barrett_png(barrett_scene, tmp_path_factory) -> Path:
    scene, moments = barrett_scene
    path = tmp_path_factory.mktemp("barrett") / "run" / "snapshots.png"
    assert draw_snapshots(path, scene, moments, TITLE) == path
    return path


def test_png_written_with_one_panel_per_view_and_moment(barrett_png: Path):
    image = read_rgb(barrett_png)
    assert image.shape[1] == sheet_width(3)
    assert image.shape[0] > len(snap.ROW_LABELS) * snap.PANEL_PX
    assert [p.name for p in barrett_png.parent.iterdir()] == ["snapshots.png"]  # no temp file
    # Every finger, the see-through object and the contacts show.
    colours = style.finger_colours(BARRETT.finger_of_link())
    for finger in BARRETT.real_fingers:
        if finger != PALM:
            assert np.count_nonzero(hue_mask(image, colours[finger])) > 3000, finger
    assert np.count_nonzero(hue_mask(image, style.OBJECT_COLOUR, tol_deg=6)) > 3000
    assert red_pixels(image) > 7 * 3 * 20  # 7 contacts in 3 views


def test_drawing_is_deterministic_and_one_column_per_moment(
    tmp_path: Path, barrett_scene, barrett_png: Path
):
    scene, moments = barrett_scene
    again = draw_snapshots(tmp_path / "again.png", scene, moments, TITLE)
    assert again.read_bytes() == barrett_png.read_bytes()
    one = draw_snapshots(tmp_path / "one.png", scene, moments[:1], "one moment")
    assert read_rgb(one).shape[1] == sheet_width(1)


def test_the_hand_region_follows_the_posture(tmp_path: Path, barrett_scene):
    scene, moments = barrett_scene
    colour = style.finger_colours(BARRETT.finger_of_link())["finger_3"]
    masks = []
    for name, q in (("open", hand_q(0, 10)), ("closed", hand_q(0, 120))):
        moment = Snapshot(name, q, moments[0].T_world_object)
        image = read_rgb(draw_snapshots(tmp_path / f"{name}.png", scene, [moment], "t"))
        masks.append(hue_mask(image, colour))
    changed = np.count_nonzero(masks[0] ^ masks[1])
    assert changed > 0.3 * max(np.count_nonzero(masks[0]), np.count_nonzero(masks[1]))


def test_contacts_are_drawn_on_top(tmp_path: Path, barrett_scene, barrett_png: Path):
    scene, moments = barrett_scene
    without = [Snapshot(m.label, m.q_by_joint, m.T_world_object, [], []) for m in moments]
    plain = read_rgb(draw_snapshots(tmp_path / "n.png", scene, without, "t"))
    # Only the legend has red markers without contacts; every contact shows in every view.
    assert red_pixels(read_rgb(barrett_png)) > red_pixels(plain) + 7 * 3 * 20


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
    box = ObjectDescription("box", "box", {"size_x": 0.05, "size_y": 0.05, "size_z": 0.08}, 0.2)
    scene = SnapshotScene(
        model=robot.model,
        T_world_root=np.eye(4),
        palm_frame=hand.palm_frame,
        finger_of_link=hand.finger_of_link(),
        joint_followers=hand.with_model_followers,
        obj=box,
        table_height=float(p_world_object[2] - 0.04),
    )
    moment = Snapshot("hold", q, make_T(p=p_world_object), np.zeros((0, 3)), [])
    colours = style.finger_colours(hand.finger_of_link())
    (placed,) = snap._place_moments(scene, [moment], colours)
    assert placed.shown.arm and all(p.translucent for p in placed.shown.arm)
    assert len(placed.shown.arm) < len(arm.joints)  # only the links at the wrist
    image = read_rgb(draw_snapshots(tmp_path / "arm.png", scene, [moment], "t"))
    assert image.shape[1] == sheet_width(1)


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
    not_an_object = SnapshotScene(**{**scene.__dict__, "obj": "cone"})
    _one_line_input_error(path, not_an_object, moments, "must be an ObjectDescription, got str")
    bad_palm = SnapshotScene(**{**scene.__dict__, "palm_frame": "no_such_frame"})
    _one_line_input_error(path, bad_palm, moments, "palm frame 'no_such_frame' is not in")
    no_fingers = SnapshotScene(**{**scene.__dict__, "finger_of_link": {"nowhere": PALM}})
    _one_line_input_error(path, no_fingers, moments, "no link of the hand's real fingers")
    unknown_joint = Snapshot("hold", {"no_such_joint": 0.1}, good.T_world_object)
    _one_line_input_error(path, scene, [unknown_joint], "'hold'.*no_such_joint")
    bad_pose = Snapshot("hold", good.q_by_joint, np.eye(3))
    _one_line_input_error(path, scene, [bad_pose], "T_world_object must be a 4x4")
    assert list(tmp_path.iterdir()) == []


def test_view_directions_keep_the_arm_behind_and_the_camera_above():
    T_world_palm = make_T(R_WORLD_PALM_DOWN, [0.5, 0.1, PALM_HEIGHT])
    side = snap.side_direction(T_world_palm)
    assert side[2] > 0 and side @ T_world_palm[:3, 1] < -0.9  # from the palm's -y side
    # An arm on the -y side: the camera moves to the +y side.
    arm = T_world_palm[:3, 3] - 0.1 * T_world_palm[:3, 1]
    assert snap.side_direction(T_world_palm, arm[None, :]) @ T_world_palm[:3, 1] > 0.9
    above = snap.above_direction(T_world_palm)  # palm down: behind the wrist, from above
    assert above[2] > 0.8 and above @ T_world_palm[:3, 0] < 0
    R_side_grasp = R_from_rpy(0.0, np.pi / 2, 0.0)  # palm +z along world +x
    above = snap.above_direction(make_T(R_side_grasp))
    assert above[0] < 0 and above[2] > 0.8  # behind the back of the hand
    # An arm behind the hand: the camera turns aside, still above.
    turned = snap.above_direction(make_T(R_side_grasp), np.array([[-0.2, 0.0, 0.0]]))
    assert turned[2] > 0.8 and abs(turned[1]) > 0.3


def leap_scene() -> SnapshotScene:
    """The LEAP hand as shipped, a palm frame added on its base, palm down over a can."""
    R_base_palm = np.column_stack([[0, 0, 1.0], [0, -1.0, 0], [1.0, 0, 0]])
    palm = FrameOffset("base", make_T(R_base_palm, [0.035, 0.0, 0.05]))
    model = read_model(LEAP_URDF, frames={"palm": palm})
    fingers = {"palm_lower": PALM}
    for finger, suffix in (("index", ""), ("middle", "_2"), ("ring", "_3")):
        fingers |= {f"{link}{suffix}": finger for link in ("mcp_joint", "pip", "dip", "fingertip")}
    fingers |= {link: "thumb" for link in ("thumb_temp_base", "thumb_pip", "thumb_dip")}
    fingers["thumb_fingertip"] = "thumb"
    collision = CollisionModel(model)
    T_world_palm = make_T(R_WORLD_PALM_DOWN, [0.5, 0.0, 0.12])
    T_world_root = T_world_palm @ inv_T(collision.T_root_frame("palm"))
    can = ObjectDescription("can", "cylinder", {"radius": 0.035, "length": 0.14}, 0.3)
    return SnapshotScene(model, T_world_root, "palm", fingers, None, can, 0.0)


def leap_q(curl: float) -> dict[str, float]:
    """Every finger flexed by `curl` [rad] (joints "1", "5", "9": MCP flexion)."""
    q = {}
    for first in (0, 4, 8):
        q |= {str(first + 1): curl, str(first + 2): 0.9 * curl, str(first + 3): 0.7 * curl}
    return q | {"12": 1.2 * curl, "13": 0.3, "14": 0.6 * curl, "15": 0.6 * curl}


@pytest.mark.skipif(not LEAP_URDF.is_file(), reason="the third-party models are not here")
def test_the_leap_hand_is_drawn_with_its_visual_meshes(tmp_path: Path):
    scene = leap_scene()
    colours = style.finger_colours(scene.finger_of_link)
    figure = RobotFigure(scene.model, scene.finger_of_link, colours)
    visual_links = {v.link for v in scene.model.visuals}
    assert visual_links <= set(figure.soups)
    # The palm is its (decimated) vendor mesh, not its collision boxes.
    assert len(figure.soups["palm_lower"]) > 1000
    T_world_object = make_T(R_from_rpy(np.pi / 2, 0, 0), [0.53, 0.0, 0.035])
    p = np.array([[0.495, 0.02, 0.05], [0.565, 0.0, 0.04]])
    moments = [
        Snapshot("open", leap_q(0.2), T_world_object),
        Snapshot("closed", leap_q(0.9), T_world_object, p, ["index", "thumb"]),
    ]
    image = read_rgb(draw_snapshots(tmp_path / "leap.png", scene, moments, "LEAP"))
    assert image.shape[1] == sheet_width(2)
    for finger in ("index", "middle", "ring", "thumb"):
        assert np.count_nonzero(hue_mask(image, colours[finger])) > 2000, finger


@pytest.mark.skipif(not LEAP_URDF.is_file(), reason="the third-party models are not here")
def test_the_palm_row_draws_the_shapes_that_are_simulated():
    """Side and above: the LEAP's visual meshes; the palm row: its collision boxes and
    hulls, the shapes the simulator and the collision checker use."""
    scene = leap_scene()
    colours = style.finger_colours(scene.finger_of_link)
    collision = RobotFigure(scene.model, scene.finger_of_link, colours, simulated=True)
    # The palm's collision shapes are boxes: 12 triangles each.
    assert len(collision.soups["palm_lower"]) % 12 == 0
    (moment,) = snap._place_moments(scene, [Snapshot("closed", leap_q(0.9), np.eye(4))], colours)
    shown = {len(p.soup) for p in moment.shown.hand}
    simulated = {len(p.soup) for p in moment.simulated.hand}
    assert len(collision.soups["palm_lower"]) in simulated
    assert len(collision.soups["palm_lower"]) not in shown
