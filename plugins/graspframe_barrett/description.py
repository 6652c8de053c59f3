"""The Barrett BH8-280 hand as graspframe sees it: joints, frames, preshapes, mapping.

Model: robots/barrett/barrett.urdf, written by tools/robot_models/barrett.py (numbers,
their sources and our assumptions in docs/robots/barrett.md). Joint angles [rad]; flexion
0 = finger lying flat, pointing away from the palm; 90 deg = upright; positive flexion
curls towards the palm.

The distal joints follow their proximal joint at 1/3 (one motor per finger), but the
TorqueSwitch breaks that coupling when the proximal link meets an object: the hand
controller enforces it (Coupling in_model=False), the URDF does not. The spread joint of
finger 2 mimics finger 1 in the URDF itself (in_model=True), so it is not a driven joint.
"""

from __future__ import annotations

import math

from graspframe.common.grasps import PALM, HumanGrasp, Preshape
from graspframe.hal.descriptions import (
    Coupling,
    DesignObject,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
)
from graspframe_robots import model_path

DEG = math.pi / 180.0
# The distal joint moves 1/3 of the proximal (Barrett BH8-series manual).
DISTAL_PER_PROXIMAL = 1.0 / 3.0

ROOT_LINK = "bh_base"
PALM_FRAME = "bh_palm_frame"
PALM_PAD = "bh_palm_pad"
SPREAD = "bh_spread_1"
SPREAD_FOLLOWER = "bh_spread_2"
FINGERS = (1, 2, 3)
PROXIMAL = tuple(f"bh_f{f}_prox" for f in FINGERS)
DISTAL = tuple(f"bh_f{f}_dist" for f in FINGERS)
FINGERTIP_FRAMES = {f"finger_{f}": f"bh_f{f}_tip" for f in FINGERS}

# Limits equal the URDF's (Barrett BH8-280 specifications: spread 0-180, proximal
# 0-140, distal 0-48 deg).
# Velocities and efforts are our assumptions (see docs/robots/barrett.md).
JOINTS = (
    JointSpec(SPREAD, 0.0, 180 * DEG, max_velocity=2.0, max_effort=2.0),
    *(JointSpec(n, 0.0, 140 * DEG, max_velocity=2.5, max_effort=3.0) for n in PROXIMAL),
    *(JointSpec(n, 0.0, 48 * DEG, max_velocity=2.5, max_effort=1.5) for n in DISTAL),
)

# TorqueSwitch: above this proximal drive torque the proximal link stops (held by its
# worm gear) and the motor drives only the distal joint (TorqueSwitch, Barrett Technology
# documentation). The preset value is
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
# checks it against Pinocchio). Palm frame: +x from finger 3 (the thumb, at x = -50 mm)
# towards fingers 1 and 2 (at x = +50 mm, y = -25 / +25 mm), +z out of the palm.
#
# Design objects and grasp centres are where the object sits in the palm frame when held;
# the planner puts the real object's centroid there (volar grasps: x and y only; non-volar
# grasps keep the object's near face where the design object's is). The numbers below were
# measured with the hand alone and on the arm (docs/robots/barrett.md, "Held").
F1, F2, F3 = "finger_1", "finger_2", "finger_3"
OPPOSED = ((F1, F3), (F2, F3))  # fingers 1 and 2 close against finger 3 in every preshape

# Wrap, roll: the human Small Diameter posture holds its handle 15 deg off its palm y
# axis; turned by 15 deg the Barrett fingers close square to the handle (a Large
# Diameter can ends 5 deg off, which is harmless). Closing across a tilted 25 mm handle,
# each finger met it at a different angle, the TorqueSwitch locked the first proximal
# link early and the handle slipped (rose 0 mm).
WRAP_ROLL = 15 * DEG
# Wrap, grasp centre x = -15 mm (towards finger 3): a thin handle there is stopped by
# finger 3's proximal link while the distal links of fingers 1 and 2 hook round it and
# press it into the palm. Centred (x = 0), the proximal joints reach their 140 deg limit
# before the fingers squeeze a handle thinner than 25 mm. Handles of 19-31 mm held from
# x = -12 to -20 mm with the hand alone; cans are indifferent.
WRAP_CENTRE_X = -0.015  # [m]
# Wrap on a thin object: fully closed, the distal links of fingers 1 and 2 and of finger 3
# cross about 4 cm above the palm and leave a wedge below the crossing. A handle pressed
# on the palm sits in the wide part of that wedge: nothing squeezes it (the distals reach
# their coupled targets untouched) and it slipped out when lifted (rose 0 mm) in 4 of 6
# runs of experiment B. Held 20 mm off the palm (centroid 32.5 mm above it), the distal
# links squeeze a 25 mm handle from both sides: the volar approach finds it with the
# palm and backs off. Objects thicker than 65 mm (cans) still rest on the palm.
WRAP_THIN_CENTRE_HEIGHT = 0.0325  # [m]
# Wrap, open proximal angles [deg] of fingers 1 and 2, and of finger 3: fingers 1 and 2
# start 60 deg further closed, so closing at equal speeds they stand over the handle
# before finger 3 sweeps it against them. Opened alike (10 deg), finger 3 arrived first
# and pushed the handle across the palm into the gap under the crossing fingers, where
# nothing squeezed it: held in 3 of 6 runs of experiment B, now 6 of 6. The open
# aperture still takes a 10 cm can (fingers 1 and 2 end 94 mm out along palm x).
WRAP_OPEN_DEG = (70.0, 10.0)

