"""The `graspframe` command line. `commands` holds the typer app, every built-in command's
options and help, and the small commands; the bodies of the larger commands are one module
each: `check_hand`, `evaluate` (options -> sweep, with its progress and tables), `listing`
(`plugins` and `objects`), `review` (a recorded run in a plugin's viewer), `run_summary`
(what `run` prints at the end), `vision` (classify) and `plugin_commands` (the commands
plugins add, such as hog_knn's `db build`). `interrupts` handles Ctrl-C and SIGTERM."""

from graspframe.common.moved_modules import forward_old_names


def _console_script() -> None:
    """The `graspframe` console script (pyproject.toml's [project.scripts]): the typer
    app of `commands`, imported only when the command runs."""
    from graspframe.cli.commands import _console_script as run_command_line

    run_command_line()


# `graspframe.cli` was one module (now `graspframe.cli.commands`): its names still import
# from here, with a DeprecationWarning.
__getattr__ = forward_old_names(__name__, "graspframe.cli.commands")
