"""Experiment sweeps: every (hand, grasp, condition) trial, resumable, local or on Dask.

Locally, trials run in long-lived supervised worker processes (workers.py); on Dask,
each in a fresh process (trials.run_trial_isolated).

Each finished trial is appended to `<out>/trials.jsonl` as one JSON line the moment it
finishes; rerunning the same sweep skips the trials already there (a line cut short by
a kill is ignored, so that trial runs again). Conditions: "A" is perfect perception,
"B0".."B<n-1>" the object position error rho in direction beta_k = 2 pi k / n.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Generator
from contextlib import closing
from dataclasses import dataclass
from itertools import product
from pathlib import Path
from typing import Any

from graspframe.common.defaults import DEFAULT_ARM, MOUNT_ARM, MOUNTS, STRATEGIES, STRATEGY_METHOD
from graspframe.common.errors import InputError, OutputError
from graspframe.common.files import make_folder, os_reason
from graspframe.experiments.trials import (
    CONDITION_A,
    TRIAL_TIME_LIMIT,
    TrialRow,
    TrialSpec,
    experiment_b_errors,
    failed_row,
    run_trial_isolated,
)
from graspframe.experiments.workers import run_in_workers

EXECUTORS = ("local", "dask")
TRIALS_FILE = "trials.jsonl"


@dataclass(frozen=True)
class SweepConfig:
    """hands, grasps: names; rho: object error radius [m]; directions: of experiment B
    (0: experiment A only); executor: "local" (worker processes here) or "dask"; scheduler: a
    Dask scheduler address (None: a local Dask cluster); time_limit: per trial [s];
    record: write a rerun recording of every trial; mounts: "arm" and/or "floating";
    sizes: [%] object sizes besides 100 at which experiment A is repeated, on the
    catalogue's scaled objects <default object>_<size> (e.g. 75 -> large_cylinder_075);
    objects: object names to run instead of the grasps' default objects, each with the
    grasps documented for it (`ObjectDescription.documented_grasps`; `grasps` must then
    be empty, and sizes too); strategies: "method" and/or "servo", each running every
    trial; camera_noise: the multiple of the servo camera's noise model; held_test: the
    held test of every trial ("graspframe" or "benchmark")."""

    hands: tuple[str, ...]
    grasps: tuple[str, ...]
    out_dir: Path
    rho: float = 0.05
    directions: int = 6
    workers: int = 2
    executor: str = "local"
    scheduler: str | None = None
    seed: int = 0
    time_limit: float = TRIAL_TIME_LIMIT
    arm: str = DEFAULT_ARM
    record: bool = False
    mounts: tuple[str, ...] = (MOUNT_ARM,)
    sizes: tuple[int, ...] = ()
    objects: tuple[str, ...] = ()
    strategies: tuple[str, ...] = (STRATEGY_METHOD,)
    camera_noise: float = 1.0
    held_test: str = "graspframe"

    def __post_init__(self) -> None:
        if self.executor not in EXECUTORS:
            raise InputError(
                f"unknown executor {self.executor!r}; executors: {', '.join(EXECUTORS)}"
            )
        if self.workers < 1 or self.directions < 0 or not self.rho >= 0:
            raise InputError("a sweep needs workers >= 1, directions >= 0 and rho >= 0")
        unknown = [m for m in self.mounts if m not in MOUNTS]
        if unknown or not self.mounts:
            raise InputError(
                f"unknown mount {unknown[0] if unknown else ''!r}; mounts: {', '.join(MOUNTS)}"
            )
        if any(not 0 < size <= 999 or size == 100 for size in self.sizes):
            raise InputError(f"sizes are percentages in 1..999 other than 100, got {self.sizes}")
        unknown = [s for s in self.strategies if s not in STRATEGIES]
        if unknown or not self.strategies:
            raise InputError(
                f"unknown strategy {unknown[0] if unknown else ''!r}; "
                f"strategies: {', '.join(STRATEGIES)}"
            )
        if self.objects and (self.grasps or self.sizes):
            raise InputError(
                "a sweep over objects runs each object's own grasps at its own size; "
                "give --objects without --grasps and --sizes"
            )


def plan_trials(config: SweepConfig) -> list[TrialSpec]:
    """Every trial: per mount, hand and grasp, A, then B0.., then A at each size."""
    from graspframe.common.grasps import HumanGrasp
    from graspframe.plugin_system.registry import default_registry

    runs_dir = str(Path(config.out_dir) / "runs")
    conditions = [(CONDITION_A, (0.0, 0.0))]
    conditions += experiment_b_errors(config.rho, config.directions)
    if config.objects:
        return _object_trials(config, conditions, runs_dir)
    specs = []
    for mount, strategy in product(config.mounts, config.strategies):
        for hand in config.hands:
            for grasp in config.grasps:
                common: dict[str, Any] = dict(
                    seed=config.seed,
                    runs_dir=runs_dir,
                    arm=config.arm,
                    record=config.record,
                    mount=mount,
                    strategy=strategy,
                    camera_noise=config.camera_noise,
                    held_test=config.held_test,
                )
                for condition, error in conditions:
                    specs.append(TrialSpec(hand, grasp, condition, error, **common))
                if config.sizes:
                    default = default_registry().default_object_for(HumanGrasp.parse(grasp))
                    for size in config.sizes:
                        specs.append(
                            TrialSpec(
                                hand,
                                grasp,
                                size_condition(size),
                                (0.0, 0.0),
                                object=f"{default.name}_{size:03d}",
                                **common,
                            )
                        )
    return specs


def object_grasps(name: str) -> tuple[str, ...]:
    """The grasps a person would use on the registered object `name`
    (`ObjectDescription.documented_grasps`; UnknownNameError for an unknown name,
    listing the known ones)."""
    from graspframe.plugin_system.registry import default_registry

    return tuple(g.value for g in default_registry().get_object(name).documented_grasps())


def _object_trials(
    config: SweepConfig, conditions: list[tuple[str, tuple[float, float]]], runs_dir: str
) -> list[TrialSpec]:
    """Per mount, hand, object and its documented grasp: A, then B0.."""
    grasps = {name: object_grasps(name) for name in config.objects}
    return [
        TrialSpec(
            hand,
            grasp,
            condition,
            error,
            seed=config.seed,
            runs_dir=runs_dir,
            arm=config.arm,
            record=config.record,
            mount=mount,
            object=name,
            strategy=strategy,
            camera_noise=config.camera_noise,
            held_test=config.held_test,
        )
        for mount in config.mounts
        for strategy in config.strategies
        for hand in config.hands
        for name in config.objects
        for grasp in grasps[name]
        for condition, error in conditions
    ]


def size_condition(size: int) -> str:
    """The condition name of experiment A at `size` percent, e.g. "A075"."""
    return f"{CONDITION_A}{size:03d}"


def load_finished(path: Path) -> dict[str, TrialRow]:
    """trial_id -> row of every complete line of a trials file."""
    finished: dict[str, TrialRow] = {}
    if not path.is_file():
        return finished
    for line in path.read_text().splitlines():
        try:
            row = TrialRow.from_json(json.loads(line))
        except (json.JSONDecodeError, KeyError, TypeError, ValueError, AttributeError):
            continue  # a line cut short by a kill, or not a row: that trial runs again
        finished[row.trial_id] = row
    return finished


def _append(path: Path, row: TrialRow) -> None:
    # A kill can leave a last line without its newline: start on a fresh line then.
    cut_short = path.is_file() and path.stat().st_size > 0 and not _ends_with_newline(path)
    try:
        with path.open("a") as stream:
            stream.write(("\n" if cut_short else "") + json.dumps(row.to_json()) + "\n")
            stream.flush()
            os.fsync(stream.fileno())
    except OSError as error:
        raise OutputError(f"cannot write {path}: {os_reason(error)}") from error


def _ends_with_newline(path: Path) -> bool:
    with path.open("rb") as stream:
        stream.seek(-1, os.SEEK_END)
        return stream.read(1) == b"\n"


def _run_local(todo: list[TrialSpec], config: SweepConfig) -> Generator[TrialRow, None, None]:
    return run_in_workers(todo, config.workers, config.time_limit)


def _run_dask(todo: list[TrialSpec], config: SweepConfig) -> Generator[TrialRow, None, None]:
    try:
        import dask
        from distributed import Client, LocalCluster
        from distributed import as_completed as dask_as_completed
    except ImportError:
        raise InputError(
            'the dask executor needs Dask distributed: pip install ".[dask]" in the '
            "graspframe folder (the `dask` extra)"
        ) from None
    # Workers must be allowed to start the per-trial processes.
    with dask.config.set({"distributed.worker.daemon": False}):
        if config.scheduler:
            client, cluster = Client(config.scheduler), None
        else:
            cluster = LocalCluster(
                n_workers=config.workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
            )
            client = Client(cluster)
        try:
            futures = client.map(run_trial_isolated, todo, time_limit=config.time_limit, pure=False)
            spec_of = dict(zip(futures, todo, strict=True))
            for future in dask_as_completed(futures):
                try:
                    yield future.result()
                except Exception as exc:  # the worker itself was lost
                    yield failed_row(spec_of[future], f"{type(exc).__name__}: {exc}", None)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()


def run_sweep(
    config: SweepConfig, on_trial: Callable[[TrialRow, int, int], None] | None = None
) -> list[TrialRow]:
    """Run every trial not yet in the trials file; returns all rows in plan order.

    on_trial(row, done, total) is called after each finished trial (progress)."""
    out_dir = Path(config.out_dir)
    make_folder(out_dir, "output folder")
    trials_path = out_dir / TRIALS_FILE
    specs = plan_trials(config)
    finished = load_finished(trials_path)
    todo = [spec for spec in specs if spec.trial_id not in finished]
    done = len(specs) - len(todo)
    if not todo:
        return [finished[spec.trial_id] for spec in specs]
    runner = _run_local if config.executor == "local" else _run_dask
    # closing: an interrupted sweep stops its workers before the exception goes on.
    with closing(runner(todo, config)) as rows:
        for row in rows:
            _append(trials_path, row)
            finished[row.trial_id] = row
            done += 1
            if on_trial is not None:
                on_trial(row, done, len(specs))
    return [finished[spec.trial_id] for spec in specs if spec.trial_id in finished]
