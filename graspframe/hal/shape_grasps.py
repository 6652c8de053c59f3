"""The grasp a person would use on an object, from its measured shape, for objects whose
files say nothing about it (docs/objects.md, "Grasps from the shape").

The object is measured as it rests on the table (its frame at the centroid, z up): its
height h, its narrowest horizontal width w (over every direction about z, 5 deg apart),
its width across that direction W, its largest extent L = max(h, W) and how much of its
bounding box it fills (volume / (w W h)). The first rule that matches decides:

1. sphere-like (h, w and W within 25 % of each other, and filling at most 65 % of the box:
   a ball fills 52 %, an upright cylinder as tall as wide 79 %, a cube 100 %): a power
   sphere, or a pinch when smaller than 5 cm across;
2. a flat disc (h at most half of w, and a round or square plan, w at least 0.8 W): a
   precision disc;
3. a small block (L at most 8 cm): a pinch;
4. standing up (h at least W: taller than it is wide), cylinder-like: a small diameter
   grasp when w is at most 4 cm (a handle), else a large diameter grasp (a can, a
   bottle);
5. lying down (h below W): a pinch when h is at most 5 cm (a banana, a pen), else a
   large diameter grasp across its narrowest side.

Thresholds from the method's grasp table (docs/method.md: a handle 2-3 cm, a can 7-9 cm,
a ball 8-10 cm, every object about 10 cm) and the default objects; our choice where the
table is silent.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from graspframe.common.grasps import HumanGrasp

if TYPE_CHECKING:  # objects.py asks this module when an object names no grasp
    from graspframe.hal.objects import ObjectDescription

SPHERE_ASPECT = 1.25  # largest / smallest of h, w, W
SPHERE_MAX_FILL = 0.65
SMALL_SPHERE = 0.05  # [m] across: smaller balls are pinched
DISC_MAX_THICKNESS = 0.5  # h / w
DISC_MIN_ROUNDNESS = 0.8  # w / W
SMALL_BLOCK = 0.08  # [m] largest extent of a pinched block
HANDLE_MAX_WIDTH = 0.04  # [m] narrowest width of a small-diameter (handle) grasp
THIN_LYING = 0.05  # [m] height of a lying object picked with a pinch
YAW_STEP_DEG = 5


class ShapeMeasures(NamedTuple):
    """The measures of the rule [m]: height, narrowest and across widths, fill [-]."""

    height: float
    narrow: float
    across: float
    fill: float

    @property
    def largest(self) -> float:
        return max(self.height, self.across)


def _width(obj: ObjectDescription, yaw_deg: float) -> float:
    u = np.array([math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg)), 0.0])
    return obj.extent_along(u) + obj.extent_along(-u)


def shape_measures(obj: ObjectDescription) -> ShapeMeasures:
    """The object's height, narrowest width, width across it and fill (module docstring)."""
    height = obj.extent_along((0.0, 0.0, 1.0)) + obj.extent_along((0.0, 0.0, -1.0))
    widths = {yaw: _width(obj, yaw) for yaw in range(0, 180, YAW_STEP_DEG)}
    narrow_yaw = min(widths, key=lambda yaw: widths[yaw])
    narrow, across = widths[narrow_yaw], _width(obj, narrow_yaw + 90)
    fill = obj.volume / max(narrow * across * height, 1e-12)
    return ShapeMeasures(height, narrow, across, fill)


def grasp_from_shape(obj: ObjectDescription) -> tuple[HumanGrasp, str]:
    """(the grasp, the rule that chose it in words) for an object (module docstring)."""
    m = shape_measures(obj)
    size = f"{1000 * m.height:.0f} mm tall, {1000 * m.narrow:.0f} x {1000 * m.across:.0f} mm"
    extents = (m.height, m.narrow, m.across)
    if max(extents) <= SPHERE_ASPECT * min(extents) and m.fill <= SPHERE_MAX_FILL:
        if max(extents) < SMALL_SPHERE:
            return HumanGrasp.PINCH, f"a small ball ({size})"
        return HumanGrasp.POWER_SPHERE, f"sphere-like ({size}, fills {100 * m.fill:.0f} %)"
    if m.height <= DISC_MAX_THICKNESS * m.narrow and m.narrow >= DISC_MIN_ROUNDNESS * m.across:
        return HumanGrasp.PRECISION_DISC, f"a flat disc ({size})"
    if m.largest <= SMALL_BLOCK:
        return HumanGrasp.PINCH, f"a small block ({size})"
    if m.height >= m.across:
        if m.narrow <= HANDLE_MAX_WIDTH:
            return HumanGrasp.SMALL_DIAMETER, f"standing, as thin as a handle ({size})"
        return HumanGrasp.LARGE_DIAMETER, f"standing, cylinder-like ({size})"
    if m.height <= THIN_LYING:
        return HumanGrasp.PINCH, f"lying down, thin ({size})"
    return HumanGrasp.LARGE_DIAMETER, f"lying down ({size})"
