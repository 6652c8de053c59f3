"""HOG descriptors of the normalised hand crop (OpenCV's HOGDescriptor).

Window = the CROP_SIZE x CROP_SIZE crop; 8 x 8 px cells, 16 x 16 px blocks with an 8 px
stride, 9 unsigned orientation bins, L2-Hys block normalisation: 7 x 7 blocks x 4 cells x
9 bins = 1764 values for a 64 px crop.
"""

from __future__ import annotations

import functools

import cv2
import numpy as np
from numpy.typing import NDArray

from graspframe_hog_knn.segmentation import CROP_SIZE

CELL = 8  # [px]
BLOCK = 16  # [px]
STRIDE = 8  # [px]
BINS = 9

HOG_PARAMETERS = {
    "window_px": CROP_SIZE,
    "cell_px": CELL,
    "block_px": BLOCK,
    "block_stride_px": STRIDE,
    "bins": BINS,
}


@functools.cache
def _hog() -> cv2.HOGDescriptor:
    return cv2.HOGDescriptor(
        (CROP_SIZE, CROP_SIZE), (BLOCK, BLOCK), (STRIDE, STRIDE), (CELL, CELL), BINS
    )


def hog_descriptor(patch: NDArray[np.uint8]) -> NDArray[np.float32]:
    """HOG of one CROP_SIZE x CROP_SIZE grey patch -> one flat float32 descriptor."""
    return np.asarray(_hog().compute(patch)).reshape(-1).astype(np.float32)
