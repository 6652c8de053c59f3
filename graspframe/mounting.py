"""Mount any hand on any arm's flange: one combined URDF for Pinocchio and the simulator.

The hand's root link is fixed to the arm's flange link by a fixed joint whose origin is
`T_flange_hand`: the identity (the root link bolted straight on) unless a `Mounting` of
the hand is named, whose adapter then becomes one more link, `<root link>_adapter`,
fixed to the hand's root link with the adapter's collision shapes and mass. The combined
file is written once per distinct content into a cache folder (GRASPFRAME_CACHE_DIR,
default ~/.cache/graspframe) and reused afterwards.
"""

from __future__ import annotations

import hashlib
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.errors import DescriptionError
from graspframe.files import atomic_write
from graspframe.hal.descriptions import AdapterShape, ArmDescription, HandDescription, Mounting
from graspframe.transforms import as_pose, make_T, rpy_from_R

CACHE_ENV = "GRASPFRAME_CACHE_DIR"


def cache_dir() -> Path:
    """Folder for generated files (combined models); created on demand."""
    default = Path.home() / ".cache" / "graspframe"
    path = Path(os.environ.get(CACHE_ENV, default)) / "models"
    path.mkdir(parents=True, exist_ok=True)
    return path


@dataclass(frozen=True)
class MountedRobot:
    """A hand fixed to an arm's flange.

    urdf_path: the combined model (arm links, then hand links, one fixed mount joint).
    T_flange_hand: pose of the hand's root link in the flange frame.
    mounting: the name of the hand's `Mounting` used (None: no adapter).
    """

    arm: ArmDescription
    hand: HandDescription
    urdf_path: Path
    mount_joint: str
    T_flange_hand: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    mounting: str | None = None

    @property
    def name(self) -> str:
        return f"{self.arm.name}+{self.hand.name}"


def _parse(path: Path) -> ET.Element:
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as exc:
        raise DescriptionError(f"cannot read URDF {path}: {exc}") from exc
    if root.tag != "robot":
        raise DescriptionError(f"{path} is not a URDF (root element <{root.tag}>)")
    return root


def _absolute_meshes(robot: ET.Element, source: Path) -> None:
    """Mesh file names relative to the source URDF become absolute."""
    for mesh in robot.iter("mesh"):
        filename = mesh.get("filename", "")
        if filename.startswith("package://"):
            raise DescriptionError(
                f"{source.name}: package:// mesh paths are not supported; use paths relative "
                "to the URDF file"
            )
        if filename and not Path(filename).is_absolute():
            mesh.set("filename", str((source.parent / filename).resolve()))


def _origin(parent: ET.Element, T: NDArray[np.float64]) -> None:
    xyz = " ".join(f"{v:.9g}" for v in T[:3, 3])
    rpy = " ".join(f"{v:.9g}" for v in rpy_from_R(T[:3, :3]))
    ET.SubElement(parent, "origin", {"xyz": xyz, "rpy": rpy})


def _adapter_link(name: str, mounting: Mounting) -> ET.Element:
    """The adapter as a URDF link: its collision shapes and a mass spread over them."""
    link = ET.Element("link", {"name": name})
    inertial = ET.SubElement(link, "inertial")
    centre = np.mean([s.T_root_shape[:3, 3] for s in mounting.adapter], axis=0)
    _origin(inertial, make_T(p=centre))
    mass = max(mounting.mass, 1e-3)  # the simulator needs some mass on every link
    ET.SubElement(inertial, "mass", {"value": f"{mass:.9g}"})
    # A 10 cm solid sphere's inertia: only an order of magnitude, the link is welded.
    i = 0.4 * mass * 0.05**2
    moments = {"ixx": f"{i:.9g}", "iyy": f"{i:.9g}", "izz": f"{i:.9g}"}
    ET.SubElement(inertial, "inertia", {**moments, "ixy": "0", "ixz": "0", "iyz": "0"})
    for shape in mounting.adapter:
        collision = ET.SubElement(link, "collision")
        _origin(collision, shape.T_root_shape)
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


def combined_urdf_text(
    arm: ArmDescription,
    hand: HandDescription,
    T_flange_hand: NDArray[np.float64],
    mounting: Mounting | None = None,
) -> tuple[str, str]:
    """(URDF text of hand-on-arm, name of the mount joint); `mounting`'s adapter, if it
    has shapes, is a link fixed to the hand's root link."""
    arm_root, hand_root = _parse(Path(arm.model_path)), _parse(Path(hand.model_path))
    _absolute_meshes(arm_root, Path(arm.model_path))
    _absolute_meshes(hand_root, Path(hand.model_path))

    def names(root: ET.Element, tag: str) -> set[str]:
        return {element.get("name", "") for element in root.findall(tag)}

    adapter_link = f"{hand.root_link}_adapter"
    adapter_names = {adapter_link} if mounting is not None and mounting.adapter else set()
    clashes = (names(arm_root, "link") & names(hand_root, "link")) | (
        names(arm_root, "joint") & names(hand_root, "joint")
    )
    clashes |= adapter_names & (names(arm_root, "link") | names(hand_root, "link"))
    if clashes:
        raise DescriptionError(
            f"arm {arm.name!r} and hand {hand.name!r} share link/joint names: "
            f"{', '.join(sorted(clashes))}; prefix them per robot"
        )
    if arm.flange_link not in names(arm_root, "link"):
        raise DescriptionError(f"arm {arm.name!r}: flange link {arm.flange_link!r} not in model")
    if hand.root_link not in names(hand_root, "link"):
        raise DescriptionError(f"hand {hand.name!r}: root link {hand.root_link!r} not in model")

    combined = ET.Element("robot", {"name": f"{arm.name}_{hand.name}"})
    for source in (arm_root, hand_root):
        for element in source:
            if element.tag in ("link", "joint"):
                combined.append(element)
    mount_joint = f"mount_{arm.name}_{hand.name}"
    joint = ET.SubElement(combined, "joint", {"name": mount_joint, "type": "fixed"})
    ET.SubElement(joint, "parent", {"link": arm.flange_link})
    ET.SubElement(joint, "child", {"link": hand.root_link})
    _origin(joint, T_flange_hand)
    if mounting is not None and mounting.adapter:
        combined.append(_adapter_link(adapter_link, mounting))
        joint = ET.SubElement(combined, "joint", {"name": f"{adapter_link}_joint", "type": "fixed"})
        ET.SubElement(joint, "parent", {"link": hand.root_link})
        ET.SubElement(joint, "child", {"link": adapter_link})
        _origin(joint, np.eye(4))
    ET.indent(combined)
    text = '<?xml version="1.0"?>\n' + ET.tostring(combined, encoding="unicode") + "\n"
    return text, mount_joint


def mount(
    arm: ArmDescription,
    hand: HandDescription,
    T_flange_hand: NDArray[np.float64] | None = None,
    mounting: str | None = None,
) -> MountedRobot:
    """Fix `hand` to `arm`'s flange and write the combined model: at T_flange_hand
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
    text, mount_joint = combined_urdf_text(arm, hand, T_flange_hand, adapter)
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    path = cache_dir() / f"{arm.name}_{hand.name}_{digest}.urdf"
    if not path.exists():
        atomic_write(path, text)
    return MountedRobot(arm, hand, path, mount_joint, T_flange_hand, mounting)
