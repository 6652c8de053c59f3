"""The colours pictures share: real fingers, palm, arm, object, table, contacts, palm axes.

Colours are "#rrggbb" strings; `rgb` turns one into floats in [0, 1] (the rasteriser's
albedo) and `bgr255` into OpenCV's byte order.

A link is coloured by its real finger (the palm grey, arm links a muted slate). A vendor's
visual mesh keeps `MATERIAL_TINT` of its own material colour, so that a black finger
segment and its white fingertip pad still differ while the finger's colour reads first.
"""

from __future__ import annotations

from collections.abc import Mapping

from graspframe.common.grasps import PALM

FINGER_COLOURS = ("#1b9e77", "#7570b3", "#e7298a", "#66a61e", "#d95f02", "#a6761d", "#17becf")
PALM_COLOUR = "#9a9a9a"
ARM_COLOUR = "#7d8ea8"  # muted slate: the arm is context, the hand is the subject
OBJECT_COLOUR = "#ffd92f"
OBJECT_OPACITY = 0.55  # the object is see-through: contacts and fingers behind it show
TABLE_COLOURS = ("#e9e6df", "#d6d2c8")  # the table top's checker squares
TABLE_CELL = 0.05  # [m] side of a checker square
BACKGROUND = "#f0f0f0"  # of a panel; the sheet around the panels is white
CONTACT_COLOUR = "#ff0000"
CONTACT_EDGE = "#000000"
PALM_Z_COLOUR, PALM_X_COLOUR = "#d62728", "#1f4fd8"
MATERIAL_TINT = 0.3  # share of a visual mesh's own material colour in its albedo


def rgb(colour: str) -> tuple[float, float, float]:
    """ "#rrggbb" -> (r, g, b) in [0, 1]."""
    value = colour.lstrip("#")
    return (int(value[0:2], 16) / 255, int(value[2:4], 16) / 255, int(value[4:6], 16) / 255)


def rgb255(colour: str) -> tuple[int, int, int]:
    """ "#rrggbb" -> (r, g, b) in 0..255."""
    blue, green, red = bgr255(colour)
    return (red, green, blue)


def bgr255(colour: str) -> tuple[int, int, int]:
    """ "#rrggbb" -> (b, g, r) in 0..255."""
    value = colour.lstrip("#")
    return (int(value[4:6], 16), int(value[2:4], 16), int(value[0:2], 16))


def finger_colours(finger_of_link: Mapping[str, str]) -> dict[str, str]:
    """Real finger -> colour, in the order the fingers first appear; the palm is grey."""
    colours: dict[str, str] = {}
    for finger in finger_of_link.values():
        if finger not in colours and finger != PALM:
            colours[finger] = FINGER_COLOURS[len(colours) % len(FINGER_COLOURS)]
    colours[PALM] = PALM_COLOUR
    return colours


def colour_of_finger(finger: str, colours: Mapping[str, str]) -> str:
    """`colours[finger]`; a finger `colours` lacks (another hand's, such as the human
    reference's) gets a colour picked from its name, the same in every run."""
    if finger in colours:
        return colours[finger]
    return FINGER_COLOURS[sum(map(ord, finger)) % len(FINGER_COLOURS)]


def link_colour(link: str, finger_of_link: Mapping[str, str], colours: Mapping[str, str]) -> str:
    """A hand link's finger colour (the palm's for a finger without one); ARM_COLOUR for
    links that belong to no real finger."""
    finger = finger_of_link.get(link)
    if finger is None:
        return ARM_COLOUR
    return colours.get(finger, PALM_COLOUR)


def tinted(base: tuple[float, float, float], material: tuple[float, float, float] | None):
    """The albedo of a surface of colour `base` whose mesh has its own `material`
    colour (None: the base colour as it is)."""
    if material is None:
        return base
    t = MATERIAL_TINT
    return tuple((1 - t) * b + t * m for b, m in zip(base, material, strict=True))
