"""What is registered, listed: `graspframe plugins` (every plugin, its status, what it
provides and what it found and could not register) and `graspframe objects` (every
registered object with its source, mass, size and the grasps a person would use on it,
and what the object sources found and could not register, with why)."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from graspframe.common.errors import GraspframeError
from graspframe.plugin_system.registry import Registry


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


def print_objects(registry: Registry, console: Console, as_json: bool) -> None:
    """The listing as a table (or JSON), then what was found and not registered."""
    rows, unregistered = object_rows(registry)
    if as_json:
        document = {
            "objects": [asdict(row) for row in rows],
            "not_registered": [
                {"name": name, "plugin": plugin, "reason": reason}
                for name, plugin, reason in unregistered
            ],
        }
        typer.echo(json.dumps(document, indent=2))
        return
    table = Table(title="graspframe objects")
    for column in ("object", "plugin", "shape", "mass g", "size mm (x, y, z)", "grasps"):
        table.add_column(column)
    for row in rows:
        size = " x ".join(f"{v:g}" for v in row.size_mm)
        grasps = ", ".join(row.grasps)
        if row.grasps_from != "given":
            grasps += f" ({row.grasps_from})"
        table.add_row(row.name, row.plugin, row.shape, f"{row.mass_g:g}", size, escape(grasps))
    console.print(table)
    if unregistered:
        console.print(f"{len(unregistered)} object(s) found but not registered:")
        for name, plugin, reason in unregistered:
            console.print(f"  {name} ({plugin}): {escape(reason)}")


def print_plugins(registry: Registry, console: Console, details: bool, as_json: bool) -> None:
    """The plugins as a table (or JSON); with `details`, the tracebacks of failed ones."""
    if as_json:
        rows = [
            {
                "plugin": p.name,
                "module": p.module,
                "package": p.package,
                "version": p.version,
                "status": p.status,
                "provides": [{"kind": kind, "name": name} for kind, name in p.provides],
                "not_registered": [
                    {"kind": kind, "name": name, "reason": reason}
                    for kind, name, reason in p.not_registered
                ],
                "error": p.error,
            }
            for p in registry.plugins
        ]
        typer.echo(json.dumps(rows, indent=2))
        return
    table = Table(title="graspframe plugins", show_lines=False)
    for column in ("plugin", "package", "version", "status", "provides / error"):
        table.add_column(column)
    for info in registry.plugins:
        if info.status == "loaded":
            provided = ", ".join(f"{kind} {name}" for kind, name in info.provides) or "-"
            if info.not_registered:
                count = len(info.not_registered)
                provided += f"; found and not registered: {count} (graspframe objects: why)"
            status = "[green]loaded[/green]"
        else:
            provided = info.error or ""
            status = f"[red]{info.status}[/red]" if info.status == "failed" else info.status
        table.add_row(info.name, info.package, info.version, status, provided)
    console.print(table)
    failed = registry.failures
    if failed:
        console.print(
            f"{len(failed)} plugin(s) failed to load; the others work. "
            "Run with --details for tracebacks, or set GRASPFRAME_STRICT_PLUGINS=1 to stop "
            "at the first failure."
        )
        if details:
            for info in failed:
                console.print(f"\n[bold]{info.name}[/bold] ({info.package})\n{info.details}")
