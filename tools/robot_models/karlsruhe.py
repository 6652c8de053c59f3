"""Generator of the Karlsruhe humanoid hand (fluidic, 5 fingers, 8 DOF, a RIGHT hand).

    cd /work/main && python -m tools.robot_models.karlsruhe

writes robots/karlsruhe/karlsruhe.urdf. Every number comes from /work/shared/ROBOTS.md,
row "Karlsruhe humanoid hand", or is marked as OUR ASSUMPTION; docs/robots/karlsruhe.md
tabulates them.

Frames
- kh_base (root): origin at the wrist mounting interface (centre of the palm's wrist face),
  +z along the fingers (out of the arm flange), +x out of the palm on the palmar side,
  +y across the palm towards the index/thumb side.
- kh_model_frame: the published "model frame" (x towards the fingers, y out of the palm
  plane, z across the palm from little (-) to index (+)); the published finger-base
  coordinates hold in it exactly.
- Palmar side = model +y. The published frame is right-handed (the splay rotations -10 deg
  (index) and +10 deg (little) about y turn the outer fingers away from the middle only in a
  right-handed frame), and in a right-handed frame with x to the fingers and z to the thumb
  of a RIGHT hand, y = z x x points out of the palm (look at your right palm, fingers up:
  the thumb is on the right, and right x up = towards you).
- Every finger joint frame: x along the finger, y palmar, z = x cross y; joints turn about
  +z, so a positive angle flexes towards the palm.

Units here: published numbers in mm/deg with a suffix, converted to m/rad for the URDF.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from tools.robot_models.urdf_builder import Box, Cylinder, Sphere, UrdfBuilder

OUTPUT = Path(__file__).resolve().parents[2] / "robots" / "karlsruhe" / "karlsruhe.urdf"
P = "kh_"  # prefix of every link and joint name

# --- Published (ROBOTS.md, "Karlsruhe humanoid hand"), in the model frame ---------------
# finger -> (base joint position [mm], rotation of the base joint frame about model y [deg])
FINGER_BASES_MM_DEG = {
    "index": ((94.0, -1.25, 29.3), -10.0),
    "middle": ((94.3, -1.25, 3.5), 0.0),
    "ring": ((82.0, -1.25, -19.6), 7.5),
    "little": ((70.9, -1.25, -39.3), 10.0),
}
THUMB_BASE_MM = (31.2, -0.24, 26.7)
THUMB_AXIS_TILT_DEG = 60.0  # thumb base axis out of the palm plane ("roughly 60 deg")
THUMB_PROXIMAL_MM = 23.3
INDEX_MIDDLE_PROXIMAL_MM = 38.3
JOINT_LOWER_DEG, JOINT_UPPER_DEG = 0.0, 90.0  # all 8 joints

# --- OUR ASSUMPTIONS (ROBOTS.md is silent or gives a range) -----------------------------
# Lengths joint -> fingertip [mm]. ROBOTS.md: "about 30-45, human-like proportions".
# Distal = middle + distal phalanx; human ratios (ROBOTS.md, Buchholz) to the proximal
# phalanx are 0.91 (index) and 1.0 (middle).
INDEX_DISTAL_MM = 35.0
MIDDLE_DISTAL_MM = 38.0
# Ring and little are one rigid link each; human-like means as long as the whole human
# finger relative to the middle one (0.96 and 0.75 of the middle finger's 76.3 mm), longer
# than ROBOTS.md's "about 30-45", which would leave them stubs beside a 76 mm middle finger.
RING_MM = 72.0
LITTLE_MM = 57.0
# Thumb: base joint -> tip is 23.3 + 35 = 58.3 mm, about a human thumb's two phalanges at
# this hand's size (0.354 x 171 mm hand length = 60 mm); 40 mm would let the straight thumb
# hit the index knuckle while it swings across the palm.
THUMB_DISTAL_MM = 35.0
# Finger radii [mm]: the base spacing (19.7 mm ring-little) bounds them.
FINGER_RADIUS_MM = {"thumb": 9.5, "index": 9.0, "middle": 9.0, "ring": 8.5, "little": 8.0}
# Thumb: at q = 0 it lies in the palm plane, alongside the index, turned this far from
# model x towards the radial side (+z).
THUMB_REST_ANGLE_DEG = 30.0
# In-plane direction of the tilted base axis, measured from the rest thumb direction
# towards +z. At 40 deg the 90 deg thumb points 41 deg out of the palm plane (49 deg would
# give the most, 41.4; 40 deg keeps the opposed thumb a little more towards the fingers).
THUMB_AXIS_AZIMUTH_DEG = 40.0
# Palm (model frame, mm): 26 mm thick, symmetric about the model y = 0 plane; boxes
# stepped so each ends ~4 mm past the finger bases it carries; the radial side is cut out
# where the thumb swings (the thenar region of a human palm).
PALM_Y_MM = (-13.0, 13.0)
PALM_BOXES_MM = (  # (x range, y range, z range)
    ((0.0, 75.0), PALM_Y_MM, (-48.5, 0.0)),  # wrist to little base, up to the thumb's sweep
    ((70.0, 89.0), PALM_Y_MM, (-29.0, 0.0)),  # ring knuckle, to the ring base
    ((89.0, 98.0), PALM_Y_MM, (-29.0, 39.0)),  # middle/index knuckles, +-4..5 mm about them
)
PAD_THICKNESS_MM = 2.0
PAD_X_MM = (10.0, 61.0)  # clear of the flexed little finger (x >= 62.9)
PAD_Z_MM = (-44.0, -1.0)  # clear of the thumb's sweep
# Palm frame origin on the pad's outer face, at the palm's centre: halfway from the wrist
# face to the index/middle bases, across the palm at the mean of the four finger bases.
PALM_CENTRE_X_MM = 47.0
PALM_CENTRE_Z_MM = -6.5
# Masses [kg] (total ~0.65 kg; the fluidic hand is light).
MASS_PALM = 0.35
MASS_PAD = 0.01
MASS_PROXIMAL = 0.04  # index, middle
MASS_DISTAL = 0.03  # index, middle
MASS_RING = 0.05
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
P_MODEL_MOUNT_MM = np.array([0.0, sum(PALM_BOXES_MM[0][1]) / 2, sum(PALM_BOXES_MM[0][2]) / 2])


def _T(R: np.ndarray, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def _Ry(angle_deg: float) -> np.ndarray:
    return Rotation.from_euler("y", angle_deg, degrees=True).as_matrix()


def _xyz_rpy(T: np.ndarray) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """URDF origin (xyz [m], rpy [rad], R = Rz(yaw) Ry(pitch) Rx(roll)) of a transform.

    Finger frames have x along base z, so pitch is -90 deg (gimbal lock): roll is then set
    to 0 and the yaw carries the whole remaining rotation."""
    R = T[:3, :3]
    cos_pitch = math.hypot(R[0, 0], R[1, 0])
    pitch = math.atan2(-R[2, 0], cos_pitch)
    if cos_pitch > 1e-9:
        roll, yaw = math.atan2(R[2, 1], R[2, 2]), math.atan2(R[1, 0], R[0, 0])
    else:
        roll, yaw = 0.0, math.atan2(-R[0, 1], R[1, 1])
    return tuple(T[:3, 3]), (roll, pitch, yaw)


T_BASE_MODEL = _T(R_BASE_MODEL, -R_BASE_MODEL @ (P_MODEL_MOUNT_MM * MM))


def _model_point(p_mm) -> np.ndarray:
    """A model-frame point [mm] in the base frame [m]."""
    return (T_BASE_MODEL @ np.append(np.asarray(p_mm) * MM, 1.0))[:3]


def _model_box(x_mm, y_mm, z_mm) -> Box:
    """An axis-aligned model-frame box, as a shape of kh_base (axes permuted, no rotation)."""
    size_model = np.array([x_mm[1] - x_mm[0], y_mm[1] - y_mm[0], z_mm[1] - z_mm[0]]) * MM
    centre_mm = [sum(x_mm) / 2, sum(y_mm) / 2, sum(z_mm) / 2]
    return Box(tuple(np.abs(R_BASE_MODEL @ size_model)), tuple(_model_point(centre_mm)))


def _rod(length: float, radius: float, knuckle: bool, start: float = 0.0) -> list:
    """Shapes along link x from `start`: a cylinder, then a sphere at its end (a rounded
    fingertip, or a knuckle centred on the next joint that fills the gap when it flexes)."""
    end = length if knuckle else length - radius  # a fingertip is the sphere's far side
    return [
        Cylinder(radius, end - start, xyz=((start + end) / 2, 0, 0), rpy=(0, math.pi / 2, 0)),
        Sphere(radius, xyz=(end, 0.0, 0.0)),
    ]


def palm_frame_in_model_mm() -> np.ndarray:
    """Palm frame origin: on the pad's outer (object-side) face, model frame [mm]."""
    return np.array([PALM_CENTRE_X_MM, PALM_Y_MM[1] + PAD_THICKNESS_MM, PALM_CENTRE_Z_MM])


