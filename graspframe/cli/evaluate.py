"""`graspframe evaluate`: the command's options checked and turned into a sweep
(`sweep_config`), then the sweep run with a progress bar and its summary printed as a
table per experiment (`run_evaluation`, `print_summary`). commands.py holds the options and
their help."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console

from graspframe.common.defaults import MOUNT_ARM, MOUNTS, STRATEGIES, STRATEGY_METHOD
from graspframe.common.errors import InputError, UnknownNameError
from graspframe.experiments.sweep import SweepConfig

if TYPE_CHECKING:
    from graspframe.experiments.summary import SummaryRow
    from graspframe.experiments.trials import TrialRow


def names_option(text: str, kind: str, known: list[str]) -> tuple[str, ...]:
    """A comma-separated list of names (or "all"), each checked against the known ones;
    for hands, a spec file path (*.toml) is loaded and checked instead, for objects a
    mesh file with its sidecar."""
    from graspframe.plugin_system.registry import default_registry
    from graspframe.specs import is_spec_path
    from graspframe.specs.objects import is_object_path

    if text.strip() == "all":
        return tuple(known)
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    for name in names:
        if kind == "hand" and is_spec_path(name):
            default_registry().get_hand(name)  # a spec that does not load fails here
        elif kind == "object" and (is_object_path(name) or name not in known):
            # a mesh without its sidecar, or an object found and not registered, says why
            default_registry().get_object(name)
        elif name not in known:
            raise UnknownNameError(kind, name, known)
    if not names:
        raise InputError(f"no {kind} given; pass a comma-separated list or 'all'")
    return names


def sizes_option(text: str) -> tuple[int, ...]:
    """ "75,125" -> (75, 125): object sizes in percent."""
    try:
        return tuple(int(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise InputError(
            f"--sizes must be whole percentages separated by commas, e.g. '75,125'; got {text!r}"
        ) from None


def sweep_config(
    *,
    hands: str,
    grasps: str | None,
    arm: str,
    rho_mm: float,
    directions: int | None,
    workers: int,
    executor: str,
    scheduler: str | None,
    out: Path,
    seed: int,
    time_limit: float,
    record: bool,
    mount: str,
    sizes: str,
    objects: str,
    strategy: str = STRATEGY_METHOD,
    camera_noise: float = 1.0,
    held_test: str = "graspframe",
) -> SweepConfig:
    """The sweep the options ask for (their text as given on the command line, rho_mm
    [mm], time_limit [s]); an unknown name or a bad value fails before any trial."""
    from graspframe.common.grasps import HumanGrasp
    from graspframe.plugin_system.registry import default_registry
    from graspframe.strategy.held_check import held_test_named

    held_test_named(held_test)  # an unknown held test fails before any trial
    registry = default_registry()
    registry.get_arm(arm)  # an unknown arm or a spec that does not load fails before any trial
    object_names = names_option(objects, "object", registry.names("object")) if objects else ()
    if object_names and grasps is not None:
        raise InputError(
            "--objects runs each object's documented grasps; leave out --grasps "
            f"(got --grasps {grasps})"
        )
    all_grasps = [g.value for g in HumanGrasp]
    grasp_names = () if object_names else names_option(grasps or "all", "grasp", all_grasps)
    hand_names = names_option(hands, "hand", registry.names("hand"))
    mount_names = names_option(mount, "mount", list(MOUNTS))
    if MOUNT_ARM in mount_names:
        from graspframe.robot_models.mounting import check_mounts

        for hand in hand_names:  # a hand whose links overlap the arm's fails before any trial
            check_mounts(registry.get_arm(arm), registry.get_hand(hand))
    return SweepConfig(
        hands=hand_names,
        grasps=grasp_names,
        out_dir=out,
        rho=rho_mm / 1000.0,
        directions=(0 if object_names else 6) if directions is None else directions,
        workers=workers,
        executor=executor,
        scheduler=scheduler,
        seed=seed,
        time_limit=time_limit,
        record=record,
        mounts=mount_names,
        sizes=sizes_option(sizes),
        arm=arm,
        objects=object_names,
        strategies=names_option(strategy, "strategy", list(STRATEGIES)),
        camera_noise=camera_noise,
        held_test=held_test,
    )


def run_evaluation(config: SweepConfig, console: Console, err_console: Console) -> None:
    """Run the sweep (progress on `err_console`), write its tables and figure, and print
    the summary table and where the files are on `console`."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    from graspframe.experiments.summary import plot_summary, summarize, table_note, write_tables
    from graspframe.experiments.sweep import plan_trials, run_sweep

    out = Path(config.out_dir)
    total = len(plan_trials(config))
    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=err_console,
    ) as progress:
        task = progress.add_task("trials", total=total)

        def on_trial(row: TrialRow, done: int, _total: int) -> None:
            state = "ok" if row.success else row.error or row.failure_reason
            progress.update(task, completed=done, description=f"{row.trial_id}: {state}"[:60])

        rows = run_sweep(config, on_trial=on_trial)
        progress.update(task, completed=len(rows))
    summary = summarize(rows)
    note = table_note(config.held_test)
    csv_path, md_path = write_tables(summary, out, note)
    figure = plot_summary(summary, out / "summary.png")
    print_summary(summary, console, note)
    console.print(
        f"trials: {out / 'trials.jsonl'}\nsummary: {csv_path}, {md_path}\nfigure: {figure}"
    )


def print_summary(summary: list[SummaryRow], console: Console, note: str | None = None) -> None:
    """The summary as terminal tables, one per experiment (summary.md has them in one
    markdown table), then the note that explains them."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    from graspframe.experiments.summary import TABLE_NOTE, summary_table

    titles = {"A": "Experiment A: perfect perception", "B": "Experiment B: object position error"}
    for experiment, title in titles.items():
        headers, rows = summary_table(summary, experiment)
        table = Table(title=title, box=box.SIMPLE_HEAD, padding=(0, 1))
        for column, header in enumerate(headers):
            # Never narrower than its widest cell or header word: headers wrap between
            # words, values are never cut. Text: "[mm]" is not read as markup.
            widest = max([len(cells[column]) for cells in rows] + [len(w) for w in header.split()])
            table.add_column(Text(header), min_width=widest)
        for cells in rows:
            table.add_row(*(Text(cell) for cell in cells))
        # Wider than the console: printed whole (a terminal wraps the lines; a file or
        # a pipe keeps them), not cut at its edge.
        console.print(table, crop=False)
    console.print(note or TABLE_NOTE, markup=False, highlight=False)
