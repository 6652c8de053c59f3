"""The human right hand as data: the reference hand for scoring (and for rendering).

Model: robots/human/human.urdf, written by tools/robot_models/human.py for a 190 mm hand
(Buchholz et al. 1992 segment ratios; every number and assumption is listed in
docs/robots/human.md). 20 joints: per finger ab/adduction and flexion at the knuckle, the
PIP, and the DIP, which is a URDF <mimic> of the PIP at 2/3 (so not a driven joint); the
thumb has CMC abduction and flexion, MCP and IP. Angles [rad]; positive flexion bends
towards the palm, positive finger ab/adduction turns a finger towards the little finger.

Frames (links of the URDF):
- hh_wrist (root): the wrist crease, mid-plane of the palm; +z along the hand towards the
  fingers, +x out of the back of the hand, +y towards the little finger.
- hh_palm_frame: centre of the palmar surface (outer face of the pad), +x towards the
  fingertips, +z out of the palm on the palmar side, y = z x x; the thumb is on its -y side.
- hh_<digit>_tip: fingertip markers at the end of each digit.

Instead of robot preshapes the human hand has one posture per human grasp, named by the
grasp (grasp_map is the identity). open_q is the pre-grasp posture (shaped for the object,
open enough for it to come in along the palm normal), closed_q the closing targets past
contact with the object; closed_q stays clear of self-collision so the hand reaches it in
free space. The postures were fitted to their design objects (each posture's
`design_object`, POSTURE_OBJECTS: shapes in the palm frame) by forward kinematics and
collision distances (see the doc).
"""

from __future__ import annotations

import math

from graspframe.common.grasps import PALM, THUMB, HumanGrasp
from graspframe.hal.descriptions import (
    Coupling,
    DesignObject,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
)
from graspframe_robots import model_path

NAME = "human"
MODEL_FILE = "human/human.urdf"
HAND_LENGTH = 0.19  # [m] the chosen adult size (a typical adult hand: about 190 mm)
ROOT_LINK = "hh_wrist"
PALM_FRAME = "hh_palm_frame"
PALM_SENSOR_LINK = "hh_palm_pad"
FINGERS = ("index", "middle", "ring", "little")
DIGITS = (THUMB, *FINGERS)
DIP_PER_PIP = 2.0 / 3.0  # the end joint coupled to the middle one at 2/3 (Rijpkema & Girard 1991)

DEG = math.pi / 180.0
# Limits [deg], equal to the generator's (the contract checks them against the URDF).
# The usual 20-DOF hand model (docs/robots/human.md): ab/adduction +-20 index, +-10
# middle, +-20 ring, +-30 little; MCP and PIP -10..90. Thumb: our assumption from
# typical human ranges (docs/robots/human.md).
ABD_LIMIT_DEG = {"index": 20.0, "middle": 10.0, "ring": 20.0, "little": 30.0}
FLEX_LIMITS_DEG = (-10.0, 90.0)
THUMB_LIMITS_DEG = {
    "cmc_abd": (-10.0, 100.0),
    "cmc_flex": (-20.0, 50.0),
    "mcp": (-10.0, 60.0),
    "ip": (-20.0, 80.0),
}
VELOCITY_LIMIT = 5.0  # [rad/s] assumption: fast voluntary finger motion
EFFORT_LIMITS = {  # [N m] assumption, equal to the URDF's
    "abd": 1.0,
    "mcp": 3.0,
    "pip": 1.5,
    "thumb_cmc_abd": 3.0,
    "thumb_cmc_flex": 3.0,
    "thumb_mcp": 2.0,
    "thumb_ip": 1.0,
}


def _joint(name: str, limits_deg: tuple[float, float], effort: float) -> JointSpec:
    return JointSpec(
        f"hh_{name}",
        limits_deg[0] * DEG,
        limits_deg[1] * DEG,
        max_velocity=VELOCITY_LIMIT,
        max_effort=effort,
    )


JOINTS = (
    *(
        _joint(f"thumb_{j}", THUMB_LIMITS_DEG[j], EFFORT_LIMITS[f"thumb_{j}"])
        for j in ("cmc_abd", "cmc_flex", "mcp", "ip")
    ),
    *(
        spec
        for f in FINGERS
        for spec in (
            _joint(f"{f}_abd", (-ABD_LIMIT_DEG[f], ABD_LIMIT_DEG[f]), EFFORT_LIMITS["abd"]),
            _joint(f"{f}_mcp", FLEX_LIMITS_DEG, EFFORT_LIMITS["mcp"]),
            _joint(f"{f}_pip", FLEX_LIMITS_DEG, EFFORT_LIMITS["pip"]),
        )
    ),
)

