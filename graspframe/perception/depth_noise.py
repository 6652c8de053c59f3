"""The noise of a structured-light depth sensor of the Kinect class, applied to an ideal
depth image (camera-frame z [m] per pixel, +inf: nothing in range).

Taken from two measured models of that sensor class (docs/perception.md):

- axial noise (Nguyen, Izadi and Lovell, "Modeling Kinect Sensor Noise for Improved 3D
  Reconstruction and Tracking", 3DIMPVT 2012, eq. 6): a standard deviation of
  sigma_z = 0.0012 + 0.0019 (z - 0.4)^2 [m] for surfaces seen within about 60 deg of
  head-on, growing with the angle theta between the ray and the surface normal by
  0.0001 / sqrt(z) * theta^2 / (pi/2 - theta)^2 [m];
- quantisation (Khoshelham and Oude Elberink, "Accuracy and Resolution of Kinect Depth
  Data for Indoor Mapping Applications", Sensors 12(2), 2012): depth comes from a
  disparity measured in steps of 1/8 px with a focal length of about 580 px over a
  baseline of 7.5 cm, so depth is quantised in steps of z^2 / (8 * 580 * 0.075) [m]
  (2.9 mm at 1 m);
- missing pixels: no return where the surface is seen at more than GRAZING_DEG from
  head-on, none beyond the working range, and none at a depth edge (a jump of more than
  EDGE_JUMP between neighbours) with probability EDGE_DROP: the projected pattern is
  shadowed or smeared there.

`scale` multiplies the axial noise (2.0: the acceptance's "noise doubled"); a seeded
generator makes it repeatable.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

AXIAL_BASE = 0.0012  # [m]
AXIAL_QUADRATIC = 0.0019  # [1/m]
AXIAL_REFERENCE_Z = 0.4  # [m]
ANGULAR_GAIN = 0.0001  # [m^1.5]
FOCAL_PX = 580.0  # [px] the sensor's infrared camera
BASELINE = 0.075  # [m] projector to infrared camera
DISPARITY_STEP_PX = 1.0 / 8.0  # [px]
MIN_RANGE, MAX_RANGE = 0.5, 4.0  # [m] working range of the sensor class
GRAZING_DEG = 75.0  # [deg] surfaces seen more obliquely return nothing
EDGE_JUMP = 0.02  # [m] a depth step this large between neighbours is an edge
EDGE_DROP = 0.5  # probability that an edge pixel returns nothing


@dataclass(frozen=True)
class DepthNoise:
    """The noise model above; `scale` multiplies the axial noise."""

    scale: float = 1.0

    def axial_sigma(self, z: NDArray[np.float64], theta: NDArray[np.float64]) -> NDArray:
        """[m] standard deviation of the depth at distance z [m], surface angle theta [rad]."""
        theta = np.minimum(theta, np.radians(89.0))
        angular = ANGULAR_GAIN / np.sqrt(z) * theta**2 / (np.pi / 2 - theta) ** 2
        return self.scale * (AXIAL_BASE + AXIAL_QUADRATIC * (z - AXIAL_REFERENCE_Z) ** 2 + angular)

    def apply(
        self, depth_m: NDArray[np.float32], fx: float, fy: float, rng: np.random.Generator
    ) -> NDArray[np.float32]:
        """The measured image (NaN: no return) of the ideal `depth_m` (+inf: nothing)."""
        z = depth_m.astype(np.float64)
        seen = np.isfinite(z)
        theta = _surface_angle(z, fx, fy)
        missing = ~seen | (z < MIN_RANGE) | (z > MAX_RANGE)
        missing |= theta > np.radians(GRAZING_DEG)
        missing |= _edges(z) & (rng.random(z.shape) < EDGE_DROP)
        z_seen = np.where(seen, z, 1.0)
        noisy = z_seen + rng.standard_normal(z.shape) * self.axial_sigma(z_seen, theta)
        step = z_seen**2 * DISPARITY_STEP_PX / (FOCAL_PX * BASELINE)
        measured = np.round(noisy / step) * step
        return np.where(missing, np.nan, measured).astype(np.float32)


def _surface_angle(z: NDArray[np.float64], fx: float, fy: float) -> NDArray[np.float64]:
    """[rad] angle between each pixel's ray and its surface's normal, from the depth
    gradient (0: seen head-on); pi/2 where the neighbours give no gradient."""
    finite = np.where(np.isfinite(z), z, np.nan)
    dz_dv, dz_du = np.gradient(finite)
    # Metric slope of the surface along the image axes: a pixel spans z / f metres.
    with np.errstate(invalid="ignore", divide="ignore"):
        slope_x = dz_du * fx / finite
        slope_y = dz_dv * fy / finite
        cos_theta = 1.0 / np.sqrt(1.0 + slope_x**2 + slope_y**2)
    return np.where(np.isfinite(cos_theta), np.arccos(np.clip(cos_theta, 0.0, 1.0)), np.pi / 2)


def _edges(z: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Pixels with a neighbour (4-connected) more than EDGE_JUMP nearer or further;
    nothing-in-range counts as far."""
    far = np.where(np.isfinite(z), z, 1e3)
    edge = np.zeros(z.shape, dtype=bool)
    jump_rows = np.abs(np.diff(far, axis=0)) > EDGE_JUMP
    jump_columns = np.abs(np.diff(far, axis=1)) > EDGE_JUMP
    edge[:-1] |= jump_rows
    edge[1:] |= jump_rows
    edge[:, :-1] |= jump_columns
    edge[:, 1:] |= jump_columns
    return edge
