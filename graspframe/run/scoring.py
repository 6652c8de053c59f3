"""The score stage of a run: the robot's grasp against the human reference (the
virtual-finger metric, docs/method.md) and the grasp quality of both contact sets."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError, NoContactsError
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import make_T
from graspframe.hal.objects import ObjectDescription
from graspframe.metrics.quality import grasp_quality
from graspframe.metrics.virtual_fingers import (
    VirtualFingerGrasp,
    compare,
    virtual_fingers_from_contacts,
)
from graspframe.run.request import RunInputs
from graspframe.run.result import Quality, Score
from graspframe.strategy.arm_path import CheckedPlan
from graspframe.strategy.execution import GraspOutcome
from graspframe.strategy.human_reference import HumanReference, human_reference


def score_grasp(
    inputs: RunInputs, grasp: HumanGrasp, checked: CheckedPlan, outcome: GraspOutcome
) -> tuple[Score, HumanReference]:
    """(the robot's grasp scored against the human reference, that reference)."""
    obj, human = inputs.obj, inputs.human
    # The human reference is simulated on the default backend whatever backend executes
    # the robot: the same reference for every robot backend (its cache key names it).
    reference = inputs.reference_file or human_reference(
        grasp, obj, human, inputs.reference_backend_cls(), inputs.held_test
    )
    # A grasp turned about a symmetric object's axis is scored in the turned object frame.
    T_world_object_scored = outcome.T_world_object_at_hold @ make_T(checked.plan.R_object_symmetry)
    robot_contacts = tuple(c.in_object_frame(T_world_object_scored) for c in outcome.contacts)
    score = Score(
        human_source=reference.source,
        human_touching_fingers=tuple(reference.touching_fingers),
        human_held=reference.held,
        robot_contacts=robot_contacts,
        human_contacts=tuple(reference.contacts),
        quality_robot=contact_quality(list(robot_contacts), obj),
        quality_human=contact_quality(list(reference.contacts), obj),
        human_joint_limit_violations=reference.joint_limit_violations,
    )
    try:
        robot_vf = _virtual_fingers("the robot", robot_contacts)
        human_vf = _virtual_fingers("the human reference", reference.contacts)
        comparison = compare(
            robot_vf,
            human_vf,
            robot_real_fingers=list(inputs.hand.finger_names),
            human_real_fingers=list(human.finger_names),
        )
    except GraspframeError as exc:
        return replace(score, error=str(exc)), reference
    return replace(score, robot=robot_vf, human=human_vf, comparison=comparison), reference


def _virtual_fingers(side: str, contacts_object: Sequence[Contact]) -> VirtualFingerGrasp:
    """The virtual fingers of one side's contacts; a side without contacts is named in
    the error (the run summary lists the robot's contacts, not the human's)."""
    try:
        return virtual_fingers_from_contacts(list(contacts_object))
    except NoContactsError as exc:
        raise NoContactsError(f"{side}: {exc}") from exc


def contact_quality(contacts_object: Sequence[Contact], obj: ObjectDescription) -> Quality:
    """Ferrari-Canny L1 quality of contacts given in the object frame (no values without
    contacts): the object's static friction, torques about its centroid over its half
    largest dimension (docs/method.md, "Grasp quality")."""
    if not contacts_object:
        return Quality()
    try:
        quality = grasp_quality(
            [c.p for c in contacts_object],
            [-np.asarray(c.n) for c in contacts_object],  # contact normals point out
            obj.static_friction,
            torque_length=obj.largest_dimension / 2,
        )
    except GraspframeError as exc:  # e.g. a measured contacts file without normals
        return Quality(error=str(exc))
    return Quality(quality)
