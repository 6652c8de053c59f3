"""Generator of the Karlsruhe humanoid hand (fluidic, 5 fingers, 8 DOF, a RIGHT hand).

    cd /work/main && python -m tools.robot_models.karlsruhe

writes robots/karlsruhe/karlsruhe.urdf. Sources: the 8-DOF fluidic hand of Gaiser et al.,
"A new anthropomorphic robotic hand", IEEE-RAS Humanoids 2008, and its GraspIt! model
(Miller & Allen, "GraspIt! A versatile simulator for robotic grasping", IEEE RAM 2004) as
used by Romero, Kjellstroem & Kragic, "Modeling and evaluation of human-to-robot mapping
of grasps", ICAR 2009: the finger base positions, the DH values and the thumb transform.
Every other number is marked OUR ASSUMPTION; docs/robots/karlsruhe.md tabulates them.

Frames
- kh_base (root): origin at the wrist mounting interface (centre of the palm's wrist face),
  +z along the fingers (out of the arm flange), +x out of the palm on the palmar side,
  +y across the palm towards the index/thumb side.
- kh_model_frame: the published model frame (x towards the fingers, y out of the palm
  plane on the palmar side, z across the palm from little (-) to index (+)); the published
  finger bases and the thumb transform hold in it exactly.
- Every finger joint turns about the z axis of its DH frame; a positive angle flexes the
  finger towards model +y (palmar). The thumb's first joint raises it out of the palm
  plane (palmar), its second joint swings it onto the index and middle fingers.

Units here: published numbers in mm/deg with a suffix, converted to m/rad for the URDF.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from graspframe.common.transforms import make_T
from tools.robot_models.urdf_builder import Box, Cylinder, Sphere, UrdfBuilder

OUTPUT = Path(__file__).resolve().parents[2] / "robots" / "karlsruhe" / "karlsruhe.urdf"
P = "kh_"  # prefix of every link and joint name

# --- Published (GraspIt! model of the hand), in the model frame [mm, deg] ----------------
# finger -> (base joint position [mm], rotation of the finger chain about model y [deg])
FINGER_BASES_MM_DEG = {
    "index": ((94.0, -1.25, 29.3), -10.0),
    "middle": ((94.3, -1.25, 3.5), 0.0),
    "ring": ((82.0, -1.25, -19.6), 7.5),
    "little": ((70.9, -1.25, -39.3), 10.0),
}
INDEX_MIDDLE_PROXIMAL_MM = 38.3  # DH a of the proximal joint (index, middle)
# Thumb base: translation, then rotations about the MOVING axes z, x, z (intrinsic,
# R = Rz(a) Rx(b) Rz(c)); then two DH joints (theta about z, d along z, a along x,
# alpha about x).
THUMB_BASE_MM = (31.1829, -0.2415, 26.6908)
THUMB_BASE_ZXZ_DEG = (-83.3914, 60.1651, 86.7012)
THUMB_DH = ((0.0, 23.3027, -90.0), (0.0, 0.0, 180.0))  # (d [mm], a [mm], alpha [deg])
JOINT_LOWER_DEG, JOINT_UPPER_DEG = 0.0, 90.0  # all 8 joints

# --- OUR ASSUMPTIONS (the model gives a range or nothing) --------------------------------
# Distal segments, joint -> fingertip [mm]: "about 30-45, human-like proportions". Human
# (middle + distal phalanx) / proximal phalanx is about 0.9-1.1 (index, middle).
INDEX_DISTAL_MM = 40.0
MIDDLE_DISTAL_MM = 42.0
# Ring and little are one rigid link each, joint -> tip. Human-like proportions: a whole
# human ring finger is about 0.95, a little finger about 0.75 of the middle finger (here
# 38.3 + 42 = 80.3 mm from its base joint).
RING_MM = 72.0
LITTLE_MM = 57.0
# Thumb distal segment along x of the frame after joint 2: a human thumb's proximal +
# distal phalanx (~50 mm). With 40 mm the opposed thumb could not reach over the 100 mm
# can and ball (they popped out under it; docs/robots/karlsruhe.md).
THUMB_DISTAL_MM = 50.0
# Finger radii [mm]: below half the narrowest base spacing (ring-little, 19.7 mm).
FINGER_RADIUS_MM = {"thumb": 9.0, "index": 9.0, "middle": 9.0, "ring": 8.5, "little": 8.0}
# Palm body (model frame, mm): 22 mm thick from the back of the hand (y = -14) to y = 8,
# under a 2 mm pad: the palm surface (y = 10) stands 2.25 mm in front of the palmar side
# of the finger bases (y = -1.25 + 9), so the fully hooked index and middle close 18 mm
# above the palm (a 19 mm handle is squeezed). Stepped in x so each finger's flexing base
# clears it (a flexed finger stands one radius in front of its joint); cut out where the
# thumb swings (z > 14 up to the index knuckles, the thenar region); narrow at the wrist,
# so a hand held with the little finger down reaches lower on short objects (the planner
# keeps the whole hand 1 cm above the table).
PALM_Y_MM = (-14.0, 8.0)
PAD_THICKNESS_MM = 2.0
PALM_BOXES_MM = (  # (x range, z range); all share PALM_Y_MM
    ((0.0, 50.0), (-15.0, 14.0)),  # wrist half: narrow (29 mm), like a wrist, not a paddle
    ((50.0, 61.0), (-47.5, 14.0)),  # full width to the little base (70.9 - 8 - 1.4)
    ((61.0, 72.0), (-29.5, 14.0)),  # to the ring base (82 - 8.5 radius - 1.5 clearance)
    ((61.0, 84.0), (-8.0, 39.0)),  # to the index/middle bases (94 - 9 - 1)
)
# Back plate behind the thumb base (dorsal, clear of the thumb's sweep, y <= -9.7).
THENAR_BACK_MM = ((14.0, 61.0), (-14.0, -10.5), (14.0, 40.0))  # x, y, z ranges
# Palm frame origin on the pad's outer face, at the palm's centre: halfway from the wrist
# face to the index/middle bases (x), across the palm at the mean of the four finger
# bases (z).
PALM_CENTRE_X_MM = 47.0
PALM_CENTRE_Z_MM = -6.5
# Masses [kg] (total 0.647 kg; the fluidic hand is light).
MASS_PALM = 0.35
MASS_PAD = 0.01
MASS_PROXIMAL = 0.04  # index, middle
MASS_DISTAL = 0.03  # index, middle
MASS_RING = 0.04
MASS_LITTLE = 0.035
MASS_THUMB_PROXIMAL = 0.035
MASS_THUMB_DISTAL = 0.03
# Drive limits written into the URDF (the description repeats them).
JOINT_EFFORT = 2.0  # [N m] soft fluidic actuators
JOINT_VELOCITY = 2.0  # [rad/s]

MM = 1e-3
LOWER, UPPER = math.radians(JOINT_LOWER_DEG), math.radians(JOINT_UPPER_DEG)
# model frame -> base frame: model x -> base z, model y -> base x, model z -> base y
R_BASE_MODEL = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
# The mounting interface: centre of the wrist face (model x = 0) of the first palm box.
P_MODEL_MOUNT_MM = np.array([0.0, sum(PALM_Y_MM) / 2, sum(PALM_BOXES_MM[0][1]) / 2])


def _Ry(angle_deg: float) -> np.ndarray:
    return Rotation.from_euler("y", angle_deg, degrees=True).as_matrix()


def thumb_base_rotation() -> np.ndarray:
    """Rz(a) Rx(b) Rz(c): the published rotations about the moving axes."""
    return Rotation.from_euler("ZXZ", THUMB_BASE_ZXZ_DEG, degrees=True).as_matrix()


def _xyz_rpy(T: np.ndarray) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """URDF origin (xyz [m], rpy [rad], R = Rz(yaw) Ry(pitch) Rx(roll)) of a transform.

    At pitch = +-90 deg (gimbal lock) roll is set to 0 and yaw carries the rest: the
    opposite of `graspframe.common.transforms.rpy_from_R`, kept because the shipped URDF's
    digits follow it."""
    R = T[:3, :3]
    cos_pitch = math.hypot(R[0, 0], R[1, 0])
    pitch = math.atan2(-R[2, 0], cos_pitch)
    if cos_pitch > 1e-9:
        roll, yaw = math.atan2(R[2, 1], R[2, 2]), math.atan2(R[1, 0], R[0, 0])
    else:
        roll, yaw = 0.0, math.atan2(-R[0, 1], R[1, 1])
    return tuple(T[:3, 3]), (roll, pitch, yaw)


T_BASE_MODEL = make_T(R_BASE_MODEL, -R_BASE_MODEL @ (P_MODEL_MOUNT_MM * MM))


def _model_point(p_mm) -> np.ndarray:
    """A model-frame point [mm] in the base frame [m]."""
    return (T_BASE_MODEL @ np.append(np.asarray(p_mm) * MM, 1.0))[:3]


def _model_box(x_mm, y_mm, z_mm, relative_to=(0.0, 0.0, 0.0)) -> Box:
    """An axis-aligned model-frame box as a shape of a link whose frame has the base
    frame's axes and sits at base point `relative_to` [m]."""
    size_model = np.array([x_mm[1] - x_mm[0], y_mm[1] - y_mm[0], z_mm[1] - z_mm[0]]) * MM
    centre_mm = [sum(x_mm) / 2, sum(y_mm) / 2, sum(z_mm) / 2]
    centre = _model_point(centre_mm) - np.asarray(relative_to)
    return Box(tuple(np.abs(R_BASE_MODEL @ size_model)), tuple(centre))


