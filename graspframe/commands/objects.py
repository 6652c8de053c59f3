"""`graspframe objects`: every registered object with its source, mass, size and the
grasps a person would use on it, and what the object sources found and could not
register, with why."""

from __future__ import annotations

from dataclasses import dataclass

from graspframe.errors import GraspframeError
from graspframe.registry import Registry


@dataclass(frozen=True)
class ObjectRow:
    """One registered object: size_mm [mm] along its x, y, z as it rests; grasps: their
    names; grasps_from: "given" or the shape rule's reason (hal/shape_grasps.py)."""

    name: str
    plugin: str
    shape: str
    mass_g: float
    size_mm: tuple[float, float, float]
    grasps: tuple[str, ...]
    grasps_from: str
    summary: str


def object_row(registry: Registry, name: str) -> ObjectRow:
    """The listing row of a registered object (a mesh's geometry is computed, and
    cached, when first needed)."""
    from graspframe.hal.shape_grasps import grasp_from_shape

    entry = registry.entry("object", name)
    obj = entry.item
    size = tuple(round(2000 * h, 1) for h in obj.half_extents)
    given = bool(obj.grasps or obj.default_for)
    return ObjectRow(
        name=name,
        plugin=entry.plugin,
        shape=obj.shape,
        mass_g=round(1000 * obj.mass, 1),
        size_mm=(size[0], size[1], size[2]),
        grasps=tuple(g.value for g in obj.documented_grasps()),
        grasps_from="given" if given else f"from its shape: {grasp_from_shape(obj)[1]}",
        summary=obj.summary,
    )


def object_rows(registry: Registry) -> tuple[list[ObjectRow], list[tuple[str, str, str]]]:
    """(a row per registered object, (name, plugin, why) per object found and not
    registered). An object whose files cannot be read is a row of the second list."""
    rows, unregistered = [], []
    for name in registry.names("object"):
        try:
            rows.append(object_row(registry, name))
        except GraspframeError as exc:
            unregistered.append((name, registry.entry("object", name).plugin, str(exc)))
    for name, found in sorted(registry.not_registered("object").items()):
        for plugin, reason in found:
            unregistered.append((name, plugin, reason))
    return rows, unregistered
