"""Reading an image file and checking an image array, for every classifier.

`read_image` turns a file into a BGR uint8 array (as OpenCV reads it); `check_image`
refuses an array no classifier can use. Both raise `InputError` with a one-line message
saying what is wrong and what is accepted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import InputError

MAX_SIDE = 4096  # [px] larger images are refused
MIN_SIDE = 32  # [px] smaller images are refused


def read_image(path: Path) -> np.ndarray:
    """Read an image file as BGR uint8; InputError if missing, unreadable or not an image."""
    import cv2

    path = Path(path)
    if not path.is_file():
        raise InputError(f"image file not found: {path}")
    data = np.fromfile(path, dtype=np.uint8)
    if data.size == 0:
        raise InputError(f"{path} is empty")
    image = cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    if image is None:
        raise InputError(
            f"{path} is not a readable image (accepted: PNG, JPEG, BMP, TIFF, WebP, PPM)"
        )
    if image.ndim == 3 and image.shape[2] == 4:
        image = cv2.cvtColor(image, cv2.COLOR_BGRA2BGR)
    if image.dtype == np.uint16:
        image = (image // 257).astype(np.uint8)
    return image


def check_image(image_bgr) -> NDArray[np.uint8]:
    """The image if it is usable (H x W x 3 uint8 colour, 32..4096 px a side), else an
    InputError saying what is wrong."""
    if not isinstance(image_bgr, np.ndarray):
        raise InputError(
            f"expected an image array (H x W x 3 uint8), got {type(image_bgr).__name__}"
        )
    if image_bgr.size == 0:
        raise InputError(f"the image is empty (shape {image_bgr.shape})")
    if image_bgr.ndim == 2 or (image_bgr.ndim == 3 and image_bgr.shape[2] == 1):
        raise InputError("the image is grey-level; skin segmentation needs a colour (BGR) image")
    if image_bgr.ndim != 3 or image_bgr.shape[2] != 3:
        raise InputError(f"expected an H x W x 3 colour image, got shape {image_bgr.shape}")
    if image_bgr.dtype != np.uint8:
        raise InputError(f"expected 8-bit pixels (uint8), got {image_bgr.dtype}")
    h, w = image_bgr.shape[:2]
    if max(h, w) > MAX_SIDE:
        raise InputError(f"the image is {w}x{h} px; the accepted maximum is {MAX_SIDE} px a side")
    if min(h, w) < MIN_SIDE:
        raise InputError(f"the image is {w}x{h} px; the accepted minimum is {MIN_SIDE} px a side")
    b, g, r = image_bgr[..., 0], image_bgr[..., 1], image_bgr[..., 2]
    if np.array_equal(b, g) and np.array_equal(g, r):
        raise InputError("the image is grey-level; skin segmentation needs a colour image")
    return image_bgr
