"""The grasp vocabulary: the six human grasps (Cutkosky numbers) and robot preshape names."""

from __future__ import annotations

from enum import StrEnum

from graspframe.common.errors import UnknownNameError


class HumanGrasp(StrEnum):
    """Six grasps of Cutkosky's taxonomy; the value is the name used on the command line."""

    LARGE_DIAMETER = "large_diameter"
    SMALL_DIAMETER = "small_diameter"
    ABDUCTED_THUMB = "abducted_thumb"
    PINCH = "pinch"
    POWER_SPHERE = "power_sphere"
    PRECISION_DISC = "precision_disc"

    @property
    def cutkosky_number(self) -> int:
        return _CUTKOSKY_NUMBER[self]

    @property
    def volar_for_human(self) -> bool:
        """True when the human palm touches the object in this grasp."""
        return self in _VOLAR_FOR_HUMAN

    @property
    def volar_for_robot(self) -> bool:
        """True when the robot strategy is volar (approach until the palm touches).

        Only the two diameter grasps: the robot hands cannot reproduce the palm contact
        of Abducted Thumb and Power Sphere (docs/method.md, section 1).
        """
        return self in (HumanGrasp.LARGE_DIAMETER, HumanGrasp.SMALL_DIAMETER)

    @classmethod
    def parse(cls, name: str) -> HumanGrasp:
        """The grasp called `name` (case and '-' tolerant), or an error listing the names."""
        key = name.strip().lower().replace("-", "_").replace(" ", "_")
        try:
            return cls(key)
        except ValueError:
            raise UnknownNameError("grasp", name, [g.value for g in cls]) from None


_CUTKOSKY_NUMBER = {
    HumanGrasp.LARGE_DIAMETER: 1,
    HumanGrasp.SMALL_DIAMETER: 2,
    HumanGrasp.ABDUCTED_THUMB: 4,
    HumanGrasp.PINCH: 9,
    HumanGrasp.POWER_SPHERE: 10,
    HumanGrasp.PRECISION_DISC: 12,
}

_VOLAR_FOR_HUMAN = frozenset(
    {
        HumanGrasp.LARGE_DIAMETER,
        HumanGrasp.SMALL_DIAMETER,
        HumanGrasp.ABDUCTED_THUMB,
        HumanGrasp.POWER_SPHERE,
    }
)


class Preshape(StrEnum):
    """Preshape names of the built-in robot hands (docs/method.md, section 1).

    A hand plugin may define preshapes with other names; these are the shared ones.
    """

    # Barrett
    WRAP = "wrap"
    PRECISION = "precision"
    PRECISION_DISC = "precision_disc"
    # Karlsruhe (also uses WRAP)
    POWER = "power"
    SPHERE = "sphere"
    DISC = "disc"


# Real-finger names. A hand may use its own names (a Barrett hand has finger_1..3);
# the palm is always called PALM so the volar strategy and the metric can find it.
PALM = "palm"
THUMB = "thumb"
# The registered name of the human reference hand (its grasps are the references the
# robots are scored against).
HUMAN_HAND = "human"
