"""A hand spec drafted from a URDF: what the model's tree and collision geometry decide.

`draft_hand(urdf)` reads the model and finds, with no value typed by hand:

- the palm: the link where the chains of moving joints split (the lowest common
  ancestor of every leaf below a moving joint); the palm real finger is it and every
  link rigidly attached to it, with the links above it (a wrist, a forearm);
- the fingers: one per chain of moving joints hanging from the palm, root to tip;
- each joint's closing sign: a revolute joint closes towards the larger side of its
  range (a finger bends further towards the palm than away), a prismatic one towards
  the other fingertips; its role: it curls the finger (axis parallel to the finger's
  last joint: flexion), or it places it (spread, thumb rotation);
- the fingertip frames: a collision-free link at the end of the chain (the vendor's tip
  frame), else a frame added at the far point of the last link's collision shapes;
- the thumb: the finger whose tip, closing, moves most against the others' tips (over
  the values of its placing joints); none when no finger opposes the others;
- the palm frame: +z the direction the fingers close towards (the mean closing motion
  of the fingertips other than the thumb; the fingers' direction for a gripper whose
  fingers close against each other), +x along the fingers, the origin on the palm's
  collision surface below the finger roots' centroid; the palm pad: the palm surface
  within 3 mm of that height, 5 mm in from its edges;
- the drive: the force limit from the URDF's largest effort, a stiffness reaching it
  at 0.1 rad of tracking error, damping 3 % of the stiffness (s), the joints' speed
  the URDF's velocity limit up to 2 rad/s (our choice, as for the vendor hands).

What it cannot decide (no effort in the URDF, no finger that opposes the others, joints
above the palm) it writes as a named key with a comment and lists in `notes`.
`write_spec` writes the spec file; the preshapes come from the synthesis
(graspframe/mapping/synthesis.py) or, with none, a generic wrap that closes every
finger to its flexion limit.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.model_files.urdf_model import ModelFile, UrdfModel, load_model_file

MOVING = ("revolute", "prismatic", "continuous")
PARALLEL_AXES = 0.8  # |cos| above which two joint axes count as parallel
PALM_SURFACE_LAYER = 0.003  # [m] palm points this close to the palm height form its pad
PAD_MARGIN = 0.005  # [m] the pad stays this far inside the palm surface's outline
MIN_PAD_SIDE = 0.01  # [m]
TRACKING_ERROR_AT_FORCE_LIMIT = 0.1  # [rad] the stiffness reaches the force limit here
DAMPING_RATIO = 0.03  # [s] damping / stiffness
MAX_JOINT_SPEED = 2.0  # [rad/s] (or m/s) the controller's, when the URDF's is faster
GENERIC_OPENING = 0.2  # the generic wrap opens this part of the way to closed
DEFAULT_FORCE_LIMIT = 1.0  # [N m] written (and named) when the URDF gives no effort


@dataclass(frozen=True)
class Joint:
    """A URDF joint as the draft reads it: limits [rad or m], axis in its own frame."""

    name: str
    kind: str
    parent: str
    child: str
    lower: float
    upper: float
    effort: float
    velocity: float
    mimic: str | None

    @property
    def moving(self) -> bool:
        return self.kind in MOVING

    @property
    def rest(self) -> float:
        """The value nearest 0 within the limits (the extended finger, in every URDF
        seen: the vendors model the flat hand at 0)."""
        return min(max(0.0, self.lower), self.upper)


@dataclass
class DraftFinger:
    """A finger found in the model: its links (root to tip), its moving joints (root to
    tip, <mimic> followers included), the joints that curl it and those that place it,
    each joint's closing sign, its tip frame and whether that frame is added."""

    name: str
    links: list[str]
    joints: list[str]
    flexion: list[str]
    placing: list[str]
    closing_sign: dict[str, float]
    tip_frame: str
    tip_offset: tuple[str, NDArray[np.float64]] | None = None  # (parent link, xyz [m])


