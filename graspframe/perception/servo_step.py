"""One measurement of the servo strategy (graspframe/strategy/servo.py): the object
fitted to a depth image at one stage, and the correction it led to. Kept with the
perception so that the servo picture and the run result read it without the strategy."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from graspframe.perception.localise import ObjectFit


@dataclass(frozen=True)
class ServoStep:
    """One measurement of the servo strategy.

    stage: "start", "via", "pre-approach" or "standoff"; step: its number in the stage
    (from 1); fit: the object fitted to the depth image; correction_mm: [mm] the palm's
    move (x, y), world frame, (0, 0) for none; skipped: why a correction the fit asked
    for was not made (None: made, or none was needed).
    """

    stage: str
    step: int
    fit: ObjectFit
    correction_mm: tuple[float, float]
    skipped: str | None = None

    def to_json(self) -> dict[str, Any]:
        """Its execute.servo event payload, and result.json's servo step ("skipped"
        only when set)."""
        data: dict[str, Any] = {
            "stage": self.stage,
            "step": self.step,
            "fit": self.fit.to_json(),
            "correction_mm": list(self.correction_mm),
        }
        if self.skipped is not None:
            data["skipped"] = self.skipped
        return data
