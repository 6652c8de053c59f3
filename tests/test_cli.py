"""The command line: exit codes and one-line errors."""

from __future__ import annotations

import json

import pytest

from graspframe.cli import main


def test_plugins_lists_what_is_registered(capsys):
    assert main(["plugins", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {"plugin", "package", "version", "status", "provides", "error"} <= set(rows[0])


def test_unknown_command_is_a_usage_error():
    assert main(["no-such-command"]) == 2


def test_no_arguments_shows_help(capsys):
    assert main([]) != 0
    assert "Usage" in capsys.readouterr().out


@pytest.mark.parametrize("command", [["classify"], ["review"], ["db", "build"]])
def test_commands_not_built_yet_say_so_in_one_line(command, capsys):
    assert main(command) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "not available" in err


def test_run_without_a_grasp_says_what_to_pass(capsys):
    assert main(["run", "--hand", "barrett"]) == 1
    assert "pass --grasp with one of: large_diameter" in capsys.readouterr().err


def test_verbose_shows_the_traceback(capsys):
    assert main(["--verbose", "classify"]) == 1
    assert "Traceback" in capsys.readouterr().err
