"""`graspframe evaluate`: the command's options checked and turned into a sweep
(`sweep_config`), then the sweep run with a progress bar and its tables printed
(`run_evaluation`). cli.py holds the options and their help."""

from __future__ import annotations

from pathlib import Path

from rich.console import Console

from graspframe.defaults import MOUNTS
from graspframe.errors import InputError, UnknownNameError
from graspframe.experiments.sweep import SweepConfig


def names_option(text: str, kind: str, known: list[str]) -> tuple[str, ...]:
    """A comma-separated list of names (or "all"), each checked against the known ones;
    for hands, a spec file path (*.toml) is loaded and checked instead."""
    from graspframe.specs import is_spec_path

    if text.strip() == "all":
        return tuple(known)
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    for name in names:
        if kind == "hand" and is_spec_path(name):
            from graspframe.registry import default_registry

            default_registry().get_hand(name)  # a spec that does not load fails here
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
) -> SweepConfig:
    """The sweep the options ask for (their text as given on the command line, rho_mm
    [mm], time_limit [s]); an unknown name or a bad value fails before any trial."""
    from graspframe.grasps import HumanGrasp
    from graspframe.registry import default_registry

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
    return SweepConfig(
        hands=names_option(hands, "hand", registry.names("hand")),
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
        mounts=names_option(mount, "mount", list(MOUNTS)),
        sizes=sizes_option(sizes),
        arm=arm,
        objects=object_names,
    )


def run_evaluation(config: SweepConfig, console: Console, err_console: Console) -> None:
    """Run the sweep (progress on `err_console`), write its tables and figure, and print
    the summary table and where the files are on `console`."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    from graspframe.experiments.summary import plot_summary, summarize, write_tables
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

        def on_trial(row: dict, done: int, _total: int) -> None:
            state = "ok" if row.get("success") else row.get("error") or row.get("failure_reason")
            progress.update(task, completed=done, description=f"{row['trial_id']}: {state}"[:60])

        rows = run_sweep(config, on_trial=on_trial)
        progress.update(task, completed=len(rows))
    summary = summarize(rows)
    csv_path, md_path = write_tables(summary, out)
    figure = plot_summary(summary, out / "summary.png")
    console.print(md_path.read_text(), markup=False, highlight=False)
    console.print(
        f"trials: {out / 'trials.jsonl'}\nsummary: {csv_path}, {md_path}\nfigure: {figure}"
    )
