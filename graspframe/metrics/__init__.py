"""Grasp metrics: pure functions on plain arrays, usable on contacts from any source."""

from graspframe.common.errors import NoContactsError
from graspframe.metrics.cohesion import (
    Partition,
    best_partition,
    cohesive_index,
    effective_cohesion,
    force_coupling,
    pair_cohesion,
)
from graspframe.metrics.real_fingers import RealFingerContacts, group_by_real_finger
from graspframe.metrics.virtual_fingers import (
    MatchedPair,
    VirtualFinger,
    VirtualFingerComparison,
    VirtualFingerGrasp,
    compare,
    virtual_finger,
    virtual_fingers_from_contacts,
    virtual_fingers_from_real_fingers,
)

__all__ = [
    "MatchedPair",
    "NoContactsError",
    "Partition",
    "RealFingerContacts",
    "VirtualFinger",
    "VirtualFingerComparison",
    "VirtualFingerGrasp",
    "best_partition",
    "cohesive_index",
    "compare",
    "effective_cohesion",
    "force_coupling",
    "group_by_real_finger",
    "pair_cohesion",
    "virtual_finger",
    "virtual_fingers_from_contacts",
    "virtual_fingers_from_real_fingers",
]
