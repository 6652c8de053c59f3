"""The `graspframe` command line.

Every error graspframe raises on purpose is printed as one line and exits non-zero;
`--verbose` shows the traceback as well.
"""

from __future__ import annotations

import json
import logging
import sys
import traceback
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from graspframe import __version__
from graspframe.errors import GraspframeError, NotAvailableError

app = typer.Typer(
    name="graspframe",
    help="Map one image of a human grasp onto a robot hand on an arm, execute it, score it.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
)
db_app = typer.Typer(help="The synthetic view database of the hog_knn classifier.")
app.add_typer(db_app, name="db")

console = Console()
err_console = Console(stderr=True)
_state = {"verbose": False}

EXIT_ERROR = 1


def _version_callback(value: bool) -> None:
    if value:
        console.print(f"graspframe {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    verbose: Annotated[
        bool, typer.Option("--verbose", "-v", help="Log progress and show tracebacks.")
    ] = False,
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version_callback, is_eager=True, help="Show version."),
    ] = False,
) -> None:
    _state["verbose"] = verbose
    logging.basicConfig(
        level=logging.INFO if verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )


def _not_yet(what: str) -> NotAvailableError:
    return NotAvailableError(f"{what} is not available in graspframe {__version__} yet")


@app.command()
def plugins(
    details: Annotated[
        bool, typer.Option("--details", help="Show the full traceback of failed plugins.")
    ] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """List the plugins: name, package and version, load status, what each provides."""
    from graspframe.registry import default_registry

    registry = default_registry()
    if as_json:
        rows = [
            {
                "plugin": p.name,
                "module": p.module,
                "package": p.package,
                "version": p.version,
                "status": p.status,
                "provides": [{"kind": kind, "name": name} for kind, name in p.provides],
                "error": p.error,
            }
            for p in registry.plugins
        ]
        print(json.dumps(rows, indent=2))
        return
    table = Table(title="graspframe plugins", show_lines=False)
    for column in ("plugin", "package", "version", "status", "provides / error"):
        table.add_column(column)
    for info in registry.plugins:
        if info.status == "loaded":
            provided = ", ".join(f"{kind} {name}" for kind, name in info.provides) or "-"
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


@app.command()
def run() -> None:
    """Image of a human grasp -> robot grasp on the arm in simulation, scored."""
    raise _not_yet("graspframe run")


@app.command()
def classify() -> None:
    """Classify the human grasp and hand orientation in one image."""
    raise _not_yet("graspframe classify")


@app.command()
def evaluate() -> None:
    """Reproduce experiments A and B for the robot hands."""
    raise _not_yet("graspframe evaluate")


@app.command()
def review() -> None:
    """Open a recorded run in the rerun viewer."""
    raise _not_yet("graspframe review")


@db_app.command("build")
def db_build() -> None:
    """(Re)build the synthetic view database."""
    raise _not_yet("graspframe db build")


def main(argv: list[str] | None = None) -> int:
    """Entry point: run the app, turn deliberate errors into one line and an exit code."""
    try:
        # Standalone mode: usage errors print their own message and raise SystemExit.
        app(args=argv, prog_name="graspframe")
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except GraspframeError as exc:
        if _state["verbose"]:
            traceback.print_exc()
        err_console.print(f"[red]error:[/red] {exc}", highlight=False, soft_wrap=True)
        return EXIT_ERROR
    except Exception as exc:  # a bug, not a user error: still one line unless --verbose
        if _state["verbose"]:
            traceback.print_exc()
        else:
            err_console.print(
                f"[red]internal error:[/red] {type(exc).__name__}: {exc} "
                "(run with --verbose for the traceback)",
                highlight=False,
                soft_wrap=True,
            )
        return EXIT_ERROR
    return 0


def _console_script() -> None:
    sys.exit(main())


if __name__ == "__main__":
    _console_script()
