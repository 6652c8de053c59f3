"""A hand draft written as a spec file (see graspframe/specs/draft.py): the drafted keys
with their comments, what could not be decided marked NOT DECIDED, then the preshape
tables (the synthesis's, or one generic wrap) and the grasp map."""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.specs.draft import (
    DAMPING_RATIO,
    DEFAULT_FORCE_LIMIT,
    MAX_JOINT_SPEED,
    TRACKING_ERROR_AT_FORCE_LIMIT,
    HandDraft,
)
from graspframe.specs.draft_kinematics import Joint
from graspframe.specs.draft_palm import DORSAL_PLATE_SIDE, DORSAL_PLATE_THICKNESS

ALUMINIUM_DENSITY = 2700.0  # [kg/m^3]

GENERIC_OPENING = 0.2  # the generic wrap opens this part of the way to closed


def _rpy_deg(R: NDArray[np.float64]) -> list[float]:
    from scipy.spatial.transform import Rotation

    with warnings.catch_warnings():  # a palm turned 90 deg: gimbal lock, still exact
        warnings.simplefilter("ignore", UserWarning)
        angles = Rotation.from_matrix(R).as_euler("xyz", degrees=True)
    return [round(v, 4) for v in angles]


def _vector(values: Sequence[float] | NDArray[np.float64], digits: int = 5) -> str:
    return "[" + ", ".join(f"{round(float(v), digits):g}" for v in values) + "]"


def _key(name: str) -> str:
    return name if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_-]*", name) else f'"{name}"'


def spec_text(draft: HandDraft, preshape_tables: str, grasp_map: Mapping[str, str]) -> str:
    """The spec file's text: the drafted keys, then the preshape tables and grasp map."""
    stiffness = draft.force_limit / TRACKING_ERROR_AT_FORCE_LIMIT
    effort_line = [] if draft.has_efforts else [
        f"max_effort = {DEFAULT_FORCE_LIMIT:g}  # NOT DECIDED: the URDF gives no effort"
    ]  # fmt: skip
    lines = [
        f"# {draft.name}: a hand spec drafted by `graspframe spec draft` from "
        f"{Path(draft.urdf).name}.",
        "# Every value below comes from the URDF's tree and collision geometry, except where",
        "# a comment says NOT DECIDED: check those keys.",
    ]
    lines += [f"# NOT DECIDED: {note}" for note in draft.notes]
    fingers = ", ".join(f for f in draft.fingers if f != draft.thumb)
    lines += [
        'kind = "hand"',
        f'name = "{draft.name}"',
        f'summary = "{draft.name}: {len(draft.fingers)} fingers, {len(draft.driven())} '
        'driven joints (drafted from its URDF)"',
        f'urdf = "{draft.urdf}"',
        *_mount_lines(draft),
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
    if draft.mount_frame != draft.root_link:
        lines += [
            "",
            f"# The flange's face: {draft.root_link}'s frame moved back along its -z until no "
            "shape of the",
            "# hand lies behind it near the axis.",
            f"[frames.{_key(draft.mount_frame)}]",
            f'parent = "{draft.root_link}"',
            f"xyz = {_vector([0.0, 0.0, -draft.behind_root])}",
        ]
    lines += _dorsal_mounting(draft)
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
        *effort_line,
        "",
        "# The force limit is the URDF's largest joint effort; the stiffness reaches it at",
        f"# {TRACKING_ERROR_AT_FORCE_LIMIT:g} rad of tracking error, damping "
        f"{100 * DAMPING_RATIO:g} % of it.",
        "[drive]",
        f"stiffness = {round(stiffness, 4):g}",
        f"damping = {round(DAMPING_RATIO * stiffness, 5):g}",
        f"force_limit = {round(draft.force_limit, 4):g}",
        "# The controller moves every joint to a posture together (the closing the",
        "# synthesis plans); false: each joint at its own velocity limit.",
        "synchronised = true",
        "",
        preshape_tables.rstrip(),
        "",
        "[grasp_map]",
    ]
    lines += [f'{grasp} = "{preshape}"' for grasp, preshape in grasp_map.items()]
    return "\n".join(lines) + "\n"


def _mount_lines(draft: HandDraft) -> list[str]:
    if draft.mount_frame == draft.root_link:
        return [
            "# The URDF's root link: the hand is bolted to the arm's flange there.",
            f'mount_link = "{draft.root_link}"',
        ]
    return [
        f"# Bolted to the arm's flange at its root link, {1000 * draft.behind_root:.1f} mm "
        "further back: the hand",
        f"# reaches that far behind {draft.root_link}'s frame (see [frames.{draft.mount_frame}]).",
        f'mount_link = "{draft.mount_frame}"',
    ]