# Precision, roll: the human Abducted Thumb posture holds its cylinder at 50 deg to its
# palm x axis, so the Barrett closing direction (palm x) must turn 40 deg (or -140 deg) to
# close square to the cylinder; at roll 0 the fingertips closed 40 deg off and the 6 cm
# cylinder slipped. -140 deg (not +40) puts finger 1 below finger 3 on a side grasp, so on
# a short cylinder that the table keeps low in the hand the pinching pair (fingers 1 and
# 3) still straddles it. A pinch block seen from above is then closed on 40 deg off its
# faces; the fingertips square it up while closing (held in every run).
PRECISION_ROLL = -140 * DEG
# Precision, grasp centre y = -12.5 mm: the object sits between finger 1 (y -36 .. -14 mm)
# and finger 3 (y -11 .. 11 mm). Centred (y = 0), a 25 mm block fits in the 28 mm gap
# between fingers 1 and 2 and finger 3 pushed it through and over.
# Near face 56 mm from the palm: the fingertips meet a 4.5-7.5 cm cylinder on or just
# beyond its equator (pulling it into the hand, not pushing it out); 45-58 mm held the
# hand alone (one miss at 50 mm), 56-58 mm also on the arm.
PRECISION_CENTRE = (0.0, -0.0125, 0.081)  # [m]

# Precision disc: at spread 60 deg the closing planes meet in a line 14.4 mm from the palm
# axis towards finger 3; the object is centred on it, so every finger pushes through the
# object's centre. The knuckles of fingers 1 and 2 are 79 mm from that line, finger 3's
# only 36 mm: finger 3 opens 22 deg further (8 instead of 30 deg), so that, closing at
# equal speeds, the three fingertips stay equally far (within 3 mm) from the line and
# reach an object at the same time. With equal opening angles finger 3 arrived first
# and pushed a 6.75 cm ball off the table.
DISC_CENTRE = (-0.0144, 0.0, 0.075)  # [m]


def _wrap_open() -> dict[str, float]:
    """Wrap, open: fingers 1 and 2 already at 70 deg, finger 3 at 10 deg (see WRAP_OPEN)."""
    q = hand_q(0, WRAP_OPEN_DEG[0])
    q[PROXIMAL[2]] = WRAP_OPEN_DEG[1] * DEG
    q[DISTAL[2]] = WRAP_OPEN_DEG[1] * DEG * DISTAL_PER_PROXIMAL
    return q


def _disc_open() -> dict[str, float]:
    q = hand_q(60, 30)
    q[PROXIMAL[2]] = 8 * DEG
    q[DISTAL[2]] = 8 * DEG * DISTAL_PER_PROXIMAL
    return q


PRESHAPES = {
    p.name: p
    for p in (
        # Large aperture (fingers 1-2 raised to 70 deg, finger 3 nearly flat; see
        # WRAP_OPEN_DEG), fingers 1-2 opposing the thumb; closing targets at the proximal
        # limit (140 deg), well past contact, so the fingers wrap.
        # Design object: a 4 cm handle lying across the palm (volar: it rests on it).
        HandPreshape(
            Preshape.WRAP.value,
            _wrap_open(),
            hand_q(0, 140),
            delta=0.0922,
            design_object=DesignObject(
                "cylinder", (WRAP_CENTRE_X, 0.0, 0.02), 0.02, axis=(0.0, 1.0, 0.0), length=0.15
            ),
            roll=WRAP_ROLL,
            opposed=OPPOSED,
            volar_centre_height=WRAP_THIN_CENTRE_HEIGHT,
        ),
        # Fingertip grasp. Open at 60 deg (tips 117 mm apart along palm x, at their
        # deepest, 94 mm from the palm): at the former 72 deg (69 mm apart) the open tips
        # touched a 6 cm cylinder during the approach and pushed it away from the palm.
        # Closing targets at 120 deg, ~28 deg past the angle where the tips meet (~92 deg):
        # at 105 deg a 4.5 cm cylinder pulled into the hand was held too loosely to lift
        # (115-125 deg all hold).
        # Design object: the 25 x 25 x 50 mm pinch block as its enclosing cylinder, held
        # upright from above.
        HandPreshape(
            Preshape.PRECISION.value,
            hand_q(0, 60),
            hand_q(0, 120),
            delta=0.0943,
            design_object=DesignObject(
                "cylinder", PRECISION_CENTRE, 0.0177, axis=(0.0, 0.0, 1.0), length=0.05
            ),
            roll=PRECISION_ROLL,
            opposed=OPPOSED,
        ),
        # Spread 60 deg: the three fingers' closing planes are 120 deg apart. Finger 3
        # opens further (see DISC_CENTRE). Closing targets at the proximal limit: at
        # 130 deg a 9 cm disc slipped on the arm (the fingertips of fingers 1 and 2 reach
        # a flat disc only near its top edge, see docs/robots/barrett.md).
        # Design object: a 9 cm ball, its top 30 mm from the palm (a disc on the table
        # ends as deep as the table lets the hand go).
        HandPreshape(
            Preshape.PRECISION_DISC.value,
            _disc_open(),
            hand_q(60, 140),
            delta=0.0759,
            design_object=DesignObject("sphere", DISC_CENTRE, 0.045),
            opposed=OPPOSED,
        ),
    )
}

# The method's mapping table (docs/method.md, section 1).
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
    fingertip_frames=FINGERTIP_FRAMES,
)
