"""A command a plugin adds to the `graspframe` command line."""

from __future__ import annotations

from dataclasses import dataclass

import typer


@dataclass(frozen=True)
class PluginCommand:
    """`graspframe NAME ...`: a typer app a plugin adds to the command line, with its own
    commands, options and help (e.g. the hog_knn plugin's `db`, whose command `build`
    builds its view database).

    name: the command word, none of the built-in commands; app: the typer app, whose
    help is the line `graspframe --help` shows for it. Its commands print their results
    and end with `raise typer.Exit(code)`; a GraspframeError they raise is printed as one
    line with exit code 1, like a built-in command's.
    """

    name: str
    app: typer.Typer
