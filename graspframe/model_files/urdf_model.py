"""A robot model file as every tool loads it: one URDF text in memory.

A vendor URDF is read exactly as shipped (the file is never edited or copied) and turned,
in memory, into the model that Pinocchio, placo, the collision checker, the simulator
and the pictures all load (`UrdfModel`):

- quirks of real files are tolerated: attribute values with leading or trailing spaces;
- mesh file names are resolved: relative to the URDF file, `package://NAME/...` through
  a package map (NAME -> folder), `file://` and absolute paths; a missing file is an
  error naming the link and the path looked at;
- `<visual>` elements are taken out (a physics-only scene cannot load them) and kept as
  `Visual`s for the pictures;
- every collision mesh becomes its convex pieces (graspframe/model_files/convex.py), so that the
  simulator (which takes a mesh as a convex hull), the collision checker and the
  pictures see the same solid;
- frames the file lacks (a palm frame, a palm pad, fingertip frames, a flange) are added
  as links fixed to existing links at given offsets (`FrameOffset`);
- an arm is cut at its flange: whatever the vendor mounted beyond it (its own gripper)
  is dropped, and so are the shapes of a tool the vendor merged into a link (its
  `tool_links`);
- the tree is rooted where the robot is fixed: a hand at its mount link, an arm at its
  base link, whatever link the file is rooted at (graspframe/model_files/urdf_tree.py); continuous
  joints become revolute joints within the file's limits, one value per joint;
- only links and joints are kept (materials, transmissions, simulator tags are not
  needed by any tool here).

`combine` joins an arm's model and a hand's model with a fixed joint; `read_model`'s
prefix renames every link and joint of a file (to resolve name clashes between the two).
"""

from __future__ import annotations

import functools
import hashlib
import os
import xml.etree.ElementTree as ET
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.model_files.urdf_elements import (
    Visual,
    floats,
    named_colours,
    origin_T,
    parse_urdf,
    resolve_mesh,
    set_origin,
    to_text,
    visual_of,
)
from graspframe.model_files.urdf_tree import continuous_as_revolute, descendants, drop_links, reroot

# Mass and inertia of an added frame link: the simulator wants some on every link; it is
# welded to its parent, so only the order of magnitude matters.
FRAME_LINK_MASS = 1e-3  # [kg]
FRAME_LINK_INERTIA = 1e-8  # [kg m^2]


@dataclass(frozen=True)
class FrameOffset:
    """A frame the model file lacks, fixed to one of its links.

    parent: the link it is fixed to; T_parent_frame: its pose in the parent link's frame.
    pad: [m] full sizes (x, y, z) of a collision box centred on the frame, part of the
        model (a contact region such as a palm pad); None: a frame only.
    """

    parent: str
    T_parent_frame: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    pad: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        from graspframe.common.transforms import as_pose

        object.__setattr__(self, "T_parent_frame", as_pose(self.T_parent_frame, "frame offset"))
        if self.pad is not None:
            pad = tuple(float(v) for v in self.pad)
            if len(pad) != 3 or not all(np.isfinite(pad)) or min(pad) <= 0:
                raise DescriptionError(f"a pad needs three sizes > 0 [m], got {self.pad}")
            object.__setattr__(self, "pad", pad)


