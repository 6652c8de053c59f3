"""A URDF file's elements as its vendor ships them, read without edits.

`parse_urdf` reads a file and tolerates attribute values with stray spaces;
`resolve_mesh` finds the file a mesh name points at (relative to the URDF, through a
package map for `package://NAME/...`, `file://`, absolute); `origin_T` / `set_origin`
read and write an element's pose; `visual_of` turns a `<visual>` element into a `Visual`
for the pictures; `primitive_dimensions` reads a box, cylinder or sphere. The model built
from them is graspframe/model_files/urdf_model.py's.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import R_from_rpy, make_T, rpy_from_R


@dataclass(frozen=True)
class Visual:
    """One visual element of a link, for pictures.

    shape: "mesh", "box", "cylinder" or "sphere"; dimensions: [m] for primitives, as
    `ObjectDescription.dimensions`; mesh_path, scale: the mesh file (resolved) and its
    per-axis scale; rgba: colour in [0, 1] when the file gives one.
    """

    link: str
    T_link_visual: NDArray[np.float64]
    shape: str
    dimensions: Mapping[str, float] = field(default_factory=dict)
    mesh_path: Path | None = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rgba: tuple[float, float, float, float] | None = None


def parse_urdf(path: Path) -> ET.Element:
    """The <robot> element of a URDF file, attribute values stripped of surrounding
    spaces; DescriptionError when the file is missing or not a URDF."""
    path = Path(path)
    if not path.is_file():
        raise DescriptionError(f"model file not found: {path}")
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as exc:
        raise DescriptionError(f"cannot read URDF {path}: {exc}") from exc
    if root.tag != "robot":
        raise DescriptionError(f"{path} is not a URDF (root element <{root.tag}>)")
    for element in root.iter():
        for key, value in element.attrib.items():
            if value != value.strip():
                element.set(key, value.strip())
    return root


def resolve_mesh(filename: str, urdf_dir: Path, packages: Mapping[str, Path], where: str) -> Path:
    """The file a URDF mesh name points at: relative to the URDF's folder,
    package://NAME/... through `packages`, file:// or absolute; DescriptionError naming
    `where` (e.g. "link 'fingertip'") when it cannot be found."""
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://") :].partition("/")
        if package not in packages:
            known = ", ".join(sorted(packages)) or "none"
            raise DescriptionError(
                f"{where}: mesh {filename!r} is in package {package!r}, which the package "
                f"map does not name (packages: {known}); add {package} = FOLDER to it"
            )
        path = Path(packages[package]) / rest
    elif filename.startswith("file://"):
        path = Path(filename[len("file://") :])
    else:
        path = Path(filename)
        if not path.is_absolute():
            path = urdf_dir / path
    if not path.is_file():
        raise DescriptionError(f"{where}: mesh {filename!r} not found (looked at {path})")
    return path.resolve()


def floats(text: str | None, n: int, default: float, what: str) -> tuple[float, ...]:
    if text is None or not text.strip():
        return (default,) * n
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        raise DescriptionError(f"{what}: {text!r} is not {n} numbers") from None
    if len(values) == 1 and n == 3:  # a single scale value applies to every axis
        values = values * 3
    if len(values) != n:
        raise DescriptionError(f"{what}: {text!r} is not {n} numbers")
    return values


def origin_T(element: ET.Element, what: str) -> NDArray[np.float64]:
    """The 4x4 pose of an element's <origin> (identity when absent)."""
    origin = element.find("origin")
    if origin is None:
        return np.eye(4)
    xyz = floats(origin.get("xyz"), 3, 0.0, f"{what} origin xyz")
    rpy = floats(origin.get("rpy"), 3, 0.0, f"{what} origin rpy")
    return make_T(R_from_rpy(*rpy), xyz)


def set_origin(element: ET.Element, T: NDArray[np.float64]) -> None:
    """Replace an element's <origin> by the pose T."""
    for old in element.findall("origin"):
        element.remove(old)
    origin = ET.Element(
        "origin",
        {
            "xyz": " ".join(f"{v:.9g}" for v in T[:3, 3]),
            "rpy": " ".join(f"{v:.9g}" for v in rpy_from_R(T[:3, :3])),
        },
    )
    element.insert(0, origin)


def named_colours(robot: ET.Element) -> dict[str, tuple[float, ...]]:
    """Named materials declared at the robot level: name -> rgba."""
    colours = {}
    for material in robot.findall("material"):
        colour = material.find("color")
        if colour is not None and colour.get("rgba"):
            rgba = floats(colour.get("rgba"), 4, 1.0, f"material {material.get('name')!r}")
            colours[material.get("name", "")] = tuple(rgba)
    return colours


def visual_of(
    link: str,
    element: ET.Element,
    named: Mapping[str, tuple],
    urdf_dir: Path,
    packages: Mapping[str, Path],
) -> Visual | None:
    geometry = element.find("geometry")
    if geometry is None or len(geometry) == 0:
        return None
    shape = geometry[0]
    where = f"link {link!r} visual"
    T_link_visual = origin_T(element, where)
    rgba = None
    material = element.find("material")
    if material is not None:
        colour = material.find("color")
        if colour is not None and colour.get("rgba"):
            rgba = tuple(floats(colour.get("rgba"), 4, 1.0, where))
        else:
            rgba = named.get(material.get("name", ""))
    if shape.tag == "mesh":
        path = resolve_mesh(shape.get("filename", ""), urdf_dir, packages, f"link {link!r}")
        scale = floats(shape.get("scale"), 3, 1.0, f"{where} mesh scale")
        return Visual(link, T_link_visual, "mesh", mesh_path=path, scale=scale, rgba=rgba)  # type: ignore[arg-type]
    dimensions = primitive_dimensions(shape, where)
    if dimensions is None:
        return None
    return Visual(link, T_link_visual, shape.tag, dimensions, rgba=rgba)  # type: ignore[arg-type]


def primitive_dimensions(shape: ET.Element, where: str) -> dict[str, float] | None:
    """[m] dimensions of a URDF box, cylinder or sphere element in `ObjectDescription`'s
    convention; None for other kinds."""
    if shape.tag == "box":
        sx, sy, sz = floats(shape.get("size"), 3, 0.0, f"{where} box size")
        return {"size_x": sx, "size_y": sy, "size_z": sz}
    if shape.tag == "cylinder":
        (radius,) = floats(shape.get("radius"), 1, 0.0, f"{where} cylinder radius")
        (length,) = floats(shape.get("length"), 1, 0.0, f"{where} cylinder length")
        return {"radius": radius, "length": length}
    if shape.tag == "sphere":
        (radius,) = floats(shape.get("radius"), 1, 0.0, f"{where} sphere radius")
        return {"radius": radius}
    return None


def to_text(robot: ET.Element) -> str:
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"