@dataclass
class HandDraft:
    """Everything the draft decided, and what it could not (`notes`: one line each,
    naming the spec key to check)."""

    name: str
    urdf: str
    model: UrdfModel
    root_link: str
    palm_link: str
    palm_links: list[str]
    fingers: dict[str, DraftFinger]
    thumb: str | None
    joints: dict[str, Joint]
    T_palmlink_palm: NDArray[np.float64]  # the palm frame in the palm link's frame
    pad_centre: NDArray[np.float64]  # [m] in the palm frame
    pad_size: NDArray[np.float64]  # [m]
    mass: float
    force_limit: float
    max_velocity: float
    has_efforts: bool = True  # the URDF gives the driven joints' efforts
    held_at_rest: list[str] = field(default_factory=list)  # joints above the palm
    notes: list[str] = field(default_factory=list)

    @property
    def palm_frame(self) -> str:
        return f"{self.name}_palm"

    @property
    def pad_frame(self) -> str:
        return f"{self.name}_palm_pad"

    def driven(self) -> list[str]:
        """The driven joints (not <mimic> followers), in file order."""
        return [j.name for j in self.joints.values() if j.moving and j.mimic is None]

    def rest_q(self) -> dict[str, float]:
        return {name: self.joints[name].rest for name in self.driven()}

    def closed_flexion(self, fingers: Sequence[str] | None = None) -> dict[str, float]:
        """The curling joints (not followers) of `fingers` (default: all) at the limit
        that closes them."""
        closed = {}
        for finger in self.fingers.values():
            if fingers is not None and finger.name not in fingers:
                continue
            for name in finger.flexion:
                joint = self.joints[name]
                if joint.mimic is None and name not in self.held_at_rest:
                    closed[name] = joint.upper if finger.closing_sign[name] > 0 else joint.lower
        return closed


def _read_joints(model: UrdfModel) -> dict[str, Joint]:
    joints = {}
    for element in model.root().findall("joint"):
        parent, child = element.find("parent"), element.find("child")
        if parent is None or child is None:
            continue
        kind = element.get("type", "fixed")
        limit = element.find("limit")
        values = {} if limit is None else limit.attrib
        mimic = element.find("mimic")
        lower = float(values.get("lower", -math.pi if kind == "continuous" else 0.0))
        upper = float(values.get("upper", math.pi if kind == "continuous" else 0.0))
        name = element.get("name", "")
        joints[name] = Joint(
            name, kind, parent.get("link", ""), child.get("link", ""), lower, upper,
            float(values.get("effort", 0.0)), float(values.get("velocity", 0.0)),
            None if mimic is None else mimic.get("joint"),
        )  # fmt: skip
    return joints


def _mass(model: UrdfModel) -> float:
    total = 0.0
    for link in model.root().findall("link"):
        mass = link.find("inertial/mass")
        if mass is not None:
            total += float(mass.get("value", 0.0))
    return total


def _token(names: Sequence[str]) -> str:
    """A finger's name from its links' common prefix ("ff" of ffknuckle, ffproximal),
    "" when they share none worth the name."""
    prefix = names[0]
    for name in names[1:]:
        while not name.startswith(prefix):
            prefix = prefix[:-1]
    prefix = re.sub(r"[^a-z0-9]+$", "", prefix.lower())
    prefix = re.sub(r"[^a-z0-9_]", "_", prefix)
    return prefix if len(prefix) >= 2 and not prefix[0].isdigit() else ""


