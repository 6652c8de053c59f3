"""One panel: a rendered view with the contacts and the palm axes drawn on top.

Contacts and palm axes are projected into the view and drawn over the render (sheet.py's
markers), so every contact shows in every view: a filled dot where it is in sight (also
through the see-through object), a ring where the hand hides it (render3d.visible).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from graspframe.pictures import style
from graspframe.pictures.render3d import Placed, View, render, visible
from graspframe.pictures.sheet import LegendEntry, draw_arrow, draw_contacts

ARROW_LENGTH = 0.03  # [m] palm axes
# The cameras of every grasp picture (snapshots.png, check-hand's pictures).
FOV_DEG = 30.0  # horizontal field of view
PALM_VIEW_DIRECTION = (0.0, -0.3, 1.0)  # palm frame: from the object's side, a little to -y


def render_panel(
    placed: Sequence[Placed],
    view: View,
    contacts_world: NDArray[np.float64],
    T_world_palm: NDArray[np.float64],
    occluders: Sequence[Placed] = (),
) -> NDArray[np.uint8]:
    """The BGR panel: the placed soups rendered from `view`, then the palm axes (palm +z,
    palm +x, ARROW_LENGTH each, from the palm origin) and the contact markers (world
    points (n, 3) [m]): rings for those that `occluders` (the hand) hide."""
    image = render(placed, view, style.bgr255(style.BACKGROUND), style.OBJECT_OPACITY)
    origin = T_world_palm[:3, 3]
    tips = [origin + ARROW_LENGTH * T_world_palm[:3, axis] for axis in (2, 0)]
    pixels, depth = view.project(np.stack([origin, *tips]))
    if np.all(depth > 0):
        draw_arrow(image, pixels[0], pixels[1], style.PALM_Z_COLOUR)
        draw_arrow(image, pixels[0], pixels[2], style.PALM_X_COLOUR)
    if len(contacts_world):
        contact_pixels, contact_depth = view.project(contacts_world)
        in_front = contact_depth > 0
        in_sight = visible(occluders, view, contacts_world) if occluders else in_front
        draw_contacts(image, contact_pixels[in_front & ~in_sight], hidden=True)
        draw_contacts(image, contact_pixels[in_sight])
    return image


def legend_entries(
    colours: Mapping[str, str], with_arm: bool, with_table: bool
) -> list[LegendEntry]:
    """The legend of a grasp picture: the real fingers (colours: finger -> colour), the
    arm, the object, the table, contacts and the palm axes."""
    entries = [LegendEntry("patch", colour, finger) for finger, colour in colours.items()]
    if with_arm:
        entries.append(LegendEntry("patch", style.ARM_COLOUR, "arm (see-through)"))
    entries.append(LegendEntry("patch", style.OBJECT_COLOUR, "object (see-through)"))
    if with_table:
        squares = f"table, {style.TABLE_CELL * 100:g} cm squares"
        entries.append(LegendEntry("patch", style.TABLE_COLOURS[1], squares))
    entries += [
        LegendEntry("dot", style.CONTACT_COLOUR, "contact"),
        LegendEntry("ring", style.CONTACT_COLOUR, "contact hidden by the hand"),
        LegendEntry("arrow", style.PALM_Z_COLOUR, "palm +z"),
        LegendEntry("arrow", style.PALM_X_COLOUR, "palm +x"),
    ]
    return entries
