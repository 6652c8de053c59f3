"""A picture of a grasp: `snapshots.png`, a grid of shaded 3-D views written next to a
run's result.

One column per moment of the grasp (e.g. "first contact", "hold", "after lift"), headed
by its contact count per real finger; one row per view, each a perspective render
(graspframe/pictures/):

- side: from the palm's -y side (square to the plane the fingers curl in; from its +y
  side when the arm would stand between), 20 deg above the horizontal, world z up;
- above: from 60 deg above the table, behind the back of the hand (or, for a hand that
  faces down, behind the wrist; turned 60 deg aside when the arm would stand in the
  way), world z up: how the fingers reach around the object;
- palm: in the palm frame of each moment, looking at the palm from the object's side,
  fingertips (palm +x) up: what touches the palm and the inner finger faces. This row
  draws the simulated shapes (every link's collision shapes, a mesh object's convex
  pieces), on which the contacts lie; for a vendor model whose visual meshes differ
  from its collision shapes, the two rows above show what the hand looks like.

The side and above views keep one camera for all moments (fitted to the hand and the
object in all of them): the lift and any slip show as motion between columns. The palm
view keeps one camera in the palm frame.

The side and above panels show the robot's meshes (each link's visual meshes when the
model has them, else its collision shapes; hand links coloured by real finger, the palm
grey, a vendor mesh keeping a tint of its material colour; arm links only near the
palm, muted), the object (`graspframe.robot_models.shapes.object_mesh`), the table top as a checker
of 5 cm squares (a floor and a scale for the eye), the contacts and the palm axes (red
arrow: palm +z, blue arrow: palm +x; 3 cm each).

Readable at a glance for a failed grasp: what matters is where the fingers touch, and
most contacts are on the far side of the object or under a finger from some view. So the
object and the arm links are see-through (55 % opaque, one layer deep: the solid hand
and table show through them tinted), and contacts and palm axes are drawn on top of the
render after projecting them, so every contact is visible in every view; the three views
then say which side it is on. The hand itself stays opaque: its shape is the subject.

Rendered by graspframe/pictures/rasteriser.py's CPU rasteriser (one context per process); the
sheet is composed with OpenCV and Pillow and written atomically.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError, InputError
from graspframe.common.transforms import R_from_axis_angle, as_pose, inv_T, transform_points
from graspframe.hal.descriptions import HandDescription, joints_by_name
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.hal.objects import ObjectDescription
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.pictures import style
from graspframe.pictures.inputs import checked_figure, checked_object_soup, contact_points
from graspframe.pictures.panel import (
    FOV_DEG,
    PALM_VIEW_DIRECTION,
    legend_entries,
    render_panel,
)
from graspframe.pictures.render3d import Camera, Placed, View, box_corners, fit_view
from graspframe.pictures.robot_scene import RobotFigure, distance_to, table_soup
from graspframe.pictures.sheet import compose, write_png

PICTURE_STYLE = 3  # changes with the look of the pictures (cached pictures are redrawn)
PANEL_PX = 360  # [px] side of a square panel
FAR_OBJECT = 0.5  # [m] an object further from the palm is left out of the framing
NEAR_HAND = 0.10  # [m] arm links with a vertex this close to the palm origin are drawn (the wrist)
TABLE_HALF_SIZE = 0.6  # [m] the table top drawn around the framed hand and object
SIDE_ELEVATION_DEG = 20.0
ABOVE_ELEVATION_DEG = 60.0
ABOVE_TURN_DEG = 60.0
WORLD_UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class SnapshotScene:
    """What stays the same over a run.

    model: the robot model (hand alone, or on an arm or a floating base); each link is
        drawn with its visual meshes (`model.visuals`), else its collision shapes.
    T_world_root: pose of the URDF root link in the world.
    palm_frame: the palm frame link of the URDF.
    finger_of_link: hand link -> real finger ("palm", "finger_1", ...); other links are arm links.
    joint_followers: adds <mimic> follower joints to a joint dict
        (HandDescription.with_model_followers); None: the dict is used as it is.
    obj: the object (its display mesh is `graspframe.robot_models.shapes.object_mesh(obj)`).
    table_height: [m] world z of the table top (the table is the half-space below).
    """

    model: UrdfModel
    T_world_root: NDArray[np.float64]
    palm_frame: str
    finger_of_link: Mapping[str, str]
    joint_followers: Callable[[dict[str, float]], dict[str, float]] | None
    obj: ObjectDescription
    table_height: float


def scene_of_robot(
    model: UrdfModel,
    T_world_root: NDArray[np.float64],
    hand: HandDescription,
    obj: ObjectDescription,
    table_height: float,
) -> SnapshotScene:
    """The scene of a hand (a HandDescription, alone or mounted: `model` is the model
    drawn, its root at T_world_root) and an ObjectDescription on a table."""
    return SnapshotScene(
        model=model,
        T_world_root=T_world_root,
        palm_frame=hand.palm_frame,
        finger_of_link=hand.finger_of_link(),
        joint_followers=hand.with_model_followers,
        obj=obj,
        table_height=table_height,
    )


class GraspMoment(Protocol):
    """What a picture reads of a moment of an execution (strategy/execution.py's
    `Moment`; declared here so that pictures need nothing of the strategy): q_arm [rad]
    in the arm's joint order (None: no arm), q_hand [rad or m] by joint name, the
    object's pose and the contacts in the world frame."""

    @property
    def label(self) -> str: ...
    @property
    def q_arm(self) -> NDArray[np.float64] | None: ...
    @property
    def q_hand(self) -> Mapping[str, float]: ...
    @property
    def T_world_object(self) -> NDArray[np.float64]: ...
    @property
    def contacts(self) -> tuple[Contact, ...]: ...


