"""Hand segmentation by skin colour, and the scale-normalised crop around the hand.

Skin test: the classical chrominance box in YCrCb (Chai and Ngan, 1999):
133 <= Cr <= 173 and 77 <= Cb <= 127, on 8-bit OpenCV YCrCb, plus a minimum
luma so that near-black pixels (undefined chroma) do not count. The mask is cleaned
by a morphological opening and closing; the hand is the largest skin region together
with every region at least `KEEP_FRACTION` of its size (fingers that an object in front
of the palm cuts off from it).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import cast

import cv2
import numpy as np
from numpy.typing import NDArray

from graspframe.vision.common import NoHandFoundError

CR_RANGE = (133, 173)
CB_RANGE = (77, 127)
MIN_LUMA = 20
KEEP_FRACTION = 0.08
MIN_HAND_PIXELS = 150  # [px] a smaller skin region is not taken for a hand
MIN_HAND_FRACTION = 0.002  # [-] nor one below this share of the image
CROP_MARGIN = 0.08  # [-] margin around the hand's box, as a share of its side
CROP_SIZE = 64  # [px] side of the normalised crop
MIN_GREY_SPREAD = 12  # [grey levels] a flatter image (2nd to 98th percentile) is blank
SURFACE_FRACTION = 0.9  # [-] skin over this share of the image, no hand detected: a surface
# Landmark segmentation (optional hand detector):
ROI_MARGIN = 0.25  # [-] box around the landmarks, as a share of the hand size
BONE_WIDTH = 0.04  # [-] width of the drawn skeleton, as a share of the hand size
SKIN_SIGMAS = 3.0  # [-] Mahalanobis radius of the per-image skin model
SKIN_VARIANCE_FLOOR = 4.0  # [(8-bit chroma)^2] keeps the model's covariance invertible
WRIST_CUT = 0.2  # [-] the forearm cut, this share of wrist -> middle knuckle past the wrist


@dataclass(frozen=True)
class HandCrop:
    """The segmented hand: `patch` CROP_SIZE^2 grey level, zero outside the hand;
    `mask` full-image uint8 (255 = hand); `box` (u0, v0, side) [px] the square crop in
    the image; `centroid` (u, v) [px] of the mask; `area` [px] of the mask; `mirrored` True when
    the image was flipped left-right (a left hand made to look like the right-hand
    database): then `mask`, `box` and `centroid` are in the flipped image."""

    patch: NDArray[np.uint8]
    mask: NDArray[np.uint8]
    box: tuple[float, float, float]
    centroid: tuple[float, float]
    area: int
    mirrored: bool = False


def skin_pixels(image_bgr: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Raw per-pixel skin test: uint8 mask, 255 where the colour is skin-like."""
    ycrcb = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2YCrCb)
    lower = np.array([MIN_LUMA, CR_RANGE[0], CB_RANGE[0]], np.uint8)
    upper = np.array([255, CR_RANGE[1], CB_RANGE[1]], np.uint8)
    return cast(NDArray[np.uint8], cv2.inRange(ycrcb, lower, upper))


