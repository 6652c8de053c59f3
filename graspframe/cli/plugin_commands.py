"""The commands plugins add to `graspframe` (graspframe.hal.PluginCommand): the core's
command line knows none of them by name.

`WithPluginCommands` is the command group of the app: a built-in command is found
without asking the registry; any other command word, and the full list `--help` shows,
is looked up among the commands of the loaded plugins. A word no loaded plugin offers
while some plugin is not loaded (disabled or failed) is answered with one line naming
those plugins: their commands are what is missing.
"""

from __future__ import annotations

import functools

import typer.main
from typer import _click as click  # typer vendors click: the types of its command groups
from typer.core import TyperGroup

from graspframe.common.errors import NotAvailableError


@functools.cache
def plugin_commands() -> dict[str, click.Command]:
    """The click command of each command the loaded plugins add, by its word."""
    from graspframe.plugin_system.registry import default_registry

    commands: dict[str, click.Command] = {}
    for entry in default_registry().entries("command"):
        command = typer.main.get_group(entry.item.app)
        command.name = entry.item.name
        commands[entry.item.name] = command
    return commands


def _missing_command(name: str) -> NotAvailableError | None:
    """The error for a command word nothing offers when plugins are not loaded, else None
    (the word is then simply not a command: a usage error)."""
    from graspframe.plugin_system.registry import default_registry

    absent = [p for p in default_registry().plugins if p.status != "loaded"]
    if not absent:
        return None
    plugins = ", ".join(f"{p.name} ({p.error})" for p in absent)
    return NotAvailableError(
        f"unknown command {name!r}; it may come from a plugin that is not loaded: {plugins}"
    )


class WithPluginCommands(TyperGroup):
    """The built-in commands, then those the loaded plugins add."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        built_in = super().list_commands(ctx)
        return [*built_in, *(name for name in plugin_commands() if name not in built_in)]

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        command = super().get_command(ctx, cmd_name)
        if command is not None:
            return command
        command = plugin_commands().get(cmd_name)
        if command is None and not ctx.resilient_parsing and not cmd_name.startswith("-"):
            missing = _missing_command(cmd_name)
            if missing is not None:
                raise missing
        return command
