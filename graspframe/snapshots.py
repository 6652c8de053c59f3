"""A picture of a grasp: `snapshots.png`, a grid of 2-D views written next to a run's result.

One column per moment of the grasp (e.g. "first contact", "hold", "after lift"), one row
per view:

- world x-z: world x to the right, world z up (seen from -y);
- world y-z: world y to the right, world z up (seen from +x);
- palm x-z: the palm frame of that moment, x towards the fingertips to the right, z (the
  palm normal, out of the palm towards the object) up (seen from palm -y).

Each panel shows the orthographic projection of the robot's collision shapes (hand links
coloured by real finger, palm grey; arm links slate, only those near the palm), the object
(yellow; a mesh object as its display mesh, `graspframe.shapes.object_mesh`, its
triangles shaded by how squarely they face the viewer), the table (thick black line at
the table top, grey below; in the palm view the table plane's intersection with the
palm x-z plane), the object contacts (red dots), and
the palm axes at the palm origin (red arrow: palm +z, blue arrow: palm +x; 3 cm each).
Every shape is a convex primitive, so its projection is the 2-D convex hull of points
sampled on its surface; shapes are painted far to near along the viewing axis (a mesh
object's triangles far to near among themselves, at the object's place). The rows
keep the same limits in all columns, so moments compare directly.

Drawn with a bare `matplotlib.figure.Figure` (Agg canvas): no pyplot global state, no 3-D
axes. The file is written atomically.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import NDArray

from graspframe.errors import GraspframeError, InputError
from graspframe.files import atomic_output
from graspframe.hal.objects import SHAPES
from graspframe.shapes import geometry_mesh, object_mesh, primitive_mesh
from graspframe.transforms import inv_T, transform_points

FAR_OBJECT = 0.5  # [m] an object further from the palm is left out of the framing
PANEL_INCH = 4.0  # per panel; plus margins for the title, x labels, row labels:
TITLE_INCH, XLABEL_INCH, LEFT_INCH, RIGHT_INCH = 1.0, 0.4, 0.8, 0.2
LEGEND_ENTRY_INCH, LEGEND_ROW_INCH = 1.25, 0.22  # the legend wraps to the figure's width
LEGEND_FIXED_ENTRIES = 6  # arm, object, table, contact, palm +z, palm +x (+ one per finger)
DPI = 80
NEAR_HAND = 0.25  # [m] arm links with a shape point this close to the palm origin are drawn
MIN_SPAN = 0.25  # [m] smallest width of a panel
MARGIN = 0.03  # [m] around the object and the hand
ARROW_LENGTH = 0.03  # [m] palm axes
RING_POINTS = 24  # samples per circle (cylinder rims, sphere outlines)

FINGER_COLOURS = ("#1b9e77", "#7570b3", "#e7298a", "#66a61e", "#d95f02", "#a6761d", "#17becf")
PALM_COLOUR = "#9a9a9a"
ARM_COLOUR = "#3b4f6b"
OBJECT_COLOUR, OBJECT_EDGE = "#ffd92f", "#5c4a00"
TABLE_COLOUR, TABLE_FILL = "#000000", "#e4e4e4"
CONTACT_COLOUR = "#ff0000"
PALM_Z_COLOUR, PALM_X_COLOUR = "#d62728", "#1f4fd8"
PALM = "palm"


@dataclass(frozen=True)
class SnapshotScene:
    """What stays the same over a run.

    urdf_path: the robot model (hand alone, or on an arm or a floating base); only its
        collision shapes are drawn.
    T_world_root: pose of the URDF root link in the world.
    palm_frame: the palm frame link of the URDF.
    finger_of_link: hand link -> real finger ("palm", "finger_1", ...); other links are arm links.
    joint_followers: adds <mimic> follower joints to a joint dict
        (HandDescription.with_model_followers); None: the dict is used as it is.
    object_shape: "box", "cylinder" (axis = object z) or "sphere".
    object_dimensions: [m] box: size_x, size_y, size_z; cylinder: radius, length;
        sphere: radius.
    table_height: [m] world z of the table top (the table is the half-space below).
    object_mesh: a mesh object's display mesh in the object frame (drawn instead of the
        shape; object_shape is then "mesh").
    """

    urdf_path: Path
    T_world_root: NDArray[np.float64]
    palm_frame: str
    finger_of_link: Mapping[str, str]
    joint_followers: Callable[[dict[str, float]], dict[str, float]] | None
    object_shape: str
    object_dimensions: Mapping[str, float]
    table_height: float
    object_mesh: trimesh.Trimesh | None = None


def scene_of_robot(urdf_path: Path, T_world_root, hand, obj, table_height: float) -> SnapshotScene:
    """The scene of a hand (a HandDescription, alone or mounted: `urdf_path` is the model
    drawn, its root at T_world_root) and an ObjectDescription on a table."""
    return SnapshotScene(
        urdf_path=urdf_path,
        T_world_root=T_world_root,
        palm_frame=hand.palm_frame,
        finger_of_link=hand.finger_of_link(),
        joint_followers=hand.with_model_followers,
        object_shape=obj.shape,
        object_dimensions=obj.dimensions,
        table_height=table_height,
        object_mesh=object_mesh(obj) if obj.is_mesh else None,
    )


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
    def with_contacts(cls, label: str, q_by_joint, T_world_object, contacts: Sequence) -> Snapshot:
        """The moment with `contacts` (graspframe.contacts.Contact, world frame) drawn."""
        return cls(
            label=label,
            q_by_joint=q_by_joint,
            T_world_object=T_world_object,
            contact_points_world=np.array([c.p for c in contacts]).reshape(-1, 3),
            contact_fingers=[c.real_finger for c in contacts],
        )


@dataclass(frozen=True)
class View:
    """A 2-D view of a frame: picture axes are the frame's axes `right` and `up`;
    `towards_viewer` is the frame direction pointing out of the picture (painter's depth)."""

    name: str
    in_palm_frame: bool
    right: int
    up: int
    towards_viewer: tuple[float, float, float]
    xlabel: str
    ylabel: str


VIEWS = (
    View("world x-z", False, 0, 2, (0.0, -1.0, 0.0), "world x [m]", "world z [m]"),
    View("world y-z", False, 1, 2, (1.0, 0.0, 0.0), "world y [m]", "world z [m]"),
    View("palm x-z", True, 0, 2, (0.0, -1.0, 0.0), "palm x (to fingertips) [m]", "palm z [m]"),
)


@dataclass(frozen=True)
class Solid:
    """A convex solid as sample points plus discs (centre, radius) whose projections are
    circles of that radius (spheres, capsule ends): its projection is the hull of both."""

    points: NDArray[np.float64]  # (m, 3)
    disc_centres: NDArray[np.float64]  # (k, 3)
    disc_radii: NDArray[np.float64]  # (k,)

    def moved(self, T_a_b: NDArray[np.float64]) -> Solid:
        """This solid (given in frame b) expressed in frame a."""
        return Solid(
            transform_points(T_a_b, self.points).reshape(-1, 3),
            transform_points(T_a_b, self.disc_centres).reshape(-1, 3),
            self.disc_radii,
        )

    def distance_to(self, p: NDArray[np.float64]) -> float:
        """Smallest distance [m] from the sample points or discs to the point p."""
        d = [np.linalg.norm(self.points - p, axis=1)]
        d.append(np.linalg.norm(self.disc_centres - p, axis=1) - self.disc_radii)
        d = np.concatenate(d)
        return float(d.min()) if d.size else math.inf


@dataclass(frozen=True)
class Surface:
    """A triangle mesh drawn triangle by triangle (a mesh object's display mesh)."""

    vertices: NDArray[np.float64]  # (n, 3)
    faces: NDArray[np.int64]  # (m, 3)

    def moved(self, T_a_b: NDArray[np.float64]) -> Surface:
        """This surface (given in frame b) expressed in frame a."""
        return Surface(transform_points(T_a_b, self.vertices).reshape(-1, 3), self.faces)


_ANGLES = np.linspace(0, 2 * np.pi, RING_POINTS, endpoint=False)
_UNIT_CIRCLE = np.c_[np.cos(_ANGLES), np.sin(_ANGLES)]
_NO_POINTS = np.zeros((0, 3))
_NO_RADII = np.zeros(0)


def _sphere(radius: float) -> Solid:
    return Solid(_NO_POINTS, np.zeros((1, 3)), np.array([radius]))


def _mesh_solid(mesh) -> Solid:
    return Solid(np.asarray(mesh.vertices, dtype=float), _NO_POINTS, _NO_RADII)


def solid_of_geometry(geometry) -> Solid | None:
    """The Solid (in the shape's frame) of a coal collision geometry; None if it cannot be
    drawn. Spheres and capsules are discs (exact outlines); other kinds are the vertices
    of their mesh (`graspframe.shapes.geometry_mesh`)."""
    kind = type(geometry).__name__
    if kind == "Sphere":
        return _sphere(float(geometry.radius))
    if kind == "Capsule":
        h = float(geometry.halfLength)
        return Solid(_NO_POINTS, np.array([[0, 0, -h], [0, 0, h]]), np.full(2, geometry.radius))
    mesh = geometry_mesh(geometry, sections=RING_POINTS)
    return None if mesh is None else _mesh_solid(mesh)


def object_solid(shape: str, dimensions: Mapping[str, float]) -> Solid:
    """The object's Solid in the object frame; InputError for an unknown shape or a
    missing or non-positive dimension."""
    if shape not in SHAPES:
        known = ", ".join(SHAPES)
        raise InputError(f"unknown object shape {shape!r}; known shapes: {known}")
    values = {}
    for key in SHAPES[shape]:
        try:
            values[key] = float(dimensions[key])
        except (KeyError, TypeError, ValueError):
            raise InputError(
                f"object {shape}: dimension {key!r} missing or not a number "
                f"(needs {', '.join(SHAPES[shape])} [m])"
            ) from None
        if not (math.isfinite(values[key]) and values[key] > 0):
            raise InputError(f"object {shape}: dimension {key!r} must be > 0 m, got {values[key]}")
    if shape == "sphere":
        return _sphere(values["radius"])
    return _mesh_solid(primitive_mesh(shape, values, sections=RING_POINTS))


def project(solid: Solid, view: View) -> tuple[NDArray[np.float64], float]:
    """(2-D outline polygon (m, 2) [m], nearness to the viewer [m]) of a solid given in the
    view's frame."""
    axes = [view.right, view.up]
    points_2d = [solid.points[:, axes]]
    for centre, radius in zip(solid.disc_centres, solid.disc_radii, strict=True):
        points_2d.append(centre[axes] + radius * _UNIT_CIRCLE)
    outline_points = np.concatenate(points_2d)
    centres = np.concatenate([solid.points, solid.disc_centres])
    nearness = float((centres @ np.asarray(view.towards_viewer)).mean())
    return _convex_hull(outline_points), nearness


def _convex_hull(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Counter-clockwise hull of 2-D points; a degenerate (flat) set gives its two extreme
    points, which the polygon's edge draws as a line."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        return points[ConvexHull(points).vertices]
    except (QhullError, ValueError):
        ends = points[[0, int(np.argmax(np.linalg.norm(points - points[0], axis=1)))]]
        return ends


def project_points(p_frame: NDArray[np.float64], view: View) -> NDArray[np.float64]:
    """(n, 2) picture coordinates [m] of points (n, 3) given in the view's frame."""
    return np.asarray(p_frame, dtype=float).reshape(-1, 3)[:, [view.right, view.up]]


@dataclass
class _Moment:
    """One snapshot placed: solids per link in the world, palm pose, object, contacts."""

    snapshot: Snapshot
    T_world_palm: NDArray[np.float64]
    link_solids: list[tuple[str, Solid]]  # world frame, hand links and near arm links
    object_world: Solid | Surface
    contacts_world: NDArray[np.float64]

    def in_view_frame(self, view: View):
        """(T_view_world, link solids, object solid, contacts) in the view's frame."""
        T_view_world = inv_T(self.T_world_palm) if view.in_palm_frame else np.eye(4)
        if not view.in_palm_frame:
            return T_view_world, self.link_solids, self.object_world, self.contacts_world
        links = [(link, s.moved(T_view_world)) for link, s in self.link_solids]
        contacts = transform_points(T_view_world, self.contacts_world).reshape(-1, 3)
        return T_view_world, links, self.object_world.moved(T_view_world), contacts


def _pose(value, what: str) -> NDArray[np.float64]:
    try:
        T = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a 4x4 matrix of numbers") from None
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise InputError(f"{what} must be a finite 4x4 matrix, got shape {T.shape}")
    return T


def _contacts(snapshot: Snapshot) -> NDArray[np.float64]:
    what = f"snapshot {snapshot.label!r}"
    try:
        points = np.asarray(snapshot.contact_points_world, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what}: contact_points_world must be an (n, 3) array [m]") from None
    if points.size == 0:
        points = np.zeros((0, 3))
    if points.ndim != 2 or points.shape[1] != 3 or not np.all(np.isfinite(points)):
        raise InputError(
            f"{what}: contact_points_world must be a finite (n, 3) array [m], got shape "
            f"{points.shape}"
        )
    if len(snapshot.contact_fingers) != len(points):
        raise InputError(
            f"{what}: {len(points)} contact points but {len(snapshot.contact_fingers)} "
            "contact fingers; give one finger per point"
        )
    return points


def _place_moments(scene: SnapshotScene, snapshots: Sequence[Snapshot]) -> list[_Moment]:
    from graspframe.robot_model import CollisionModel

    T_world_root = _pose(scene.T_world_root, "scene T_world_root")
    solid_object: Solid | Surface
    if scene.object_mesh is not None:
        mesh = scene.object_mesh
        solid_object = Surface(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces))
    else:
        solid_object = object_solid(scene.object_shape, scene.object_dimensions)
    checked = [
        (s, _pose(s.T_world_object, f"snapshot {s.label!r}: T_world_object"), _contacts(s))
        for s in snapshots
    ]
    try:
        model = CollisionModel(scene.urdf_path)
    except GraspframeError as exc:
        raise InputError(f"snapshots: {exc}") from None
    if not model.model.existFrame(scene.palm_frame):
        raise InputError(f"palm frame {scene.palm_frame!r} is not in {Path(scene.urdf_path).name}")
    local = [(link, geometry, solid_of_geometry(geometry)) for link, geometry, _ in model.shapes()]
    moments = []
    for snapshot, T_world_object, contacts in checked:
        q = dict(snapshot.q_by_joint)
        if scene.joint_followers is not None:
            q = scene.joint_followers(q)
        try:
            model.place(q)
            T_root_palm = model.T_root_frame(scene.palm_frame)
        except GraspframeError as exc:
            raise InputError(f"snapshot {snapshot.label!r}: {exc}") from None
        T_world_palm = T_world_root @ T_root_palm
        placed = [
            (link, solid.moved(T_world_root @ T_root_shape))
            for (link, _, solid), (_, _, T_root_shape) in zip(local, model.shapes(), strict=True)
            if solid is not None
        ]
        p_world_palm = T_world_palm[:3, 3]
        near_arm_links = {
            link
            for link, solid in placed
            if link not in scene.finger_of_link and solid.distance_to(p_world_palm) <= NEAR_HAND
        }
        link_solids = [
            (link, solid)
            for link, solid in placed
            if link in scene.finger_of_link or link in near_arm_links
        ]
        moments.append(
            _Moment(
                snapshot, T_world_palm, link_solids, solid_object.moved(T_world_object), contacts
            )
        )
    return moments


def finger_colours(finger_of_link: Mapping[str, str]) -> dict[str, str]:
    """Real finger -> colour, in the order the fingers first appear; the palm is grey."""
    colours: dict[str, str] = {}
    for finger in finger_of_link.values():
        if finger not in colours and finger != PALM:
            colours[finger] = FINGER_COLOURS[len(colours) % len(FINGER_COLOURS)]
    colours[PALM] = PALM_COLOUR
    return colours


def _object_in_view(moment: _Moment) -> bool:
    """False when the object is far from the hand (knocked away, or fallen through the
    table after a simulation failure): the views then frame the hand alone."""
    p_world_object = np.asarray(moment.snapshot.T_world_object, dtype=float)[:3, 3]
    return float(np.linalg.norm(p_world_object - moment.T_world_palm[:3, 3])) <= FAR_OBJECT


def _limits(view: View, frames, scene: SnapshotScene, moments) -> tuple[float, float, float]:
    """(centre x, centre y, half width) [m], shared by the moments of one view: fits the
    object (when near the hand) and the hand links (and, in world views, the table top)
    with a margin."""
    outlines = []
    for (_, links, object_solid_view, _), moment in zip(frames, moments, strict=True):
        if _object_in_view(moment):
            if isinstance(object_solid_view, Surface):
                outlines.append(project_points(object_solid_view.vertices, view))
            else:
                outlines.append(project(object_solid_view, view)[0])
        outlines.extend(project(s, view)[0] for link, s in links if link in scene.finger_of_link)
    points = np.concatenate(outlines)
    low, high = points.min(axis=0), points.max(axis=0)
    if not view.in_palm_frame:
        low[1] = min(low[1], scene.table_height)
        high[1] = max(high[1], scene.table_height)
    centre = (low + high) / 2
    half = max(MIN_SPAN / 2, float((high - low).max()) / 2 + MARGIN)
    return float(centre[0]), float(centre[1]), half


def table_line(view: View, T_view_world, table_height: float):
    """(point, direction, towards-table normal) of the table top in picture coordinates,
    or None when the table plane is parallel to the picture plane (no line to draw)."""
    # Points p_view with p_world.z = table_height: n . p_view = d, n = world z in the view.
    T_world_view = inv_T(T_view_world)
    n_view, d = T_world_view[2, :3], table_height - T_world_view[2, 3]
    n_2d = n_view[[view.right, view.up]]  # in the picture plane (depth coordinate = 0)
    norm = float(np.linalg.norm(n_2d))
    if norm < 1e-6:
        return None
    point = n_2d * d / norm**2
    normal = n_2d / norm
    return point, np.array([-normal[1], normal[0]]), -normal


def _draw_panel(ax, view: View, frame, moment: _Moment, scene, colours, limits) -> None:
    from matplotlib.collections import PolyCollection
    from matplotlib.patches import Polygon
    from matplotlib.ticker import MaxNLocator

    T_view_world, links, object_view, contacts_view = frame
    cx, cy, half = limits
    far = 20 * half

    table = table_line(view, T_view_world, scene.table_height)
    if table is not None:
        point, direction, down = table
        a, b = point - far * direction, point + far * direction
        ax.add_patch(
            Polygon(
                [a, b, b + far * down, a + far * down],
                closed=True,
                facecolor=TABLE_FILL,
                edgecolor="none",
                zorder=0,
            )
        )
        ax.plot([a[0], b[0]], [a[1], b[1]], color=TABLE_COLOUR, linewidth=3, zorder=1)

    items: list = []  # (nearness, polygon, face colour, edge colour, edge width)
    for link, solid in links:
        polygon, nearness = project(solid, view)
        finger = scene.finger_of_link.get(link)
        colour = ARM_COLOUR if finger is None else colours.get(finger, PALM_COLOUR)
        items.append(((nearness, 0.0), polygon, colour, "#202020", 0.5))
    if isinstance(object_view, Surface):
        items.extend(_surface_items(object_view, view))
    else:
        polygon, nearness = project(object_view, view)
        items.append(((nearness, 0.0), polygon, OBJECT_COLOUR, OBJECT_EDGE, 1.2))
    items.sort(key=lambda item: item[0])  # far first: near shapes paint over them
    ax.add_collection(
        PolyCollection(
            [item[1] for item in items],
            facecolors=[item[2] for item in items],
            edgecolors=[item[3] for item in items],
            linewidths=[item[4] for item in items],
            alpha=0.9,
            zorder=2,
        ),
        autolim=False,
    )

    if len(contacts_view):
        xy = project_points(contacts_view, view)
        ax.scatter(
            xy[:, 0], xy[:, 1], s=36, c=CONTACT_COLOUR, edgecolors="black", linewidths=0.8, zorder=4
        )

    T_view_palm = T_view_world @ moment.T_world_palm
    origin = project_points(T_view_palm[:3, 3], view)[0]
    for axis, colour in ((2, PALM_Z_COLOUR), (0, PALM_X_COLOUR)):
        tip = project_points(T_view_palm[:3, 3] + ARROW_LENGTH * T_view_palm[:3, axis], view)[0]
        if np.linalg.norm(tip - origin) < 1e-3:  # pointing at the viewer: a dot says so
            ax.plot(*origin, marker="o", markersize=4, color=colour, zorder=5)
            continue
        ax.annotate(
            "",
            xy=tip,
            xytext=origin,
            zorder=5,
            arrowprops={
                "arrowstyle": "-|>",
                "color": colour,
                "linewidth": 2,
                "shrinkA": 0,
                "shrinkB": 0,
                "mutation_scale": 12,
            },
        )

    ax.set_xlim(cx - half, cx + half)
    ax.set_ylim(cy - half, cy + half)
    ax.set_aspect("equal", adjustable="box")
    # Few ticks: tick labels are most of the drawing time.
    ax.xaxis.set_major_locator(MaxNLocator(nbins=4))
    ax.yaxis.set_major_locator(MaxNLocator(nbins=4))
    ax.tick_params(labelsize=8)
    ax.grid(True, linewidth=0.3, color="#bbbbbb", zorder=-1)


def _surface_items(surface: Surface, view: View) -> list:
    """Painter items of a surface's triangles that face the viewer: at the surface's
    nearness among the other shapes, far to near among themselves, shaded."""
    from matplotlib.colors import to_rgb

    towards_viewer = np.asarray(view.towards_viewer, dtype=float)
    triangles = surface.vertices[surface.faces]  # (m, 3, 3)
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    facing = normals @ towards_viewer
    keep = (lengths > 0) & (facing > 0)
    if not keep.any():
        return []
    nearness = float((surface.vertices @ towards_viewer).mean())
    depth = triangles[keep].mean(axis=1) @ towards_viewer
    light = 0.55 + 0.45 * facing[keep] / lengths[keep]
    base = np.array(to_rgb(OBJECT_COLOUR))
    polygons = triangles[keep][:, :, [view.right, view.up]]
    # Each triangle edged in its own colour: no seams between neighbours.
    return [
        ((nearness, float(d)), polygon, tuple(base * shade), tuple(base * shade), 0.3)
        for d, polygon, shade in zip(depth, polygons, light, strict=True)
    ]


def _legend_layout(n_columns: int, n_fingers: int) -> tuple[int, float]:
    """(legend columns, height [in] of the legend band) for n_fingers (palm included)."""
    width = LEFT_INCH + PANEL_INCH * n_columns + RIGHT_INCH
    n_entries = n_fingers + LEGEND_FIXED_ENTRIES
    n_legend_columns = max(1, min(n_entries, int(width // LEGEND_ENTRY_INCH)))
    rows = -(-n_entries // n_legend_columns)
    return n_legend_columns, LEGEND_ROW_INCH * rows + 0.15


def figure_size(n_columns: int, n_fingers: int) -> tuple[float, float]:
    """(width, height) [in] of the figure for n_columns moments and n_fingers real fingers
    (palm included, they make the legend); times DPI gives pixels."""
    width = LEFT_INCH + PANEL_INCH * n_columns + RIGHT_INCH
    legend_inch = _legend_layout(n_columns, n_fingers)[1]
    return width, TITLE_INCH + PANEL_INCH * len(VIEWS) + XLABEL_INCH + legend_inch


def _contact_summary(snapshot: Snapshot) -> str:
    if not len(snapshot.contact_fingers):
        return "no contacts"
    counts: dict[str, int] = {}
    for finger in snapshot.contact_fingers:
        counts[finger] = counts.get(finger, 0) + 1
    listing = ", ".join(f"{finger} {n}" for finger, n in counts.items())
    total = len(snapshot.contact_fingers)
    return f"{total} contact{'s' if total != 1 else ''}: {listing}"


def draw_snapshots(
    path: Path, scene: SnapshotScene, snapshots: Sequence[Snapshot], title: str
) -> Path:
    """Draw the snapshots (one column each) in the three views (rows) to the PNG `path`,
    atomically; returns `path`. InputError (one line) for unusable input."""
    from matplotlib.artist import Artist
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    path = Path(path)
    if not snapshots:
        raise InputError("no snapshots to draw")
    moments = _place_moments(scene, snapshots)
    colours = finger_colours(scene.finger_of_link)

    width, height = figure_size(len(moments), len(colours))
    n_legend_columns, legend_inch = _legend_layout(len(moments), len(colours))
    fig = Figure(figsize=(width, height), dpi=DPI)
    fig.subplots_adjust(
        left=LEFT_INCH / width,
        right=1 - RIGHT_INCH / width,
        top=1 - TITLE_INCH / height,
        bottom=(legend_inch + XLABEL_INCH) / height,
        wspace=0.25,
        hspace=0.3,
    )
    axes = fig.subplots(len(VIEWS), len(moments), squeeze=False)
    for row, view in enumerate(VIEWS):
        frames = [moment.in_view_frame(view) for moment in moments]
        limits = _limits(view, frames, scene, moments)
        for column, (moment, frame) in enumerate(zip(moments, frames, strict=True)):
            ax = axes[row][column]
            _draw_panel(ax, view, frame, moment, scene, colours, limits)
            ax.set_xlabel(view.xlabel, fontsize=8, labelpad=1)
            if column == 0:
                ax.set_ylabel(f"{view.name} view\n{view.ylabel}", fontsize=9)
            else:  # same limits along the row: the first column's labels read for all
                ax.tick_params(labelleft=False)
            if row == 0:
                label = moment.snapshot.label
                if not _object_in_view(moment):
                    label += " (object out of view)"
                ax.set_title(f"{label}\n{_contact_summary(moment.snapshot)}", fontsize=10)

    fig.suptitle(title, fontsize=12, wrap=True, y=1 - 0.1 / height, va="top")
    handles: list[Artist] = [
        Patch(facecolor=c, edgecolor="#202020", label=f) for f, c in colours.items()
    ]
    handles += [
        Patch(facecolor=ARM_COLOUR, edgecolor="#202020", label="arm"),
        Patch(facecolor=OBJECT_COLOUR, edgecolor=OBJECT_EDGE, label="object"),
        Line2D([], [], color=TABLE_COLOUR, linewidth=3, label="table top"),
        Line2D(
            [],
            [],
            marker="o",
            linestyle="none",
            markerfacecolor=CONTACT_COLOUR,
            markeredgecolor="black",
            label="contact",
        ),
        Line2D([], [], color=PALM_Z_COLOUR, linewidth=2, label="palm +z"),
        Line2D([], [], color=PALM_X_COLOUR, linewidth=2, label="palm +x"),
    ]
    assert len(handles) == len(colours) + LEGEND_FIXED_ENTRIES
    fig.legend(
        handles=handles, loc="lower center", ncol=n_legend_columns, fontsize=9, frameon=False
    )

    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_output(path) as stream:
        fig.savefig(stream, format="png", dpi=DPI, metadata={"Software": None})
    return path
