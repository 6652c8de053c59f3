"""The `graspframe` command line: the typer app, every built-in command's options and
help, and the small commands; the bodies of the larger ones are in graspframe/cli/,
and plugins add commands of their own (graspframe/cli/plugin_commands.py).

Every error graspframe raises on purpose is printed as one line and exits non-zero;
`--verbose` shows the traceback as well. Exit codes (docs/cli.md): 0 done (`run`: the
grasp held), 1 an error, 2 a wrong command line, 3 `run` ran but the grasp was not held,
130 interrupted (Ctrl-C or SIGTERM).
"""

from __future__ import annotations

import logging
import sys
import traceback
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape

from graspframe import __version__
from graspframe.cli.interrupts import ignore_until_exit, interruptible
from graspframe.cli.plugin_commands import WithPluginCommands
from graspframe.cli.spec_draft import spec_app
from graspframe.common.defaults import (
    DEFAULT_ARM,
    DEFAULT_BACKEND,
    DEFAULT_CLASSIFIER,
    DEFAULT_HAND,
    DISTURBANCE_FRACTION,
    LIFT_HEIGHT,
    MOUNT_ARM,
    STRATEGY_METHOD,
    Mount,
    Strategy,
)
from graspframe.common.errors import GraspframeError, InputError
from graspframe.experiments.trials import TRIAL_TIME_LIMIT

app = typer.Typer(
    name="graspframe",
    help="Map one image of a human grasp onto a robot hand on an arm, execute it, score it.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
    cls=WithPluginCommands,  # and the commands the plugins add
)

console = Console()
err_console = Console(stderr=True)
_state = {"verbose": False}

EXIT_OK = 0  # the command did what it was asked (`run`: the grasp held)
EXIT_ERROR = 1  # bad input, a failed stage, a bug
EXIT_NOT_HELD = 3  # `run`: the grasp was executed and scored, but it was not held
# (2: the command line itself is wrong, reported by typer before a command runs)
EXIT_INTERRUPTED = 130  # Ctrl-C or SIGTERM: 128 + SIGINT, as shells report it


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


