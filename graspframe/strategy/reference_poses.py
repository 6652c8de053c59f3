"""Where a human puts the palm, relative to the object, for each of the six grasps.

These are the reference placements used when no image is given (`graspframe run --grasp`)
and for the simulated human reference grasps. Each human posture carries the object it
was shaped for (`HandPreshape.design_object`, in the palm frame); the reference placement
puts the real object where that design object sits, with its centroid at the design
centre, moved along the palm normal by the difference between the real and the design
object's extent (a bigger can sits further from the palm).

Orientation (objects stand upright, z up; palm z out of the palm, x to the fingertips):
- a cylinder lying across the palm (Large/Small Diameter, Abducted Thumb): its axis is
  the object's z, the palm faces the object's +x (the palm normal is horizontal), the
  fingertips point up rather than down (towards the table). An object wider one way
  than the other (a bottle, a box) is held across its narrowest side, as a person
  holds a mustard bottle by its label: the palm turns about the object's z to face it
  along the horizontal direction of its smallest width (the nearest such direction to
  +x; an object symmetric about its z, or one within SIDE_WIDTH_TOLERANCE as narrow
  along x, keeps the palm facing +x, so a cylinder or a square box is held as before);
- a cylinder along the palm normal (a disc) or a ball/block: the palm faces down, palm x
  along the object's x.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import make_T
from graspframe.hal.descriptions import DesignObject, HandPreshape
from graspframe.hal.objects import ObjectDescription

# Columns are the palm axes (x, y, z) in the object frame: palm facing down.
R_OBJECT_PALM_TOP = np.column_stack([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
# An axis this close to the palm normal counts as "along" it (a disc held from above).
AXIS_ALONG_NORMAL_COS = 0.7
# A side grasp turns to the object's narrowest side only when it is this much narrower
# than the object along x [m].
SIDE_WIDTH_TOLERANCE = 0.001
SIDE_YAWS_DEG = tuple(range(-85, 95, 5))  # palm normal directions tried, about the object z


class ReferencePlacement(NamedTuple):
    """T_object_palm: the human palm in the object frame; p_palm_grasp: [m] the human
    grasp point (where the object's centroid sits) in the palm frame."""

    T_object_palm: NDArray[np.float64]
    p_palm_grasp: NDArray[np.float64]


def _unit(v) -> NDArray[np.float64]:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def R_object_palm_for_design(design: DesignObject) -> NDArray[np.float64]:
    """The palm orientation, in the frame of the object standing upright, that holds it
    the way `design` lies in the palm (see the module docstring)."""
    if design.axis is None or abs(_unit(design.axis)[2]) > AXIS_ALONG_NORMAL_COS:
        return R_OBJECT_PALM_TOP
    # Map the palm normal to object +x and the cylinder axis (in the palm plane) to
    # object -z; the third axis follows.
    z_palm = np.array([0.0, 0.0, 1.0])
    u = _unit(design.axis)
    u = _unit(u - (u @ z_palm) * z_palm)
    palm_basis = np.column_stack([z_palm, u, np.cross(z_palm, u)])
    x_obj, minus_z_obj = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, -1.0])
    object_basis = np.column_stack([x_obj, minus_z_obj, np.cross(x_obj, minus_z_obj)])
    R = object_basis @ palm_basis.T
    if R[2, 0] < 0.0:
        # The fingers (palm x) would point down into the table: turn the hand half a
        # turn about its palm normal (the object's x), so the axis maps to +z instead.
        R = np.diag([1.0, -1.0, -1.0]) @ R
    return R


def _design_extent_along_normal(design: DesignObject) -> float:
    if design.axis is not None and abs(_unit(design.axis)[2]) > AXIS_ALONG_NORMAL_COS:
        return (design.length or 0.0) / 2
    return design.radius


def reference_placement(obj: ObjectDescription, posture: HandPreshape) -> ReferencePlacement:
    """The human palm pose in the object frame for `posture` holding `obj`."""
    design = posture.design_object
    if design is None:
        raise DescriptionError(
            f"posture {posture.name!r} has no design_object; the reference placement needs "
            "the object the posture is shaped for"
        )
    R = R_object_palm_for_design(design)
    if abs(R[2, 2]) < 1e-9:  # the palm normal is horizontal: a side grasp
        yaw = _narrowest_side_yaw(obj)
        if yaw:
            R = _Rz(yaw) @ R
    normal_in_object = R[:, 2]
    p_palm_grasp = np.array(design.centre, dtype=float)
    # The object's face towards the palm: its extent back along the palm normal.
    p_palm_grasp[2] += obj.extent_along(-normal_in_object) - _design_extent_along_normal(design)
    return ReferencePlacement(make_T(R, -R @ p_palm_grasp), p_palm_grasp)


def _width(obj: ObjectDescription, yaw: float) -> float:
    """[m] the object's width along the horizontal direction at `yaw` from its x axis."""
    u = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    return obj.extent_along(u) + obj.extent_along(-u)


def _narrowest_side_yaw(obj: ObjectDescription) -> float:
    """[rad] the turn about the object's z that points a horizontal palm normal (object
    +x) across the object's narrowest side (see the module docstring): 0 unless some
    direction is narrower than x by more than SIDE_WIDTH_TOLERANCE."""
    if obj.symmetric_about_z:
        return 0.0
    widths = {np.radians(deg): _width(obj, np.radians(deg)) for deg in SIDE_YAWS_DEG}
    yaw = min(widths, key=lambda a: (widths[a], abs(a)))
    return yaw if widths[yaw] < _width(obj, 0.0) - SIDE_WIDTH_TOLERANCE else 0.0


def _Rz(angle: float) -> NDArray[np.float64]:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
