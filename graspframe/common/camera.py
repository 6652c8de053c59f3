"""The pinhole camera: one type for the pictures' rasteriser, the simulated depth camera
and every plugin that renders or measures through a camera."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Camera:
    """Pinhole intrinsics: the image's width and height [px], focal lengths fx, fy and
    principal point cx, cy [px], in the OpenCV camera frame (x right, y down, z forward).
    Pixel (column, row) covers [column, column + 1) x [row, row + 1); its centre is at
    + 0.5."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @classmethod
    def from_fov(cls, width: int, height: int, fov_x_deg: float) -> Camera:
        """A centred camera with horizontal field of view fov_x_deg [deg], square pixels."""
        f = 0.5 * width / np.tan(np.radians(fov_x_deg) / 2)
        return cls(width, height, f, f, width / 2, height / 2)