def _rod(length: float, radius: float, start_sphere: bool, end_sphere: bool, start=0.0) -> list:
    """Shapes along link x: a cylinder from `start`, an optional sphere on the joint (a
    knuckle that fills the gap while the link turns) and a sphere at the end (a knuckle
    centred on the next joint, or, when end_sphere is False, a rounded fingertip whose far
    side is the end)."""
    end = length if end_sphere else length - radius
    shapes = [
        Cylinder(radius, end - start, xyz=((start + end) / 2, 0, 0), rpy=(0, math.pi / 2, 0)),
        Sphere(radius, xyz=(end, 0.0, 0.0)),
    ]
    if start_sphere:
        shapes.insert(0, Sphere(radius, xyz=(0.0, 0.0, 0.0)))
    return shapes


def palm_frame_in_model_mm() -> np.ndarray:
    """Palm frame origin: on the pad's outer (object-side) face, model frame [mm]."""
    return np.array([PALM_CENTRE_X_MM, PALM_Y_MM[1] + PAD_THICKNESS_MM, PALM_CENTRE_Z_MM])


def palm_boxes_mm() -> list[tuple[tuple[float, float], ...]]:
    """(x, y, z) ranges [mm] of the palm body's boxes in the model frame."""
    return [(x, PALM_Y_MM, z) for x, z in PALM_BOXES_MM] + [THENAR_BACK_MM]


