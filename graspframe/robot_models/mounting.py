"""Mount any hand on any arm's flange: one combined model for Pinocchio and the simulator.

The hand's root link is fixed to the arm's flange link by a fixed joint whose origin is
`T_flange_hand`: the identity (the root link bolted straight on) unless a `Mounting` of
the hand is named, whose adapter then becomes one more link, `<root link>_adapter`,
fixed to the hand's root link with the adapter's collision shapes and mass. The combined
model lives in memory (`UrdfModel`); nothing is written. When the arm and the hand share
a link or joint name (vendor files often call their root link "base"), every name of
the arm gets the prefix "<arm name>_" and the mounted robot's arm description says so.

A hand whose links overlap the arm's once mounted is refused (`mount_overlaps`,
`check_mount`): every hand link against every arm link, the arm at its home pose and
the hand in each preshape's open and closed posture, measured on the collision shapes
Pinocchio places (coal signed distances). Up to MOUNT_OVERLAP_TOLERANCE deep is
accepted: a hand bolted flat against the flange touches it at distance 0, and a convex
piece may lie up to 1.5 mm off its vendor mesh (graspframe/model_files/convex.py). An adapter's
shapes are fixed to the hand and not checked against it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import as_pose, make_T
from graspframe.hal.descriptions import AdapterShape, ArmDescription, HandDescription, Mounting
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.model_files.urdf_elements import set_origin
from graspframe.model_files.urdf_model import UrdfModel, combine
from graspframe.robot_models.model import model_of

MOUNT_OVERLAP_TOLERANCE = 0.002  # [m] the deepest overlap a mount may have (see above)


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
    arm_model, hand_model = model_of(arm), model_of(hand)
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
    if arm.flange_link not in model_of(arm).link_names:
        raise DescriptionError(f"arm {arm.name!r}: flange link {arm.flange_link!r} not in model")
    if hand.root_link not in model_of(hand).link_names:
        raise DescriptionError(f"hand {hand.name!r}: root link {hand.root_link!r} not in model")
    extra: list[ET.Element] = []
    if mounting is not None and mounting.adapter:
        adapter_link = f"{hand.root_link}_adapter"
        if adapter_link in model_of(arm).link_names | model_of(hand).link_names:
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
        model_of(arm),
        model_of(hand),
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
    check: bool = True,
) -> MountedRobot:
    """Fix `hand` to `arm`'s flange and build the combined model: at T_flange_hand
    (identity by default), or through the hand's mounting of that name (its adapter and
    its T_flange_hand; a T_flange_hand given as well must be the same).
    DescriptionError when the hand's links overlap the arm's (`check_mount`; check=False
    leaves that to the caller, to measure the overlaps)."""
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
    robot = MountedRobot(arm, hand, model, mount_joint, T_flange_hand, mounting)
    if check:
        check_mount(robot)
    return robot


@dataclass(frozen=True)
class MountOverlap:
    """A hand link inside an arm link once mounted: depth [m] (> 0), and the posture it
    was found in ("preshape <name> open" or "... closed")."""

    hand_link: str
    arm_link: str
    depth: float
    posture: str

    def describe(self) -> str:
        return (
            f"hand link {self.hand_link!r} is {1000 * self.depth:.1f} mm deep in arm link "
            f"{self.arm_link!r} ({self.posture}, the arm at home)"
        )


def _postures(hand: HandDescription) -> list[tuple[str, dict[str, float]]]:
    """(name, joint values [rad]) of every preshape open and closed, followers included
    (joints the model lacks left out: the description check names them)."""
    joints = model_of(hand).joint_names
    postures = []
    for preshape in hand.preshapes.values():
        for label, q in (("open", preshape.open_q), ("closed", preshape.closed_q)):
            q_model = hand.with_model_followers(dict(q))
            known = {name: value for name, value in q_model.items() if name in joints}
            postures.append((f"preshape {preshape.name} {label}", known))
    return postures or [("the hand at zero", {})]


def mount_overlaps(
    robot: MountedRobot, tolerance: float = MOUNT_OVERLAP_TOLERANCE
) -> list[MountOverlap]:
    """Every (hand link, arm link) pair overlapping by more than `tolerance` [m], the
    deepest posture of each, deepest first (see the module docstring)."""
    if not any(True for _ in model_of(robot.arm).root().iter("collision")):
        return []  # an arm without shapes (the floating base) overlaps nothing
    postures = _postures(robot.hand)
    key = (
        robot.model.digest,
        tuple(robot.arm.home_q),
        tuple((name, tuple(sorted(q.items()))) for name, q in postures),
        tolerance,
    )
    if key not in _OVERLAPS:
        _OVERLAPS[key] = _measure_overlaps(robot, postures, tolerance)
    return list(_OVERLAPS[key])


_OVERLAPS: dict[tuple, tuple[MountOverlap, ...]] = {}


def _measure_overlaps(
    robot: MountedRobot, postures: list[tuple[str, dict[str, float]]], tolerance: float
) -> tuple[MountOverlap, ...]:
    import coal

    from graspframe.robot_models.model import CollisionModel

    arm_links = model_of(robot.arm).link_names
    hand_links = model_of(robot.hand).link_names
    collision = CollisionModel(robot.model)
    q_arm = dict(zip(robot.arm.joint_names, robot.arm.home_q, strict=True))
    deepest: dict[tuple[str, str], MountOverlap] = {}
    for posture, q_hand in postures:
        collision.place({**q_arm, **q_hand})
        placed = list(collision.shapes())
        hand_shapes = [(link, s, T) for link, s, T in placed if link in hand_links]
        arm_shapes = [(link, s, T) for link, s, T in placed if link in arm_links]
        for hand_link, hand_shape, T_hand in hand_shapes:
            tf_hand = coal.Transform3s(T_hand[:3, :3], T_hand[:3, 3])
            for arm_link, arm_shape, T_arm in arm_shapes:
                tf_arm = coal.Transform3s(T_arm[:3, :3], T_arm[:3, 3])
                request, result = coal.CollisionRequest(), coal.CollisionResult()
                if not coal.collide(hand_shape, tf_hand, arm_shape, tf_arm, request, result):
                    continue
                depth = -float(
                    coal.distance(
                        hand_shape,
                        tf_hand,
                        arm_shape,
                        tf_arm,
                        coal.DistanceRequest(),
                        coal.DistanceResult(),
                    )
                )
                key = (hand_link, arm_link)
                if depth > tolerance and (key not in deepest or depth > deepest[key].depth):
                    deepest[key] = MountOverlap(hand_link, arm_link, depth, posture)
    return tuple(sorted(deepest.values(), key=lambda o: -o.depth))


def check_mount(robot: MountedRobot) -> None:
    """DescriptionError, one line naming the links and the depth, when the hand's links
    overlap the arm's once mounted."""
    overlaps = mount_overlaps(robot)
    if overlaps:
        more = f" (and {len(overlaps) - 1} more pairs)" if len(overlaps) > 1 else ""
        raise DescriptionError(
            f"{robot.hand.name} mounted on {robot.arm.name}"
            f"{f' through its {robot.mounting} mounting' if robot.mounting else ''}: "
            f"{overlaps[0].describe()}{more}; mount the hand at the link it is bolted by "
            f"(mount_link), or through an adapter that clears the arm"
        )


def check_mounts(arm: ArmDescription, hand: HandDescription) -> dict[str | None, MountedRobot]:
    """The hand bolted straight on (None) and through each of its mountings (by name),
    those whose links clear the arm's (`check_mount`): what a run and a sweep ask before
    anything runs, and carry on to their planning. The mounts are alternatives: one that
    overlaps is left out (a synthesised thumb curling behind the wrist into the arm's
    last link, with a plate on the back of the palm that clears it); the first one's
    DescriptionError when none clears."""
    robots: dict[str | None, MountedRobot] = {}
    refusals: list[DescriptionError] = []
    for mounting in (None, *hand.mountings):
        robot = mount(arm, hand, mounting=mounting, check=False)
        try:
            check_mount(robot)
        except DescriptionError as exc:
            refusals.append(exc)
            continue
        robots[mounting] = robot
    if not robots:
        raise refusals[0]
    return robots
