"""Generate robots/kuka/kuka.urdf: the KUKA KR 5 sixx R850 arm (6 DOF).

    cd /work/main && python -m tools.robot_models.kuka [OUTPUT.urdf]

Kinematics come from the modified (Craig) DH table of the KR 5 spec (docs/robots/kuka.md):
the generator evaluates the DH frames at the zero pose and places each URDF joint on its DH
axis, with every link frame parallel to the base frame at the zero pose. So the URDF joint
angles are KUKA's A1..A6 values (theta_i = A_i + theta offset) and the axis directions are
the DH z axes:
A1 +z, A2 +y, A3 +y, A4 +x, A5 +y, A6 +x (base frame, zero pose = arm stretched forward).
Joint limits are read from the plugin's description (plugins/graspframe_kuka), so the
model and the description cannot disagree. Collision shapes and masses are assumptions.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from graspframe_kuka.description import JOINTS

from tools.robot_models.urdf_builder import Box, Cylinder, UrdfBuilder

OUTPUT = Path(__file__).resolve().parents[2] / "robots" / "kuka" / "kuka.urdf"

# KR 5 spec (docs/robots/kuka.md), modified DH (Craig), one row per joint A1..A6:
# alpha_{i-1} [deg], a_{i-1} [mm], d_i [mm], theta offset [deg].
DH_TABLE = (
    (0.0, 0.0, 335.0, 0.0),
    (-90.0, 75.0, 0.0, 0.0),
    (0.0, 365.0, 0.0, -90.0),
    (-90.0, 90.0, 405.0, 0.0),
    (90.0, 0.0, 0.0, 0.0),
    (-90.0, 0.0, 80.0, 180.0),
)

# Where each URDF joint sits on its DH axis: a shift [m] along the axis from the DH frame
# origin (kinematically free; chosen so that each link body sits where the real one is).
AXIS_SHIFTS = (
    -0.235,  # A1: at the top of the fixed foot, z = 0.100 (assumption: foot height)
    0.0,  # A2: shoulder
    0.0,  # A3: elbow
    -0.405,  # A4: DH origin is the wrist point; put the joint at the elbow end of the forearm
    0.0,  # A5: wrist point
    -0.080,  # A6: DH origin is the flange centre; put the joint at the wrist point
)

# Assumption: masses [kg] sharing the arm's about 29 kg (KUKA data sheet figure, not in
# the KR 5 spec's axis data): heavy foot and carousel (A1/A2 motors), lighter outer links.
MASSES = {
    "kr5_base": 7.0,
    "kr5_link_1": 7.0,
    "kr5_link_2": 5.0,
    "kr5_link_3": 4.5,
    "kr5_link_4": 3.5,
    "kr5_link_5": 1.5,
    "kr5_link_6": 0.5,
}

_ALONG_X = (0.0, math.pi / 2, 0.0)  # rpy turning a cylinder's axis (local z) onto x
_ALONG_Y = (math.pi / 2, 0.0, 0.0)  # ... onto y

# Assumption: collision shapes [m] roughly following the real silhouette, in each link's
# frame (origin on its joint axis, axes parallel to the base frame at the zero pose).
SHAPES = {
    "kr5_base": [
        Box((0.22, 0.22, 0.03), xyz=(0.0, 0.0, 0.015)),  # foot plate
        Cylinder(0.09, 0.10, xyz=(0.0, 0.0, 0.05)),  # A1 housing
    ],
    "kr5_link_1": [
        Cylinder(0.085, 0.17, xyz=(0.0, 0.0, 0.085)),  # carousel
        Cylinder(0.075, 0.20, xyz=(0.075, 0.0, 0.235), rpy=_ALONG_Y),  # A2 housing
    ],
    "kr5_link_2": [
        Box((0.30, 0.07, 0.10), xyz=(0.1825, 0.0, 0.0)),  # upper arm, between the housings
    ],
    "kr5_link_3": [
        Cylinder(0.065, 0.15, rpy=_ALONG_Y),  # A3 housing
        Cylinder(0.06, 0.16, xyz=(0.0, 0.0, 0.09), rpy=_ALONG_X),  # A4 motor housing
    ],
    "kr5_link_4": [
        Cylinder(0.05, 0.25, xyz=(0.205, 0.0, 0.0), rpy=_ALONG_X),  # forearm tube
        Box((0.10, 0.13, 0.07), xyz=(0.38, 0.0, 0.0)),  # wrist fork around A5
    ],
    "kr5_link_5": [
        Cylinder(0.04, 0.09, rpy=_ALONG_Y),  # A5 housing
        Cylinder(0.035, 0.05, xyz=(0.035, 0.0, 0.0), rpy=_ALONG_X),  # towards the flange
    ],
    "kr5_link_6": [
        Cylinder(0.032, 0.02, xyz=(0.07, 0.0, 0.0), rpy=_ALONG_X),  # flange disc
    ],
}


def _dh_transform(alpha: float, a: float, theta: float, d: float) -> np.ndarray:
    """Craig's modified DH: Rot_x(alpha) Trans_x(a) Rot_z(theta) Trans_z(d)."""
    ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array(
        [
            [ct, -st, 0.0, a],
            [st * ca, ct * ca, -sa, -sa * d],
            [st * sa, ct * sa, ca, ca * d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def dh_frames_at_zero() -> list[np.ndarray]:
    """T_base_i of the DH frames 1..6 with all axis values A_i = 0 [m]."""
    frames, T = [], np.eye(4)
    for alpha_deg, a_mm, d_mm, offset_deg in DH_TABLE:
        T = T @ _dh_transform(
            math.radians(alpha_deg), a_mm / 1000, math.radians(offset_deg), d_mm / 1000
        )
        frames.append(T)
    return frames


def _rpy_of(R: np.ndarray) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw of a rotation matrix (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.hypot(R[0, 0], R[1, 0]) < 1e-9:  # pitch = +-90 deg: put the whole turn in roll
        return math.atan2(-R[1, 2], R[1, 1]), pitch, 0.0
    return math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0])


def _clean(v) -> tuple[float, ...]:
    """Round away floating-point noise so the output is tidy and deterministic."""
    return tuple(float(x) + 0.0 for x in np.round(np.asarray(v, dtype=float), 9))


def build() -> UrdfBuilder:
    b = UrdfBuilder(
        "kuka",
        comment="KUKA KR 5 sixx R850, generated by tools/robot_models/kuka.py from the KR 5 "
        "spec (docs/robots/kuka.md); "
        "joint angles = KUKA A1..A6; collision-only primitives, masses are assumptions",
    )
    frames = dh_frames_at_zero()
    links = ["kr5_base"] + [f"kr5_link_{i}" for i in range(1, 7)]
    for link in links:
        b.link(link, MASSES[link], SHAPES[link])
    b.link("kr5_flange")

    previous = np.zeros(3)  # origin of the parent link, base frame at the zero pose
    for i, (spec, T) in enumerate(zip(JOINTS, frames, strict=True)):
        axis = T[:3, 2]
        origin = T[:3, 3] + AXIS_SHIFTS[i] * axis
        b.joint(
            spec.name,
            "revolute",
            links[i],
            links[i + 1],
            xyz=_clean(origin - previous),
            axis=_clean(axis),
            lower=spec.lower,
            upper=spec.upper,
            effort=spec.max_effort,
            velocity=spec.max_velocity,
        )
        previous = origin
    # Flange (tool0-style): the DH frame 6, whose z points out of the flange.
    T6 = frames[-1]
    b.joint(
        "kr5_flange_joint",
        "fixed",
        links[-1],
        "kr5_flange",
        xyz=_clean(T6[:3, 3] - previous),
        rpy=_clean(_rpy_of(T6[:3, :3])),
    )
    return b


def main(argv: list[str]) -> None:
    out = Path(argv[0]) if argv else OUTPUT
    path = build().write(out)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(sys.argv[1:])