def pad_boxes_mm() -> list[tuple[tuple[float, float], ...]]:
    """(x, y, z) ranges [mm] of the pad: the palmar face of every palm box, so an object
    coming at the palm touches the pad (the palm sensor) first."""
    pad_y = (PALM_Y_MM[1], PALM_Y_MM[1] + PAD_THICKNESS_MM)
    return [(x, pad_y, z) for x, z in PALM_BOXES_MM]


def build() -> UrdfBuilder:
    b = UrdfBuilder(
        "karlsruhe",
        comment="Karlsruhe humanoid hand (right), generated by tools/robot_models/karlsruhe.py "
        "from its GraspIt! model (Romero et al., ICAR 2009); do not edit by hand.",
    )
    b.link(f"{P}base", MASS_PALM, [_model_box(*box) for box in palm_boxes_mm()])

    # Published model frame, fixed to the palm.
    b.link(f"{P}model_frame")
    xyz, rpy = _xyz_rpy(T_BASE_MODEL)
    b.joint(f"{P}model_frame_joint", "fixed", f"{P}base", f"{P}model_frame", xyz, rpy)

    # Palm sensor pad on the palmar surface (frame at the palm centre, base axes) and the
    # palm frame on its outer face.
    p_pad = _model_point([PALM_CENTRE_X_MM, PALM_Y_MM[1] + PAD_THICKNESS_MM / 2, 0.0])
    b.link(
        f"{P}palm_pad", MASS_PAD, [_model_box(*box, relative_to=p_pad) for box in pad_boxes_mm()]
    )
    b.joint(f"{P}palm_pad_joint", "fixed", f"{P}base", f"{P}palm_pad", tuple(p_pad))
    # palm x = model x, palm z = model y (palmar), palm y = z x x = -model z
    R_model_palm = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
    T_base_palm = T_BASE_MODEL @ make_T(R_model_palm, palm_frame_in_model_mm() * MM)
    b.link(f"{P}palm_frame")
    xyz, rpy = _xyz_rpy(T_base_palm)
    b.joint(f"{P}palm_frame_joint", "fixed", f"{P}base", f"{P}palm_frame", xyz, rpy)

    limits = {"lower": LOWER, "upper": UPPER, "effort": JOINT_EFFORT, "velocity": JOINT_VELOCITY}

    # Index and middle: proximal (DH a = 38.3, alpha = 0) and distal; ring and little: one
    # rigid link. The chain frame is the model frame turned about y; the joints turn about
    # its z, which flexes the finger towards model +y.
    distal_mm = {"index": INDEX_DISTAL_MM, "middle": MIDDLE_DISTAL_MM}
    whole_mm = {"ring": RING_MM, "little": LITTLE_MM}
    for finger, (p_mm, angle_deg) in FINGER_BASES_MM_DEG.items():
        r = FINGER_RADIUS_MM[finger] * MM
        xyz, rpy = _xyz_rpy(T_BASE_MODEL @ make_T(_Ry(angle_deg), np.asarray(p_mm) * MM))
        if finger in distal_mm:
            prox, dist = f"{P}{finger}_proximal", f"{P}{finger}_distal"
            length_p = INDEX_MIDDLE_PROXIMAL_MM * MM
            length_d = distal_mm[finger] * MM
            b.link(prox, MASS_PROXIMAL, _rod(length_p, r, True, True))
            b.joint(f"{P}{finger}_prox", "revolute", f"{P}base", prox, xyz, rpy, **limits)
            b.link(dist, MASS_DISTAL, _rod(length_d, r, False, False, start=r))
            b.joint(f"{P}{finger}_dist", "revolute", prox, dist, (length_p, 0, 0), **limits)
            tip_parent, tip_x = dist, length_d
        else:
            link = f"{P}{finger}_link"
            mass = MASS_RING if finger == "ring" else MASS_LITTLE
            b.link(link, mass, _rod(whole_mm[finger] * MM, r, True, False))
            b.joint(f"{P}{finger}", "revolute", f"{P}base", link, xyz, rpy, **limits)
            tip_parent, tip_x = link, whole_mm[finger] * MM
        b.link(f"{P}{finger}_tip")
        b.joint(f"{P}{finger}_tip_joint", "fixed", tip_parent, f"{P}{finger}_tip", (tip_x, 0, 0))

    # Thumb, exactly the published chain. Joint 1 turns the base frame about its z; the
    # proximal link frame is that frame (its x along the 23.3 mm segment). Joint 2 sits at
    # the segment's end, its frame turned by alpha_1 about x; the distal link frame is
    # frame 2 before its alpha (d_2 = a_2 = 0; alpha_2 = 180 deg only flips y and z of
    # frame 2, x stays along the distal segment).
    r = FINGER_RADIUS_MM["thumb"] * MM
    xyz, rpy = _xyz_rpy(
        T_BASE_MODEL @ make_T(thumb_base_rotation(), np.asarray(THUMB_BASE_MM) * MM)
    )
    (d1, a1, alpha1), _ = THUMB_DH
    prox, dist = f"{P}thumb_proximal", f"{P}thumb_distal"
    length_d = THUMB_DISTAL_MM * MM
    b.link(prox, MASS_THUMB_PROXIMAL, _rod(a1 * MM, r, True, True))
    b.joint(f"{P}thumb_base", "revolute", f"{P}base", prox, xyz, rpy, **limits)
    b.link(dist, MASS_THUMB_DISTAL, _rod(length_d, r, False, False, start=r))
    b.joint(
        f"{P}thumb_flex",
        "revolute",
        prox,
        dist,
        (a1 * MM, 0.0, d1 * MM),
        (math.radians(alpha1), 0.0, 0.0),
        **limits,
    )
    b.link(f"{P}thumb_tip")
    b.joint(f"{P}thumb_tip_joint", "fixed", dist, f"{P}thumb_tip", (length_d, 0, 0))
    return b


def main(path: Path = OUTPUT) -> Path:
    written = build().write(path)
    print(f"wrote {written}")
    return written


if __name__ == "__main__":
    main()
