"""A run whose files cannot be written (a file where its folder goes, no space left) ends
with one line naming the path and the cause and exit code 1: no traceback, no rerun
noise, and no result.json that claims success."""

from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from graspframe.cli.commands import main

RUN = ["run", "--hand", "barrett", "--grasp", "pinch"]
GRASPFRAME = [
    sys.executable,
    "-m",
    "graspframe.cli.commands",
]  # the command, in a process of its own


@pytest.fixture(autouse=True)
def cache(tmp_path: Path, monkeypatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(folder))
    return folder


def _messages(stderr: str) -> list[str]:
    """stderr without the run's progress lines ("· planning ...")."""
    return [line for line in stderr.splitlines() if line.strip() and not line.startswith("·")]


def _no_space_from_call(monkeypatch, first_failing: int) -> None:
    """Every file write from the `first_failing`-th on (1: the first) fails as on a full
    disk: at the fsync, where a full disk shows at the latest."""
    real_fsync = os.fsync
    calls = []

    def fsync(fd: int) -> None:
        calls.append(fd)
        if len(calls) >= first_failing:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", fsync)


def test_an_out_folder_under_a_file_is_one_line(tmp_path: Path, capsys):
    a_file = tmp_path / "notes.txt"
    a_file.write_text("not a folder")
    assert main([*RUN, "--no-record", "--out", str(a_file / "runs")]) == 1
    (message,) = _messages(capsys.readouterr().err)
    assert message.startswith(f"error: cannot create run folder {a_file}/runs/")
    assert message.endswith("-barrett-pinch: Not a directory")
    assert a_file.read_text() == "not a folder"


@pytest.mark.parametrize(
    ("command", "what"),
    [
        (["evaluate", "--hands", "barrett", "--grasps", "pinch", "--directions", "0"], "output"),
        (["check-hand", "barrett", "--no-hold"], "pictures"),
    ],
)
def test_other_commands_say_so_of_their_folders_too(command, what, tmp_path: Path, capsys):
    a_file = tmp_path / "notes.txt"
    a_file.write_text("not a folder")
    option = "--out" if command[0] == "evaluate" else "--pictures"
    assert main([*command, option, str(a_file / "here")]) == 1
    err = capsys.readouterr().err  # evaluate's progress bar comes first
    assert err.strip().splitlines()[-1] == (
        f"error: cannot create {what} folder {a_file}/here: Not a directory"
    )
    assert "Traceback" not in err and err.count("error") == 1


def test_no_space_for_the_first_result_json(tmp_path: Path, capsys, monkeypatch):
    _no_space_from_call(monkeypatch, 1)
    assert main([*RUN, "--no-record", "--out", str(tmp_path / "runs")]) == 1
    (run_dir,) = (tmp_path / "runs").iterdir()
    (message,) = _messages(capsys.readouterr().err)
    assert message == f"error: cannot write {run_dir}/result.json: No space left on device"
    assert list(run_dir.iterdir()) == []  # no temporary file left


@pytest.mark.slow
def test_no_space_midway_leaves_the_result_running(tmp_path: Path, capsys, monkeypatch):
    """The disk fills after result.json was first written: the first file that fails is
    named, and result.json keeps saying "running" (it cannot be rewritten either)."""
    _no_space_from_call(monkeypatch, 2)
    assert main([*RUN, "--no-record", "--out", str(tmp_path / "runs")]) == 1
    (run_dir,) = (tmp_path / "runs").iterdir()
    (message,) = _messages(capsys.readouterr().err)
    assert message == f"error: cannot write {run_dir}/snapshots.png: No space left on device"
    assert json.loads((run_dir / "result.json").read_text())["status"] == "running"
    assert [p.name for p in run_dir.iterdir()] == ["result.json"]


def _on_a_small_file_system(tmp_path: Path, size_kb: int, args: list[str]):
    """Run graspframe with `--out` on a tmpfs of `size_kb` mounted in a mount namespace of
    its own; (the completed process, a copy of what it left there). Skips where the
    platform cannot mount one."""
    if shutil.which("unshare") is None:
        pytest.skip("no unshare here to mount a small file system")
    mount_point, copy = tmp_path / "small", tmp_path / "left_on_small"
    mount_point.mkdir()
    script = (
        'mount -t tmpfs -o size="$1"k tmpfs "$2" || exit 97; shift 2; '
        '"$@"; status=$?; cp -a "$MOUNT/." "$COPY"; exit $status'
    )
    command = ["unshare", "--mount", "--map-root-user", "sh", "-c", script, "sh"]
    command += [str(size_kb), str(mount_point), *GRASPFRAME, *args]
    command += ["--out", str(mount_point / "runs")]
    env = dict(os.environ, MOUNT=str(mount_point), COPY=str(copy))
    copy.mkdir()
    completed = subprocess.run(command, capture_output=True, text=True, env=env, timeout=600)
    if completed.returncode == 97 or "unshare:" in completed.stderr:
        pytest.skip(f"cannot mount a small file system here: {completed.stderr.strip()}")
    return completed, copy


@pytest.mark.slow
def test_a_full_file_system_under_the_recording_is_one_line(tmp_path: Path):
    """A real full file system: room for everything of the run but its recording."""
    args = [*RUN, "--record"]
    normal = subprocess.run(
        [*GRASPFRAME, *args, "--out", str(tmp_path / "normal")],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "error" not in normal.stderr
    (normal_run,) = (tmp_path / "normal").iterdir()
    sizes = {p.name: p.stat().st_size for p in normal_run.iterdir()}
    others_kb = sum(size for name, size in sizes.items() if name != "recording.rrd") // 1024
    room_kb = 64  # left for the recording: far too little
    assert sizes["recording.rrd"] // 1024 > 4 * room_kb

    completed, left = _on_a_small_file_system(tmp_path, others_kb + room_kb, args)
    assert completed.returncode == 1, completed.stderr
    (message,) = _messages(completed.stderr)  # no traceback, no log line of rerun's
    assert message.startswith(f"error: cannot write {tmp_path / 'small' / 'runs'}/")
    assert message.endswith("/recording.rrd: No space left on device")
    (run_dir,) = (left / "runs").iterdir()
    assert sorted(p.name for p in run_dir.iterdir()) == [
        "human_reference.png",
        "result.json",
        "snapshots.png",
    ]  # no half recording, no temporary file
    result = json.loads((run_dir / "result.json").read_text())
    assert result["status"] == "failed"
    assert result["error"].startswith("OutputError: cannot write ")
    assert result["error"].endswith("recording.rrd: No space left on device")
    assert "recording" not in result
