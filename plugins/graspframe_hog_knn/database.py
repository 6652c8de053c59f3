"""The synthetic view database: build (render, segment, describe), save and load.

Each view i of a build draws its parameters from `numpy.random.default_rng([seed, i])`
and shows grasp GRASPS[i % 6], so a build is the same for a seed whatever the number of
worker processes. Stored per view: the PCA-reduced HOG descriptor (float16), the class
label, the exact R_camera_palm (quat_xyzw), and two numbers for the palm position: the
crop side at the palm's depth [m] and the palm's image offset from the crop centre
(share of the crop side).

Files: `<name>.npz` (arrays) and `<name>.json` (metadata: format, graspframe version,
build parameters, counts, build time).
"""

from __future__ import annotations

import json
import signal
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError, InputError
from graspframe.common.files import atomic_output, atomic_write
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import quat_xyzw_from_R
from graspframe_hog_knn.features import HOG_PARAMETERS, hog_descriptor
from graspframe_hog_knn.index import Pca
from graspframe_hog_knn.segmentation import CROP_SIZE, NoHandFoundError, segment_hand
from graspframe_hog_knn.views import DISTRIBUTIONS, GRASPS, TRAIN, RenderedView

FORMAT = "graspframe.views/1"
DEFAULT_VIEWS_PER_GRASP = 2000
DEFAULT_SIZE = 128  # [px]
DEFAULT_SEED = 0
DEFAULT_PCA_DIMS = 96
CHUNK = 40  # views per worker task
DATABASE_NAME = "views"


@dataclass
class ViewDatabase:
    """Arrays of N views: descriptors (N, D) PCA space, labels (N,) index into GRASPS,
    quat_xyzw (N, 4) R_camera_palm, crop_extent_m (N,), palm_offset (N, 2), view_ids (N,),
    the PCA and the metadata."""

    descriptors: NDArray[np.float32]
    labels: NDArray[np.int64]
    quat_xyzw: NDArray[np.float32]
    crop_extent_m: NDArray[np.float32]
    palm_offset: NDArray[np.float32]
    view_ids: NDArray[np.int64]
    pca: Pca
    metadata: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.labels)

    def grasp(self, i: int) -> HumanGrasp:
        return GRASPS[int(self.labels[i])]

    def save(self, npz_path: Path) -> tuple[Path, Path]:
        """Write `<stem>.npz` and `<stem>.json`; returns both paths."""
        npz_path = Path(npz_path).with_suffix(".npz")
        npz_path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_output(npz_path) as stream:
            np.savez_compressed(
                stream,
                descriptors=self.descriptors.astype(np.float16),
                labels=self.labels.astype(np.uint8),
                quat_xyzw=self.quat_xyzw.astype(np.float32),
                crop_extent_m=self.crop_extent_m.astype(np.float16),
                palm_offset=self.palm_offset.astype(np.float16),
                view_ids=self.view_ids.astype(np.int32),
                pca_mean=self.pca.mean.astype(np.float32),
                pca_components=self.pca.components.astype(np.float16),
            )
        json_path = atomic_write(
            npz_path.with_suffix(".json"), json.dumps(self.metadata, indent=2) + "\n"
        )
        return npz_path, json_path


def shipped_database_path() -> Path:
    """Where the default database ships: graspframe_hog_knn/data/views.npz."""
    from importlib.resources import files

    return Path(str(files("graspframe_hog_knn") / "data" / f"{DATABASE_NAME}.npz"))


def read_metadata(npz_path: Path | None = None) -> dict:
    """The metadata (JSON next to the .npz) of a database; the shipped one by default."""
    path = Path(npz_path or shipped_database_path()).with_suffix(".json")
    if not path.is_file():
        raise InputError(f"view database metadata not found: {path}")
    return json.loads(path.read_text())


def load_database(npz_path: Path | None = None) -> ViewDatabase:
    """Load a database (the shipped one by default); a clear error if it is missing."""
    path = Path(npz_path or shipped_database_path()).with_suffix(".npz")
    if not path.is_file():
        raise InputError(f"view database not found: {path}; build it with `graspframe db build`")
    metadata = read_metadata(path)
    if metadata.get("format") != FORMAT:
        raise InputError(f"{path.name}: format {metadata.get('format')!r}, expected {FORMAT!r}")
    with np.load(path) as z:
        return ViewDatabase(
            descriptors=z["descriptors"].astype(np.float32),
            labels=z["labels"].astype(np.int64),
            quat_xyzw=z["quat_xyzw"].astype(np.float32),
            crop_extent_m=z["crop_extent_m"].astype(np.float32),
            palm_offset=z["palm_offset"].astype(np.float32),
            view_ids=z["view_ids"].astype(np.int64),
            pca=Pca(z["pca_mean"].astype(np.float32), z["pca_components"].astype(np.float32)),
            metadata=metadata,
        )


# ---- rendering views (one renderer per process) ---------------------------------------

_WORKER: dict = {}


def _worker_state():
    if not _WORKER:
        from graspframe.pictures.rasteriser import Renderer, single_thread_llvmpipe
        from graspframe_hog_knn.hand_scene import HandModel

        single_thread_llvmpipe()
        _WORKER["renderer"] = Renderer()
        _WORKER["hand"] = HandModel()
    return _WORKER["renderer"], _WORKER["hand"]


def render_view_by_id(view_id: int, seed: int, size: int, distribution: str) -> RenderedView:
    """Render view `view_id` of the build with `seed` (grasp GRASPS[view_id % 6])."""
    from graspframe_hog_knn.views import render_view, sample_view

    renderer, hand = _worker_state()
    rng = np.random.default_rng([seed, view_id])
    params = sample_view(rng, GRASPS[view_id % len(GRASPS)], hand, DISTRIBUTIONS[distribution])
    return render_view(renderer, hand, params, size)


