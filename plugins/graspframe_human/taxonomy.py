"""Where a person touches the object in each of the six grasps, as the grasp taxonomy
describes it (docs/method.md#where-the-human-hand-touches): the expectation the simulated
human reference grasps are tested against.

Parts are named by the human model's links: the palm (the palm pad, the thenar eminence
on hh_thumb_cmc, the metacarpals: the real finger "palm"), and per digit its proximal,
intermediate and distal phalanx (the thumb: metacarpal, proximal, distal). A fingertip
contact is one on the distal phalanx (or its tip marker).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from graspframe.common.grasps import PALM, THUMB, HumanGrasp
from graspframe_human.description import FINGERS

# The segments of a digit, by link name suffix; "tip" is the marker at the distal end.
DISTAL = ("distal", "tip")


@dataclass(frozen=True)
class ContactExpectation:
    """palm: True, the palm must touch; False, it must not.
    thumb_segments: the thumb must touch on one of these segments.
    min_fingers: at least this many of the four fingers touch.
    required_fingers: these fingers must be among them.
    fingertips_only: every finger and thumb contact is on a distal phalanx.
    text: the taxonomy's words, for the docs and error messages."""

    palm: bool
    thumb_segments: tuple[str, ...]
    min_fingers: int
    required_fingers: tuple[str, ...] = ()
    fingertips_only: bool = False
    text: str = ""


_ANY_THUMB = ("metacarpal", "proximal", "distal", "tip")

EXPECTED_CONTACTS = {
    HumanGrasp.LARGE_DIAMETER: ContactExpectation(
        palm=True,
        thumb_segments=_ANY_THUMB,
        min_fingers=3,
        text="power wrap: the palm, the fingers wrapped round the object, the thumb opposed",
    ),
    HumanGrasp.SMALL_DIAMETER: ContactExpectation(
        palm=True,
        thumb_segments=_ANY_THUMB,
        min_fingers=3,
        text="power wrap of a thin object: the palm, the fingers curled fully round it, "
        "the thumb closed over it",
    ),
    HumanGrasp.ABDUCTED_THUMB: ContactExpectation(
        palm=True,
        thumb_segments=_ANY_THUMB,
        min_fingers=3,
        text="power wrap with the thumb abducted along the object: the palm, the fingers "
        "round it, the thumb lying on it",
    ),
    HumanGrasp.PINCH: ContactExpectation(
        palm=False,
        thumb_segments=DISTAL,
        min_fingers=1,
        required_fingers=("index",),
        fingertips_only=True,
        text="precision, thumb and index finger: the pads of the thumb and the index "
        "fingertip, no palm",
    ),
    HumanGrasp.POWER_SPHERE: ContactExpectation(
        palm=True,
        thumb_segments=_ANY_THUMB,
        min_fingers=3,
        text="power, circular: the palm, the fingers spread round the ball, the thumb opposed",
    ),
    HumanGrasp.PRECISION_DISC: ContactExpectation(
        palm=False,
        thumb_segments=DISTAL,
        min_fingers=2,
        fingertips_only=True,
        text="precision, circular: the fingertips and the thumb tip round the rim, no palm",
    ),
}


def _digit_and_segment(link: str) -> tuple[str, str] | None:
    """("index", "distal") for "hh_index_distal"; None for a palm link."""
    parts = link.removeprefix("hh_").split("_", 1)
    if len(parts) != 2 or parts[0] not in (THUMB, *FINGERS):
        return None
    return parts[0], parts[1]


def contact_problems(grasp: HumanGrasp, contacts: Iterable) -> list[str]:
    """How the contacts (objects with .link and .real_finger) differ from the taxonomy's
    expectation for `grasp`; empty when they match."""
    expectation = EXPECTED_CONTACTS[grasp]
    contacts = list(contacts)
    touching = {c.real_finger for c in contacts}
    segments = {ds for c in contacts if (ds := _digit_and_segment(c.link)) is not None}
    problems = []
    if expectation.palm and PALM not in touching:
        problems.append("the palm does not touch")
    if not expectation.palm and PALM in touching:
        problems.append("the palm touches")
    if not any(d == THUMB and s in expectation.thumb_segments for d, s in segments):
        problems.append(f"the thumb does not touch on its {'/'.join(expectation.thumb_segments)}")
    fingers = sorted(touching & set(FINGERS))
    if len(fingers) < expectation.min_fingers:
        touch = "1 finger touches" if len(fingers) == 1 else f"{len(fingers)} fingers touch"
        problems.append(
            f"{touch} ({', '.join(fingers) or 'none'}); at least {expectation.min_fingers} should"
        )
    missing = [f for f in expectation.required_fingers if f not in touching]
    if missing:
        problems.append(f"{', '.join(missing)} does not touch")
    if expectation.fingertips_only:
        off_tips = sorted(f"{d} {s}" for d, s in segments if s not in DISTAL)
        if off_tips:
            problems.append(f"contacts off the fingertips: {', '.join(off_tips)}")
    return problems
