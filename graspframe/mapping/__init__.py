"""Mapping a human grasp onto any hand: `synthesis.py` synthesises a hand's preshapes
from the human reference grasps, on the joint roles its URDF's draft gives
(graspframe/specs/draft.py)."""
