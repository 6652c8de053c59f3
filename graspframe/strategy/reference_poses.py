"""Where a human puts the palm, relative to the object, for each of the six grasps.

These are the reference placements used when no image is given (`graspframe run
--grasp ...`) and for the simulated human reference grasps. Objects stand upright with
their frame at the centroid (z up). Palm frame: +z out of the palm, +x towards the
fingertips; for a right hand the thumb is on the -y side.

- Large and Small Diameter: the hand upright beside the cylinder, palm facing its axis
  (palm z = object +x), thumb up (palm y = object -z), palm touching the side at
  mid-height. This is the "Small Diameter orientation" that selects a side approach.
- Abducted Thumb, Power Sphere, Precision Disc, Pinch: from above, palm facing down
  (palm z = object -z), fingers along object +x. The palm rests on the top (Abducted
  Thumb, Power Sphere) or hovers so the fingertips close around the object (Pinch,
  Precision Disc: `grasp_depth` below the palm, from the human posture).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from graspframe.grasps import HumanGrasp
from graspframe.hal.objects import ObjectDescription
from graspframe.transforms import make_T

# Columns are the palm axes (x, y, z) in the object frame.
R_OBJECT_PALM_SIDE = np.column_stack([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
R_OBJECT_PALM_TOP = np.column_stack([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])

SIDE_GRASPS = frozenset({HumanGrasp.LARGE_DIAMETER, HumanGrasp.SMALL_DIAMETER})
# Human grasps whose palm rests on the object (the human volar grasps).
PALM_ON_OBJECT = frozenset(
    {
        HumanGrasp.LARGE_DIAMETER,
        HumanGrasp.SMALL_DIAMETER,
        HumanGrasp.ABDUCTED_THUMB,
        HumanGrasp.POWER_SPHERE,
    }
)


def _half_width_x(obj: ObjectDescription) -> float:
    """[m] distance from the object's axis to its side along object x."""
    d = obj.dimensions
    return d["size_x"] / 2 if obj.shape == "box" else d["radius"]


def reference_T_object_palm(
    grasp: HumanGrasp, obj: ObjectDescription, grasp_depth: float = 0.0
) -> NDArray[np.float64]:
    """Pose of the human palm frame in the object frame for `grasp` on `obj`.

    grasp_depth: [m] for fingertip grasps from above (Pinch, Precision Disc), how far
        below the palm the fingertips close (from the human posture); the palm is put so
        that they close at the object's centroid height.
    """
    if grasp in SIDE_GRASPS:
        return make_T(R_OBJECT_PALM_SIDE, [-_half_width_x(obj), 0.0, 0.0])
    if grasp in PALM_ON_OBJECT:
        return make_T(R_OBJECT_PALM_TOP, [0.0, 0.0, obj.half_height])
    return make_T(R_OBJECT_PALM_TOP, [0.0, 0.0, grasp_depth])
