"""The Barrett BH8-280 hand as graspframe sees it: joints, frames, preshapes, mapping.

Model: robots/barrett/barrett.urdf, written by tools/robot_models/barrett.py (numbers and
assumptions in docs/robots/barrett.md). Joint angles [rad]; flexion 0 = finger lying flat,
pointing away from the palm; 90 deg = upright; positive flexion curls towards the palm.

The distal joints follow their proximal joint at 1/3 (one motor per finger), but the
TorqueSwitch breaks that coupling when the proximal link meets an object: the hand
controller enforces it (Coupling in_model=False), the URDF does not. The spread joint of
finger 2 mimics finger 1 in the URDF itself (in_model=True), so it is not a driven joint.
"""

from __future__ import annotations

import math

from graspframe.grasps import PALM, HumanGrasp, Preshape
from graspframe.hal.descriptions import (
    Coupling,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
)
from graspframe_robots import model_path

DEG = math.pi / 180.0
DISTAL_PER_PROXIMAL = 1.0 / 3.0  # ROBOTS.md: distal moves 1/3 of proximal

ROOT_LINK = "bh_base"
PALM_FRAME = "bh_palm_frame"
PALM_PAD = "bh_palm_pad"
SPREAD = "bh_spread_1"
SPREAD_FOLLOWER = "bh_spread_2"
FINGERS = (1, 2, 3)
PROXIMAL = tuple(f"bh_f{f}_prox" for f in FINGERS)
DISTAL = tuple(f"bh_f{f}_dist" for f in FINGERS)
FINGERTIP_LINKS = tuple(f"bh_f{f}_tip" for f in FINGERS)

# Limits equal the URDF's (ROBOTS.md: spread 0-180, proximal 0-140, distal 0-48 deg).
# Velocities and efforts are our assumptions (see docs/robots/barrett.md).
JOINTS = (
    JointSpec(SPREAD, 0.0, 180 * DEG, max_velocity=2.0, max_effort=2.0),
    *(JointSpec(n, 0.0, 140 * DEG, max_velocity=2.5, max_effort=3.0) for n in PROXIMAL),
    *(JointSpec(n, 0.0, 48 * DEG, max_velocity=2.5, max_effort=1.5) for n in DISTAL),
)

# TorqueSwitch: above this proximal drive torque the proximal link stops (held by its
# worm gear) and the motor drives only the distal joint (ROBOTS.md). The preset value is
# our assumption: a third of the proximal effort limit, so a finger stops on an object
# well before its drive saturates.
BREAKAWAY_TORQUE = 1.0  # [N m]

COUPLINGS = (
    Coupling(SPREAD_FOLLOWER, SPREAD, 1.0, in_model=True),
    *(
        Coupling(dist, prox, DISTAL_PER_PROXIMAL, in_model=False, breakaway_torque=BREAKAWAY_TORQUE)
        for prox, dist in zip(PROXIMAL, DISTAL, strict=True)
    ),
)


def hand_q(spread_deg: float, proximal_deg: float) -> dict[str, float]:
    """All seven driven joints [rad]: one spread, every finger at the same proximal angle,
    distal at 1/3 of it (the free-space coupling)."""
    q = {SPREAD: spread_deg * DEG}
    for prox, dist in zip(PROXIMAL, DISTAL, strict=True):
        q[prox] = proximal_deg * DEG
        q[dist] = proximal_deg * DEG * DISTAL_PER_PROXIMAL
    return q


# Preshapes. delta [m]: fingertip height above the palm surface in the open preshape,
# from forward kinematics (printed by `python -m tools.robot_models.barrett`; a test
# checks it against Pinocchio).
PRESHAPES = {
    p.name: p
    for p in (
        # Large aperture (fingertips ~29 cm apart), fingers 1-2 opposing the thumb;
        # closing targets at the proximal limit (140 deg), well past contact, so the
        # fingers wrap: a 2.5 cm handle on the palm is first touched at ~135 deg.
        HandPreshape(Preshape.WRAP.value, hand_q(0, 10), hand_q(0, 140), delta=0.0447),
        # Fingertip grasp: tips ~7 cm apart (along the palm x axis) when open; the closed
        # targets lie ~13 deg past the angle where the tips meet (~92 deg), to squeeze.
        HandPreshape(Preshape.PRECISION.value, hand_q(0, 72), hand_q(0, 105), delta=0.0913),
        # Spread 60 deg: the three fingers' closing planes are 120 deg apart.
        HandPreshape(Preshape.PRECISION_DISC.value, hand_q(60, 30), hand_q(60, 130), delta=0.0759),
    )
}

# METHOD.md section 1.
GRASP_MAP = {
    HumanGrasp.LARGE_DIAMETER: Preshape.WRAP.value,
    HumanGrasp.SMALL_DIAMETER: Preshape.WRAP.value,
    HumanGrasp.ABDUCTED_THUMB: Preshape.PRECISION.value,
    HumanGrasp.PINCH: Preshape.PRECISION.value,
    HumanGrasp.POWER_SPHERE: Preshape.PRECISION_DISC.value,
    HumanGrasp.PRECISION_DISC: Preshape.PRECISION_DISC.value,
}

REAL_FINGERS = {
    "finger_1": ("bh_f1_spread_link", "bh_f1_prox_link", "bh_f1_dist_link", "bh_f1_tip"),
    "finger_2": ("bh_f2_spread_link", "bh_f2_prox_link", "bh_f2_dist_link", "bh_f2_tip"),
    "finger_3": ("bh_f3_prox_link", "bh_f3_dist_link", "bh_f3_tip"),  # the thumb
    PALM: (ROOT_LINK, PALM_PAD, PALM_FRAME),
}

BARRETT = HandDescription(
    name="barrett",
    model_path=model_path("barrett/barrett.urdf"),
    root_link=ROOT_LINK,
    joints=JOINTS,
    palm_frame=PALM_FRAME,
    palm_sensor_link=PALM_PAD,
    real_fingers=REAL_FINGERS,
    preshapes=PRESHAPES,
    grasp_map=GRASP_MAP,
    # Electric finger motors behind worm gears: stiff enough to hold a pose, force limited
    # near the proximal effort limit (assumptions).
    drive=DriveGains(stiffness=10.0, damping=0.5, force_limit=3.0),
    couplings=COUPLINGS,
    mass=1.2,
    summary="Barrett BH8-280: 3 fingers, 4 motors (spread + one per finger), 8 joints",
    extras={"fingertip_links": FINGERTIP_LINKS, "thumb": "finger_3"},
)
