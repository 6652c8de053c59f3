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
The modules: this one (the tree, the fingers, the thumb, the drive), draft_kinematics.py
(joints, forward kinematics, fingertip motion), draft_palm.py (palm frame and pad),
draft_text.py (`spec_text`: the spec file; its preshapes come from the synthesis,
graspframe/mapping/synthesis.py, or a generic wrap that closes every finger).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.model_files.urdf_model import ModelFile, UrdfModel, load_model_file
from graspframe.specs.draft_kinematics import (
    Axes,
    DraftFinger,
    Joint,
    Joints,
    Kinematics,
    closing_direction,
    joint_axes,
    placing_grid,
    read_joints,
    tip_motion,
    tip_position,
)
from graspframe.specs.draft_palm import back_of_palm, behind_the_flange, palm_frame

PARALLEL_AXES = 0.8  # |cos| above which two joint axes count as parallel
TRACKING_ERROR_AT_FORCE_LIMIT = 0.1  # [rad] the stiffness reaches the force limit here
DAMPING_RATIO = 0.03  # [s] damping / stiffness
MAX_JOINT_SPEED = 2.0  # [rad/s] (or m/s) the controller's, when the URDF's is faster
DEFAULT_FORCE_LIMIT = 1.0  # [N m] written (and named) when the URDF gives no effort


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
    back_of_palm: float | None = None  # [m] behind the palm frame: a dorsal plate's face
    behind_root: float = 0.0  # [m] the hand behind its root link's z = 0 plane (see draft_palm)

    @property
    def mount_frame(self) -> str:
        """The link bolted to the flange: the root link, or a frame behind it when the
        hand reaches behind the root link's frame."""
        return f"{self.name}_mount" if self.behind_root > 0 else self.root_link

    @property
    def dorsal_frame(self) -> str:
        return f"{self.name}_dorsal"

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


def draft_hand(urdf: Path | str, name: str | None = None) -> HandDraft:
    """Read the URDF and decide everything its tree and geometry determine (see the
    module docstring); a DescriptionError when it holds no hand (no moving chain)."""
    path = Path(urdf)
    model = load_model_file(ModelFile(path))
    joints = read_joints(model)
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
    if len(paths) == 1:  # one chain, no split: the palm is where its moving joints start
        palm_link = next(parent_joint[c].parent for c in paths[0][1:] if parent_joint[c].moving)
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

    kin = Kinematics(model, palm_link)
    axes = joint_axes(model)
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
        chain_depth = {link: len(path_to(link)) for link in finger_links}
        tip_link = max(finger_links, key=lambda link: (chain_depth[link], link))
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
    T_palmlink_palm, pad_centre, pad_size = palm_frame(
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
        back_of_palm=back_of_palm(
            kin, T_palmlink_palm, [link for link, _s, _T in kin.collision.shapes()]
        ),
        behind_root=behind_the_flange(kin, root),
    )


def _spec_name(text: str) -> str:
    name = re.sub(r"[^a-z0-9_]+", "_", text.lower()).strip("_")
    return name or "hand"


def _tip_frame(
    finger: DraftFinger,
    kin: Kinematics,
    shapes_of: set[str],
    parent_joint: Mapping[str, Joint],
    path_to: Callable[[str], list[str]],
    joints: Joints,
) -> None:
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


def _joint_roles(finger: DraftFinger, joints: Joints, kin: Kinematics, axes: Axes) -> None:
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


def _closing_signs(
    fingers: Mapping[str, DraftFinger], joints: Joints, kin: Kinematics, axes: Axes
) -> None:
    """Each joint's closing sign: a revolute joint bends further towards the palm than
    away (the larger side of its range); a prismatic one moves its tip towards the
    other fingertips."""
    tips = {name: tip_position(f, kin) for name, f in fingers.items()}
    for name, finger in fingers.items():
        for joint_name in finger.joints:
            joint = joints[joint_name]
            if joint.kind == "prismatic":
                others = [tips[n] for n in fingers if n != name]
                target = np.mean(others, axis=0) if others else np.zeros(3)
                motion = tip_motion(finger, joints, kin, axes, joint_name)
                sign = 1.0 if float(motion @ (target - tips[name])) >= 0 else -1.0
            else:
                sign = 1.0 if abs(joint.upper) >= abs(joint.lower) else -1.0
            finger.closing_sign[joint_name] = sign


def _thumb(
    fingers: Mapping[str, DraftFinger],
    joints: Joints,
    kin: Kinematics,
    axes: Axes,
    rest: Mapping[str, float],
) -> tuple[str | None, str | None]:
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