def _dorsal_mounting(draft: HandDraft) -> list[str]:
    """A second mounting, tried when the arm finds no path with the hand bolted at its
    root link: a plate on the back of the palm, the flange's axis along the palm normal
    (an anthropomorphic hand bolted at its wrist has the arm's wrist below the palm in
    side grasps of short objects). None when the palm has no shape behind its frame."""
    if draft.back_of_palm is None:
        return []
    side, thick = DORSAL_PLATE_SIDE, DORSAL_PLATE_THICKNESS
    mass = ALUMINIUM_DENSITY * side * side * thick
    return [
        "",
        "# A mounting tried when the arm finds no path with the hand bolted at its root",
        "# link: a plate on the back of the palm (an adapter, not part of the hand:",
        f"# {1000 * side:g} x {1000 * side:g} x {1000 * thick:g} mm of aluminium, our choice), "
        "centred behind the palm",
        "# frame, its face on the hand's deepest point there, the flange's axis along the",
        "# palm normal.",
        f"[frames.{_key(draft.dorsal_frame)}]",
        f'parent = "{draft.palm_frame}"',
        f"xyz = {_vector([0.0, 0.0, -(draft.back_of_palm + thick)])}",
        "",
        "[mountings.dorsal]",
        f'frame = "{draft.dorsal_frame}"',
        f"mass = {round(mass, 3):g}",
        'summary = "a plate on the back of the palm, the flange axis along the palm normal"',
        f'adapter = [{{ shape = "box", size = {_vector([side, side, thick])}, '
        f"xyz = {_vector([0.0, 0.0, thick / 2])} }}]",
    ]


def posture_table(
    name: str, key: str, q: Mapping[str, float], joints: Mapping[str, Joint]
) -> list[str]:
    """`[preshapes.NAME.KEY_deg]` (revolute joints in degrees) or `[...KEY]` with metres
    for a prismatic hand."""
    prismatic = any(joints[j].kind == "prismatic" for j in q)
    table = f"[preshapes.{_key(name)}.{key}{'' if prismatic else '_deg'}]"
    lines = [table]
    for joint, value in q.items():
        lines.append(f'"{joint}" = {_shown(value, joints[joint], prismatic):g}')
    return lines


def _shown(value: float, joint: Joint, prismatic: bool) -> float:
    """A joint value as posture_table writes it: [deg] to 0.01 (a prismatic hand's [m]
    to 1e-5), rounded inwards where rounding would pass a limit (-20.0 deg of a -0.349
    rad limit)."""
    digits = 5 if prismatic else 2
    limits = (joint.lower, joint.upper)
    if not prismatic:
        value, limits = math.degrees(value), (math.degrees(limits[0]), math.degrees(limits[1]))
    shown = round(value, digits)
    step = 10.0**-digits
    if shown < limits[0]:
        shown = math.ceil(limits[0] / step) * step
    if shown > limits[1]:
        shown = math.floor(limits[1] / step) * step
    return round(shown, digits)


def written_posture(q: Mapping[str, float], joints: Mapping[str, Joint]) -> dict[str, float]:
    """q [rad or m] as it reads back from posture_table's lines."""
    prismatic = any(joints[j].kind == "prismatic" for j in q)
    return {
        name: _shown(value, joints[name], prismatic) * (1.0 if prismatic else math.pi / 180.0)
        for name, value in q.items()
    }


def generic_wrap(draft: HandDraft) -> tuple[str, dict[str, str]]:
    """(preshape tables, grasp map) of one wrap: open at rest, every finger closed to its
    flexion limit, every grasp mapped to it (for a draft without synthesis)."""
    open_q, closed_q = draft.rest_q(), draft.rest_q()
    for name, value in draft.closed_flexion().items():
        closed_q[name] = value
        open_q[name] += GENERIC_OPENING * (value - open_q[name])
    lines = [
        "# NOT DECIDED: the preshapes. This one wrap (open 20 % of the way closed, every",
        "# finger closed to its flexion limit) serves every grasp until `graspframe",
        "# check-hand SPEC --synthesize` writes preshapes synthesised from the human",
        "# reference grasps.",
        "[preshapes.wrap]",
        *posture_table("wrap", "open", open_q, draft.joints),
        *posture_table("wrap", "closed", closed_q, draft.joints),
    ]
    from graspframe.common.grasps import HumanGrasp

    return "\n".join(lines), {g.value: "wrap" for g in HumanGrasp}
