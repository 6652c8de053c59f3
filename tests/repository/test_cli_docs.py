"""Every command shown in docs/cli.md runs, with the documented arguments."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

import pytest

from graspframe.cli.commands import EXIT_NOT_HELD, EXIT_OK, main

ROOT = Path(__file__).parents[2]
COMMANDS = [
    shlex.split(line.strip())
    for line in (ROOT / "docs" / "cli.md").read_text().splitlines()
    if line.startswith("    graspframe ")
]


def test_the_page_shows_every_command():
    shown = {args[1] for args in COMMANDS}
    shown_expected = {"run", "classify", "evaluate", "plugins", "objects", "check-hand", "review"}
    shown_expected |= {"spec"}
    assert shown == {*shown_expected, "db"}


# Run, with more to check, by tests/cli/test_cli.py::test_check_hand_passes_on_a_builtin_hand.
RUN_ELSEWHERE = [["graspframe", "check-hand", "barrett"]]
RUN_HERE = [args for args in COMMANDS if args not in RUN_ELSEWHERE]


@pytest.mark.slow
@pytest.mark.parametrize("args", RUN_HERE, ids=[" ".join(a[1:3]) for a in RUN_HERE])
def test_documented_command_runs(args, tmp_path, monkeypatch, request):
    monkeypatch.chdir(tmp_path)  # runs/ and other outputs land here
    (tmp_path / "graspframe").symlink_to(ROOT / "graspframe")  # the documented demo paths
    (tmp_path / "docs").symlink_to(ROOT / "docs")  # the worked specs
    command = " ".join(args)
    if "leap_hand.toml" in command:
        request.getfixturevalue("leap_hand_dir")  # the vendor files, or skip
    if "panda.toml" in command:
        request.getfixturevalue("panda_description_dir")
    if "kinova_jaco2.toml" in command:
        request.getfixturevalue("kinova_description_dir")
    if args[1] == "review":
        assert main(["run", "--hand", "barrett", "--grasp", "pinch", "--out", "runs"]) == 0
        (run_dir,) = (tmp_path / "runs").iterdir()
        args = [a.replace("runs/<run>", str(run_dir)) for a in args]
        # The viewer is interactive: check the recording is found, not the window (on
        # a display this machine may not have).
        monkeypatch.setenv("DISPLAY", ":0")
        monkeypatch.setattr("subprocess.call", lambda command: 0)
    code = main(args[1:])
    if args[1] == "run":  # ran to the end; the exit code says whether the grasp held
        (result_path,) = (tmp_path / "runs").glob("*/result.json")
        result = json.loads(result_path.read_text())
        assert result["status"] == "ok"
        assert code == (EXIT_OK if result["outcome"]["success"] else EXIT_NOT_HELD)
    else:
        assert code == EXIT_OK
