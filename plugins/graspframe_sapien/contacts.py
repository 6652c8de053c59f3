"""Contacts between hand links and the object, read from the PhysX contact report."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from graspframe.common.contacts import Contact

# A contact point counts when it pushes with at least this force: PhysX also reports
# points within its contact offset that carry no force yet (the hand is about to touch).
MIN_CONTACT_FORCE = 0.01  # [N]


def read_contacts(
    scene, object_entity, finger_of_link: Mapping[str, str], timestep: float
) -> list[Contact]:
    """Every force-carrying contact point between the object and a hand link, ordered
    by link name, then position.

    PhysX reports per pair (bodies[0], bodies[1]) points whose normal points from
    bodies[1] into bodies[0] and whose impulse acts on bodies[0] [N s].
    """
    contacts = []
    for pair in scene.get_contacts():
        body_0, body_1 = pair.bodies
        if body_1.entity is object_entity and body_0.name in finger_of_link:
            link, sign = body_0.name, 1.0  # normal already points object -> hand
        elif body_0.entity is object_entity and body_1.name in finger_of_link:
            link, sign = body_1.name, -1.0
        else:
            continue
        for point in pair.points:
            impulse_on_body_0 = np.asarray(point.impulse, dtype=float)
            # Force the hand exerts on the object: on bodies[0] if that is the object.
            f_world = -sign * impulse_on_body_0 / timestep
            if np.linalg.norm(f_world) < MIN_CONTACT_FORCE:
                continue
            contacts.append(
                Contact(
                    link=link,
                    real_finger=finger_of_link[link],
                    p=np.asarray(point.position, dtype=float),
                    n=sign * np.asarray(point.normal, dtype=float),
                    f=f_world,
                )
            )
    # PhysX lists the pairs in an order that depends on what the process simulated
    # before; a fixed order keeps sums over the contacts (grasp quality) the same in
    # every process, fresh or long-lived.
    contacts.sort(key=_contact_order)
    return contacts


def _contact_order(contact: Contact) -> tuple:
    return (contact.link, *contact.p, *contact.n, *contact.f)