@dataclass(frozen=True)
class Snapshot:
    """One moment of the grasp.

    q_by_joint: [rad or m] every driven joint of the URDF by name (arm and hand); mimic
        followers are added by the scene's joint_followers.
    contact_points_world: (n, 3) [m] object contacts, may be empty (shape (0, 3)).
    contact_fingers: the real finger of each contact point (same length).
    """

    label: str
    q_by_joint: Mapping[str, float]
    T_world_object: NDArray[np.float64]
    contact_points_world: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))
    contact_fingers: Sequence[str] = ()

    @classmethod
    def from_moment(cls, moment: GraspMoment, arm_joint_names: Sequence[str]) -> Snapshot:
        """A moment of an execution (strategy/execution.py), the arm's joints named in
        `arm_joint_names` order."""
        q = joints_by_name(arm_joint_names, moment.q_arm, moment.q_hand)
        return cls.with_contacts(moment.label, q, moment.T_world_object, moment.contacts)

    @classmethod
    def with_contacts(
        cls,
        label: str,
        q_by_joint: Mapping[str, float],
        T_world_object: NDArray[np.float64],
        contacts: Sequence[Contact],
    ) -> Snapshot:
        """The moment with `contacts` (graspframe.common.contacts.Contact, world frame) drawn."""
        return cls(
            label=label,
            q_by_joint=q_by_joint,
            T_world_object=T_world_object,
            contact_points_world=np.array([c.p for c in contacts]).reshape(-1, 3),
            contact_fingers=[c.real_finger for c in contacts],
        )


@dataclass
class _Bodies:
    """What a panel draws of one moment, placed in the world."""

    hand: list[Placed]
    arm: list[Placed]  # translucent: the links near the palm
    object: Placed  # translucent

    def all(self) -> list[Placed]:
        return [*self.hand, *self.arm, self.object]


@dataclass(frozen=True)
class _Moment:
    """One snapshot placed in the world: as it looks (`shown`: visual meshes where the
    model has them) and as it is simulated (`simulated`: collision shapes, the object's
    convex pieces), and its contacts."""

    snapshot: Snapshot
    T_world_palm: NDArray[np.float64]
    shown: _Bodies
    simulated: _Bodies
    contacts_world: NDArray[np.float64]

    @property
    def object_near(self) -> bool:
        """False when the object is far from the hand (knocked away, or fallen through
        the table after a simulation failure): the views then frame the hand alone."""
        p_world_object = self.shown.object.T_world_soup[:3, 3]
        return float(np.linalg.norm(p_world_object - self.T_world_palm[:3, 3])) <= FAR_OBJECT

    def framed_points(self) -> NDArray[np.float64]:
        """(n, 3) [m] world points a view must show: the hand, and the object when near."""
        boxes = [box_corners(p) for p in self.shown.hand]
        if self.object_near:
            boxes.append(box_corners(self.shown.object))
        return np.concatenate(boxes)