@dataclass(frozen=True, eq=False)
class UrdfModel:
    """A robot model ready for every tool.

    name: the robot's name; text: the URDF (links and joints only, no visuals, collision
    meshes as convex pieces with absolute file names); visuals: the visual elements, by
    link; sources: the files it was read from, as shipped.
    """

    name: str
    text: str = field(repr=False)
    visuals: tuple[Visual, ...] = ()
    sources: tuple[Path, ...] = ()

    @functools.cached_property
    def digest(self) -> str:
        """A hash of the model text (identifies the model in caches)."""
        return hashlib.sha256(self.text.encode()).hexdigest()[:16]

    def json_summary(self) -> dict[str, object]:
        """What the model is in result.json (not its text): name, digest, source files."""
        return {"name": self.name, "digest": self.digest, "sources": [str(p) for p in self.sources]}

    def root(self) -> ET.Element:
        """A fresh parse of the text (callers may change it)."""
        return ET.fromstring(self.text)

    @functools.cached_property
    def link_names(self) -> frozenset[str]:
        return frozenset(e.get("name", "") for e in self.root().findall("link"))

    @functools.cached_property
    def joint_names(self) -> frozenset[str]:
        return frozenset(e.get("name", "") for e in self.root().findall("joint"))

    @functools.cached_property
    def mimic_followers(self) -> dict[str, tuple[str, float, float]]:
        """follower joint -> (leader, multiplier, offset) for every <mimic>."""
        followers = {}
        for joint in self.root().iter("joint"):
            mimic = joint.find("mimic")
            if mimic is not None:
                followers[joint.get("name", "")] = (
                    mimic.get("joint", ""),
                    float(mimic.get("multiplier", 1.0)),
                    float(mimic.get("offset", 0.0)),
                )
        return followers

    def describe(self) -> str:
        """A short name for messages: the source file, or the model's name."""
        return self.sources[0].name if len(self.sources) == 1 else self.name


def _convex_collisions(link: ET.Element, urdf_dir: Path, packages: Mapping[str, Path]) -> None:
    """Replace every collision mesh of the link by one collision per convex piece."""
    from graspframe.model_files.convex import convex_pieces

    name = link.get("name", "")
    for index, collision in enumerate(list(link.findall("collision"))):
        mesh = collision.find("geometry/mesh")
        if mesh is None:
            continue
        path = resolve_mesh(mesh.get("filename", ""), urdf_dir, packages, f"link {name!r}")
        scale = floats(mesh.get("scale"), 3, 1.0, f"link {name!r} collision mesh scale")
        pieces = convex_pieces(path, scale)
        position = list(link).index(collision)
        link.remove(collision)
        T_link_collision = origin_T(collision, f"link {name!r} collision")
        for k, piece_file in enumerate(pieces.files):
            piece = ET.Element("collision", {"name": f"{name}_mesh{index}_piece{k}"})
            set_origin(piece, T_link_collision)
            geometry = ET.SubElement(piece, "geometry")
            ET.SubElement(geometry, "mesh", {"filename": str(piece_file)})
            link.insert(position + k, piece)


def _frame_link(name: str, offset: FrameOffset) -> tuple[ET.Element, ET.Element]:
    """(link, fixed joint) of an added frame."""
    link = ET.Element("link", {"name": name})
    inertial = ET.SubElement(link, "inertial")
    set_origin(inertial, np.eye(4))
    ET.SubElement(inertial, "mass", {"value": f"{FRAME_LINK_MASS:g}"})
    i = f"{FRAME_LINK_INERTIA:g}"
    ET.SubElement(
        inertial, "inertia", {"ixx": i, "iyy": i, "izz": i, "ixy": "0", "ixz": "0", "iyz": "0"}
    )
    if offset.pad is not None:
        collision = ET.SubElement(link, "collision", {"name": f"{name}_pad"})
        set_origin(collision, np.eye(4))
        geometry = ET.SubElement(collision, "geometry")
        ET.SubElement(geometry, "box", {"size": " ".join(f"{v:.9g}" for v in offset.pad)})
    joint = ET.Element("joint", {"name": f"{name}_joint", "type": "fixed"})
    set_origin(joint, offset.T_parent_frame)
    ET.SubElement(joint, "parent", {"link": offset.parent})
    ET.SubElement(joint, "child", {"link": name})
    return link, joint


