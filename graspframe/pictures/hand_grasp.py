"""One hand closed around an object, as `graspframe check-hand` shows a preshape: a PNG
with two shaded views in the palm frame, the contacts, the palm axes and a caption.

- palm view: looking at the palm from the object's side, fingertips (palm +x) up, the
  object see-through (as snapshots.py's palm row);
- side view: from the palm's -y side, 20 deg above the palm plane, palm +x to the right
  and the palm normal (+z) up (the plane most fingers curl in).

The hand is drawn as in snapshots.png: each link's visual meshes when the model has
them, else its collision shapes, coloured by real finger; no arm, no table.

Example (a preshape closed around its design object; contacts in the object frame):

    draw_hand_grasp(
        Path("wrap.png"), hand, hand.preshapes["wrap"].closed_q, obj, T_palm_object,
        [transform_points(T_palm_object, c.p) for c in contacts],
        [c.real_finger for c in contacts],
        "karlsruhe wrap: closed around its design handle",
    )
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError, InputError
from graspframe.common.transforms import as_pose, inv_T
from graspframe.hal.descriptions import HandDescription
from graspframe.hal.objects import ObjectDescription
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.pictures import style
from graspframe.pictures.inputs import checked_figure, checked_object_soup, contact_points
from graspframe.pictures.panel import (
    FOV_DEG,
    PALM_VIEW_DIRECTION,
    legend_entries,
    render_panel,
)
from graspframe.pictures.render3d import Camera, Placed, box_corners, fit_view
from graspframe.pictures.sheet import compose, write_png
from graspframe.robot_models.model import model_of

PANEL_PX = 400  # [px] side of a square panel
SIDE_VIEW_DIRECTION = (0.0, -1.0, 0.36)  # palm frame: from -y, 20 deg above the palm plane
VIEW_NAMES = ("palm view, facing the palm", "side view, from palm -y")


def draw_hand_grasp(
    path: Path,
    hand: HandDescription,
    q_by_joint: Mapping[str, float],
    obj: ObjectDescription,
    T_palm_object,
    contact_points_palm,
    contact_fingers: Sequence[str],
    caption: str,
    model: UrdfModel | None = None,
) -> Path:
    """Draw `hand` at the joints `q_by_joint` [rad or m] (its driven joints by name; the
    <mimic> followers are added) around `obj`, placed at T_palm_object (the object frame
    in the palm frame), with the contacts `contact_points_palm` (n, 3) [m, palm frame]
    of the real fingers `contact_fingers` (one each; may be empty), captioned `caption`,
    to the PNG `path` (atomically; folders created); returns `path`.

    model: the model to draw (default `model_of(hand)`; a hand alone, its root anywhere:
    the picture is in the palm frame). InputError (one line) for unusable input.
    """
    path = Path(path)
    T_palm_object = as_pose(T_palm_object, "T_palm_object")
    contacts_palm = contact_points(contact_points_palm, contact_fingers, "contact_points_palm")
    object_soup = checked_object_soup(obj, "hand picture")
    colours = style.finger_colours(hand.finger_of_link())
    if model is None:
        try:
            model = model_of(hand)
        except GraspframeError as exc:
            raise InputError(f"hand picture: {exc}") from None
    figure = checked_figure(
        model, hand.finger_of_link(), colours, hand.palm_frame, f"hand {hand.name}"
    )
    try:
        figure.place(hand.with_model_followers(dict(q_by_joint)))
    except GraspframeError as exc:
        raise InputError(f"hand {hand.name}: {exc}") from None
    T_palm_root = inv_T(figure.T_root_frame(hand.palm_frame))
    links = figure.placed_links(T_palm_root)  # the palm frame is the world here
    hand_placed = [p for link, p in links.items() if figure.is_hand_link(link)]
    placed_object = Placed(object_soup, T_palm_object, translucent=True)
    placed = [*hand_placed, placed_object]
    points = np.concatenate([box_corners(p) for p in placed])
    camera = Camera.from_fov(PANEL_PX, PANEL_PX, FOV_DEG)
    views = [
        fit_view(camera, points, PALM_VIEW_DIRECTION, (1.0, 0.0, 0.0)),
        fit_view(camera, points, SIDE_VIEW_DIRECTION, (0.0, 0.0, 1.0)),
    ]
    T_palm_palm: NDArray[np.float64] = np.eye(4)
    panels = [
        [render_panel(placed, view, contacts_palm, T_palm_palm, hand_placed) for view in views]
    ]
    sheet = compose(
        caption, VIEW_NAMES, (), panels, legend_entries(colours, with_arm=False, with_table=False)
    )
    return write_png(path, sheet)
