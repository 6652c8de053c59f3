"""Contacts between a hand and an object, the raw material of the metric."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.transforms import inv_T, rotate_vectors, transform_points


@dataclass(frozen=True)
class Contact:
    """One contact point between a hand link and the object, in the world frame.

    link: the hand link touching the object.
    real_finger: the real finger that link belongs to (see HandDescription.real_fingers).
    p_world: contact position [m].
    n_world: unit contact normal pointing from the object into the hand.
    f_world: force the hand exerts on the object at this point [N].
    """

    link: str
    real_finger: str
    p_world: NDArray[np.float64]
    n_world: NDArray[np.float64]
    f_world: NDArray[np.float64]

    def in_frame(self, T_world_frame: NDArray[np.float64]) -> Contact:
        """The same contact expressed in another frame (e.g. the object frame)."""
        T_frame_world = inv_T(T_world_frame)
        return Contact(
            link=self.link,
            real_finger=self.real_finger,
            p_world=transform_points(T_frame_world, self.p_world),
            n_world=rotate_vectors(T_frame_world, self.n_world),
            f_world=rotate_vectors(T_frame_world, self.f_world),
        )

    def to_dict(self) -> dict:
        return {
            "link": self.link,
            "real_finger": self.real_finger,
            "p": [float(v) for v in self.p_world],
            "n": [float(v) for v in self.n_world],
            "f": [float(v) for v in self.f_world],
        }


@dataclass(frozen=True)
class PalmSensorReading:
    """What the palm tactile sensor and the first-contact detector report.

    touched: any contact on the hand.
    on_palm: at least one contact is on a palm link (the real finger "palm").
    first_contact: the contact with the largest force (None when nothing touches).
    """

    touched: bool
    on_palm: bool
    first_contact: Contact | None