def read_model(
    path: Path,
    packages: Mapping[str, Path] | None = None,
    frames: Mapping[str, FrameOffset] | None = None,
    cut_below: str | None = None,
    prefix: str = "",
    root_at: str | None = None,
    root_role: str = "the root link",
    tool_links: Collection[str] = (),
) -> UrdfModel:
    """The model of a URDF file as shipped (see the module docstring).

    packages: package name -> folder, for package:// mesh names.
    frames: frames to add, by name (each fixed to an existing link).
    cut_below: drop every link below this one (an arm's flange link).
    prefix: put before every link and joint name of the file; `frames`, `cut_below` and
        `root_at` use the prefixed names.
    root_at: the link (or added frame) the model is rooted at (a hand's mount link, an
        arm's base link: graspframe/model_files/urdf_tree.py); None: the file's root. `root_role`
        names it in errors.
    tool_links: links (names as in the file) whose visual and collision shapes are the
        vendor's own tool, which a mounted hand replaces (a gripper housing merged into
        an arm's last link): left out, the links kept.
    """
    path = Path(path)
    packages = {name: Path(folder) for name, folder in (packages or {}).items()}
    source = parse_urdf(path)
    urdf_dir = path.parent
    colours = named_colours(source)
    robot = ET.Element("robot", {"name": source.get("name", path.stem)})
    visuals: list[Visual] = []
    file_links = {e.get("name", "") for e in source.findall("link")}
    # Links an arm's cut drops are never loaded: their meshes are not decomposed.
    cut_links = set()
    if cut_below is not None and cut_below.removeprefix(prefix) in file_links:
        cut_links = descendants(source, cut_below.removeprefix(prefix))
    for name in tool_links:
        if name not in file_links:
            raise DescriptionError(
                f"{path.name}: tool link {name!r} (the vendor's tool, left out) is not a link "
                "of the file"
            )
    for element in source:
        if element.tag not in ("link", "joint"):
            continue
        if element.tag == "link":
            name = element.get("name", "")
            if name in tool_links:  # the vendor's tool: its shapes go, the link stays
                for shape in element.findall("visual") + element.findall("collision"):
                    element.remove(shape)
            for visual in element.findall("visual"):
                element.remove(visual)
                found = visual_of(name, visual, colours, urdf_dir, packages)
                if found is not None:
                    visuals.append(found)
            if name not in cut_links:
                _convex_collisions(element, urdf_dir, packages)
        robot.append(element)
    if prefix:
        _rename_in_place(robot, {n: prefix + n for n in _names(robot)})
        visuals = [_visual_renamed(v, prefix + v.link) for v in visuals]
    if cut_below is not None:
        if cut_below not in {e.get("name") for e in robot.findall("link")}:
            raise DescriptionError(
                f"{path.name}: link {cut_below!r} (the flange) is not in the file"
            )
        dropped = descendants(robot, cut_below)
        drop_links(robot, dropped)
        visuals = [v for v in visuals if v.link not in dropped]
    add_frames(robot, frames or {}, path.name)
    if root_at is not None:
        reroot(robot, root_at, path.name, root_role)
    continuous_as_revolute(robot)
    return UrdfModel(robot.get("name", path.stem), to_text(robot), tuple(visuals), (path,))


def add_frames(robot: ET.Element, frames: Mapping[str, FrameOffset], what: str) -> None:
    """Add each frame as a link fixed to its parent link (DescriptionError for a parent
    that is not a link, or a name the model already has)."""
    links = {e.get("name", "") for e in robot.findall("link")}
    joints = {e.get("name", "") for e in robot.findall("joint")}
    for name, offset in frames.items():
        if name in links or f"{name}_joint" in joints:
            raise DescriptionError(f"{what}: added frame {name!r} is already a link of the model")
        if offset.parent not in links:
            raise DescriptionError(
                f"{what}: added frame {name!r} hangs from {offset.parent!r}, which is not a "
                f"link of the model"
            )
        link, joint = _frame_link(name, offset)
        robot.append(link)
        robot.append(joint)
        links.add(name)


# -- renaming and combining ----------------------------------------------------------------


def _names(robot: ET.Element) -> set[str]:
    return {e.get("name", "") for e in robot if e.tag in ("link", "joint")}


def _visual_renamed(visual: Visual, link: str) -> Visual:
    from dataclasses import replace

    return replace(visual, link=link)


