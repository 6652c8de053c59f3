"""Generate robots/barrett/barrett.urdf: the Barrett BH8-280 hand, from the published numbers
(BH8-series User's Manual, Barrett Technology; docs/robots/barrett.md).

    cd /work/main && python -m tools.robot_models.barrett

Frames (base = `bh_base`, at the mounting flange, +z out of the flange = palm normal):
- Fingers 1 and 2 stand side by side at +y, finger 3 (the thumb) opposes them at -y.
- Each finger link frame: x = flexion axis, y = along the link (outwards from the palm at
  zero flexion), z = the link's grasping face side. Positive flexion turns y towards z.
- Zero flexion = proximal link lying flat, pointing away from the palm (the manufacturer's
  kinematic zero); 90 deg = upright; 140 deg = leaning 50 deg over the palm.
  See docs/robots/barrett.md for why this and not "upright at zero".

Prints the palm-to-fingertip distance (delta) of each preshape of the plugin's description
and checks it against the value written there.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from tools.robot_models.urdf_builder import Box, Cylinder, UrdfBuilder

MM = 1e-3
DEG = math.pi / 180.0

# --- BH8-series manual, "Barrett BH8-280" ------------------------------------------------------
SPREAD_AXIS_X = 25 * MM  # Aw: finger 1/2 spread axes at (+-25, 0, 41.5)
SPREAD_AXIS_Z = 41.5 * MM
SPREAD_LINK = 50 * MM  # A1: spread axis to flexion axis, horizontally
SPREAD_LINK_RISE = 33.9 * MM  # spread link to flexion axis, vertically: flexion at z = 75.4
FINGER3_AXIS_Y = -50 * MM  # finger 3 flexion axis (0, -50, 75.4)
FLEXION_AXIS_Z = SPREAD_AXIS_Z + SPREAD_LINK_RISE  # 75.4 mm
PROXIMAL_LENGTH = 69.9 * MM  # A2: proximal to distal joint (3 mm lateral offset ignored)
DISTAL_LENGTH = 50 * MM  # A3: distal joint to fingertip
DISTAL_REST = 42 * DEG  # distal link rests bent towards closing at zero joint angle
SPREAD_UPPER = 180 * DEG
PROXIMAL_UPPER = 140 * DEG
DISTAL_UPPER = 48 * DEG
PALM_RADIUS = 45 * MM  # palm collision: cylinder radius 45, height 66
PALM_HEIGHT = 66 * MM
PAD_HALF_X = 38 * MM  # tactile palm pad spans x +-38, y +-21.5
PAD_HALF_Y = 21.5 * MM
HAND_MASS = 1.2  # [kg] about 1.2 kg

# --- Our assumptions (the manual is silent) ----------------------------------------------
# Palm surface at Dw = 84 mm ("wrist to palm", BH8-series manual), 8.6 mm above the plane of the
# flexion axes (75.4 mm). A palm in the flexion plane would contradict Dw, and there the
# closed wrap fingers passed 2-5 mm clear of a 2.5 cm handle lying on the palm.
PALM_SURFACE_Z = 84 * MM
PAD_THICKNESS = 3 * MM  # a thin tactile pad on top of the palm plate
PLATE_HALF_X = PAD_HALF_X  # palm plate under the pad, closing the palm body up to the pad
PLATE_HALF_Y = 30 * MM  # pad plus a rim; clear of the knuckles (>= 42 mm from the axis)
FINGER_WIDTH = 22 * MM  # along the flexion axis; leaves 3 mm between interleaved fingers
PROXIMAL_THICKNESS = 16 * MM
DISTAL_THICKNESS = 14 * MM
KNUCKLE_RADIUS = 8 * MM  # housing of each flexion axis (a cylinder along the axis)
KNUCKLE_LENGTH = 20 * MM
POST_SIDE = 20 * MM  # knuckle support from the palm top up to the flexion axis
# Masses [kg]: fingers from a light aluminium build, the palm body takes the rest of 1.2 kg.
SPREAD_LINK_MASS = 0.08
PROXIMAL_MASS = 0.065
DISTAL_MASS = 0.04
PAD_MASS = 0.02
BASE_MASS = HAND_MASS - 2 * SPREAD_LINK_MASS - 3 * (PROXIMAL_MASS + DISTAL_MASS) - PAD_MASS
# Motion and force limits of the URDF (electric motors through worm gears).
SPREAD_VELOCITY = 2.0  # [rad/s] 180 deg in about 1.6 s
FINGER_VELOCITY = 2.5  # [rad/s] a finger closes 140 deg in about 1 s
SPREAD_EFFORT = 2.0  # [N m]
PROXIMAL_EFFORT = 3.0  # [N m] ~ 25 N at a fingertip 12 cm out
DISTAL_EFFORT = 1.5  # [N m]

ROBOT_NAME = "barrett"
URDF_PATH = Path(__file__).parents[2] / "robots" / "barrett" / "barrett.urdf"

# Names (links and joints live in one namespace in Pinocchio frames: keep them distinct).
BASE = "bh_base"
PALM_PAD = "bh_palm_pad"
PALM_FRAME = "bh_palm_frame"
SPREAD_1, SPREAD_2 = "bh_spread_1", "bh_spread_2"


def prox_joint(finger: int) -> str:
    return f"bh_f{finger}_prox"


def dist_joint(finger: int) -> str:
    return f"bh_f{finger}_dist"


def spread_link(finger: int) -> str:
    return f"bh_f{finger}_spread_link"


def prox_link(finger: int) -> str:
    return f"bh_f{finger}_prox_link"


def dist_link(finger: int) -> str:
    return f"bh_f{finger}_dist_link"


def tip_link(finger: int) -> str:
    return f"bh_f{finger}_tip"


def _knuckle_shapes(axis_xyz: tuple[float, float, float], post_bottom_z: float) -> list:
    """A housing around a flexion axis (along x) and a post down to the palm top."""
    x, y, z = axis_xyz
    post_height = z - post_bottom_z
    return [
        Cylinder(KNUCKLE_RADIUS, KNUCKLE_LENGTH, xyz=axis_xyz, rpy=(0.0, math.pi / 2, 0.0)),
        Box((POST_SIDE, POST_SIDE, post_height), xyz=(x, y, post_bottom_z + post_height / 2)),
    ]


def _finger(b: UrdfBuilder, finger: int, parent: str, xyz, rpy) -> None:
    """Proximal, distal and tip marker of one finger, the flexion joint at xyz in parent."""
    b.joint(
        prox_joint(finger), "revolute", parent, prox_link(finger), xyz=xyz, rpy=rpy,
        axis=(1.0, 0.0, 0.0), lower=0.0, upper=PROXIMAL_UPPER, effort=PROXIMAL_EFFORT,
        velocity=FINGER_VELOCITY,
    )  # fmt: skip
    b.link(
        prox_link(finger),
        PROXIMAL_MASS,
        [
            Box(
                (FINGER_WIDTH, PROXIMAL_LENGTH, PROXIMAL_THICKNESS),
                xyz=(0.0, PROXIMAL_LENGTH / 2, 0.0),
            )
        ],
    )
    b.joint(
        dist_joint(finger), "revolute", prox_link(finger), dist_link(finger),
        xyz=(0.0, PROXIMAL_LENGTH, 0.0), rpy=(DISTAL_REST, 0.0, 0.0), axis=(1.0, 0.0, 0.0),
        lower=0.0, upper=DISTAL_UPPER, effort=DISTAL_EFFORT, velocity=FINGER_VELOCITY,
    )  # fmt: skip
    b.link(
        dist_link(finger),
        DISTAL_MASS,
        [Box((FINGER_WIDTH, DISTAL_LENGTH, DISTAL_THICKNESS), xyz=(0.0, DISTAL_LENGTH / 2, 0.0))],
    )
    b.joint(
        f"bh_f{finger}_tip_joint", "fixed", dist_link(finger), tip_link(finger),
        xyz=(0.0, DISTAL_LENGTH, 0.0),
    )  # fmt: skip
    b.link(tip_link(finger))


def build() -> UrdfBuilder:
    b = UrdfBuilder(
        ROBOT_NAME,
        comment="Barrett BH8-280 hand. Generated by tools/robot_models/barrett.py from the "
        "published numbers in docs/robots/barrett.md; do not edit by hand.",
    )
    # Palm body: the manual's palm cylinder, a plate up to the pad, finger 3's knuckle.
    plate_height = PALM_SURFACE_Z - PAD_THICKNESS - PALM_HEIGHT
    base_shapes = [
        Cylinder(PALM_RADIUS, PALM_HEIGHT, xyz=(0.0, 0.0, PALM_HEIGHT / 2)),
        Box(
            (2 * PLATE_HALF_X, 2 * PLATE_HALF_Y, plate_height),
            xyz=(0.0, 0.0, PALM_HEIGHT + plate_height / 2),
        ),
        *_knuckle_shapes((0.0, FINGER3_AXIS_Y, FLEXION_AXIS_Z), PALM_HEIGHT),
    ]
    b.link(BASE, BASE_MASS, base_shapes)

    # Tactile palm pad (the palm sensor link); its frame is at the palm surface centre.
    b.joint("bh_palm_pad_joint", "fixed", BASE, PALM_PAD, xyz=(0.0, 0.0, PALM_SURFACE_Z))
    b.link(
        PALM_PAD,
        PAD_MASS,
        [Box((2 * PAD_HALF_X, 2 * PAD_HALF_Y, PAD_THICKNESS), xyz=(0.0, 0.0, -PAD_THICKNESS / 2))],
    )
    # Palm frame: +z out of the palm, +x from finger 3 towards fingers 1-2 (base +y).
    b.joint(
        "bh_palm_frame_joint", "fixed", BASE, PALM_FRAME,
        xyz=(0.0, 0.0, PALM_SURFACE_Z), rpy=(0.0, 0.0, math.pi / 2),
    )  # fmt: skip
    b.link(PALM_FRAME)

    # Fingers 1 (x > 0) and 2 (x < 0): one spread motor turns them in opposite senses, so
    # that a growing spread carries them apart around the palm towards finger 3.
    for finger, side, spread, axis_z in ((1, 1.0, SPREAD_1, -1.0), (2, -1.0, SPREAD_2, 1.0)):
        b.joint(
            spread, "revolute", BASE, spread_link(finger),
            xyz=(side * SPREAD_AXIS_X, 0.0, SPREAD_AXIS_Z), axis=(0.0, 0.0, axis_z),
            lower=0.0, upper=SPREAD_UPPER, effort=SPREAD_EFFORT, velocity=SPREAD_VELOCITY,
            mimic=(SPREAD_1, 1.0, 0.0) if finger == 2 else None,
        )  # fmt: skip
        axis_xyz = (0.0, SPREAD_LINK, SPREAD_LINK_RISE)
        b.link(
            spread_link(finger),
            SPREAD_LINK_MASS,
            _knuckle_shapes(axis_xyz, PALM_HEIGHT - SPREAD_AXIS_Z),
        )
        _finger(b, finger, spread_link(finger), xyz=axis_xyz, rpy=(0.0, 0.0, 0.0))

    # Finger 3: fixed on the palm, pointing to -y, so its link frame is turned 180 deg.
    _finger(b, 3, BASE, xyz=(0.0, FINGER3_AXIS_Y, FLEXION_AXIS_Z), rpy=(0.0, 0.0, math.pi))
    return b


def palm_to_fingertip(urdf_path: Path, q_by_name: dict[str, float]) -> float:
    """delta [m]: the largest fingertip height above the palm surface, along the palm
    normal, with the spread mimic applied (Pinocchio forward kinematics)."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(urdf_path), False)
    data = model.createData()
    q = pin.neutral(model)
    full = {**q_by_name, SPREAD_2: q_by_name[SPREAD_1]}
    for name, value in full.items():
        q[model.joints[model.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(model, data, q)
    T_base_palm = data.oMf[model.getFrameId(PALM_FRAME)]
    heights = []
    for finger in (1, 2, 3):
        p_base_tip = data.oMf[model.getFrameId(tip_link(finger))].translation
        p_palm_tip = T_base_palm.actInv(np.asarray(p_base_tip))
        heights.append(float(p_palm_tip[2]))
    return max(heights)


def main() -> None:
    path = build().write(URDF_PATH)
    print(f"wrote {path}")
    from graspframe_barrett.description import BARRETT

    for preshape in BARRETT.preshapes.values():
        delta = palm_to_fingertip(path, dict(preshape.open_q))
        status = "ok" if abs(delta - preshape.delta) < 5e-4 else "UPDATE description.py"
        line = f"delta {preshape.name}: {delta:.4f} m (in description: {preshape.delta})"
        print(line, status)


if __name__ == "__main__":
    main()
