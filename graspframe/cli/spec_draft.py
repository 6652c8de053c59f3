"""`graspframe spec draft URDF --out SPEC` and `check-hand SPEC --synthesize`: the draft
and the synthesis of graspframe/mapping/spec_files.py, with progress on stderr and a
report of the steps' times and what the draft could not decide."""

from __future__ import annotations

import time
from pathlib import Path

import typer

from graspframe.common.errors import InputError
from graspframe.plugin_system.registry import default_registry
from graspframe.specs import is_spec_path


def _progress(started: float):
    def progress(message: str) -> None:
        typer.echo(f"· {message} ({time.perf_counter() - started:.0f} s)", err=True)

    return progress


def _report(written) -> None:
    synthesis = written.synthesis
    if synthesis is not None:
        for result in synthesis.grasps:
            held = {None: "not tested", True: "held", False: "NOT held"}[result.held]
            measured = (
                f", measured {result.measured_position_err_mm:.1f} mm "
                f"{result.measured_orientation_err_deg:.1f} deg"
                if result.measured_position_err_mm is not None
                and result.measured_orientation_err_deg is not None
                else ""
            )
            why = f" ({result.failure})" if result.failure else ""
            typer.echo(
                f"{result.grasp.value} -> preshape {synthesis.grasp_map[result.grasp.value]}: "
                f"{held}{why}; virtual-finger error predicted "
                f"{result.chosen.position_err_mm:.1f} mm {result.chosen.orientation_err_deg:.1f} deg"
                f"{measured}; {result.evaluated} candidates, {len(result.trials)} held "
                f"trials, {result.seconds:.0f} s"
            )
    steps = ", ".join(f"{step} {seconds:.0f} s" for step, seconds in written.steps.items())
    typer.echo(f"wrote {written.path} ({steps})")
    if written.notes:
        typer.echo("not decided (check these keys, marked NOT DECIDED in the file):")
        for note in written.notes:
            typer.echo(f"  - {note}")


def spec_draft_command(
    urdf: Path, out: Path, synthesize: bool, name: str | None, backend: str
) -> int:
    registry = default_registry()
    physics = registry.get_backend(backend)() if synthesize else None
    from graspframe.mapping.spec_files import draft_spec_file

    written = draft_spec_file(urdf, out, registry, physics, _progress(time.perf_counter()), name)
    _report(written)
    return 0


def synthesize_command(spec: str, backend: str) -> None:
    if not is_spec_path(spec):
        raise InputError(
            f"--synthesize rewrites a spec file's preshapes; {spec!r} is not a spec file (*.toml)"
        )
    registry = default_registry()
    physics = registry.get_backend(backend)()
    from graspframe.mapping.spec_files import synthesize_spec_file

    _report(synthesize_spec_file(Path(spec), registry, physics, _progress(time.perf_counter())))
