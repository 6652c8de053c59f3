"""servo.png: what the servo strategy saw and did, one panel per measurement.

Each panel is the depth image around the object with the robot filtered out (near:
yellow, far: blue; white: no return, or the robot), the object's model drawn at the
fitted position (green dots, its side facing the camera), the position the robot
believed before the measurement (red cross) and the fitted one (green cross); its title
gives the stage, the correction and
the fit's quality, or why the fit was refused.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from graspframe.common.files import atomic_output
from graspframe.common.transforms import inv_T
from graspframe.hal.depth_camera import DepthImage
from graspframe.perception.localise import ObjectModel

if TYPE_CHECKING:  # the servo strategy draws its steps with this module
    from graspframe.perception.servo_step import ServoStep

PANEL_INCHES = 3.4
MAX_COLUMNS = 3
CROP_PX = 70  # [px] shown around the believed and fitted positions


def _pixels(image: DepthImage, p_world: ArrayLike) -> np.ndarray:
    """(n, 2) (column, row) of world points in the image."""
    T = inv_T(image.T_world_camera)
    p = np.asarray(p_world, dtype=float).reshape(-1, 3) @ T[:3, :3].T + T[:3, 3]
    c = image.intrinsics
    return np.stack([c.fx * p[:, 0] / p[:, 2] + c.cx, c.fy * p[:, 1] / p[:, 2] + c.cy], axis=1)


def _title(step: ServoStep) -> str:
    fit = step.fit
    moved = np.hypot(*step.correction_mm)
    head = f"{step.stage}, step {step.step}"
    if not fit.accepted:
        return f"{head}: fit refused\n{fit.reason}"
    what = "path shifted" if step.stage == "start" else "hand moved"  # start: no move yet
    action = f"{what} {moved:.1f} mm" if moved > 0 else "within tolerance: no move"
    quality = (
        f"{fit.points} points, {100 * fit.inlier_fraction:.0f} % on the model, "
        f"rms {fit.rms_mm:.1f} mm"
    )
    return f"{head}: {action}\n{quality}"


def draw_servo_picture(
    steps: Sequence[tuple[DepthImage, ServoStep]], model: ObjectModel, title: str, path: Path
) -> Path:
    """Draw the measurements `steps` (the depth image, the step with its fit) to `path`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    columns = min(MAX_COLUMNS, len(steps))
    rows = -(-len(steps) // columns)
    figure, axes = plt.subplots(
        rows, columns, figsize=(PANEL_INCHES * columns, PANEL_INCHES * 0.85 * rows + 0.6),
        squeeze=False,
    )  # fmt: skip
    for ax in axes.ravel()[len(steps) :]:
        ax.axis("off")
    for ax, (image, step) in zip(axes.ravel(), steps, strict=False):
        fit = step.fit
        depth = np.ma.masked_invalid(image.depth_m)
        ax.imshow(depth, cmap="viridis_r")
        ax.set_facecolor("white")
        R, p_fit = fit.T_world_object[:3, :3], fit.T_world_object[:3, 3]
        eye = image.T_world_camera[:3, 3]
        surface = model.p_object @ R.T + p_fit
        facing = np.einsum("ij,ij->i", model.n_object @ R.T, eye - surface) > 0
        dots = _pixels(image, surface[facing])
        colour = "#1a9850" if fit.accepted else "#999999"
        ax.scatter(dots[:, 0], dots[:, 1], s=0.6, c=colour, alpha=0.6, linewidths=0)
        believed = p_fit - np.array([*np.asarray(fit.shift_xy), 0.0])
        marks = _pixels(image, np.stack([believed, p_fit]))
        for (u, v), marker_colour in zip(marks, ("#d73027", colour), strict=True):
            ax.plot(u, v, marker="+", markersize=12, markeredgewidth=2, color=marker_colour)
        c = image.intrinsics
        low = np.clip(marks.min(axis=0) - CROP_PX, 0, (c.width, c.height))
        high = np.clip(marks.max(axis=0) + CROP_PX, 0, (c.width, c.height))
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(high[1], low[1])
        ax.set_title(_title(step), fontsize=8)
        ax.set_xticks([])
        ax.set_yticks([])
    legend = (
        "red +: believed position, green +: fitted, dots: the model as fitted; "
        "white: no return, or the robot (filtered out)"
    )
    figure.suptitle(f"{title}\n{legend}", fontsize=9)
    figure.tight_layout()
    with atomic_output(path) as staging:
        figure.savefig(staging, dpi=110, format="png")
    plt.close(figure)
    return path