def build() -> UrdfBuilder:
    b = UrdfBuilder(
        "karlsruhe",
        comment="Karlsruhe humanoid hand (right), generated by tools/robot_models/karlsruhe.py "
        "from the published numbers in ROBOTS.md; do not edit by hand.",
    )
    b.link(f"{P}base", MASS_PALM, [_model_box(*box) for box in PALM_BOXES_MM])

    # Published model frame, fixed to the palm.
    b.link(f"{P}model_frame")
    xyz, rpy = _xyz_rpy(T_BASE_MODEL)
    b.joint(f"{P}model_frame_joint", "fixed", f"{P}base", f"{P}model_frame", xyz, rpy)

    # Palm sensor pad on the palmar surface and the palm frame on its outer face.
    pad = _model_box(PAD_X_MM, (PALM_Y_MM[1], PALM_Y_MM[1] + PAD_THICKNESS_MM), PAD_Z_MM)
    b.link(f"{P}palm_pad", MASS_PAD, [Box(pad.size)])
    b.joint(f"{P}palm_pad_joint", "fixed", f"{P}base", f"{P}palm_pad", pad.xyz)
    # palm x = model x, palm z = model y (palmar), palm y = z x x = -model z
    R_model_palm = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
    T_base_palm = T_BASE_MODEL @ _T(R_model_palm, palm_frame_in_model_mm() * MM)
    b.link(f"{P}palm_frame")
    xyz, rpy = _xyz_rpy(T_base_palm)
    b.joint(f"{P}palm_frame_joint", "fixed", f"{P}base", f"{P}palm_frame", xyz, rpy)

    joint_limits = {
        "lower": LOWER,
        "upper": UPPER,
        "effort": JOINT_EFFORT,
        "velocity": JOINT_VELOCITY,
    }

    # Index and middle: proximal and distal; ring and little: one rigid link.
    distal_mm = {"index": INDEX_DISTAL_MM, "middle": MIDDLE_DISTAL_MM}
    whole_mm = {"ring": RING_MM, "little": LITTLE_MM}
    for finger, (p_mm, angle_deg) in FINGER_BASES_MM_DEG.items():
        r = FINGER_RADIUS_MM[finger] * MM
        T_base_joint = T_BASE_MODEL @ _T(_Ry(angle_deg), np.asarray(p_mm) * MM)
        xyz, rpy = _xyz_rpy(T_base_joint)
        if finger in distal_mm:
            prox, dist = f"{P}{finger}_proximal", f"{P}{finger}_distal"
            length_p = INDEX_MIDDLE_PROXIMAL_MM * MM
            length_d = distal_mm[finger] * MM
            b.link(prox, MASS_PROXIMAL, _rod(length_p, r, knuckle=True))
            b.joint(f"{P}{finger}_prox", "revolute", f"{P}base", prox, xyz, rpy, **joint_limits)
            b.link(dist, MASS_DISTAL, _rod(length_d, r, knuckle=False, start=r))
            b.joint(f"{P}{finger}_dist", "revolute", prox, dist, (length_p, 0, 0), **joint_limits)
            tip_parent, tip_x = dist, length_d
        else:
            link = f"{P}{finger}_link"
            mass = MASS_RING if finger == "ring" else MASS_LITTLE
            b.link(link, mass, _rod(whole_mm[finger] * MM, r, knuckle=False))
            b.joint(f"{P}{finger}", "revolute", f"{P}base", link, xyz, rpy, **joint_limits)
            tip_parent, tip_x = link, whole_mm[finger] * MM
        b.link(f"{P}{finger}_tip")
        b.joint(f"{P}{finger}_tip_joint", "fixed", tip_parent, f"{P}{finger}_tip", (tip_x, 0, 0))

    # Thumb: the base joint frame has x along the thumb at rest (in the palm plane, turned
    # THUMB_REST_ANGLE_DEG towards +z), y palmar. Its axis leans THUMB_AXIS_TILT_DEG out of
    # the palm plane (towards palmar); turning it swings the thumb across the palm and up.
    r = FINGER_RADIUS_MM["thumb"] * MM
    T_base_thumb = T_BASE_MODEL @ _T(_Ry(-THUMB_REST_ANGLE_DEG), np.asarray(THUMB_BASE_MM) * MM)
    xyz, rpy = _xyz_rpy(T_base_thumb)
    tilt, azimuth = math.radians(THUMB_AXIS_TILT_DEG), math.radians(THUMB_AXIS_AZIMUTH_DEG)
    axis = (math.cos(tilt) * math.cos(azimuth), math.sin(tilt), math.cos(tilt) * math.sin(azimuth))
    prox, dist = f"{P}thumb_proximal", f"{P}thumb_distal"
    length_p, length_d = THUMB_PROXIMAL_MM * MM, THUMB_DISTAL_MM * MM
    b.link(prox, MASS_THUMB_PROXIMAL, _rod(length_p, r, knuckle=True))
    b.joint(f"{P}thumb_base", "revolute", f"{P}base", prox, xyz, rpy, axis, **joint_limits)
    b.link(dist, MASS_THUMB_DISTAL, _rod(length_d, r, knuckle=False, start=r))
    b.joint(f"{P}thumb_flex", "revolute", prox, dist, (length_p, 0, 0), **joint_limits)
    b.link(f"{P}thumb_tip")
    b.joint(f"{P}thumb_tip_joint", "fixed", dist, f"{P}thumb_tip", (length_d, 0, 0))
    return b


def main(path: Path = OUTPUT) -> Path:
    written = build().write(path)
    print(f"wrote {written}")
    return written


if __name__ == "__main__":
    main()