COUPLINGS = tuple(
    Coupling(f"hh_{f}_dip", f"hh_{f}_pip", DIP_PER_PIP, in_model=True) for f in FINGERS
)

# Postures [deg] per human grasp: the open and the closed posture, one column per joint
# of POSTURE_JOINTS (joint names without the hh_ prefix), and delta [m]: the mean height
# of the five fingertip markers above the palm surface (along palm +z) in the open
# posture, from forward kinematics (a test recomputes it). The mean, not the highest: one
# digit held out of the way (an extended thumb) would dominate.
POSTURE_JOINTS = (
    *(f"{finger}_{joint}" for finger in FINGERS for joint in ("abd", "mcp", "pip")),
    *(f"thumb_{joint}" for joint in ("cmc_abd", "cmc_flex", "mcp", "ip")),
)
# fmt: off
_POSTURES_DEG = {
    #    index           middle          ring            little          thumb (cmc abd, cmc flex)
    #    abd  mcp  pip   abd  mcp  pip   abd  mcp  pip   abd  mcp  pip   abd flex  mcp   ip
    # Bottle, diameter 80 mm, across the palm: fingers curved but open, thumb abducted
    # out of the palm and extended; closing wraps fingers and thumb around it.
    HumanGrasp.LARGE_DIAMETER: (
        (  0,  16,  24,    0,  23,  31,    0,  21,  28,    0,  18,  18,   95, -17,  -4,   9),
        (  0,  47,  63,    0,  59,  74,    0,  57,  69,    0,  52,  52,   95,  -1,  18,  53),
        0.0519,
    ),
    # Handle, diameter 25 mm, across the palm just short of the knuckles: fingers hooked,
    # closing curls them fully round it (MCP 85-90, PIP 90); the thumb comes in (CMC
    # abduction 68 -> 60) and closes over the bar beside the index.
    HumanGrasp.SMALL_DIAMETER: (
        (  0,  21,  38,    0,  42,  58,    0,  43,  61,    0,  37,  52,   68, -14,  10,   5),
        (  0,  85,  90,    0,  90,  90,    0,  90,  90,    0,  85,  90,   60,  -7,  60,  80),
        0.0610,
    ),
    # Cylinder, diameter 50 mm, lying obliquely across the palm: the fingers wrap it, the
    # thumb is not opposed but lies extended along the cylinder axis.
    HumanGrasp.ABDUCTED_THUMB: (
        (  0,  18,  36,    0,  46,  52,    0,  59,  40,    0,  74,  28,   27,   4,  -3,  -9),
        (  0,  55,  90,    0,  84,  90,    0,  90,  76,    0,  90,  54,   36,  15,  25,  -1),
        0.0560,
    ),
    # Small object (a 20 mm ball) between the thumb tip and the index tip, the middle
    # finger alongside the index, turned 8 deg away from it (towards the little finger) so
    # that it meets the object with its tip, if at all; ring and little curled out of the
    # way.
    HumanGrasp.PINCH: (
        (  0,  30,  25,    8,  35,  30,    0,  60,  70,    0,  65,  70,   81,   2,  18,  -1),
        (  0,  42,  58,    8,  47,  63,    0,  60,  70,    0,  65,  70,   95,   8,  30,  18),
        0.0576,
    ),
    # Ball, diameter 90 mm, in the palm: fingers spread and curved, thumb opposed. The ball
    # is reached from above on a table, and an open thumb standing higher above the palm
    # than the ball's diameter meets the table first: the open thumb is curled at the IP,
    # so that the table bends it further round the ball rather than back past its limits.
    HumanGrasp.POWER_SPHERE: (
        (-15,  49,  29,   -4,  34,  33,   10,  35,  31,   22,  57,   6,   90, -20, -10,  40),
        (-15,  68,  44,   -4,  66,  65,   10,  65,  60,   22,  86,  27,  100, -12,  36,  30),
        0.0701,
    ),
    # Disc (lid), diameter 90 mm, held by the fingertips in front of the palm, its
    # centre towards the thumb side: index, middle and ring come down nearly
    # straight beyond the distal rim and curl onto it, the little finger is curled aside;
    # the thumb, extended beside the proximal-radial rim and above the table, closes
    # across it against the fingers. The palm does not touch. Fitted in simulation to the
    # 75, 100 and 125 % discs (tools/human_references.py).
    HumanGrasp.PRECISION_DISC: (
        (-19,  47,  -4,   -4,  34,   8,    9,  32,  16,   20,  60,  44,   51, -20, -10,  78),
        (-19,  33,  78,   -4,  39,  74,    9,  83,  48,   20,  74,  37,   77, -11,   3,  80),
        0.0534,
    ),
}
# fmt: on