def _place_moments(
    scene: SnapshotScene, snapshots: Sequence[Snapshot], colours: Mapping[str, str]
) -> list[_Moment]:
    T_world_root = as_pose(scene.T_world_root, "scene T_world_root")
    soup = checked_object_soup(scene.obj, "snapshots")
    checked = [
        (
            s,
            as_pose(s.T_world_object, f"snapshot {s.label!r}: T_world_object"),
            contact_points(
                s.contact_points_world,
                s.contact_fingers,
                f"snapshot {s.label!r}: contact_points_world",
            ),
        )
        for s in snapshots
    ]
    figure = checked_figure(
        scene.model, scene.finger_of_link, colours, scene.palm_frame, "snapshots"
    )
    # The simulated shapes differ from those shown where the model has visual meshes or
    # the object is a mesh (drawn from its scan, simulated as convex pieces).
    simulated_figure = figure
    if scene.model.visuals:
        simulated_figure = checked_figure(
            scene.model, scene.finger_of_link, colours, scene.palm_frame, "snapshots", True
        )
    simulated_soup = soup
    if scene.obj.is_mesh:
        simulated_soup = checked_object_soup(scene.obj, "snapshots", simulated=True)
    moments = []
    for snapshot, T_world_object, contacts in checked:
        q = dict(snapshot.q_by_joint)
        if scene.joint_followers is not None:
            q = scene.joint_followers(q)
        try:
            figure.place(q)
            simulated_figure.place(q)
        except GraspframeError as exc:
            raise InputError(f"snapshot {snapshot.label!r}: {exc}") from None
        T_world_palm = T_world_root @ figure.T_root_frame(scene.palm_frame)
        shown = _bodies(
            figure, T_world_root, T_world_palm, Placed(soup, T_world_object, translucent=True)
        )
        simulated = _bodies(
            simulated_figure,
            T_world_root,
            T_world_palm,
            Placed(simulated_soup, T_world_object, translucent=True),
        )
        moments.append(_Moment(snapshot, T_world_palm, shown, simulated, contacts))
    return moments


def _bodies(
    figure: RobotFigure,
    T_world_root: NDArray[np.float64],
    T_world_palm: NDArray[np.float64],
    placed_object: Placed,
) -> _Bodies:
    """The figure's hand links, its arm links near the palm (translucent), the object."""
    links = figure.placed_links(T_world_root)
    hand = [p for link, p in links.items() if figure.is_hand_link(link)]
    arm = [
        Placed(p.soup, p.T_world_soup, translucent=True)
        for link, p in links.items()
        if not figure.is_hand_link(link) and distance_to(p, T_world_palm[:3, 3]) <= NEAR_HAND
    ]
    return _Bodies(hand, arm, placed_object)


