"""Real fingers: a grasp's contacts grouped by the finger (or the palm) that made them.

Step 1 of the virtual-finger metric (docs/method.md, 5): contacts from any source -> one
`RealFingerContacts` per real finger, in the object frame.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from graspframe.common.contacts import WORLD, Contact
from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import as_pose
from graspframe.metrics.vectors import Vectors, checked_unit_vectors, checked_vectors


@dataclass(frozen=True, eq=False)
class RealFingerContacts:
    """The contacts of one real finger, all in one common frame (the object frame).

    name: real finger name (a finger or the palm).
    positions: (N,3) contact positions [m].
    normals: (N,3) unit contact normals, from the object into the hand.
    forces: (N,3) forces the finger exerts on the object at each contact [N].
    Arrays are copied and made read-only; N >= 1.
    """

    name: str
    positions: Vectors
    normals: Vectors
    forces: Vectors

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise GraspframeError(f"real finger name must be a non-empty string, got {self.name!r}")
        what = f"real finger {self.name!r}"
        positions = checked_vectors(self.positions, f"{what} positions")
        count = len(positions)
        object.__setattr__(self, "positions", positions)
        normals = checked_unit_vectors(self.normals, f"{what} normals", count)
        object.__setattr__(self, "normals", normals)
        object.__setattr__(self, "forces", checked_vectors(self.forces, f"{what} forces", count))

    @property
    def contact_count(self) -> int:
        return len(self.positions)

    @property
    def force(self) -> Vectors:
        """(3,) net force of the real finger: the sum of its contact forces [N]."""
        return self.forces.sum(axis=0)


def group_by_real_finger(
    contacts: Iterable[Contact], T_world_object: ArrayLike | None = None
) -> tuple[RealFingerContacts, ...]:
    """Contacts grouped by `Contact.real_finger`, in the object frame (sorted by name).

    contacts: contacts in the world or the object frame (`Contact.frame`).
    T_world_object: 4x4 pose of the object frame in the world [m]; needed when a contact
    is in the world frame.
    Returns an empty tuple when there are no contacts.
    """
    T = None if T_world_object is None else as_pose(T_world_object, "T_world_object")
    rows: dict[str, list[Contact]] = {}
    for contact in contacts:
        if not isinstance(contact, Contact):
            raise GraspframeError(
                f"expected graspframe.common.contacts.Contact, got {type(contact)}"
            )
        if contact.frame == WORLD:
            if T is None:
                raise GraspframeError("world-frame contacts need T_world_object")
            contact = contact.in_object_frame(T)
        rows.setdefault(contact.real_finger, []).append(contact)
    return tuple(
        RealFingerContacts(
            name=name,
            positions=np.array([c.p for c in group]),
            normals=np.array([c.n for c in group]),
            forces=np.array([c.f for c in group]),
        )
        for name, group in sorted(rows.items())
    )
