"""The kinematic tree of a URDF's elements: which links hang below which, cutting a
branch off, re-rooting the tree at another link, one value per joint.

Vendors root their files wherever their tools put the origin: a hand's URDF may be
rooted at its finger roots with the wrist a fixed child below, an arm's at a "world"
link above its base plate. graspframe mounts a hand at the link it is bolted by and
stands an arm on its base link, so the model every tool loads is rooted there
(`reroot`): each fixed joint between the file's root and that link is turned round
(parent and child swapped, its origin inverted). Link frames, and everything placed in
them (inertials, collisions, visuals, added frames), are unchanged; only the tree's
direction is. A movable joint on that path cannot be turned round without moving a
link frame, so it is refused with the joint's name.

`continuous` joints become `revolute` joints limited to the file's `<limit>` (±2π when
it gives none): Pinocchio gives a continuous joint two configuration values (cos, sin),
every other tool one; with one value per joint, a joint angle means the same thing in
the IK, the collision checker, the simulator and a spec's home pose.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import inv_T
from graspframe.model_files.urdf_elements import origin_T, set_origin

CONTINUOUS_RANGE = 2 * math.pi  # [rad] either side of zero, when the file gives none


def _ends(joint: ET.Element) -> tuple[str, str]:
    parent, child = joint.find("parent"), joint.find("child")
    return (
        "" if parent is None else parent.get("link", ""),
        "" if child is None else child.get("link", ""),
    )


def descendants(robot: ET.Element, link: str) -> set[str]:
    """Every link below `link` in the kinematic tree (not `link` itself)."""
    children: dict[str, list[str]] = {}
    for joint in robot.findall("joint"):
        parent, child = _ends(joint)
        children.setdefault(parent, []).append(child)
    found: set[str] = set()
    stack = list(children.get(link, []))
    while stack:
        name = stack.pop()
        if name not in found:
            found.add(name)
            stack.extend(children.get(name, []))
    return found


def drop_links(robot: ET.Element, links: set[str]) -> None:
    """Remove the links and every joint whose child is one of them."""
    for element in list(robot):
        name = element.get("name") if element.tag == "link" else _ends(element)[1]
        if element.tag in ("link", "joint") and name in links:
            robot.remove(element)


def reroot(robot: ET.Element, link: str, what: str, role: str) -> None:
    """Make `link` the root of the tree, turning round every joint between it and the
    current root (see the module docstring). `role` says what the link is for
    ("the mount link", "the base link") in errors."""
    links = {e.get("name", "") for e in robot.findall("link")}
    if link not in links:
        raise DescriptionError(
            f"{what}: {role} {link!r} is not a link of the model (or an added frame); "
            f"links: {', '.join(sorted(links))}"
        )
    joint_of_child = {_ends(j)[1]: j for j in robot.findall("joint")}
    path = []
    current = link
    while current in joint_of_child:
        joint = joint_of_child[current]
        path.append(joint)
        current = _ends(joint)[0]
    for joint in path:
        if joint.get("type") != "fixed":
            raise DescriptionError(
                f"{what}: {role} {link!r} is separated from the file's root link "
                f"{current!r} by the {joint.get('type')} joint {joint.get('name')!r}; "
                "name a link that only fixed joints join to the root"
            )
    for joint in path:
        parent, child = _ends(joint)
        T_parent_child = origin_T(joint, f"joint {joint.get('name')!r}")
        set_origin(joint, inv_T(T_parent_child))
        parent_element, child_element = joint.find("parent"), joint.find("child")
        assert parent_element is not None and child_element is not None
        parent_element.set("link", child)
        child_element.set("link", parent)


def continuous_as_revolute(robot: ET.Element) -> None:
    """Every continuous joint as a revolute joint within the file's limits (±2π when
    the file gives none or an empty range)."""
    for joint in robot.findall("joint"):
        if joint.get("type") != "continuous":
            continue
        joint.set("type", "revolute")
        limit = joint.find("limit")
        if limit is None:
            limit = ET.SubElement(joint, "limit", {"effort": "0", "velocity": "0"})
        lower = float(limit.get("lower", "0") or 0)
        upper = float(limit.get("upper", "0") or 0)
        if not (math.isfinite(lower) and math.isfinite(upper) and lower < upper):
            lower, upper = -CONTINUOUS_RANGE, CONTINUOUS_RANGE
        limit.set("lower", f"{lower:.12g}")
        limit.set("upper", f"{upper:.12g}")
