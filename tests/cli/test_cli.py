"""The command line: exit codes and one-line errors."""

from __future__ import annotations

import json
import re

import pytest
import typer
import typer.main

from graspframe.cli.commands import app, main


def test_plugins_lists_what_is_registered(capsys):
    assert main(["plugins", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {"plugin", "package", "version", "status", "provides", "error"} <= set(rows[0])


def test_unknown_command_is_a_usage_error():
    assert main(["no-such-command"]) == 2


def test_no_arguments_shows_help(capsys):
    assert main([]) != 0
    assert "Usage" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (["classify", "/nonexistent.png"], "not found"),
        (["review", "/nonexistent"], "no recording at /nonexistent"),
        (["check-hand", "allegro"], "unknown hand 'allegro'; known hands: barrett"),
        (["evaluate", "--hands", "allegro"], "unknown hand 'allegro'"),
        (["evaluate", "--executor", "slurm"], "unknown executor 'slurm'; executors: local, dask"),
        (["evaluate", "--mount", "wall"], "unknown mount 'wall'; known mounts: arm, floating"),
        (["evaluate", "--sizes", "big"], "--sizes must be whole percentages"),
        (["evaluate", "--sizes", "100"], "sizes are percentages in 1..999 other than 100"),
        (
            ["evaluate", "--strategy", "servoo"],
            "unknown strategy 'servoo'; known strategies: method",
        ),
        (
            ["run", "--strategy", "servoo"],
            "unknown strategy 'servoo'; known strategies: method, servo",
        ),
        (["run", "--strategy", "servo", "--camera-noise", "-1"], "camera noise -1 is outside"),
    ],
)
def test_bad_arguments_give_one_line_and_exit_1(command, message, capsys):
    assert main(command) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) <= 2  # one message, which rich may wrap
    assert message in " ".join(err.split())


def test_check_hand_passes_on_a_builtin_hand(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # its pictures go to runs/check-hand/barrett
    assert main(["check-hand", "barrett"]) == 0
    out = capsys.readouterr().out
    assert "hand barrett: 5 of 5 checks ran, all passed" in out and "3 of 3 held" in out
    assert "3. mounted on kuka: no hand link inside an arm link" in out
    assert "5. the hand alone holds experiment A's object for every human grasp" in out
    assert "6 of 6 held" in out
    # One picture per preshape closed without physics, one per hold trial (3 on the
    # design objects, 6 on experiment A's).
    assert len(list((tmp_path / "runs" / "check-hand" / "barrett").glob("*.png"))) == 12


def test_run_refuses_a_grasp_and_an_image_together(capsys, tmp_path):
    args = ["run", "--grasp", "pinch", "--image", "x.png", "--out", str(tmp_path)]
    assert main(args) == 1
    assert "either --grasp (no vision) or --image" in capsys.readouterr().err


def test_verbose_shows_the_traceback(capsys):
    assert main(["--verbose", "classify", "/nonexistent.png"]) == 1
    assert "Traceback" in capsys.readouterr().err


def _commands(group, path: tuple[str, ...] = ()):
    """(command words, command) of every command of the app, subcommands included (and
    those the plugins add)."""
    context = typer.Context(group)
    for name in group.list_commands(context):
        command = group.get_command(context, name)
        if hasattr(command, "commands"):
            yield from _commands(command, (*path, name))
        else:
            yield (*path, name), command


COMMANDS = list(_commands(typer.main.get_command(app)))


@pytest.mark.parametrize(("words", "command"), COMMANDS, ids=[" ".join(w) for w, _ in COMMANDS])
def test_help_shows_every_option_help_whole_with_its_units(words, command, capsys, monkeypatch):
    """rich reads a bare `[mm]` as markup and drops it ("error of experiment B ."): each
    option's help must come out of `--help` as written, its units in brackets kept."""
    monkeypatch.setenv("COLUMNS", "1000")  # one line per option: nothing wrapped
    assert main([*words, "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    for param in command.params:
        if getattr(param, "help", None):
            written = " ".join(param.help.replace("\\[", "[").split())
            assert written in out, f"{param.name}: {written!r} not in the help"


def test_the_units_in_brackets_are_those_of_the_options():
    """What the test above checks: the options with a unit write it in their help."""
    units = {
        (" ".join(words), param.name): re.findall(r"\\\[([^\]]+)\]", param.help or "")
        for words, command in COMMANDS
        for param in command.params
    }
    assert units[("run", "object_error_mm")] == ["mm"]
    assert units[("run", "lift_height_mm")] == ["mm"]
    assert units[("evaluate", "rho_mm")] == ["mm"]
    assert units[("evaluate", "time_limit")] == ["s"]
    assert units[("evaluate", "sizes")] == ["%"]
    assert units[("db build", "size")] == ["px"]
    # An option named after its unit says it in its help.
    for (words, name), found in units.items():
        for suffix, unit in (("_mm", "mm"), ("_deg", "deg"), ("_px", "px"), ("_s", "s")):
            if name.endswith(suffix):
                assert unit in found, f"{words} --{name.replace('_', '-')} has no [{unit}]"


def test_db_build_needs_the_hog_knn_plugin(tmp_path):
    """The database and its command belong to the hog_knn plugin: without it, one line
    naming the plugin that is not loaded, before anything is built."""
    import os
    import subprocess
    import sys

    environment = {**os.environ, "GRASPFRAME_DISABLE_PLUGINS": "hog_knn"}
    out = tmp_path / "views.npz"
    done = subprocess.run(
        [sys.executable, "-m", "graspframe.cli.commands", "db", "build", "--out", str(out)],
        capture_output=True,
        text=True,
        env=environment,
        timeout=120,
    )
    assert done.returncode == 1
    message = " ".join(done.stderr.split())
    assert (
        "unknown command 'db'; it may come from a plugin that is not loaded: "
        "hog_knn (disabled by GRASPFRAME_DISABLE_PLUGINS)"
    ) in message
    assert not out.exists()
