"""The vision command `graspframe classify` (any registered classifier). (The view
database of the hog_knn classifier is built by `graspframe db build`, a command of its
plugin.)

commands.py wires it into the typer app; it prints its result (rich) and returns an exit
code, and raises GraspframeError subclasses (one-line messages) for bad input.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from graspframe.common.defaults import DEFAULT_CLASSIFIER
from graspframe.common.errors import InputError
from graspframe.common.transforms import rpy_from_R
from graspframe.hal.classifier import ClassifierOptions, HumanGraspEstimate
from graspframe.vision.images import read_image

EULER_CONVENTION = (
    "roll-pitch-yaw about the fixed camera axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll)"
)


CAMERA_FRAME = "OpenCV: x right, y down, z forward"


def euler_deg(R_camera_palm: np.ndarray) -> tuple[float, float, float]:
    """Roll, pitch, yaw [deg] of a rotation, in EULER_CONVENTION."""
    roll, pitch, yaw = np.degrees(rpy_from_R(R_camera_palm))
    return float(roll), float(pitch), float(yaw)


def estimate_as_json(estimate: HumanGraspEstimate) -> dict[str, object]:
    """The JSON document `classify --json` prints (angles [deg], position [m])."""
    roll, pitch, yaw = euler_deg(estimate.R_camera_palm)
    return {
        "grasp": estimate.grasp.value,
        "confidence": round(estimate.confidence, 4),
        "R_camera_palm": np.round(estimate.R_camera_palm, 6).tolist(),
        "euler_deg": {"roll": round(roll, 2), "pitch": round(pitch, 2), "yaw": round(yaw, 2)},
        "euler_convention": EULER_CONVENTION,
        "camera_frame": CAMERA_FRAME,
        "p_camera_palm_m": None
        if estimate.p_camera_palm is None
        else np.round(estimate.p_camera_palm, 4).tolist(),
        "neighbours": [
            {
                "view_id": n.view_id,
                "grasp": n.grasp.value,
                "distance": round(n.distance, 4),
                "euler_deg": [round(angle, 2) for angle in euler_deg(n.R_camera_palm)],
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
    from graspframe.plugin_system.registry import get_classifier

    classifier_class = get_classifier(classifier)
    if k < 1:
        raise InputError(f"--k must be >= 1, got {k}")
    options = ClassifierOptions(k=k)  # a classifier without neighbours ignores k
    estimate = classifier_class.with_options(options).classify(read_image(image))
    if as_json:
        sys.stdout.write(json.dumps(estimate_as_json(estimate), indent=2) + "\n")
        return 0
    _print_estimate(estimate)
    return 0


def _print_estimate(estimate: HumanGraspEstimate) -> None:
    """The estimate as text and a table of its neighbours (rich)."""
    from rich.console import Console
    from rich.table import Table

    console = Console()
    console.print(
        f"grasp: [bold]{estimate.grasp.value}[/bold]  confidence {estimate.confidence:.2f}"
    )
    console.print(
        f"hand orientation R_camera_palm (camera frame {CAMERA_FRAME}):\n"
        + "\n".join("  " + "  ".join(f"{v:+.3f}" for v in row) for row in estimate.R_camera_palm)
    )
    roll, pitch, yaw = euler_deg(estimate.R_camera_palm)
    console.print(
        f"Euler \\[deg]: roll {roll:+.1f}, pitch {pitch:+.1f}, yaw {yaw:+.1f}  ({EULER_CONVENTION})"
    )
    if estimate.p_camera_palm is not None:
        x, y, z = estimate.p_camera_palm
        console.print(
            f"palm position \\[m] (assumes a 60 deg horizontal field of view): "
            f"{x:+.3f} {y:+.3f} {z:+.3f}"
        )
    table = Table(title="neighbours (nearest first)")
    for column in ("view", "grasp", "distance", "roll/pitch/yaw \\[deg]"):
        table.add_column(column)
    for n in estimate.neighbours:
        table.add_row(
            str(n.view_id),
            n.grasp.value,
            f"{n.distance:.3f}",
            " / ".join(f"{v:+.0f}" for v in euler_deg(n.R_camera_palm)),
        )
    console.print(table)