def _horizontal(v: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """The unit horizontal part of a world vector, None when it is nearly vertical."""
    h = np.array([v[0], v[1], 0.0])
    n = float(np.linalg.norm(h))
    return None if n < 0.2 else h / n


def _elevated(horizontal: NDArray[np.float64], elevation_deg: float) -> NDArray[np.float64]:
    e = math.radians(elevation_deg)
    return math.cos(e) * horizontal + math.sin(e) * WORLD_UP


def side_direction(
    T_world_palm: NDArray[np.float64], p_world_arm: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """World direction from the hand towards the side view's camera: from the palm's -y
    side, or its +y side when the arm's points `p_world_arm` (n, 3) [m] lie more towards
    the -y camera (the arm stays behind the hand)."""
    R = np.asarray(T_world_palm)[:3, :3]
    horizontal = _horizontal(-R[:, 1])
    if horizontal is None:  # palm y vertical: look along the palm normal's side instead
        horizontal = _horizontal(np.cross(WORLD_UP, R[:, 2]))
    if horizontal is None:
        horizontal = np.array([0.0, -1.0, 0.0])
    if p_world_arm is not None and len(p_world_arm):
        towards_camera = float(np.mean((p_world_arm - T_world_palm[:3, 3]) @ horizontal))
        if towards_camera > 0:
            horizontal = -horizontal
    return _elevated(horizontal, SIDE_ELEVATION_DEG)


def above_direction(
    T_world_palm: NDArray[np.float64], p_world_arm: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """World direction from the hand towards the above view's camera: behind the back of
    the hand, or behind the wrist when the palm faces down or up; turned ABOVE_TURN_DEG
    to either side when that keeps the arm's points `p_world_arm` (n, 3) [m] further
    from the line of sight (the arm comes from behind the hand)."""
    R = np.asarray(T_world_palm)[:3, :3]
    horizontal = _horizontal(-R[:, 2])
    if horizontal is None:
        horizontal = _horizontal(-R[:, 0])
    if horizontal is None:
        horizontal = np.array([-1.0, 0.0, 0.0])
    candidates = [_elevated(horizontal, ABOVE_ELEVATION_DEG)]
    if p_world_arm is not None and len(p_world_arm):
        for turn_deg in (ABOVE_TURN_DEG, -ABOVE_TURN_DEG):
            R_turn = R_from_axis_angle(WORLD_UP, math.radians(turn_deg))
            candidates.append(_elevated(R_turn @ horizontal, ABOVE_ELEVATION_DEG))
        offsets = np.asarray(p_world_arm, dtype=float) - T_world_palm[:3, 3]
        candidates.sort(key=lambda d: float(np.mean(offsets @ d)))  # stable: behind first
    return candidates[0]


def _camera() -> Camera:
    return Camera.from_fov(PANEL_PX, PANEL_PX, FOV_DEG)


def _world_views(moments: Sequence[_Moment], direction: NDArray[np.float64]) -> list[View]:
    points = np.concatenate([m.framed_points() for m in moments])
    view = fit_view(_camera(), points, direction, WORLD_UP)
    return [view] * len(moments)


def _palm_views(moments: Sequence[_Moment]) -> list[View]:
    points_palm = np.concatenate(
        [transform_points(inv_T(m.T_world_palm), m.framed_points()) for m in moments]
    )
    in_palm = fit_view(_camera(), points_palm, PALM_VIEW_DIRECTION, (1.0, 0.0, 0.0))
    return [View(in_palm.camera, m.T_world_palm @ in_palm.T_world_camera) for m in moments]


def contact_summary(snapshot: Snapshot) -> str:
    """ "n contacts: finger k, ..." or "no contacts"."""
    if not len(snapshot.contact_fingers):
        return "no contacts"
    counts: dict[str, int] = {}
    for finger in snapshot.contact_fingers:
        counts[finger] = counts.get(finger, 0) + 1
    listing = ", ".join(f"{finger} {n}" for finger, n in counts.items())
    total = len(snapshot.contact_fingers)
    return f"{total} contact{'s' if total != 1 else ''}: {listing}"


ROW_LABELS = ("side", "from above", "palm frame, facing the palm: the simulated shapes")
ROW_CONTENT = ((True, False), (True, False), (False, True))  # (with the table, simulated)


def draw_snapshots(
    path: Path, scene: SnapshotScene, snapshots: Sequence[Snapshot], title: str
) -> Path:
    """Draw the snapshots (one column each) in the three views (rows) to the PNG `path`,
    atomically; returns `path`. InputError (one line) for unusable input."""
    path = Path(path)
    if not snapshots:
        raise InputError("no snapshots to draw")
    colours = style.finger_colours(scene.finger_of_link)
    moments = _place_moments(scene, snapshots, colours)
    reference = moments[0].T_world_palm
    arm_points = [box_corners(p) for m in moments for p in m.shown.arm]
    p_world_arm = np.concatenate(arm_points) if arm_points else None
    rows = [
        _world_views(moments, side_direction(reference, p_world_arm)),
        _world_views(moments, above_direction(reference, p_world_arm)),
        _palm_views(moments),
    ]
    points = np.concatenate([m.framed_points() for m in moments])
    centre_xy = (points.min(axis=0) + points.max(axis=0))[:2] / 2
    table = Placed(table_soup(centre_xy, TABLE_HALF_SIZE, scene.table_height), np.eye(4))
    panels = []
    for views, (with_table, simulated) in zip(rows, ROW_CONTENT, strict=True):
        row = []
        for moment, view in zip(moments, views, strict=True):
            bodies = moment.simulated if simulated else moment.shown
            placed = bodies.all() + ([table] if with_table else [])
            row.append(
                render_panel(placed, view, moment.contacts_world, moment.T_world_palm, bodies.hand)
            )
        panels.append(row)
    headers = []
    for moment in moments:
        label = moment.snapshot.label
        if not moment.object_near:
            label += " (object out of view)"
        headers.append(f"{label}\n{contact_summary(moment.snapshot)}")
    with_arm = any(m.shown.arm for m in moments)
    sheet = compose(
        title, headers, ROW_LABELS, panels, legend_entries(colours, with_arm, with_table=True)
    )
    return write_png(path, sheet)


def draw_grasp(
    path: Path,
    robot: MountedRobot,
    T_world_root: NDArray[np.float64],
    obj: ObjectDescription,
    table_height: float,
    moments: Sequence[GraspMoment],
    what: str,
    held: bool,
    failure: str | None,
) -> Path:
    """The picture of an executed grasp (the robot's run, the human reference, a hand's
    check): `robot` (its model's root at T_world_root), the object and the table at each
    of `moments`, titled "<what>; held" or "<what>; not held: <failure>"."""
    scene = scene_of_robot(robot.model, T_world_root, robot.hand, obj, table_height)
    frames = [Snapshot.from_moment(m, robot.arm.joint_names) for m in moments]
    verdict = "held" if held else f"not held: {failure}"
    return draw_snapshots(path, scene, frames, f"{what}; {verdict}")
