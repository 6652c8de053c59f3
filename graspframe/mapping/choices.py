"""The search space of the synthesis's candidates (mapping/candidates.py): the grid of
each parameter, one candidate's parameters (Choice) and a candidate closed
kinematically and scored (Evaluated)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from graspframe.hal.descriptions import HandPreshape

ROLLS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)
OPEN_FRACTIONS = (0.0, 0.15, 0.3, 0.45)
CLOSE_FRACTIONS = (1.0, 0.75, 0.5)  # of the way from rest to the closing limit
STOW_FRACTIONS = (1.0, 0.6, 0.3, 0.0)  # a finger that does not close: of the way curled
SPREADS = (0.0, 1.0 / 3.0)  # of the way from rest to a spread joint's far limit
SHIFTS_X = (-0.045, -0.03, -0.015, 0.0, 0.015, 0.03, 0.045)  # [m] grasp centre along palm x
SHIFTS_Y = (-0.04, -0.02, 0.0, 0.02, 0.04)  # [m] along palm y
STANDOFFS = (0.0, 0.015, 0.03)  # [m] non-volar: beyond the planner's palm clearance


@dataclass(frozen=True)
class Choice:
    """One candidate preshape's parameters (mapping/synthesis.py's docstring says what
    each does)."""

    fingers: tuple[str, ...]
    roll_deg: float = 0.0
    thumb: tuple[tuple[str, float], ...] = ()
    spread: float = 0.0
    open_fraction: float = 0.0  # the widest aperture: the likeliest to clear the object
    close_fraction: float = 1.0
    stow_fraction: float = 1.0
    shift_x: float = 0.0
    shift_y: float = 0.0
    standoff: float = 0.0


@dataclass(frozen=True)
class Evaluated:
    """A candidate closed kinematically: its preshape, the objective (inf: refused, with
    `refused` saying why), the errors and the real fingers that touched."""

    choice: Choice
    preshape: HandPreshape
    cost: float
    position_err_mm: float = math.nan
    orientation_err_deg: float = math.nan
    touched: tuple[str, ...] = ()
    refused: str | None = None
    unbalanced: float = math.nan  # the contacts' unbalanced push (see imbalance)
    epsilon: float = math.nan  # the contacts' Ferrari-Canny L1 epsilon (see epsilon_of)
