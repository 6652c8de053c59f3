"""Contacts between a hand and an object, the raw material of the metric."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import inv_T, rotate_vectors, transform_points

WORLD = "world"  # the frame a backend measures contacts in
OBJECT = "object"  # the object's centroid frame, where grasps are compared
CONTACT_FRAMES = (WORLD, OBJECT)


@dataclass(frozen=True)
class Contact:
    """One contact point between a hand link and the object, expressed in `frame`.

    link: the hand link touching the object.
    real_finger: the real finger that link belongs to (see HandDescription.real_fingers).
    p: contact position [m].
    n: unit contact normal pointing from the object into the hand.
    f: force the hand exerts on the object at this point [N].
    frame: "world" (as a backend reports it) or "object" (the object's centroid frame).
    """

    link: str
    real_finger: str
    p: NDArray[np.float64]
    n: NDArray[np.float64]
    f: NDArray[np.float64]
    frame: str = WORLD

    def __post_init__(self) -> None:
        if self.frame not in CONTACT_FRAMES:
            raise GraspframeError(f"contact frame {self.frame!r} is not one of {CONTACT_FRAMES}")

    def in_object_frame(self, T_world_object: NDArray[np.float64]) -> Contact:
        """This world-frame contact expressed in the object frame at T_world_object."""
        if self.frame != WORLD:
            raise GraspframeError(f"the contact is in the {self.frame} frame, not the world frame")
        T_object_world = inv_T(T_world_object)
        return Contact(
            link=self.link,
            real_finger=self.real_finger,
            p=transform_points(T_object_world, self.p),
            n=rotate_vectors(T_object_world, self.n),
            f=rotate_vectors(T_object_world, self.f),
            frame=OBJECT,
        )

    def to_dict(self) -> dict:
        """The contact as JSON-ready values; the frame is named by where it is stored."""
        return {
            "link": self.link,
            "real_finger": self.real_finger,
            "p": [float(v) for v in self.p],
            "n": [float(v) for v in self.n],
            "f": [float(v) for v in self.f],
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
