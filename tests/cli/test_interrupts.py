"""Ctrl-C and SIGTERM stop a command cleanly; exit codes say how a command ended.

Each interruption test starts the real command in its own process, waits until it is
in the middle of its work, sends the signal, and checks what is left: the exit code 130
and the one line "interrupted", no worker process left behind, result.json marked
"interrupted", a readable recording, and (for a sweep) a clean resume.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from rerun.chunk import RrdReader

from graspframe.cli.commands import EXIT_INTERRUPTED, EXIT_NOT_HELD, main
from graspframe.common.errors import NoContactsError
from graspframe.run import scoring

HANG_GUARD = 120.0  # [s] a command still running this long after the signal has hung
START_GUARD = 300.0  # [s] for a command to reach the moment the test interrupts


class _Command:
    """`graspframe ARGS` in a process of its own, its stderr read line by line as it
    comes; with `ignore_sigint` started as a shell starts a background job, with SIGINT
    ignored."""

    def __init__(self, args: list[str], ignore_sigint: bool = False) -> None:
        def ignore() -> None:
            signal.signal(signal.SIGINT, signal.SIG_IGN)

        self.process = subprocess.Popen(
            [sys.executable, "-m", "graspframe.cli.commands", *args],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=ignore if ignore_sigint else None,
        )
        self.stderr_lines: list[str] = []
        self._reader = threading.Thread(target=self._read_stderr, daemon=True)
        self._reader.start()

    def _read_stderr(self) -> None:
        assert self.process.stderr is not None
        for line in self.process.stderr:
            self.stderr_lines.append(line)

    @property
    def stderr(self) -> str:
        return "".join(self.stderr_lines)

    def wait_for(self, condition: Callable[[], bool]) -> None:
        started = time.monotonic()
        while not condition():
            assert self.process.poll() is None, f"ended before it was interrupted: {self.stderr}"
            assert time.monotonic() - started < START_GUARD, "never reached the moment"
            time.sleep(0.1)

    def interrupt(self, signum: int) -> tuple[int, str, list[int]]:
        """Send `signum`; (exit code, stderr, the children it had that are still alive
        a few seconds after it ended)."""
        children = _children(self.process.pid)
        self.process.send_signal(signum)
        self.process.wait(timeout=HANG_GUARD)
        self._reader.join(timeout=HANG_GUARD)
        deadline = time.monotonic() + 5.0
        alive = children
        while alive and time.monotonic() < deadline:
            alive = [child for child in alive if Path(f"/proc/{child}").exists()]
            time.sleep(0.1)
        return self.process.returncode, self.stderr, alive


def _children(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(child) for child in path.read_text().split()] if path.exists() else []


def _running_run(out: Path) -> Path | None:
    """The run folder once its result.json (written first, "running") is there."""
    return next((path.parent for path in out.glob("*/result.json")), None)


@pytest.mark.parametrize(
    ("signum", "ignore_sigint"),
    [(signal.SIGINT, False), (signal.SIGTERM, False), (signal.SIGINT, True)],
    ids=["ctrl-c", "sigterm", "ctrl-c-in-a-background-job"],
)
def test_an_interrupted_run_stops_and_says_so(tmp_path, signum, ignore_sigint):
    out = tmp_path / "runs"
    command = _Command(
        ["run", "--hand", "barrett", "--grasp", "pinch", "--out", str(out)], ignore_sigint
    )
    # In the middle of the grasp's physics (seconds long), not as the run ends.
    command.wait_for(lambda: "· executing" in command.stderr)
    time.sleep(0.5)
    code, stderr, alive = command.interrupt(signum)

    assert code == EXIT_INTERRUPTED, stderr
    assert stderr.strip().splitlines()[-1] == "interrupted", stderr
    assert "Traceback" not in stderr
    assert not alive
    run_dir = _running_run(out)
    result = json.loads((run_dir / "result.json").read_text())
    assert result["status"] == "interrupted", (result["status"], result.get("error"), stderr)
    assert signal.Signals(signum).name in result["error"]
    # The recording so far is written, readable, and ends with how the run ended.
    chunks = list(RrdReader(run_dir / "recording.rrd").stream())
    log = [
        text
        for chunk in chunks
        if chunk.entity_path == "/log"
        for row in chunk.to_record_batch().column("TextLog:text").to_pylist()
        for text in row
    ]
    assert log[-1].startswith("run interrupted"), log[-3:]


def test_an_interrupted_sweep_stops_its_workers_and_resumes(tmp_path):
    out = tmp_path / "sweep"
    args = [
        "evaluate", "--hands", "barrett", "--grasps", "pinch,large_diameter,power_sphere",
        "--directions", "0", "--sizes", "75", "--mount", "floating", "--workers", "2",
        "--out", str(out),
    ]  # fmt: skip
    trials = out / "trials.jsonl"
    command = _Command(args)
    command.wait_for(lambda: trials.exists() and trials.read_text().count("\n") >= 1)
    code, stderr, alive = command.interrupt(signal.SIGINT)

    assert code == EXIT_INTERRUPTED
    assert stderr.strip().splitlines()[-1] == "interrupted"
    assert not alive, "worker processes were left running"
    before = trials.read_text().splitlines()
    assert main(args) == 0  # resumed: only the trials without a row run
    after = trials.read_text().splitlines()
    assert 1 <= len(before) < len(after)
    assert after[: len(before)] == before
    trial_ids = [json.loads(row)["trial_id"] for row in after]
    assert len(set(trial_ids)) == len(trial_ids), "a trial ran twice"
    grasps = {json.loads(row)["grasp"] for row in after}
    assert grasps == {"pinch", "large_diameter", "power_sphere"}


def test_an_interrupted_database_build_stops_its_workers_and_writes_nothing(tmp_path):
    out = tmp_path / "db" / "views.npz"
    args = ["db", "build", "--views-per-grasp", "200", "--workers", "2", "--out", str(out)]
    command = _Command(args)
    command.wait_for(lambda: len(_children(command.process.pid)) >= 2)
    time.sleep(3.0)  # rendering
    code, stderr, alive = command.interrupt(signal.SIGINT)

    assert code == EXIT_INTERRUPTED
    assert stderr.strip().splitlines()[-1] == "interrupted"
    assert not alive, "rendering processes were left running"
    assert not out.exists() and not out.with_suffix(".json").exists()


def test_an_interrupted_hand_check_stops(tmp_path):
    pictures = tmp_path / "pictures"
    command = _Command(["check-hand", "barrett", "--pictures", str(pictures)])
    command.wait_for(lambda: any(pictures.glob("*.png")))  # the preshapes drawn
    time.sleep(2.0)  # into the hold trials
    code, stderr, _ = command.interrupt(signal.SIGTERM)

    assert code == EXIT_INTERRUPTED
    assert stderr.strip().splitlines()[-1] == "interrupted"
    assert "Traceback" not in stderr


def test_a_run_whose_grasp_is_not_held_exits_3(tmp_path, capsys):
    """The 19 mm handle on the arm: it sits loose under the Barrett's crossing fingers."""
    args = ["run", "--hand", "barrett", "--grasp", "small_diameter", "--object", "handle_075"]
    code = main([*args, "--no-record", "--out", str(tmp_path)])
    assert code == EXIT_NOT_HELD
    assert "grasp failed: the object slipped during the lift" in capsys.readouterr().out


def test_a_grasp_the_fingers_cannot_reach_is_refused_with_exit_1(tmp_path, capsys):
    """The 19 mm disc on the table: kept off the table, the Barrett's fingers miss it."""
    args = ["run", "--hand", "barrett", "--grasp", "precision_disc", "--object", "disc_075"]
    code = main([*args, "--mount", "floating", "--no-record", "--out", str(tmp_path)])
    assert code == 1
    err = " ".join(capsys.readouterr().err.split())
    assert "keeping the barrett hand 10 mm above the table raises it 59 mm" in err
    assert "where only finger_3 reaches the 19 mm tall disc_075" in err


def test_interrupts_are_handled_only_while_a_command_runs():
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    assert main(["plugins"]) == 0
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before


def test_a_side_without_contacts_is_named_when_virtual_fingers_are_not_scored():
    with pytest.raises(NoContactsError, match=r"^the human reference: no contacts"):
        scoring._virtual_fingers("the human reference", ())
