"""Hand segmentation by skin colour, and the scale-normalised crop around the hand.

Skin test: the classical chrominance box in YCrCb (Chai and Ngan, 1999):
133 <= Cr <= 173 and 77 <= Cb <= 127, on 8-bit OpenCV YCrCb, plus a minimum
luma so that near-black pixels (undefined chroma) do not count. The mask is cleaned
by a morphological opening and closing; the hand is the largest skin region together
with every region at least `KEEP_FRACTION` of its size (fingers that an object in front
of the palm cuts off from it).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from graspframe.errors import GraspframeError

CR_RANGE = (133, 173)
CB_RANGE = (77, 127)
MIN_LUMA = 20
KEEP_FRACTION = 0.08
MIN_HAND_PIXELS = 150  # [px] a smaller skin region is not taken for a hand
MIN_HAND_FRACTION = 0.002  # [-] nor one below this share of the image
CROP_MARGIN = 0.08  # [-] margin around the hand's box, as a share of its side
CROP_SIZE = 64  # [px] side of the normalised crop


class NoHandFoundError(GraspframeError):
    """No skin-coloured region large enough to be a hand."""


@dataclass(frozen=True)
class HandCrop:
    """The segmented hand: `patch` CROP_SIZE^2 grey level, zero outside the hand;
    `mask` full-image uint8 (255 = hand); `box` (u0, v0, side) [px] the square crop in
    the image; `centroid` (u, v) [px] of the mask; `area` [px] of the mask."""

    patch: NDArray[np.uint8]
    mask: NDArray[np.uint8]
    box: tuple[float, float, float]
    centroid: tuple[float, float]
    area: int


def skin_pixels(image_bgr: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Raw per-pixel skin test: uint8 mask, 255 where the colour is skin-like."""
    ycrcb = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2YCrCb)
    lower = np.array([MIN_LUMA, CR_RANGE[0], CB_RANGE[0]], np.uint8)
    upper = np.array([255, CR_RANGE[1], CB_RANGE[1]], np.uint8)
    return cv2.inRange(ycrcb, lower, upper)


def hand_mask(image_bgr: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Cleaned skin mask of the hand (uint8, 255 = hand); raises NoHandFoundError."""
    h, w = image_bgr.shape[:2]
    raw = skin_pixels(image_bgr)
    k = max(1, round(min(h, w) / 160))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * k + 1, 2 * k + 1))
    mask = cv2.morphologyEx(raw, cv2.MORPH_OPEN, kernel)
    mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, kernel)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    if count <= 1:
        raise NoHandFoundError("no hand found: the image has no skin-coloured region")
    areas = stats[1:, cv2.CC_STAT_AREA]
    largest = int(areas.max())
    needed = max(MIN_HAND_PIXELS, MIN_HAND_FRACTION * h * w)
    if largest < needed:
        raise NoHandFoundError(
            f"no hand found: the largest skin-coloured region has {largest} px, "
            f"a hand needs at least {int(needed)} px"
        )
    keep = np.flatnonzero(areas >= KEEP_FRACTION * largest) + 1
    return np.where(np.isin(labels, keep), 255, 0).astype(np.uint8)


def crop_hand(image_bgr: NDArray[np.uint8], mask: NDArray[np.uint8]) -> HandCrop:
    """Square crop around the mask, grey level with the background zeroed, resized to
    CROP_SIZE x CROP_SIZE (scale normalisation)."""
    v, u = np.nonzero(mask)
    u_min, u_max, v_min, v_max = u.min(), u.max() + 1, v.min(), v.max() + 1
    side = max(u_max - u_min, v_max - v_min) * (1 + 2 * CROP_MARGIN)
    cu, cv_ = (u_min + u_max) / 2, (v_min + v_max) / 2
    u0, v0 = cu - side / 2, cv_ - side / 2
    grey = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY)
    grey = np.where(mask > 0, grey, 0).astype(np.uint8)
    s = max(1, round(float(side)))
    x0, y0 = round(float(u0)), round(float(v0))
    region = np.zeros((s, s), np.uint8)  # the square, zero where it leaves the image
    h, w = grey.shape
    xa, ya, xb, yb = max(x0, 0), max(y0, 0), min(x0 + s, w), min(y0 + s, h)
    region[ya - y0 : yb - y0, xa - x0 : xb - x0] = grey[ya:yb, xa:xb]
    interpolation = cv2.INTER_AREA if s > CROP_SIZE else cv2.INTER_LINEAR
    patch = cv2.resize(region, (CROP_SIZE, CROP_SIZE), interpolation=interpolation)
    return HandCrop(
        patch=patch,
        mask=mask,
        box=(float(x0), float(y0), float(s)),
        centroid=(float(u.mean()), float(v.mean())),
        area=len(u),
    )


def segment_hand(image_bgr: NDArray[np.uint8]) -> HandCrop:
    """Skin mask, then the normalised crop; raises NoHandFoundError."""
    return crop_hand(image_bgr, hand_mask(image_bgr))