def hand_mask(image_bgr: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Cleaned skin mask of the hand (uint8, 255 = hand); raises NoHandFoundError."""
    return _largest_regions(_clean(skin_pixels(image_bgr)))


def _clean(raw: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """Morphological opening then closing, the kernel scaled with the image."""
    h, w = raw.shape[:2]
    k = max(1, round(min(h, w) / 160))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * k + 1, 2 * k + 1))
    mask = cv2.morphologyEx(raw, cv2.MORPH_OPEN, kernel)
    return cast(NDArray[np.uint8], cv2.morphologyEx(mask, cv2.MORPH_CLOSE, kernel))


def _largest_regions(mask: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """The largest region and every region >= KEEP_FRACTION of it; NoHandFoundError
    when it is too small for a hand."""
    h, w = mask.shape[:2]
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
    # OpenCV keeps the uint8 type of its input.
    patch = cast(
        NDArray[np.uint8],
        cv2.resize(region, (CROP_SIZE, CROP_SIZE), interpolation=interpolation),
    )
    return HandCrop(
        patch=patch,
        mask=mask,
        box=(float(x0), float(y0), float(s)),
        centroid=(float(u.mean()), float(v.mean())),
        area=len(u),
    )


def crop_hand_mirrored(image_bgr: NDArray[np.uint8], mask: NDArray[np.uint8]) -> HandCrop:
    """`crop_hand` of the left-right flipped image and mask (a left hand)."""
    crop = crop_hand(np.ascontiguousarray(image_bgr[:, ::-1]), np.ascontiguousarray(mask[:, ::-1]))
    return replace(crop, mirrored=True)


def check_not_blank(image_bgr: NDArray[np.uint8]) -> None:
    """NoHandFoundError for a (nearly) uniform image: its grey levels spread less than
    MIN_GREY_SPREAD between the 2nd and 98th percentiles."""
    grey = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY)
    low, high = np.percentile(grey, [2, 98])
    if high - low < MIN_GREY_SPREAD:
        raise NoHandFoundError(
            f"no hand found: the image is uniform (grey levels spread {high - low:.0f} < "
            f"{MIN_GREY_SPREAD}), nothing in it has a hand's shape or edges"
        )


def _touches_border(mask: NDArray[np.uint8]) -> bool:
    return bool(mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any())


def segment_hand(image_bgr: NDArray[np.uint8]) -> HandCrop:
    """The normalised hand crop; raises NoHandFoundError.

    1. A uniform image is refused (`check_not_blank`).
    2. Skin test + cleaning + largest regions (`hand_mask`). A mask clear of the image
       border (a whole hand on a non-skin background: every rendered database view) is
       cropped as it is.
    3. Otherwise the skin reaches the border: a forearm, or a skin-coloured background
       (wall, wood, cardboard). With the optional hand detector (`hands`), the hand is
       segmented around its landmarks (`landmark_mask`: a per-image skin colour model,
       the forearm cut at the wrist) and a left hand is mirrored. Without a
       detected hand, skin covering >= SURFACE_FRACTION of the image is refused as a
       skin-coloured surface; anything else keeps the step-2 mask.
    """
    check_not_blank(image_bgr)
    h, w = image_bgr.shape[:2]
    mask = hand_mask(image_bgr)
    if not _touches_border(mask):
        return crop_hand(image_bgr, mask)
    from graspframe.vision.hands import detect_hand

    hand = detect_hand(image_bgr)
    if hand is None:
        share = np.count_nonzero(mask) / (h * w)
        if share >= SURFACE_FRACTION:
            raise NoHandFoundError(
                f"no hand found: a skin-coloured surface fills {100 * share:.0f} % of the "
                f"image (>= {100 * SURFACE_FRACTION:.0f} %) with no hand detected in it"
            )
        return crop_hand(image_bgr, mask)
    mask = landmark_mask(image_bgr, hand)
    if hand.left:
        return crop_hand_mirrored(image_bgr, mask)
    return crop_hand(image_bgr, mask)


def landmark_mask(image_bgr: NDArray[np.uint8], hand) -> NDArray[np.uint8]:
    """Hand mask from detected landmarks. In a box around them (+ROI_MARGIN of the hand
    size), a skin colour model is fitted to the pixels under the palm polygon and the
    finger bones drawn BONE_WIDTH wide (a Gaussian in CrCb); the hand is those pixels
    plus every pixel within SKIN_SIGMAS (Mahalanobis) of the model. Pixels behind the
    line across the hand WRIST_CUT x (wrist -> middle knuckle) in front of the wrist
    landmark are cut (the forearm); then cleaning and the largest regions."""
    from graspframe.vision.hands import CHAINS, MIDDLE_MCP, PALM, WRIST

    h, w = image_bgr.shape[:2]
    points = hand.landmarks
    size = hand.size
    lo = np.floor(points.min(axis=0) - ROI_MARGIN * size).astype(int)
    hi = np.ceil(points.max(axis=0) + ROI_MARGIN * size).astype(int)
    x0, y0 = max(lo[0], 0), max(lo[1], 0)
    x1, y1 = min(hi[0], w), min(hi[1], h)
    pts = points - (x0, y0)
    bones = np.zeros((y1 - y0, x1 - x0), np.uint8)
    thickness = max(1, round(BONE_WIDTH * size))
    for chain in CHAINS:
        cv2.polylines(bones, [np.round(pts[list(chain)]).astype(np.int32)], False, 255, thickness)
    cv2.fillPoly(bones, [np.round(pts[list(PALM)]).astype(np.int32)], 255)
    chroma = cv2.cvtColor(image_bgr[y0:y1, x0:x1], cv2.COLOR_BGR2YCrCb)[..., 1:]
    chroma = chroma.reshape(-1, 2).astype(np.float64)
    samples = chroma[bones.reshape(-1) > 0]
    mean = samples.mean(axis=0)
    cov = np.cov(samples.T) + np.eye(2) * SKIN_VARIANCE_FLOOR
    diff = chroma - mean
    d2 = np.einsum("ij,jk,ik->i", diff, np.linalg.inv(cov), diff).reshape(bones.shape)
    mask = np.zeros((h, w), np.uint8)
    mask[y0:y1, x0:x1] = np.where((d2 <= SKIN_SIGMAS**2) | (bones > 0), 255, 0)
    axis = points[MIDDLE_MCP] - points[WRIST]
    length2 = float(axis @ axis)
    if length2 > 0:  # only the box can hold hand pixels: cut the forearm there
        vv, uu = np.mgrid[y0:y1, x0:x1]
        along = (uu - points[WRIST][0]) * axis[0] + (vv - points[WRIST][1]) * axis[1]
        mask[y0:y1, x0:x1][along < WRIST_CUT * length2] = 0
    return _largest_regions(_clean(mask))
