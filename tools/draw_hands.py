"""Draw every registered hand in each of its preshapes (open and closed) for docs/robots.md.

    python -m tools.draw_hands            # writes docs/images/<hand>_<preshape>.png

The collision shapes are placed by Pinocchio forward kinematics (CollisionModel) and drawn
with matplotlib, in the palm frame: +z out of the palm (up in the picture), +x towards
the fingertips.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from graspframe.common.grasps import PALM
from graspframe.common.transforms import inv_T
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.robot_models.shapes import geometry_mesh

OUT_DIR = Path(__file__).parents[1] / "docs" / "images"
FINGER_COLOURS = ["#d95f02", "#1b9e77", "#7570b3", "#e7298a", "#66a61e", "#e6ab02"]
PALM_COLOUR = "#999999"


def shape_faces(shape, T) -> np.ndarray:
    """Triangles (n, 3, 3) [m] of a collision shape's mesh, in the frame T maps into."""
    mesh = geometry_mesh(shape)
    if mesh is None:
        raise ValueError(f"cannot draw a {type(shape).__name__}")
    return (np.asarray(mesh.vertices) @ T[:3, :3].T + T[:3, 3])[mesh.faces]


def draw(hand, preshape, path: Path) -> None:
    model = CollisionModel(model_of(hand))
    finger_of_link = hand.finger_of_link()
    colours = {f: FINGER_COLOURS[i % len(FINGER_COLOURS)] for i, f in enumerate(hand.real_fingers)}
    colours[PALM] = PALM_COLOUR
    fig = plt.figure(figsize=(8, 4))
    for column, (label, q) in enumerate((("open", preshape.open_q), ("closed", preshape.closed_q))):
        model.place(hand.with_model_followers(q))
        T_palm_root = inv_T(model.T_root_frame(hand.palm_frame))
        ax = fig.add_subplot(1, 2, column + 1, projection="3d")
        all_points = []
        for link, shape, T_root_shape in model.shapes():
            faces = shape_faces(shape, T_palm_root @ T_root_shape)
            colour = colours.get(finger_of_link.get(link, PALM), PALM_COLOUR)
            ax.add_collection3d(
                Poly3DCollection(faces, facecolor=colour, edgecolor="k", linewidths=0.1, alpha=0.8),
                autolim=False,
            )
            all_points.extend(np.concatenate(faces))
        points = np.array(all_points)
        centre, span = points.mean(axis=0), (points.max(axis=0) - points.min(axis=0)).max() / 2
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
            setter(c - span, c + span)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=20, azim=-60)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.set_title(f"{label}")
        ax.plot([0, 0], [0, 0], [0, 0.04], color="r", linewidth=2)  # palm normal
    fig.suptitle(f"{hand.name}: {preshape.name} (palm frame; red line = palm +z)")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def main() -> None:
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    registry = default_registry()
    for hand_name in registry.names("hand"):
        hand = registry.get_hand(hand_name)
        for preshape in hand.preshapes.values():
            path = OUT_DIR / f"{hand_name}_{preshape.name}.png"
            draw(hand, preshape, path)
            print(path.relative_to(OUT_DIR.parents[1]))


if __name__ == "__main__":
    main()
