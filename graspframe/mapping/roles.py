"""The joint roles the synthesis builds candidates from: the hand's URDF drafted again
(graspframe/specs/draft.py), each of the hand's real fingers matched to a drafted finger
by its links."""

from __future__ import annotations

from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import PALM
from graspframe.hal.descriptions import HandDescription
from graspframe.specs.draft import HandDraft, draft_hand


def roles_of(hand: HandDescription) -> tuple[HandDraft, dict[str, str]]:
    """The URDF's drafted roles for `hand` and the draft finger of each of the hand's
    real fingers (matched by their links)."""
    draft = draft_hand(hand.model_path)
    names = {}
    for finger, links in hand.real_fingers.items():
        if finger == PALM:
            continue
        best = max(draft.fingers.values(), key=lambda f: len(set(f.links) & set(links)))
        if not set(best.links) & set(links):
            raise GraspframeError(
                f"hand {hand.name!r}: real finger {finger!r} holds none of the URDF's finger "
                "links; the synthesis needs its fingers to be the URDF's chains"
            )
        names[finger] = best.name
    return draft, names