@app.command()
def plugins(
    details: Annotated[
        bool, typer.Option("--details", help="Show the full traceback of failed plugins.")
    ] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """List the plugins: name, package and version, load status, what each provides."""
    from graspframe.cli.listing import print_plugins
    from graspframe.plugin_system.registry import default_registry

    print_plugins(default_registry(), console, details, as_json)


@app.command()
def objects(
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """List the objects: source, mass, size, the grasps a person would use; and what the
    object sources found and could not register, with why."""
    from graspframe.cli.listing import print_objects
    from graspframe.plugin_system.registry import default_registry

    print_objects(default_registry(), console, as_json)


def _parse_error_mm(text: str) -> tuple[float, float]:
    """ "DX,DY" in millimetres -> (dx, dy) in metres."""
    try:
        dx_mm, dy_mm = (float(v) for v in text.split(","))
    except ValueError:
        raise InputError(
            f"--object-error-mm must be two numbers 'DX,DY' in millimetres, got {text!r}"
        ) from None
    return dx_mm / 1000.0, dy_mm / 1000.0


STRATEGY_HELP = "method (the published strategy) or servo (corrected by a depth camera)."
NOISE_HELP = "Multiple of the servo camera's noise model (2: doubled)."
HELD_TEST_HELP = (
    "graspframe (lift, then pushes of a fraction of the weight) or benchmark (the field's "
    "convention: gravity off, the weight along +-x, +-y, +-z for 2 s, 5 cm / 15 deg)."
)


@app.command()
def run(
    hand: Annotated[
        str, typer.Option(help="Robot hand: a registered name or a hand spec file (*.toml).")
    ] = DEFAULT_HAND,
    grasp: Annotated[
        str | None, typer.Option(help="The human grasp (skips vision), e.g. large_diameter.")
    ] = None,
    image: Annotated[
        Path | None, typer.Option(help="Image of a human grasp (default: the bundled demo).")
    ] = None,
    scene: Annotated[
        Path | None, typer.Option(help="Scene file of the image: camera and object poses.")
    ] = None,
    classifier: Annotated[str, typer.Option(help="Classifier plugin name.")] = DEFAULT_CLASSIFIER,
    arm: Annotated[
        str, typer.Option(help="Arm: a registered name or an arm spec file (*.toml).")
    ] = DEFAULT_ARM,
    object_name: Annotated[
        str | None, typer.Option("--object", help="Object name (default: the grasp's own).")
    ] = None,
    object_error_mm: Annotated[
        str, typer.Option(help="Error 'DX,DY' \\[mm] added to the object position the robot uses.")
    ] = "0,0",
    seed: Annotated[int, typer.Option(help="Seed of everything random in the run.")] = 0,
    backend: Annotated[str, typer.Option(help="Backend plugin name.")] = DEFAULT_BACKEND,
    out: Annotated[Path, typer.Option(help="Folder for run folders.")] = Path("runs"),
    human_contacts: Annotated[
        Path | None,
        typer.Option(help="JSON file of measured human contacts replacing the simulated ones."),
    ] = None,
    record: Annotated[
        bool, typer.Option("--record/--no-record", help="Record the run for rerun.")
    ] = True,
    mount: Annotated[
        str,
        typer.Option(help="arm (the hand on --arm) or floating (the hand alone, free base)."),
    ] = MOUNT_ARM,
    lift_height_mm: Annotated[
        float,
        typer.Option(help="Lift of the held test \\[mm], for the robot and the human alike."),
    ] = 1000 * LIFT_HEIGHT,
    disturbance_fraction: Annotated[
        float,
        typer.Option(help="Push of the held test, a fraction of the object's weight."),
    ] = DISTURBANCE_FRACTION,
    held_test: Annotated[str, typer.Option(help=HELD_TEST_HELP)] = "graspframe",
    strategy: Annotated[str, typer.Option(help=STRATEGY_HELP)] = STRATEGY_METHOD,
    camera_noise: Annotated[float, typer.Option(help=NOISE_HELP)] = 1.0,
) -> None:
    """Image of a human grasp -> robot grasp on the arm in simulation, scored.

    With no --grasp and no --image, the bundled demo image is classified."""
    from graspframe.common.grasps import HumanGrasp
    from graspframe.plugin_system.registry import default_registry
    from graspframe.run.request import RunRequest, resolve

    if grasp is not None and (image is not None or scene is not None):
        raise InputError("pass either --grasp (no vision) or --image with --scene, not both")
    request = RunRequest(
        hand=hand,
        grasp=HumanGrasp.parse(grasp) if grasp else None,
        image=str(image) if image else None,
        scene=str(scene) if scene else None,
        classifier=classifier,
        arm=arm,
        object=object_name,
        object_error=_parse_error_mm(object_error_mm),
        seed=seed,
        backend=backend,
        out_root=str(out),
        human_contacts=str(human_contacts) if human_contacts else None,
        record=record,
        mount=Mount.parse(mount),
        lift_height=lift_height_mm / 1000.0,
        disturbance_fraction=disturbance_fraction,
        held_test_name=held_test,
        strategy=Strategy.parse(strategy),
        camera_noise=camera_noise,
    )
    registry = default_registry()
    # Every name and file is checked before the simulation's modules are imported (a
    # second or more): a mistyped name is answered at once.
    inputs = resolve(request, registry)
    from graspframe.cli.run_summary import print_run_summary
    from graspframe.run.runner import run_grasp

    result = run_grasp(
        request,
        registry,
        progress=lambda stage: err_console.print(f"[dim]· {stage}[/dim]"),
        inputs=inputs,
    )
    print_run_summary(result, console)
    held = result.outcome is not None and result.outcome.success
    raise typer.Exit(EXIT_OK if held else EXIT_NOT_HELD)


@app.command()
def classify(
    image: Annotated[Path, typer.Argument(help="Image of one hand grasping an object.")],
    k: Annotated[int, typer.Option(help="Nearest database views that vote.")] = 8,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    classifier: Annotated[
        str,
        typer.Option(help="Registered classifier: hog_knn, or landmarks (the `hands` extra)."),
    ] = DEFAULT_CLASSIFIER,
) -> None:
    """Classify the human grasp and hand orientation in one image."""
    from graspframe.cli.vision import classify_command

    raise typer.Exit(classify_command(image, k, as_json, classifier))


@app.command()
def evaluate(
    hands: Annotated[
        str, typer.Option(help="Comma-separated hands: registered names or spec files (*.toml).")
    ] = "barrett,karlsruhe",
    grasps: Annotated[
        str | None,
        typer.Option(help="Comma-separated grasps, or 'all' (the default without --objects)."),
    ] = None,
    arm: Annotated[
        str, typer.Option(help="Arm of the arm mount: a registered name or a spec file (*.toml).")
    ] = DEFAULT_ARM,
    rho_mm: Annotated[
        float, typer.Option(help="Object position error of experiment B \\[mm].")
    ] = 50.0,
    directions: Annotated[
        int | None,
        typer.Option(
            help="Directions of the error in the table plane (default 6; 0 with --objects)."
        ),
    ] = None,
    workers: Annotated[int, typer.Option(help="Trials run in parallel.")] = 2,
    executor: Annotated[str, typer.Option(help="local (processes here) or dask.")] = "local",
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address (default: a local cluster).")
    ] = None,
    out: Annotated[Path, typer.Option(help="Output folder (rerun to resume).")] = Path(
        "runs/evaluate"
    ),
    seed: Annotated[int, typer.Option(help="Seed of every trial.")] = 0,
    time_limit: Annotated[
        float, typer.Option(help="Per-trial wall-time limit \\[s].")
    ] = TRIAL_TIME_LIMIT,
    record: Annotated[
        bool, typer.Option("--record/--no-record", help="Record every trial for rerun.")
    ] = False,
    mount: Annotated[
        str, typer.Option(help="Comma-separated mounts: arm, floating (the hand alone).")
    ] = MOUNT_ARM,
    sizes: Annotated[
        str,
        typer.Option(
            help="Object sizes \\[%] besides 100 to repeat experiment A at, e.g. '75,125' "
            "('' for none)."
        ),
    ] = "",
    objects: Annotated[
        str,
        typer.Option(
            help="Comma-separated objects to run instead of the grasps' default objects, "
            "each with the grasps documented for it (docs/objects.md), e.g. "
            "'ycb_005_tomato_soup_can,ycb_025_mug'; experiment A unless --directions."
        ),
    ] = "",
    strategy: Annotated[str, typer.Option(help="Comma-separated: " + STRATEGY_HELP)] = "method",
    camera_noise: Annotated[float, typer.Option(help=NOISE_HELP)] = 1.0,
    held_test: Annotated[str, typer.Option(help=HELD_TEST_HELP)] = "graspframe",
) -> None:
    """Experiments A (perfect perception) and B (object position error) for the hands."""
    from graspframe.cli.evaluate import run_evaluation, sweep_config

    config = sweep_config(
        hands=hands,
        grasps=grasps,
        arm=arm,
        rho_mm=rho_mm,
        directions=directions,
        workers=workers,
        executor=executor,
        scheduler=scheduler,
        out=out,
        seed=seed,
        time_limit=time_limit,
        record=record,
        mount=mount,
        sizes=sizes,
        objects=objects,
        strategy=Strategy.parse(strategy),
        camera_noise=camera_noise,
        held_test=held_test,
    )
    run_evaluation(config, console, err_console)


@app.command()
def review(
    run: Annotated[Path, typer.Argument(help="A run folder, or its recording.")],
) -> None:
    """Open a recorded run in the viewer of the plugin that recorded it."""
    from graspframe.cli.review import review_command

    raise typer.Exit(review_command(run))


app.add_typer(spec_app, name="spec")


@app.command("check-hand")
def check_hand(
    name: Annotated[str, typer.Argument(help="A registered hand, or a hand spec file (*.toml).")],
    hold: Annotated[
        bool,
        typer.Option(
            "--hold/--no-hold",
            help="Also check that the hand alone holds its design objects and experiment "
            "A's object for every human grasp (physics, ~5 s a trial).",
        ),
    ] = True,
    backend: Annotated[
        str, typer.Option(help="Physics backend of the hold check.")
    ] = DEFAULT_BACKEND,
    pictures: Annotated[
        Path | None,
        typer.Option(
            help="Folder for the pictures of the hold check (default runs/check-hand/NAME)."
        ),
    ] = None,
    arm: Annotated[
        str,
        typer.Option(
            help="Arm the hand's links must clear once mounted: a registered name, an arm "
            "spec file (*.toml), or 'none'."
        ),
    ] = DEFAULT_ARM,
    held_test: Annotated[str, typer.Option(help=HELD_TEST_HELP)] = "graspframe",
    synthesize: Annotated[
        bool,
        typer.Option(
            "--synthesize",
            help="First (re)write the spec's preshapes and grasp map, synthesised from the "
            "human reference grasps (a spec file only).",
        ),
    ] = False,
    workers: Annotated[
        int, typer.Option(help="With --synthesize: grasps synthesised at once, each in a process.")
    ] = 2,
) -> None:
    """Check a hand plugin against the contract and say, in plain words, what is wrong."""
    from graspframe.cli.check_hand import check_hand_command

    on_arm = None if arm.strip().lower() == "none" else arm
    if synthesize:
        from graspframe.cli.spec_draft import synthesize_command

        synthesize_command(name, backend, workers)
    code = check_hand_command(
        name, hold=hold, backend=backend, pictures=pictures, arm=on_arm, held_test=held_test
    )
    raise typer.Exit(code)


def main(argv: list[str] | None = None) -> int:
    """Entry point: run the app, turn deliberate errors into one line and an exit code."""
    with interruptible():
        return _run_app(argv)


def _run_app(argv: list[str] | None) -> int:
    try:
        # Standalone mode: usage errors print their own message and raise SystemExit;
        # typer turns a KeyboardInterrupt into the exit code 130.
        app(args=argv, prog_name="graspframe")
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        if code == EXIT_INTERRUPTED:
            err_console.print("interrupted", highlight=False)
        return code
    except KeyboardInterrupt:  # outside a command: while printing its last lines
        err_console.print("interrupted", highlight=False)
        return EXIT_INTERRUPTED
    except GraspframeError as exc:
        if _state["verbose"]:
            traceback.print_exc()
        # escape: a message's own brackets ("[mm]", ".[hands]", paths) are not markup
        err_console.print(f"[red]error:[/red] {escape(str(exc))}", highlight=False, soft_wrap=True)
        return EXIT_ERROR
    except Exception as exc:  # a bug, not a user error: still one line unless --verbose
        if _state["verbose"]:
            traceback.print_exc()
        else:
            err_console.print(
                f"[red]internal error:[/red] {type(exc).__name__}: {escape(str(exc))} "
                "(run with --verbose for the traceback)",
                highlight=False,
                soft_wrap=True,
            )
        return EXIT_ERROR
    return 0


def _console_script() -> None:
    code = main()
    ignore_until_exit()  # the command has ended: its exit code stands (interrupts.py)
    sys.exit(code)


if __name__ == "__main__":
    _console_script()
