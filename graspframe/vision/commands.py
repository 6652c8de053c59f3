"""The `graspframe classify` and `graspframe db build` commands as plain functions.

cli.py wires them into the typer app; they print their results (rich) and return an
exit code, and raise GraspframeError subclasses (one-line messages) for bad input.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from graspframe.defaults import DEFAULT_CLASSIFIER
from graspframe.errors import InputError
from graspframe.transforms import rpy_from_R

EULER_CONVENTION = (
    "roll-pitch-yaw about the fixed camera axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll)"
)


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


def estimate_as_dict(estimate) -> dict:
    """JSON-ready form of a HumanGraspEstimate (angles [deg], position [m])."""
    roll, pitch, yaw = np.degrees(rpy_from_R(estimate.R_camera_palm))
    return {
        "grasp": estimate.grasp.value,
        "confidence": round(estimate.confidence, 4),
        "R_camera_palm": np.round(estimate.R_camera_palm, 6).tolist(),
        "euler_deg": {"roll": round(roll, 2), "pitch": round(pitch, 2), "yaw": round(yaw, 2)},
        "euler_convention": EULER_CONVENTION,
        "camera_frame": "OpenCV: x right, y down, z forward",
        "p_camera_palm_m": None
        if estimate.p_camera_palm is None
        else np.round(estimate.p_camera_palm, 4).tolist(),
        "neighbours": [
            {
                "view_id": n.view_id,
                "grasp": n.grasp.value,
                "distance": round(n.distance, 4),
                "euler_deg": np.round(np.degrees(rpy_from_R(n.R_camera_palm)), 2).tolist(),
            }
            for n in estimate.neighbours
        ],
    }


def classify_command(
    image: Path, k: int = 8, as_json: bool = False, classifier: str = DEFAULT_CLASSIFIER
) -> int:
    """Classify the human grasp in one image with a registered classifier.

    Options for the typer signature:
      IMAGE         path to a colour image (PNG, JPEG, ...) showing one hand
      --k           number of nearest neighbours that vote (default 8, >= 1)
      --json        print the result as JSON instead of a table
      --classifier  registered classifier name (default hog_knn; `landmarks` needs the
                    `hands` extra)
    Prints grasp, confidence, hand orientation (rotation matrix and Euler angles, the
    convention named) and the neighbours used. Exit code 0; errors raise InputError /
    NoHandFoundError (one line).
    """
    from graspframe.registry import get_classifier

    classifier_class = get_classifier(classifier)
    if k < 1:
        raise InputError(f"--k must be >= 1, got {k}")
    # --k is for kNN classifiers; both built-in ones take k.
    estimate = classifier_class(k=k).classify(read_image(image))  # type: ignore[call-arg]
    result = estimate_as_dict(estimate)
    if as_json:
        sys.stdout.write(json.dumps(result, indent=2) + "\n")
        return 0
    from rich.console import Console
    from rich.table import Table

    console = Console()
    console.print(f"grasp: [bold]{result['grasp']}[/bold]  confidence {result['confidence']:.2f}")
    e = result["euler_deg"]
    console.print(
        f"hand orientation R_camera_palm (camera frame {result['camera_frame']}):\n"
        + "\n".join("  " + "  ".join(f"{v:+.3f}" for v in row) for row in result["R_camera_palm"])
    )
    console.print(
        f"Euler \\[deg]: roll {e['roll']:+.1f}, pitch {e['pitch']:+.1f}, yaw {e['yaw']:+.1f}"
        f"  ({EULER_CONVENTION})"
    )
    if result["p_camera_palm_m"] is not None:
        p = result["p_camera_palm_m"]
        console.print(
            f"palm position \\[m] (assumes a 60 deg horizontal field of view): "
            f"{p[0]:+.3f} {p[1]:+.3f} {p[2]:+.3f}"
        )
    table = Table(title="neighbours (nearest first)")
    for column in ("view", "grasp", "distance", "roll/pitch/yaw \\[deg]"):
        table.add_column(column)
    for n in result["neighbours"]:
        table.add_row(
            str(n["view_id"]),
            n["grasp"],
            f"{n['distance']:.3f}",
            " / ".join(f"{v:+.0f}" for v in n["euler_deg"]),
        )
    console.print(table)
    return 0


def db_build_command(
    views_per_grasp: int = 2000,
    size: int = 128,
    workers: int = 2,
    seed: int = 0,
    out: Path | None = None,
) -> int:
    """(Re)build the synthetic view database of the hog_knn classifier.

    Options for the typer signature:
      --views-per-grasp N  rendered views per grasp (default 2000; 6 grasps)
      --size PX            rendered image side [px] (default 128, >= 32)
      --workers N          rendering processes (default 2; about one per core)
      --seed S             random seed; the same seed gives the same database (default 0)
      --out PATH           output .npz (a .json with the metadata is written next to it;
                           default: the database shipped with the package)
    Shows a progress bar; prints the size, counts and build rate.
    """
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    from graspframe.vision.database import build_database, shipped_database_path

    out = Path(out) if out is not None else shipped_database_path()
    console = Console()
    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TimeRemainingColumn(),
        console=console,
    ) as progress:
        task = progress.add_task("rendering views", total=views_per_grasp * 6)
        database = build_database(
            views_per_grasp,
            size,
            workers,
            seed,
            progress=lambda done, total: progress.update(task, completed=done),
        )
    npz, meta_path = database.save(out)
    meta = database.metadata
    console.print(
        f"wrote {npz} ({npz.stat().st_size / 1e6:.2f} MB) and {meta_path.name}: "
        f"{meta['views_stored']} views stored of {meta['views_rendered']} rendered, "
        f"{meta['views_per_second']} views/s"
    )
    return 0