def iter_views(
    view_ids, seed: int, size: int, distribution: str = TRAIN.name
) -> Iterator[RenderedView]:
    """Render the given views in this process (tests, benchmarks)."""
    for i in view_ids:
        yield render_view_by_id(int(i), seed, size, distribution)


@dataclass(frozen=True)
class DescribedView:
    """One database row before PCA (HOG descriptor raw)."""

    view_id: int
    label: int
    hog: NDArray[np.float32]
    quat_xyzw: NDArray[np.float64]
    crop_extent_m: float
    palm_offset: tuple[float, float]


def describe_view(view: RenderedView, view_id: int) -> DescribedView:
    """Segment and describe a rendered view; raises NoHandFoundError."""
    crop = segment_hand(view.image)
    u0, v0, side = crop.box
    cam = view.camera
    p = view.T_camera_palm[:3, 3]
    u_palm, v_palm = cam.fx * p[0] / p[2] + cam.cx, cam.fy * p[1] / p[2] + cam.cy
    return DescribedView(
        view_id=view_id,
        label=GRASPS.index(view.grasp),
        hog=hog_descriptor(crop.patch),
        quat_xyzw=quat_xyzw_from_R(view.T_camera_palm[:3, :3]),
        crop_extent_m=float(side * p[2] / cam.fx),
        palm_offset=((u_palm - u0) / side - 0.5, (v_palm - v0) / side - 0.5),
    )


def _leave_interrupts_to_parent() -> None:
    """A rendering process ignores Ctrl-C (it reaches the whole process group): the
    build's own process decides, and ends its workers."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _describe_chunk(args) -> list[DescribedView | None]:
    view_ids, seed, size, distribution = args
    out: list[DescribedView | None] = []
    for i in view_ids:
        try:
            out.append(describe_view(render_view_by_id(i, seed, size, distribution), i))
        except NoHandFoundError:
            out.append(None)  # the hand is hidden or too small in this view
    return out


def build_database(
    views_per_grasp: int = DEFAULT_VIEWS_PER_GRASP,
    size: int = DEFAULT_SIZE,
    workers: int = 1,
    seed: int = DEFAULT_SEED,
    pca_dims: int = DEFAULT_PCA_DIMS,
    distribution: str = TRAIN.name,
    progress: Callable[[int, int], None] | None = None,
) -> ViewDatabase:
    """Render, segment and describe views_per_grasp x 6 views [size px square] with
    `workers` processes; PCA to `pca_dims`. `progress(done, total)` is called as chunks
    finish."""
    if views_per_grasp < 1 or workers < 1 or size < 32 or pca_dims < 1:
        raise InputError("views per grasp and workers must be >= 1, size >= 32 px")
    total = views_per_grasp * len(GRASPS)
    chunks = [
        (list(range(a, min(a + CHUNK, total))), seed, size, distribution)
        for a in range(0, total, CHUNK)
    ]
    start = time.perf_counter()
    rows: list[DescribedView | None] = []
    done = 0
    results: Iterator[list[DescribedView | None]]
    if workers == 1:
        results = map(_describe_chunk, chunks)
        pool = None
    else:
        pool = get_context("spawn").Pool(workers, initializer=_leave_interrupts_to_parent)
        results = pool.imap(_describe_chunk, chunks)
    finished = False
    try:
        for chunk, result in zip(chunks, results, strict=True):
            rows.extend(result)
            done += len(chunk[0])
            if progress:
                progress(done, total)
        finished = True
    finally:
        if pool is not None:
            if finished:
                pool.close()
            else:  # an error or Ctrl-C: the chunks being rendered are not waited for
                pool.terminate()
            pool.join()
    seconds = time.perf_counter() - start
    kept = [r for r in rows if r is not None]
    if len(kept) < max(pca_dims, len(GRASPS)):
        raise GraspframeError(f"only {len(kept)} of {total} views show a segmentable hand")
    hogs = np.stack([r.hog for r in kept])
    pca = Pca.fit(hogs, min(pca_dims, hogs.shape[1], len(kept)))
    # Stored as float16: project the database with exactly what a query will use.
    pca = Pca(pca.mean, pca.components.astype(np.float16).astype(np.float32))
    from graspframe import __version__

    metadata = {
        "format": FORMAT,
        "graspframe_version": __version__,
        "grasps": [g.value for g in GRASPS],
        "build": {
            "views_per_grasp": views_per_grasp,
            "size_px": size,
            "seed": seed,
            "distribution": distribution,
            "pca_dims": int(pca.components.shape[0]),
            "crop_px": CROP_SIZE,
            "hog": HOG_PARAMETERS,
            "workers": workers,
        },
        "views_rendered": total,
        "views_stored": len(kept),
        "views_without_hand": total - len(kept),
        "build_seconds": round(seconds, 2),
        "views_per_second": round(total / seconds, 1),
        "camera": "OpenCV axes: x right, y down, z forward; labels are R_camera_palm",
    }
    return ViewDatabase(
        descriptors=pca.project(hogs),
        labels=np.array([r.label for r in kept], np.int64),
        quat_xyzw=np.array([r.quat_xyzw for r in kept], np.float32),
        crop_extent_m=np.array([r.crop_extent_m for r in kept], np.float32),
        palm_offset=np.array([r.palm_offset for r in kept], np.float32),
        view_ids=np.array([r.view_id for r in kept], np.int64),
        pca=pca,
        metadata=metadata,
    )
