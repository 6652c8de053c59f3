"""`graspframe spec draft URDF --out SPEC` and `check-hand SPEC --synthesize`: the draft
and the synthesis of graspframe/mapping/spec_files.py, with progress on stderr and a
report of the steps' times and what the draft could not decide."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from graspframe.common.defaults import DEFAULT_BACKEND
from graspframe.common.errors import InputError
from graspframe.plugin_system.registry import default_registry
from graspframe.specs import is_spec_path

if TYPE_CHECKING:
    from graspframe.mapping.spec_files import Written


def _progress(started: float) -> Callable[[str], None]:
    def progress(message: str) -> None:
        typer.echo(f"· {message} ({time.perf_counter() - started:.0f} s)", err=True)

    return progress


def _report(written: Written) -> None:
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
            why = (
                f" ({result.failure or result.design_failure})"
                if (result.failure or result.design_failure)
                else ""
            )
            if result.held and result.design_failure:
                why = f" (but not {result.design_failure})"
            typer.echo(
                f"{result.grasp.value} -> preshape {synthesis.grasp_map[result.grasp.value]}: "
                f"{held}{why}; virtual-finger error predicted "
                f"{result.chosen.position_err_mm:.1f} mm "
                f"{result.chosen.orientation_err_deg:.1f} deg"
                f"{measured}; {result.evaluated} candidates, {len(result.trials)} held "
                f"trials, {result.seconds:.0f} s"
            )
        for grasp, why in synthesis.impossible.items():
            typer.echo(f"{grasp} -> no preshape: {why}")
    steps = ", ".join(f"{step} {seconds:.0f} s" for step, seconds in written.steps.items())
    typer.echo(f"wrote {written.path} ({steps})")
    if written.notes:
        typer.echo("not decided (check these keys, marked NOT DECIDED in the file):")
        for note in written.notes:
            typer.echo(f"  - {note}")


def _checked_workers(workers: int) -> None:
    if workers < 1:
        raise InputError(f"--workers must be 1 or more (grasps synthesised at once), got {workers}")


def spec_draft_command(
    urdf: Path, out: Path, synthesize: bool, name: str | None, backend: str, workers: int = 1
) -> int:
    _checked_workers(workers)
    registry = default_registry()
    physics = registry.get_backend(backend)() if synthesize else None
    from graspframe.mapping.spec_files import draft_spec_file

    progress = _progress(time.perf_counter())
    written = draft_spec_file(urdf, out, registry, physics, progress, name, workers)
    _report(written)
    return 0


def synthesize_command(spec: str, backend: str, workers: int = 1) -> None:
    _checked_workers(workers)
    if not is_spec_path(spec):
        raise InputError(
            f"--synthesize rewrites a spec file's preshapes; {spec!r} is not a spec file (*.toml)"
        )
    registry = default_registry()
    physics = registry.get_backend(backend)()
    from graspframe.mapping.spec_files import synthesize_spec_file

    progress = _progress(time.perf_counter())
    _report(synthesize_spec_file(Path(spec), registry, physics, progress, workers=workers))


WORKERS_HELP = "Grasps synthesised at once, each in a process of its own."

spec_app = typer.Typer(help="Hand spec files: draft one from a URDF.", no_args_is_help=True)


@spec_app.command("draft")
def spec_draft(
    urdf: Annotated[Path, typer.Argument(help="The hand's URDF, as its vendor ships it.")],
    out: Annotated[Path, typer.Option(help="The spec file to write (*.toml).")],
    synthesize: Annotated[
        bool,
        typer.Option(
            "--synthesize/--no-synthesize",
            help="Synthesise the preshapes from the human reference grasps (physics, a few "
            "minutes); without, one generic wrap serves every grasp.",
        ),
    ] = True,
    name: Annotated[str | None, typer.Option(help="The hand's name (default: the URDF's).")] = None,
    backend: Annotated[
        str, typer.Option(help="Physics backend of the synthesis.")
    ] = DEFAULT_BACKEND,
    workers: Annotated[int, typer.Option(help=WORKERS_HELP)] = 2,
) -> None:
    """Draft a hand spec from a URDF: fingers, thumb, palm frame and pad, joint roles,
    drive; then its preshapes, synthesised. Says what it could not decide."""
    raise typer.Exit(spec_draft_command(urdf, out, synthesize, name, backend, workers))
