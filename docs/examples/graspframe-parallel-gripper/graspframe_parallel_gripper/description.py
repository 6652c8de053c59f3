"""The parallel gripper as graspframe sees it: joints, frames, preshapes, mapping.

Model: parallel_gripper.urdf next to this file. Two jaws on prismatic joints, each driven
on its own; a joint's value is its closing travel [m] (0 = open, 0.05 = closed), so
"closing" means increasing the value, as graspframe's hand drivers expect.

Frames (the graspframe convention):
- root `pg_base`: origin at the mounting interface, +z away from the arm, so the gripper
  mounts on any arm flange with an identity transform;
- palm frame `pg_palm_frame`: origin at the centre of the palm surface, +z out of the
  palm towards the object. A gripper's fingertips point along +z, so +x is taken along
  the jaw stroke (the axis the jaws close on, as the Barrett's thumb opposes its fingers
  along its palm x): a side grasp then closes the jaws horizontally around an upright
  object.

Prismatic joints: limits are in metres, velocities in m/s, efforts in N, and the drive
gains below read as N/m, N s/m and N.
"""

from __future__ import annotations

from pathlib import Path

from graspframe.grasps import PALM, HumanGrasp
from graspframe.hal.descriptions import (
    FINGERTIP_FRAMES_KEY,
    DesignObject,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
)

MODEL_PATH = Path(__file__).with_name("parallel_gripper.urdf")

ROOT_LINK = "pg_base"
PALM_FRAME = "pg_palm_frame"
PALM_PAD = "pg_palm_pad"
LEFT_JAW = "pg_left_jaw_joint"
RIGHT_JAW = "pg_right_jaw_joint"
FINGERTIP_FRAMES = {"left": "pg_left_tip", "right": "pg_right_tip"}

STROKE = 0.05  # [m] travel of each jaw: the opening goes from 100 mm to 0

# Limits equal the URDF's (the contract checks compare them).
JOINTS = (
    JointSpec(LEFT_JAW, 0.0, STROKE, max_velocity=0.1, max_effort=40.0),
    JointSpec(RIGHT_JAW, 0.0, STROKE, max_velocity=0.1, max_effort=40.0),
)


def jaws_at(opening: float) -> dict[str, float]:
    """Joint values [m] for a gap of `opening` [m] between the jaws' inner faces."""
    travel = STROKE - opening / 2.0
    return {LEFT_JAW: travel, RIGHT_JAW: travel}


# Preshapes. Closed targets are "fully closed": on an object the jaws stop at its surface
# and the drive squeezes with stiffness * (remaining travel), up to the force limit.
# delta [m]: fingertip height above the palm surface in the open preshape. The jaws slide
# parallel to the palm, so it is the same in both: the 53 mm jaw plus the 2 mm it clears
# the palm pad by; a test checks it by forward kinematics. The design object of a
# preshape is what it is shaped for, where it sits in the palm frame when held: between
# the jaw pads, 20 mm below their tips (the planner puts every object's centroid there;
# graspframe check-hand tests the gripper alone holds it). Its axis lies across the
# stroke (palm y), so the jaws close on its sides.
DELTA = 0.055
GRASP_CENTER = (0.0, 0.0, DELTA - 0.02)
ACROSS_THE_STROKE = (0.0, 1.0, 0.0)
OPPOSED = (("left", "right"),)

PRESHAPES = {
    p.name: p
    for p in (
        # Fully open (100 mm): cans, balls, discs and handles, up to about 9 cm.
        HandPreshape(
            "open_wide",
            jaws_at(0.100),
            jaws_at(0.0),
            DELTA,
            design_object=DesignObject(
                "cylinder", GRASP_CENTER, 0.035, axis=ACROSS_THE_STROKE, length=0.10
            ),
            opposed=OPPOSED,
        ),
        # Opened to 40 mm: small objects held between the jaw pads.
        HandPreshape(
            "pinch",
            jaws_at(0.040),
            jaws_at(0.0),
            DELTA,
            design_object=DesignObject(
                "cylinder", GRASP_CENTER, 0.0125, axis=ACROSS_THE_STROKE, length=0.05
            ),
            opposed=OPPOSED,
        ),
    )
}

# Every human grasp needs an entry: a gripper has no wrap, so only the small objects of
# the pinch use the narrow preshape.
GRASP_MAP = {
    HumanGrasp.LARGE_DIAMETER: "open_wide",
    HumanGrasp.SMALL_DIAMETER: "open_wide",
    HumanGrasp.ABDUCTED_THUMB: "open_wide",
    HumanGrasp.PINCH: "pinch",
    HumanGrasp.POWER_SPHERE: "open_wide",
    HumanGrasp.PRECISION_DISC: "open_wide",
}

REAL_FINGERS = {
    "left": ("pg_left_jaw", "pg_left_tip"),
    "right": ("pg_right_jaw", "pg_right_tip"),
    PALM: (ROOT_LINK, PALM_PAD, PALM_FRAME),
}

PARALLEL_GRIPPER = HandDescription(
    name="parallel_gripper",
    model_path=MODEL_PATH,
    root_link=ROOT_LINK,
    joints=JOINTS,
    palm_frame=PALM_FRAME,
    palm_sensor_link=PALM_PAD,
    real_fingers=REAL_FINGERS,
    preshapes=PRESHAPES,
    grasp_map=GRASP_MAP,
    # Position-controlled jaws: 2000 N/m squeezes a 25 mm block with about 25 N per jaw,
    # limited to 40 N (the joint effort); damping near critical for a 40 g jaw.
    drive=DriveGains(stiffness=2000.0, damping=20.0, force_limit=40.0),
    mass=0.59,
    summary="a two-finger parallel gripper: 100 mm stroke, two prismatic jaws",
    extras={FINGERTIP_FRAMES_KEY: FINGERTIP_FRAMES},
)