class _Kinematics:
    """Forward kinematics of the model (Pinocchio), every joint set by name, positions
    in the palm link's frame."""

    def __init__(self, model: UrdfModel, palm_link: str):
        from graspframe.robot_models.model import CollisionModel

        self.collision = CollisionModel(model)
        self.palm_link = palm_link

    def place(self, q: Mapping[str, float]) -> None:
        self.q = dict(q)
        self.collision.place(self.q)

    def collision_q(self) -> dict[str, float]:
        """The joint values last placed."""
        return dict(self.q)

    def T(self, frame: str) -> NDArray[np.float64]:
        """The frame's pose in the palm link's frame."""
        T_root_palm = self.collision.T_root_frame(self.palm_link)
        return np.linalg.inv(T_root_palm) @ self.collision.T_root_frame(frame)

    def joint_axis_origin(
        self, joint: Joint, axis_local: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(unit axis, origin) of a joint in the palm link's frame: its child link's
        frame carries the joint's axis."""
        T = self.T(joint.child)
        return T[:3, :3] @ axis_local, T[:3, 3]

    def link_points(self, links: Sequence[str]) -> NDArray[np.float64]:
        """(N, 3) the collision shapes' points of `links`, in the palm link's frame."""
        from graspframe.robot_models.shapes import shape_points

        T_palm_root = np.linalg.inv(self.collision.T_root_frame(self.palm_link))
        wanted = set(links)
        points = [
            shape_points(shape, T_palm_root @ T_root_shape)
            for link, shape, T_root_shape in self.collision.shapes()
            if link in wanted
        ]
        return np.vstack(points) if points else np.zeros((0, 3))


def _axes(model: UrdfModel) -> dict[str, NDArray[np.float64]]:
    axes = {}
    for element in model.root().findall("joint"):
        axis = element.find("axis")
        xyz = (
            [1.0, 0.0, 0.0]
            if axis is None
            else [float(v) for v in axis.get("xyz", "1 0 0").split()]
        )
        vector = np.asarray(xyz, dtype=float)
        axes[element.get("name", "")] = vector / max(np.linalg.norm(vector), 1e-12)
    return axes


def draft_hand(urdf: Path | str, name: str | None = None) -> HandDraft:
    """Read the URDF and decide everything its tree and geometry determine (see the
    module docstring); a DescriptionError when it holds no hand (no moving chain)."""
    path = Path(urdf)
    model = load_model_file(ModelFile(path))
    joints = _read_joints(model)
    children: dict[str, list[Joint]] = {}
    parent_joint: dict[str, Joint] = {}
    for joint in joints.values():
        children.setdefault(joint.parent, []).append(joint)
        parent_joint[joint.child] = joint
    links = [e.get("name", "") for e in model.root().findall("link")]
    roots = [link for link in links if link not in parent_joint]
    if len(roots) != 1:
        raise DescriptionError(f"{path.name}: expected one root link, found {roots}")
    root = roots[0]

    def path_to(link: str) -> list[str]:
        chain = [link]
        while chain[-1] in parent_joint:
            chain.append(parent_joint[chain[-1]].parent)
        return chain[::-1]

    def moving_on_path(link: str) -> bool:
        chain = path_to(link)
        return any(parent_joint[c].moving for c in chain[1:])

    leaves = [link for link in links if not children.get(link) and moving_on_path(link)]
    if not leaves:
        raise DescriptionError(f"{path.name}: no moving joint, so no finger to draft")
    # The palm: where the chains of moving joints split.
    paths = [path_to(leaf) for leaf in leaves]
    palm_link = root
    for depth in range(min(len(p) for p in paths)):
        if len({p[depth] for p in paths}) == 1:
            palm_link = paths[0][depth]
        else:
            break
    robot_name = name or _spec_name(model.name or path.stem)
    draft_notes: list[str] = []
    above = path_to(palm_link)[:-1]
    held_at_rest = [parent_joint[c].name for c in path_to(palm_link)[1:] if parent_joint[c].moving]
    if held_at_rest:
        draft_notes.append(
            f"joints above the palm ({', '.join(held_at_rest)}: a wrist) are held at their "
            "rest value in every preshape; their links count as the palm"
        )

    # Palm links: the palm link, the links rigidly attached below it, and those above.
    palm_links = [palm_link]
    stack = [palm_link]
    while stack:
        for joint in children.get(stack.pop(), []):
            if not joint.moving:
                palm_links.append(joint.child)
                stack.append(joint.child)
    palm_links = [*above, *palm_links]

    kin = _Kinematics(model, palm_link)
    axes = _axes(model)
    rest = {j.name: j.rest for j in joints.values() if j.moving}
    kin.place(rest)

    # Fingers: one per moving joint hanging from the palm's rigid body.
    rigid = set(palm_links)
    finger_roots = [
        j for link in palm_links for j in children.get(link, [])
        if j.moving and j.child not in rigid
    ]  # fmt: skip
    fingers: dict[str, DraftFinger] = {}
    for number, first in enumerate(finger_roots, start=1):
        finger_links, finger_joints = [first.child], [first.name]
        tip_link = first.child
        stack = [first.child]
        while stack:
            link = stack.pop()
            for joint in children.get(link, []):
                finger_links.append(joint.child)
                if joint.moving:
                    finger_joints.append(joint.name)
                stack.append(joint.child)
        # The tip: the end of the longest chain below the first joint.
        depth = {link: len(path_to(link)) for link in finger_links}
        tip_link = max(finger_links, key=lambda link: (depth[link], link))
        token = _token(finger_links)
        fingers[f"f{number}"] = DraftFinger(
            name=token or f"finger_{number}",
            links=finger_links,
            joints=finger_joints,
            flexion=[],
            placing=[],
            closing_sign={},
            tip_frame=tip_link,
        )
    names = [f.name for f in fingers.values()]
    if len(set(names)) != len(names):  # prefixes collide: number them
        for number, finger in enumerate(fingers.values(), start=1):
            finger.name = f"finger_{number}"
    fingers = {f.name: f for f in fingers.values()}

    shapes_of = {link for link, _shape, _T in kin.collision.shapes()}
    for finger in fingers.values():
        _tip_frame(finger, kin, shapes_of, parent_joint, path_to, joints)
        _joint_roles(finger, joints, kin, axes)
    _closing_signs(fingers, joints, kin, axes)
    thumb, thumb_note = _thumb(fingers, joints, kin, axes, rest)
    if thumb is not None:
        finger = fingers.pop(thumb)
        finger.name = "thumb"
        fingers["thumb"] = finger
        thumb = "thumb"
    if thumb_note:
        draft_notes.append(thumb_note)
    T_palmlink_palm, pad_centre, pad_size = _palm_frame(
        fingers, thumb, joints, kin, axes, rest, [link for link in palm_links if link not in above]
    )
    driven = [
        j for j in joints.values() if j.moving and j.mimic is None and j.name not in held_at_rest
    ]
    efforts = [j.effort for j in driven if j.effort > 0]
    if efforts:
        force_limit = max(efforts)
    else:
        force_limit = DEFAULT_FORCE_LIMIT
        draft_notes.append(
            f"[drive] force_limit and [joints] max_effort: {path.name} gives no joint "
            f"effort; {DEFAULT_FORCE_LIMIT:g} N m was written, set the hand's own"
        )
    velocities = [j.velocity for j in driven if j.velocity > 0]
    max_velocity = min([MAX_JOINT_SPEED, *velocities])
    return HandDraft(
        name=robot_name,
        urdf=str(urdf),
        model=model,
        root_link=root,
        palm_link=palm_link,
        palm_links=palm_links,
        fingers=fingers,
        thumb=thumb,
        joints=joints,
        T_palmlink_palm=T_palmlink_palm,
        pad_centre=pad_centre,
        pad_size=pad_size,
        mass=_mass(model),
        force_limit=force_limit,
        max_velocity=max_velocity,
        has_efforts=bool(efforts),
        held_at_rest=held_at_rest,
        notes=draft_notes,
    )


def _spec_name(text: str) -> str:
    name = re.sub(r"[^a-z0-9_]+", "_", text.lower()).strip("_")
    return name or "hand"


def _tip_frame(finger, kin, shapes_of, parent_joint, path_to, joints) -> None:
    """The finger's tip: the vendor's collision-free tip link, else a frame at the far
    point of the last link with shapes (farthest from the finger's first joint)."""
    tip = finger.tip_frame
    if tip not in shapes_of and parent_joint[tip].kind == "fixed":
        return
    chain = [link for link in path_to(tip) if link in finger.links and link in shapes_of]
    last = chain[-1] if chain else tip
    first = joints[finger.joints[0]]
    root = kin.T(first.child)[:3, 3]
    points = kin.link_points([last])
    if len(points) == 0:
        return
    far = points[int(np.argmax(np.linalg.norm(points - root, axis=1)))]
    T_last = kin.T(last)
    xyz = (np.linalg.inv(T_last) @ np.append(far, 1.0))[:3]
    finger.tip_frame = f"{finger.name}_tip"
    finger.tip_offset = (last, xyz)


def _tip_position(finger: DraftFinger, kin: _Kinematics) -> NDArray[np.float64]:
    if finger.tip_offset is None:
        return kin.T(finger.tip_frame)[:3, 3]
    link, xyz = finger.tip_offset
    return (kin.T(link) @ np.append(xyz, 1.0))[:3]


def _joint_roles(finger: DraftFinger, joints, kin: _Kinematics, axes) -> None:
    """Flexion: the moving joints whose axis (in the palm link's frame) is parallel to
    the finger's last joint's; placing: the others. Prismatic joints close the finger."""
    moving = [joints[name] for name in finger.joints]
    last = moving[-1]
    if last.kind == "prismatic":
        finger.flexion = [j.name for j in moving if j.kind == "prismatic"]
        finger.placing = [j.name for j in moving if j.kind != "prismatic"]
        return
    last_axis, _ = kin.joint_axis_origin(last, axes[last.name])
    for joint in moving:
        axis, _ = kin.joint_axis_origin(joint, axes[joint.name])
        parallel = abs(float(axis @ last_axis)) >= PARALLEL_AXES
        (finger.flexion if parallel else finger.placing).append(joint.name)


def _tip_motion(
    finger: DraftFinger, joints, kin: _Kinematics, axes, name: str
) -> NDArray[np.float64]:
    """d(tip)/dq of joint `name` [m/rad or m/m] in the palm link's frame, now."""
    joint = joints[name]
    axis, origin = kin.joint_axis_origin(joint, axes[name])
    if joint.kind == "prismatic":
        return axis
    return np.cross(axis, _tip_position(finger, kin) - origin)


def _closing_signs(fingers: Mapping[str, DraftFinger], joints, kin: _Kinematics, axes) -> None:
    """Each joint's closing sign: a revolute joint bends further towards the palm than
    away (the larger side of its range); a prismatic one moves its tip towards the
    other fingertips."""
    tips = {name: _tip_position(f, kin) for name, f in fingers.items()}
    for name, finger in fingers.items():
        for joint_name in finger.joints:
            joint = joints[joint_name]
            if joint.kind == "prismatic":
                others = [tips[n] for n in fingers if n != name]
                target = np.mean(others, axis=0) if others else np.zeros(3)
                motion = _tip_motion(finger, joints, kin, axes, joint_name)
                sign = 1.0 if float(motion @ (target - tips[name])) >= 0 else -1.0
            else:
                sign = 1.0 if abs(joint.upper) >= abs(joint.lower) else -1.0
            finger.closing_sign[joint_name] = sign


def closing_direction(finger: DraftFinger, joints, kin: _Kinematics, axes) -> NDArray[np.float64]:
    """The unit direction the fingertip moves as its flexion joints close, now."""
    motion = sum(
        finger.closing_sign[name] * _tip_motion(finger, joints, kin, axes, name)
        for name in finger.flexion
        if joints[name].mimic is None
    )
    motion = np.asarray(motion, dtype=float)
    return motion / max(np.linalg.norm(motion), 1e-12)


def placing_grid(finger: DraftFinger, joints, count: int = 3) -> list[dict[str, float]]:
    """Values of the finger's placing joints to try: `count` across the range (lower,
    middle, upper for 3) of each of the two with the largest range (not followers)."""
    grid: list[dict[str, float]] = [{}]
    # the two placing joints of the largest range (a thumb's rotation and abduction)
    placing = [n for n in finger.placing if joints[n].mimic is None]
    placing = sorted(placing, key=lambda n: joints[n].lower - joints[n].upper)[:2]
    for name in placing:
        joint = joints[name]
        values = np.linspace(joint.lower, joint.upper, count)
        grid = [{**g, name: float(v)} for g in grid for v in values]
    return grid


def _thumb(fingers, joints, kin: _Kinematics, axes, rest) -> tuple[str | None, str | None]:
    """The finger whose tip closes most against the others' (over its placing joints'
    values), and a note when that is not clear."""
    if len(fingers) < 2:
        return None, "one finger only: no thumb (every grasp closes it against the palm)"
    # Half closed, the fingers of a flat hand curl towards the thumb, and it towards them.
    half = dict(rest)
    for finger in fingers.values():
        for name in finger.flexion:
            joint = joints[name]
            closed = joint.upper if finger.closing_sign[name] > 0 else joint.lower
            half[name] = 0.5 * (joint.rest + closed)
    directions = {}
    kin.place(half)
    for name, finger in fingers.items():
        directions[name] = closing_direction(finger, joints, kin, axes)
    scores = {}
    for name, finger in fingers.items():
        others = [directions[n] for n in fingers if n != name]
        mean_others = np.mean(others, axis=0)
        best = math.inf
        for values in placing_grid(finger, joints):
            kin.place({**half, **values})
            best = min(best, float(closing_direction(finger, joints, kin, axes) @ mean_others))
        scores[name] = best
    kin.place(rest)
    thumb = min(scores, key=lambda n: (scores[n], n))
    if scores[thumb] >= 0.0:
        return None, (
            "[fingers]: no finger closes against the others (no thumb); grasps close every "
            "finger towards the palm"
        )
    ranked = sorted(scores.values())
    if len(fingers) == 2 or (len(ranked) > 1 and ranked[1] - ranked[0] < 0.05):
        return thumb, (
            f"[fingers] thumb: {len(fingers)} fingers close against each other as much; "
            f"{fingers[thumb].name} was taken as the thumb"
        )
    return thumb, None


def _palm_frame(fingers, thumb, joints, kin: _Kinematics, axes, rest, palm_links):
    """(T_palmlink_palm, pad centre [m] in the palm frame, pad size [m])."""
    kin.place(rest)
    others = [f for n, f in fingers.items() if n != thumb] or list(fingers.values())
    closing = np.mean([closing_direction(f, joints, kin, axes) for f in others], axis=0)
    roots = np.array([kin.T(joints[f.joints[0]].child)[:3, 3] for f in fingers.values()])
    tips = np.array([_tip_position(f, kin) for f in others])
    along = np.mean(
        tips - np.array([kin.T(joints[f.joints[0]].child)[:3, 3] for f in others]), axis=0
    )
    every = np.mean([closing_direction(f, joints, kin, axes) for f in fingers.values()], axis=0)
    if np.linalg.norm(every) < 0.3:  # the fingers close against each other: a gripper
        z = along / max(np.linalg.norm(along), 1e-12)
        x_guess = tips[0] - roots.mean(axis=0)
    else:
        # The normal of the plane the extended fingers' curling joints lie in,
        # turned the way they close; the thumb's points join when the others are a line.
        def chain_points(chosen):
            return np.array(
                [kin.T(joints[j].child)[:3, 3] for f in chosen for j in f.flexion]
            ).reshape(-1, 3)

        points = chain_points(others)
        spread = np.linalg.svd(points - points.mean(axis=0), compute_uv=False)
        if len(points) < 3 or spread[1] < 0.1 * spread[0]:
            points = chain_points(list(fingers.values()))
        normal = np.linalg.svd(points - points.mean(axis=0))[2][2]
        z = normal if float(normal @ closing) >= 0 else -normal
        x_guess = along
    x = x_guess - (x_guess @ z) * z
    if np.linalg.norm(x) < 1e-6:
        x = np.cross(z, [1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.cross(z, [0.0, 1.0, 0.0])
    x = x / np.linalg.norm(x)
    y = np.cross(z, x)
    R = np.column_stack([x, y, z])
    points = kin.link_points(palm_links)
    centre = roots.mean(axis=0)
    if len(points):
        local = (points - centre) @ R
        near = local[np.hypot(local[:, 0], local[:, 1]) <= max(0.03, np.ptp(local[:, 0]) / 2)]
        height = float(near[:, 2].max()) if len(near) else float(local[:, 2].max())
        # the origin: the middle of the palm surface (its points within 3 mm of the
        # height), on it
        layer = local[local[:, 2] >= height - PALM_SURFACE_LAYER]
        lo, hi = layer[:, :2].min(axis=0) + PAD_MARGIN, layer[:, :2].max(axis=0) - PAD_MARGIN
        size = np.maximum(hi - lo, MIN_PAD_SIDE)
        middle = (layer[:, :2].min(axis=0) + layer[:, :2].max(axis=0)) / 2
        middle = _solid_below(
            kin, palm_links, centre, R, height, middle, local[:, :2].min(axis=0),
            local[:, :2].max(axis=0),
        )  # fmt: skip
        lo, hi = _clear_of_fingers(kin, fingers, joints, centre, R, height, middle, lo, hi)
        size = np.maximum(hi - lo, MIN_PAD_SIDE)
        origin = centre + R @ np.array([middle[0], middle[1], height])
        pad_centre = np.array(
            [(lo[0] + hi[0]) / 2 - middle[0], (lo[1] + hi[1]) / 2 - middle[1], 0.0]
        )
    else:
        origin, size, pad_centre = centre, np.array([0.04, 0.04]), np.zeros(3)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, origin
    return T, pad_centre, np.array([size[0], size[1], 0.002])


PROBE_DEPTH = 0.0105  # [m] the palm must be solid this far below its frame's origin
PROBE_STEP = 0.003  # [m] the grid of origins tried
PAD_CLEARANCE = 0.002  # [m] finger shapes stay this far from the pad
CURL_FRACTIONS = (0.0, 0.25, 0.5, 1.0)


class _Solids:
    """The collision shapes of some links as convex hulls (half-space equations), in the
    palm link's frame: which points lie inside, and surface samples."""

    def __init__(self, kin: _Kinematics, links: Sequence[str]):
        from scipy.spatial import ConvexHull

        from graspframe.robot_models.shapes import geometry_mesh

        T_palm_root = np.linalg.inv(kin.collision.T_root_frame(kin.palm_link))
        wanted = set(links)
        self.equations, samples = [], []
        for link, shape, T_root_shape in kin.collision.shapes():
            if link not in wanted:
                continue
            mesh = geometry_mesh(shape)
            if mesh is None:
                continue
            T = T_palm_root @ T_root_shape
            vertices = np.asarray(mesh.vertices) @ T[:3, :3].T + T[:3, 3]
            try:
                self.equations.append(ConvexHull(vertices).equations)
            except Exception:  # a flat piece: no volume to be inside
                pass
            mesh.apply_transform(T)
            samples.append(vertices)
            samples.append(np.asarray(mesh.sample(400, seed=0)))
        self.samples = np.vstack(samples) if samples else np.zeros((0, 3))

    def inside(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        hit = np.zeros(len(points), dtype=bool)
        for eq in self.equations:
            hit |= np.all(points @ eq[:, :3].T + eq[:, 3] <= 1e-9, axis=1)
        return hit


def _solid_below(kin, palm_links, centre, R, height, middle, lo, hi):
    """The in-plane point nearest `middle` (palm-frame x, y [m]) of the palm surface
    below which the palm is solid to PROBE_DEPTH (the palm frame's contract)."""
    solids = _Solids(kin, palm_links)
    xs = np.arange(lo[0], hi[0] + 1e-9, PROBE_STEP)
    ys = np.arange(lo[1], hi[1] + 1e-9, PROBE_STEP)
    grid = np.array([(x, y) for x in xs for y in ys]).reshape(-1, 2)
    below = np.column_stack([grid, np.full(len(grid), height - PROBE_DEPTH)])
    above = np.column_stack([grid, np.full(len(grid), height + 0.001)])
    solid = solids.inside(centre + below @ R.T) & ~solids.inside(centre + above @ R.T)
    if not solid.any():
        return middle
    chosen = grid[solid]
    return chosen[int(np.argmin(np.linalg.norm(chosen - middle, axis=1)))]


def _clear_of_fingers(kin, fingers, joints, centre, R, height, middle, lo, hi):
    """The pad's (lo, hi) corners (palm-frame x, y [m]) cut back, edge by edge, until
    no finger shape, at rest or curled (CURL_FRACTIONS of the way closed), comes within PAD_CLEARANCE of it (the pad is 2 mm thick on
    the palm surface); the pad keeps `middle` inside."""
    finger_links = [link for f in fingers.values() for link in f.links]
    rest = {j: v for j, v in kin.collision_q().items()}
    closed = dict(rest)
    for finger in fingers.values():
        for name in finger.flexion:
            joint = joints[name]
            closed[name] = joint.upper if finger.closing_sign[name] > 0 else joint.lower
    samples = []
    for t in CURL_FRACTIONS:  # the fingers as they curl: their knuckles turn near the pad
        kin.place({j: rest[j] + t * (closed[j] - rest[j]) for j in rest})
        samples.append(_Solids(kin, finger_links).samples)
    kin.place(rest)
    points = (np.vstack(samples) - centre) @ R
    near = points[np.abs(points[:, 2] - height) <= 0.001 + PAD_CLEARANCE]
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    while True:
        inside = near[
            np.all(near[:, :2] >= lo - PAD_CLEARANCE, axis=1)
            & np.all(near[:, :2] <= hi + PAD_CLEARANCE, axis=1)
        ]
        if len(inside) == 0 or np.any(hi - lo <= MIN_PAD_SIDE):
            break
        p = inside[0, :2]
        # move the edge that loses the least pad past the point, keeping the middle in
        cuts = []
        for axis in (0, 1):
            if p[axis] >= middle[axis]:
                cuts.append((hi[axis] - (p[axis] - PAD_CLEARANCE), axis, True))
            else:
                cuts.append(((p[axis] + PAD_CLEARANCE) - lo[axis], axis, False))
        before = (lo.copy(), hi.copy())
        for _, axis, upper in sorted(cuts):
            if upper:
                hi[axis] = max(middle[axis] + MIN_PAD_SIDE / 2, p[axis] - PAD_CLEARANCE - 1e-4)
            else:
                lo[axis] = min(middle[axis] - MIN_PAD_SIDE / 2, p[axis] + PAD_CLEARANCE + 1e-4)
            if not (np.array_equal(lo, before[0]) and np.array_equal(hi, before[1])):
                break
        else:
            break  # the point lies over the middle itself: the pad cannot clear it
    return lo, hi


# -- writing the spec ---------------------------------------------------------------------


def _rpy_deg(R: NDArray[np.float64]) -> list[float]:
    from scipy.spatial.transform import Rotation

    return [round(v, 4) for v in Rotation.from_matrix(R).as_euler("xyz", degrees=True)]


def _vector(values: Sequence[float], digits: int = 5) -> str:
    return "[" + ", ".join(f"{round(float(v), digits):g}" for v in values) + "]"


def _key(name: str) -> str:
    return name if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_-]*", name) else f'"{name}"'


def spec_text(draft: HandDraft, preshape_tables: str, grasp_map: Mapping[str, str]) -> str:
    """The spec file's text: the drafted keys, then the preshape tables and grasp map."""
    lines = [
        f"# {draft.name}: a hand spec drafted by `graspframe spec draft` from {Path(draft.urdf).name}.",
        "# Every value below comes from the URDF's tree and collision geometry, except where",
        "# a comment says NOT DECIDED: check those keys.",
    ]
    lines += [f"# NOT DECIDED: {note}" for note in draft.notes]
    fingers = ", ".join(f for f in draft.fingers if f != draft.thumb)
    lines += [
        'kind = "hand"',
        f'name = "{draft.name}"',
        f'summary = "{draft.name}: {len(draft.fingers)} fingers, {len(draft.driven())} driven joints (drafted from its URDF)"',
        f'urdf = "{draft.urdf}"',
        "# The URDF's root link: the hand is bolted to the arm's flange there.",
        f'mount_link = "{draft.root_link}"',
        f"mass = {round(draft.mass, 4):g}  # [kg] the URDF's link masses, summed",
        f'palm_frame = "{draft.palm_frame}"',
        f'palm_sensor_link = "{draft.pad_frame}"',
        "",
        f"# The palm frame on {draft.palm_link}: +z the direction the fingers close towards, +x",
        "# along the fingers, the origin on the palm's collision surface below the finger roots.",
        f"[frames.{_key(draft.palm_frame)}]",
        f'parent = "{draft.palm_link}"',
        f"xyz = {_vector(draft.T_palmlink_palm[:3, 3])}",
        f"rpy_deg = {_vector(_rpy_deg(draft.T_palmlink_palm[:3, :3]), 3)}",
        "",
        "# The palm pad: the palm surface within 3 mm of the palm frame's height, 5 mm in from",
        "# its edges, 1 mm proud of it.",
        f"[frames.{_key(draft.pad_frame)}]",
        f'parent = "{draft.palm_frame}"',
        f"xyz = {_vector(draft.pad_centre)}",
        f"pad = {_vector(draft.pad_size)}",
    ]
    for finger in draft.fingers.values():
        if finger.tip_offset is not None:
            link, xyz = finger.tip_offset
            lines += [
                "",
                f"# {finger.name}'s tip: the far point of {link}'s collision shapes.",
                f"[frames.{_key(finger.tip_frame)}]",
                f'parent = "{link}"',
                f"xyz = {_vector(xyz)}",
            ]
    thumb_words = (
        f"the thumb is the finger that closes against the others ({fingers})"
        if draft.thumb
        else "no finger closes against the others"
    )
    lines += ["", f"# Root to tip; {thumb_words}.", "[fingers]"]
    for finger in draft.fingers.values():
        links = ", ".join(f'"{link}"' for link in finger.links)
        lines.append(f"{_key(finger.name)} = [{links}]")
    palm = ", ".join(f'"{link}"' for link in [*draft.palm_links, draft.palm_frame, draft.pad_frame])
    lines.append(f"palm = [{palm}]")
    lines += ["", "[fingertips]"]
    lines += [f'{_key(f.name)} = "{f.tip_frame}"' for f in draft.fingers.values()]
    lines += ["", "# Joint roles (closing sign: the direction that closes the finger):"]
    for finger in draft.fingers.values():
        flex = ", ".join(
            f"{j} ({'+' if finger.closing_sign[j] > 0 else '-'})" for j in finger.flexion
        )
        placing = ", ".join(finger.placing) or "none"
        lines.append(f"#   {finger.name}: curl {flex}; place {placing}")
    lines += [
        "",
        "# Every joint the URDF drives (its <mimic> followers follow); limits and effort from",
        f"# the URDF, speed capped at {MAX_JOINT_SPEED:g} rad/s (our choice).",
        "[joints]",
        f"max_velocity = {round(draft.max_velocity, 4):g}",
        *(
            []
            if draft.has_efforts
            else [
                f"max_effort = {DEFAULT_FORCE_LIMIT:g}  # NOT DECIDED: the URDF gives no effort",
            ]
        ),  # fmt: skip
        "",
        "# The force limit is the URDF's largest joint effort; the stiffness reaches it at",
        f"# {TRACKING_ERROR_AT_FORCE_LIMIT:g} rad of tracking error, damping {100 * DAMPING_RATIO:g} % of it.",
        "[drive]",
        f"stiffness = {round(draft.force_limit / TRACKING_ERROR_AT_FORCE_LIMIT, 4):g}",
        f"damping = {round(DAMPING_RATIO * draft.force_limit / TRACKING_ERROR_AT_FORCE_LIMIT, 5):g}",
        f"force_limit = {round(draft.force_limit, 4):g}",
        "",
        preshape_tables.rstrip(),
        "",
        "[grasp_map]",
    ]
    lines += [f'{grasp} = "{preshape}"' for grasp, preshape in grasp_map.items()]
    return "\n".join(lines) + "\n"


def posture_table(
    name: str, key: str, q: Mapping[str, float], joints: Mapping[str, Joint]
) -> list[str]:
    """`[preshapes.NAME.KEY_deg]` (revolute joints in degrees) or `[...KEY]` with metres
    for a prismatic hand."""
    prismatic = any(joints[j].kind == "prismatic" for j in q)
    table = f"[preshapes.{_key(name)}.{key}{'' if prismatic else '_deg'}]"
    lines = [table]
    for joint, value in q.items():
        shown = value if prismatic else math.degrees(value)
        lines.append(f'"{joint}" = {round(shown, 5 if prismatic else 2):g}')
    return lines


def generic_wrap(draft: HandDraft) -> tuple[str, dict[str, str]]:
    """(preshape tables, grasp map) of one wrap: open at rest, every finger closed to its
    flexion limit, every grasp mapped to it (for a draft without synthesis)."""
    open_q, closed_q = draft.rest_q(), draft.rest_q()
    for name, value in draft.closed_flexion().items():
        closed_q[name] = value
        open_q[name] += GENERIC_OPENING * (value - open_q[name])
    lines = [
        "# NOT DECIDED: the preshapes. This one wrap (open 20 % of the way closed, every finger closed to its",
        "# flexion limit) serves every grasp until `graspframe check-hand SPEC --synthesize`",
        "# writes preshapes synthesised from the human reference grasps.",
        "[preshapes.wrap]",
        *posture_table("wrap", "open", open_q, draft.joints),
        *posture_table("wrap", "closed", closed_q, draft.joints),
    ]
    from graspframe.common.grasps import HumanGrasp

    return "\n".join(lines), {g.value: "wrap" for g in HumanGrasp}