def _rad(q_deg: tuple[int, ...]) -> dict[str, float]:
    """A posture row [deg] as joint name -> angle [rad]."""
    return {f"hh_{name}": value * DEG for name, value in zip(POSTURE_JOINTS, q_deg, strict=True)}


# The objects the postures were fitted to, in the palm frame at the 190 mm size: centre
# [m], axis (unit vector; cylinders), radius and length [m]. Where a grasped object sits
# relative to the palm in each posture (the reference grasps are placed from these).
POSTURE_OBJECTS = {
    HumanGrasp.LARGE_DIAMETER.value: {
        "shape": "cylinder",
        "radius": 0.040,
        "length": 0.25,
        "centre": (0.035, -0.005, 0.0405),
        "axis": (-0.1736, 0.9848, 0.0),
    },
    HumanGrasp.SMALL_DIAMETER.value: {
        "shape": "cylinder",
        "radius": 0.0125,
        "length": 0.25,
        "centre": (0.025, -0.005, 0.013),
        "axis": (-0.2588, 0.9659, 0.0),
    },
    HumanGrasp.ABDUCTED_THUMB.value: {
        "shape": "cylinder",
        "radius": 0.025,
        "length": 0.25,
        "centre": (0.0, 0.005, 0.0255),
        "axis": (0.6428, -0.7660, 0.0),
    },
    HumanGrasp.PINCH.value: {
        "shape": "sphere",
        "radius": 0.010,
        "centre": (0.066, -0.0329, 0.0514),
    },
    HumanGrasp.POWER_SPHERE.value: {
        "shape": "sphere",
        "radius": 0.045,
        "centre": (0.030, -0.008, 0.0455),
    },
    HumanGrasp.PRECISION_DISC.value: {
        "shape": "cylinder",
        "radius": 0.045,
        "length": 0.016,
        "centre": (0.0461, -0.0392, 0.06),
        "axis": (0.0, 0.0, 1.0),
    },
}


def _design_object(spec: dict) -> DesignObject:
    return DesignObject(
        shape=spec["shape"],
        centre=tuple(spec["centre"]),
        radius=spec["radius"],
        axis=tuple(spec["axis"]) if "axis" in spec else None,
        length=spec.get("length"),
    )


PRESHAPES = {
    grasp.value: HandPreshape(
        grasp.value,
        _rad(open_deg),
        _rad(closed_deg),
        delta,
        design_object=_design_object(POSTURE_OBJECTS[grasp.value]),
    )
    for grasp, (open_deg, closed_deg, delta) in _POSTURES_DEG.items()
}
GRASP_MAP = {grasp: grasp.value for grasp in HumanGrasp}


def _finger_links(finger: str) -> tuple[str, ...]:
    parts = ("knuckle", "proximal", "intermediate", "distal", "tip")
    return tuple(f"hh_{finger}_{part}" for part in parts)


# Every link belongs to one real finger. The thenar eminence (on the link hh_thumb_cmc,
# which moves only with the CMC abduction) and the finger metacarpals count as palm; the
# moving thumb metacarpal counts as thumb.
REAL_FINGERS = {
    THUMB: ("hh_thumb_metacarpal", "hh_thumb_proximal", "hh_thumb_distal", "hh_thumb_tip"),
    **{finger: _finger_links(finger) for finger in FINGERS},
    PALM: (
        ROOT_LINK,
        PALM_SENSOR_LINK,
        PALM_FRAME,
        "hh_thumb_cmc",
        *(f"hh_{finger}_metacarpal" for finger in FINGERS),
    ),
}

HUMAN = HandDescription(
    name=NAME,
    model_path=model_path(MODEL_FILE),
    root_link=ROOT_LINK,
    joints=JOINTS,
    palm_frame=PALM_FRAME,
    palm_sensor_link=PALM_SENSOR_LINK,
    real_fingers=REAL_FINGERS,
    preshapes=PRESHAPES,
    grasp_map=GRASP_MAP,
    # Moderate muscle-like drives (assumption): stiff enough to hold a posture against
    # gravity within a fraction of a degree, soft enough to conform to an object.
    drive=DriveGains(stiffness=5.0, damping=0.2, force_limit=3.0),
    couplings=COUPLINGS,
    mass=0.464,  # [kg] sum of the URDF's link masses (0.45 kg of shapes + marker links)
    summary="Human right hand (reference), 190 mm: 20 joints, 16 driven + 4 coupled DIP",
    fingertip_frames={digit: f"hh_{digit}_tip" for digit in DIGITS},
)
