"""The HOG + weighted-kNN grasp classifier (docs/method.md, section 2; docs/vision.md).

classify(image): check the image, segment the hand by skin colour, crop and normalise
it, HOG, PCA, k nearest database views, distance-weighted class vote (weights
1 / distance), orientation = weighted rotation average of the neighbours of the winning
class, palm position from the crop's size and position under an assumed camera.

Camera frame: OpenCV axes, x right, y down, z forward. R_camera_palm is the rotation of
the human palm frame (+x to the fingertips, +z out of the palm) in that frame.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar, Self

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError, InputError
from graspframe.common.transforms import R_from_quat_xyzw
from graspframe.hal.classifier import (
    Classifier,
    ClassifierOptions,
    ClassifierPicture,
    HumanGraspEstimate,
    Neighbour,
)
from graspframe.vision.common import unmirror, weighted_vote
from graspframe.vision.images import check_image
from graspframe_hog_knn.index import NeighbourIndex

if TYPE_CHECKING:
    from graspframe_hog_knn.database import ViewDatabase
    from graspframe_hog_knn.segmentation import HandCrop

DEFAULT_K = 8
DEFAULT_FOV_X_DEG = 60.0  # [deg] assumed horizontal field of view for p_camera_palm
# [-] smallest share of the neighbours' weighted vote the winning grasp needs; below it
# the neighbours disagree and the image is refused (measured in docs/vision.md: on
# held-out renders it refuses 2 % of views, nearly all of them wrongly classified).
DEFAULT_MIN_CONFIDENCE = 0.4


class UncertainGraspError(GraspframeError):
    """The hand was found, but its nearest database views do not agree on a grasp."""


@dataclass(frozen=True)
class Timings:
    """Per-stage query time [s]."""

    segmentation: float
    features: float
    search: float


def pictures(crop: HandCrop) -> tuple[ClassifierPicture, ...]:
    """What this classifier shows of its work: "mask", the hand mask it cropped around
    (in the image's own pixels, flipped back for a left hand), and "crop", the normalised
    grey patch it described (as described: mirrored for a left hand)."""
    mask = np.ascontiguousarray(crop.mask[:, ::-1]) if crop.mirrored else crop.mask
    return (
        ClassifierPicture("mask", "mask", mask),
        ClassifierPicture("crop", "image", crop.patch),
    )


class HogKnnClassifier(Classifier):
    """HOG descriptors of the skin-segmented hand, k nearest synthetic views.

    database_path: a .npz view database (default: the one shipped with the package),
    loaded on first use; k: neighbours; index_kind: "hnsw" or "flat" (exact);
    fov_x_deg: assumed horizontal field of view of the camera [deg], used only for
    p_camera_palm; min_confidence: the winning grasp's smallest share of the weighted vote
    (0..1) below which the image is refused with UncertainGraspError (0 never refuses).
    """

    name: ClassVar[str] = "hog_knn"
    summary: ClassVar[str] = "skin segmentation + HOG + weighted kNN over rendered human-hand views"

    def __init__(
        self,
        database_path: Path | None = None,
        k: int = DEFAULT_K,
        index_kind: str = "hnsw",
        fov_x_deg: float = DEFAULT_FOV_X_DEG,
        min_confidence: float = DEFAULT_MIN_CONFIDENCE,
    ):
        if k < 1:
            raise InputError(f"k must be >= 1, got {k}")
        if not 0.0 <= min_confidence < 1.0:
            raise InputError(f"min_confidence must be in [0, 1), got {min_confidence}")
        self.min_confidence = min_confidence
        self.database_path = database_path
        self.k = k
        self.index_kind = index_kind
        self.fov_x_deg = fov_x_deg
        self._database: ViewDatabase | None = None
        self._index: NeighbourIndex | None = None

    @classmethod
    def with_options(cls, options: ClassifierOptions) -> Self:
        """The classifier with the user's `options.k` (its default when None)."""
        return cls() if options.k is None else cls(k=options.k)

    @classmethod
    def from_database(cls, database: ViewDatabase, **options) -> HogKnnClassifier:
        """A classifier over an in-memory database (tests, benchmarks)."""
        classifier = cls(**options)
        classifier._database = database
        return classifier

    @property
    def database(self) -> ViewDatabase:
        if self._database is None:
            from graspframe_hog_knn.database import load_database

            self._database = load_database(self.database_path)
        return self._database

    @property
    def index(self) -> NeighbourIndex:
        if self._index is None:
            self._index = NeighbourIndex(self.database.descriptors, self.index_kind)
        return self._index

    def classify(self, image_bgr: NDArray[np.uint8]) -> HumanGraspEstimate:
        """Estimate the grasp in a BGR uint8 image; raises InputError / NoHandFoundError."""
        return self.classify_timed(image_bgr)[0]

    def classify_timed(self, image_bgr) -> tuple[HumanGraspEstimate, Timings]:
        """`classify` plus the time spent per stage."""
        # The pipeline (OpenCV, the view database and its renderer's modules) is imported
        # at the first classification: every command loads this plugin, few classify.
        from graspframe_hog_knn.features import hog_descriptor
        from graspframe_hog_knn.segmentation import segment_hand

        image = check_image(image_bgr)
        t0 = time.perf_counter()
        crop = segment_hand(image)
        t1 = time.perf_counter()
        db, index = self.database, self.index  # loaded on first use (not timed)
        t1b = time.perf_counter()
        query = db.pca.project(hog_descriptor(crop.patch))
        t2 = time.perf_counter()
        distances, ids = index.search(query, min(self.k, len(db)))
        t3 = time.perf_counter()
        estimate = self._estimate(db, distances[0], ids[0], crop, image.shape)
        return estimate, Timings(t1 - t0, t2 - t1b, t3 - t2)

    def _estimate(self, db, distances, ids, crop, shape) -> HumanGraspEstimate:
        from graspframe_hog_knn.rotations import average_rotations
        from graspframe_hog_knn.views import GRASPS

        valid = ids >= 0
        distances, ids = distances[valid], ids[valid]
        labels = db.labels[ids]
        weights, votes = weighted_vote(labels, distances, len(GRASPS))
        winner = int(np.argmax(votes))
        confidence = float(votes[winner] / votes.sum())
        if confidence < self.min_confidence:
            raise UncertainGraspError(
                f"no grasp can be told: the {len(ids)} nearest views agree only "
                f"{confidence:.0%} on {GRASPS[winner].value} (at least "
                f"{self.min_confidence:.0%} needed); try a clearer view of the hand"
            )
        same = labels == winner
        rotations = np.array([R_from_quat_xyzw(q) for q in db.quat_xyzw[ids]])
        R_camera_palm = average_rotations(rotations[same], weights[same])
        if crop.mirrored:  # the crop was flipped left-right: flip the answer back
            R_camera_palm = unmirror(R_camera_palm)
        neighbours = tuple(
            Neighbour(int(db.view_ids[i]), GRASPS[int(db.labels[i])], R, float(d))
            for i, R, d in zip(ids, rotations, distances, strict=True)
        )
        return HumanGraspEstimate(
            grasp=GRASPS[winner],
            confidence=confidence,
            R_camera_palm=R_camera_palm,
            p_camera_palm=self._palm_position(db, ids[same], weights[same], crop, shape),
            neighbours=neighbours,
            pictures=pictures(crop),
        )

    def _palm_position(self, db, ids, weights, crop, shape) -> NDArray[np.float64]:
        """Palm position [m] in the camera frame: depth from the crop side and the
        neighbours' physical crop size, under the assumed field of view."""
        h, w = shape[:2]
        f = 0.5 * w / np.tan(np.radians(self.fov_x_deg) / 2)
        u0, v0, side = crop.box
        extent = float(np.average(db.crop_extent_m[ids], weights=weights))
        offset = np.average(db.palm_offset[ids], axis=0, weights=weights)
        depth = f * extent / side
        u = u0 + (0.5 + offset[0]) * side
        v = v0 + (0.5 + offset[1]) * side
        if crop.mirrored:
            u = w - u
        return np.array([(u - w / 2) / f * depth, (v - h / 2) / f * depth, depth])
