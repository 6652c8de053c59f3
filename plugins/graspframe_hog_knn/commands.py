"""`graspframe db build`: (re)build this classifier's synthetic view database.

The plugin adds the command `db` to the command line (`DB_COMMAND`, registered by
plugin.py through the `graspframe_register_commands` hook): its options and help are
here, the core knows nothing of it. `db_build_command` prints its progress and result
(rich) and returns an exit code, and raises GraspframeError subclasses (one-line
messages) for bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from graspframe.plugin_system.commands import PluginCommand

db_app = typer.Typer(help="The synthetic view database of the hog_knn classifier.")
DB_COMMAND = PluginCommand("db", db_app)


@db_app.command("build")
def db_build(
    views_per_grasp: Annotated[int, typer.Option(help="Rendered views per grasp.")] = 2000,
    size: Annotated[int, typer.Option(help="Rendered image side \\[px].")] = 128,
    workers: Annotated[int, typer.Option(help="Rendering processes.")] = 2,
    seed: Annotated[int, typer.Option(help="Seed; the same seed gives the same database.")] = 0,
    out: Annotated[
        Path | None, typer.Option(help="Output .npz (default: the shipped database).")
    ] = None,
) -> None:
    """(Re)build the synthetic view database of the hog_knn classifier."""
    raise typer.Exit(db_build_command(views_per_grasp, size, workers, seed, out))


def db_build_command(
    views_per_grasp: int = 2000,
    size: int = 128,
    workers: int = 2,
    seed: int = 0,
    out: Path | None = None,
) -> int:
    """(Re)build the synthetic view database of the hog_knn classifier.

    Options (the typer signature of `db_build` above):
      --views-per-grasp N  rendered views per grasp (default 2000; 6 grasps)
      --size PX            rendered image side [px] (default 128, >= 32)
      --workers N          rendering processes (default 2; about one per core)
      --seed S             random seed; the same seed gives the same database (default 0)
      --out PATH           output .npz (a .json with the metadata is written next to it;
                           default: the database shipped with the package)
    Shows a progress bar; prints the size, counts and build rate.
    """
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    from graspframe_hog_knn.database import build_database, shipped_database_path

    out = Path(out) if out is not None else shipped_database_path()
    console = Console()
    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TimeRemainingColumn(),
        console=console,
    ) as progress:
        task = progress.add_task("rendering views", total=views_per_grasp * 6)
        database = build_database(
            views_per_grasp,
            size,
            workers,
            seed,
            progress=lambda done, total: progress.update(task, completed=done),
        )
    npz, meta_path = database.save(out)
    meta = database.metadata
    console.print(
        f"wrote {npz} ({npz.stat().st_size / 1e6:.2f} MB) and {meta_path.name}: "
        f"{meta['views_stored']} views stored of {meta['views_rendered']} rendered, "
        f"{meta['views_per_second']} views/s"
    )
    return 0