def _rename_in_place(robot: ET.Element, rename: Mapping[str, str]) -> None:
    for element in robot:
        if element.tag in ("link", "joint"):
            name = element.get("name", "")
            element.set("name", rename.get(name, name))
        if element.tag == "joint":
            for tag in ("parent", "child"):
                ref = element.find(tag)
                if ref is not None:
                    ref.set("link", rename.get(ref.get("link", ""), ref.get("link", "")))
            mimic = element.find("mimic")
            if mimic is not None:
                mimic.set("joint", rename.get(mimic.get("joint", ""), mimic.get("joint", "")))


def combine(
    name: str,
    parent: UrdfModel,
    child: UrdfModel,
    joint_name: str,
    parent_link: str,
    child_link: str,
    T_parent_child: NDArray[np.float64],
    extra: Iterable[ET.Element] = (),
) -> UrdfModel:
    """One model: `child`'s root link `child_link` fixed to `parent`'s `parent_link` at
    T_parent_child by the joint `joint_name`, then the `extra` elements (links, joints).
    DescriptionError when the two share a link or joint name."""
    clashes = (parent.link_names & child.link_names) | (parent.joint_names & child.joint_names)
    if clashes:
        raise DescriptionError(
            f"{parent.name} and {child.name} share link/joint names: {', '.join(sorted(clashes))}"
        )
    if parent_link not in parent.link_names:
        raise DescriptionError(f"{parent.name}: link {parent_link!r} is not in the model")
    if child_link not in child.link_names:
        raise DescriptionError(f"{child.name}: link {child_link!r} is not in the model")
    robot = ET.Element("robot", {"name": name})
    for source in (parent.root(), child.root()):
        for element in source:
            robot.append(element)
    joint = ET.SubElement(robot, "joint", {"name": joint_name, "type": "fixed"})
    set_origin(joint, T_parent_child)
    ET.SubElement(joint, "parent", {"link": parent_link})
    ET.SubElement(joint, "child", {"link": child_link})
    for element in extra:
        robot.append(element)
    return UrdfModel(
        name,
        to_text(robot),
        parent.visuals + child.visuals,
        parent.sources + child.sources,
    )


# -- the model of a description ------------------------------------------------------------

_MODELS: dict[tuple, UrdfModel] = {}


def _file_key(path: Path) -> tuple:
    try:
        stat = os.stat(path)
    except OSError:
        return (str(path),)
    return (str(path), stat.st_mtime_ns, stat.st_size)


@dataclass(frozen=True)
class ModelFile:
    """How a robot's model file is read, as data: the file, its package map, the frames
    it lacks, the link an arm is cut below, the prefix of its names, the link it is
    rooted at (`root_role` names that link in messages) and the links whose shapes are a
    vendor tool's. A description says this (`model_file()`); `load_model_file` reads it."""

    path: Path
    packages: Mapping[str, Path] = field(default_factory=dict)
    frames: Mapping[str, FrameOffset] = field(default_factory=dict)
    cut_below: str | None = None
    prefix: str = ""
    root_at: str | None = None
    root_role: str = "the root link"
    tool_links: Collection[str] = ()


def load_model_file(model_file: ModelFile) -> UrdfModel:
    """The model `model_file` says (`read_model`), as every tool loads it: once per
    process for the same file, unchanged on disk, and options."""
    m = model_file
    key = (
        _file_key(Path(m.path)),
        tuple(sorted((k, str(v)) for k, v in m.packages.items())),
        tuple(
            (name, f.parent, f.T_parent_frame.round(12).tobytes(), f.pad)
            for name, f in sorted(m.frames.items())
        ),
        m.cut_below,
        m.prefix,
        m.root_at,
        m.root_role,
        tuple(m.tool_links),
    )
    if key not in _MODELS:
        _MODELS[key] = read_model(
            Path(m.path),
            m.packages,
            m.frames,
            m.cut_below,
            m.prefix,
            m.root_at,
            m.root_role,
            m.tool_links,
        )
    return _MODELS[key]
