"""Mount any hand on any arm's flange: one combined model for Pinocchio and the simulator.

The hand's root link is fixed to the arm's flange link by a fixed joint whose origin is
`T_flange_hand`: the identity (the root link bolted straight on) unless a `Mounting` of
the hand is named, whose adapter then becomes one more link, `<root link>_adapter`,
fixed to the hand's root link with the adapter's collision shapes and mass. The combined
model lives in memory (`UrdfModel`); nothing is written. When the arm and the hand share
a link or joint name (vendor files often call their root link "base"), every name of
the arm gets the prefix "<arm name>_" and the mounted robot's arm description says so.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
from numpy.typing import NDArray

from graspframe.errors import DescriptionError
from graspframe.hal.descriptions import AdapterShape, ArmDescription, HandDescription, Mounting
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.transforms import as_pose, make_T
from graspframe.urdf_elements import set_origin
from graspframe.urdf_model import UrdfModel, combine


def _adapter_link(name: str, mounting: Mounting) -> ET.Element:
    """The adapter as a URDF link: its collision shapes and a mass spread over them."""
    link = ET.Element("link", {"name": name})
    inertial = ET.SubElement(link, "inertial")
    centre = np.mean([s.T_root_shape[:3, 3] for s in mounting.adapter], axis=0)
    set_origin(inertial, make_T(p=centre))
    mass = max(mounting.mass, 1e-3)  # the simulator needs some mass on every link
    ET.SubElement(inertial, "mass", {"value": f"{mass:.9g}"})
    # A 10 cm solid sphere's inertia: only an order of magnitude, the link is welded.
    i = 0.4 * mass * 0.05**2
    moments = {"ixx": f"{i:.9g}", "iyy": f"{i:.9g}", "izz": f"{i:.9g}"}
    ET.SubElement(inertial, "inertia", {**moments, "ixy": "0", "ixz": "0", "iyz": "0"})
    for shape in mounting.adapter:
        collision = ET.SubElement(link, "collision")
        set_origin(collision, shape.T_root_shape)
        geometry = ET.SubElement(collision, "geometry")
        ET.SubElement(geometry, shape.shape, _geometry_attributes(shape))
    return link


def _geometry_attributes(shape: AdapterShape) -> dict[str, str]:
    d = shape.dimensions
    if shape.shape == "box":
        return {"size": f"{d['size_x']:.9g} {d['size_y']:.9g} {d['size_z']:.9g}"}
    if shape.shape == "cylinder":
        return {"radius": f"{d['radius']:.9g}", "length": f"{d['length']:.9g}"}
    return {"radius": f"{d['radius']:.9g}"}


def _without_clashes(arm: ArmDescription, hand: HandDescription) -> ArmDescription:
    """The arm, its names prefixed with "<arm name>_" when it shares any with the hand."""
    arm_model, hand_model = arm.urdf(), hand.urdf()
    shared = (arm_model.link_names | arm_model.joint_names) & (
        hand_model.link_names | hand_model.joint_names
    )
    return arm.with_name_prefix(f"{arm.name}_") if shared else arm


def combined_model(
    arm: ArmDescription,
    hand: HandDescription,
    T_flange_hand: NDArray[np.float64],
    mounting: Mounting | None = None,
) -> tuple[UrdfModel, str]:
    """(the model of hand-on-arm, name of the mount joint); `mounting`'s adapter, if it
    has shapes, is a link fixed to the hand's root link. The arm's names must not clash
    with the hand's (`mount` prefixes them)."""
    if arm.flange_link not in arm.urdf().link_names:
        raise DescriptionError(f"arm {arm.name!r}: flange link {arm.flange_link!r} not in model")
    if hand.root_link not in hand.urdf().link_names:
        raise DescriptionError(f"hand {hand.name!r}: root link {hand.root_link!r} not in model")
    extra: list[ET.Element] = []
    if mounting is not None and mounting.adapter:
        adapter_link = f"{hand.root_link}_adapter"
        if adapter_link in arm.urdf().link_names | hand.urdf().link_names:
            raise DescriptionError(f"the adapter link name {adapter_link!r} is taken")
        extra.append(_adapter_link(adapter_link, mounting))
        joint = ET.Element("joint", {"name": f"{adapter_link}_joint", "type": "fixed"})
        set_origin(joint, np.eye(4))
        ET.SubElement(joint, "parent", {"link": hand.root_link})
        ET.SubElement(joint, "child", {"link": adapter_link})
        extra.append(joint)
    mount_joint = f"mount_{arm.name}_{hand.name}"
    model = combine(
        f"{arm.name}_{hand.name}",
        arm.urdf(),
        hand.urdf(),
        mount_joint,
        arm.flange_link,
        hand.root_link,
        T_flange_hand,
        extra,
    )
    return model, mount_joint


def mount(
    arm: ArmDescription,
    hand: HandDescription,
    T_flange_hand: NDArray[np.float64] | None = None,
    mounting: str | None = None,
) -> MountedRobot:
    """Fix `hand` to `arm`'s flange and build the combined model: at T_flange_hand
    (identity by default), or through the hand's mounting of that name (its adapter and
    its T_flange_hand; a T_flange_hand given as well must be the same)."""
    adapter = None
    if mounting is not None:
        adapter = hand.mounting(mounting)
        if T_flange_hand is not None and not np.allclose(
            as_pose(T_flange_hand, "T_flange_hand"), adapter.T_flange_hand, atol=1e-9
        ):
            raise DescriptionError(
                f"T_flange_hand differs from the one of mounting {mounting!r} of {hand.name!r}"
            )
        T_flange_hand = adapter.T_flange_hand
    T_flange_hand = as_pose(np.eye(4) if T_flange_hand is None else T_flange_hand, "T_flange_hand")
    arm = _without_clashes(arm, hand)
    model, mount_joint = combined_model(arm, hand, T_flange_hand, adapter)
    return MountedRobot(arm, hand, model, mount_joint, T_flange_hand, mounting)
