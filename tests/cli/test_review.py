"""`graspframe review`: the core asks the registered viewers; the rerun plugin's opens a
run folder's recording.rrd in the rerun viewer."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import ClassVar

import pytest
from graspframe_rerun.viewer import DISPLAY_VARIABLES, RerunViewer

from graspframe.cli.commands import main
from graspframe.cli.review import review_command
from graspframe.common.errors import InputError, NotAvailableError
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.registry import Registry, default_registry
from graspframe.plugin_system.viewer import Viewer


@pytest.fixture
def run_dir(tmp_path) -> Path:
    run = tmp_path / "20260101T000000-barrett-pinch"
    run.mkdir()
    (run / "result.json").write_text("{}")
    (run / "recording.rrd").write_bytes(b"")
    return run


@pytest.fixture
def display(monkeypatch) -> None:
    """A display for the native viewer, as on a desktop (this machine may have none)."""
    for name in DISPLAY_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("DISPLAY", ":0")


@pytest.fixture
def no_display(monkeypatch) -> None:
    for name in DISPLAY_VARIABLES:
        monkeypatch.delenv(name, raising=False)


@pytest.fixture
def viewer_calls(monkeypatch, display) -> list[list[str]]:
    """The viewer program's command lines, instead of opening a window."""
    calls: list[list[str]] = []
    monkeypatch.setattr("shutil.which", lambda name: f"/opt/bin/{name}")
    monkeypatch.setattr("subprocess.call", lambda command: calls.append(command) or 3)
    return calls


def test_the_rerun_plugin_offers_its_viewer():
    assert default_registry().entry("viewer", "rerun").item is RerunViewer


@pytest.mark.parametrize("given", ["folder", "file"])
def test_a_run_folder_or_its_recording_opens_in_the_rerun_viewer(given, run_dir, viewer_calls):
    path = run_dir if given == "folder" else run_dir / "recording.rrd"
    assert review_command(path) == 3  # the viewer's exit code
    assert viewer_calls == [["/opt/bin/rerun", str(run_dir / "recording.rrd")]]


def test_review_exits_with_the_viewer_exit_code(run_dir, viewer_calls):
    assert main(["review", str(run_dir)]) == 3


def test_a_folder_without_a_recording_is_one_line(run_dir, capsys):
    (run_dir / "recording.rrd").unlink()
    assert main(["review", str(run_dir)]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert f"no recording at {run_dir}; the rerun viewer opens a run folder's recording.rrd" in err
    with pytest.raises(InputError, match="no recording at"):
        review_command(run_dir / "result.json")  # not a recording


def test_a_missing_viewer_program_is_one_line(run_dir, monkeypatch, tmp_path, capsys, display):
    monkeypatch.setattr("shutil.which", lambda name: None)
    monkeypatch.setattr("sys.executable", str(tmp_path / "bin" / "python"))
    assert main(["review", str(run_dir)]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) <= 2
    assert "the rerun viewer is not installed (it ships with rerun-sdk)" in " ".join(err.split())


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the display variables of Linux")
@pytest.mark.parametrize("variable", DISPLAY_VARIABLES)
def test_any_display_variable_lets_the_native_viewer_open(
    variable, run_dir, viewer_calls, monkeypatch
):
    monkeypatch.delenv("DISPLAY")
    monkeypatch.setenv(variable, "wayland-0" if variable.startswith("WAYLAND") else ":1")
    assert review_command(run_dir) == 3
    assert len(viewer_calls) == 1


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the display variables of Linux")
def test_without_a_display_review_says_how_to_view_the_recording(
    run_dir, monkeypatch, capsys, no_display
):
    """No window is tried (rerun's own error would be a raw winit EventLoopError): one
    line saying how to view the recording elsewhere, and exit 1."""
    calls: list[list[str]] = []
    monkeypatch.setattr("shutil.which", lambda name: f"/opt/bin/{name}")
    monkeypatch.setattr("subprocess.call", lambda command: calls.append(command) or 0)
    assert main(["review", str(run_dir)]) == 1
    assert calls == []
    err = capsys.readouterr().err.strip()
    recording = run_dir / "recording.rrd"
    assert len(err.splitlines()) <= 3  # one message, which rich may wrap
    assert " ".join(err.split()) == (
        "error: no display for the rerun viewer (DISPLAY, WAYLAND_DISPLAY, WAYLAND_SOCKET "
        f"unset): view the recording in a browser with `rerun --web-viewer {recording}`, or "
        f"copy {recording} to a machine with a display and run `rerun recording.rrd` there"
    )


def test_without_a_viewer_no_plugin_can_show_the_run(run_dir):
    with pytest.raises(NotAvailableError, match="no plugin can show a run"):
        review_command(run_dir, Registry(strict=True))


class _McapViewer(Viewer):
    """A third-party viewer of run.mcap files."""

    name: ClassVar[str] = "mcap"
    shows: ClassVar[str] = "a run folder's run.mcap"
    opened: ClassVar[list[Path]] = []

    def find(self, path: Path) -> Path | None:
        recording = path / "run.mcap"
        return recording if recording.is_file() else None

    def show(self, recording: Path) -> int:
        self.opened.append(recording)
        return 0


class _McapPlugin:
    @hookimpl
    def graspframe_register_viewers(self, register):
        register(_McapViewer)


def test_any_plugin_may_offer_a_viewer(tmp_path):
    registry = Registry(strict=True)
    registry.add_plugin("mcap", _McapPlugin())
    assert registry.names("viewer") == ["mcap"]
    (tmp_path / "run.mcap").write_bytes(b"")
    assert review_command(tmp_path, registry) == 0
    assert _McapViewer.opened == [tmp_path / "run.mcap"]
    with pytest.raises(InputError, match=r"the mcap viewer opens a run folder's run\.mcap"):
        review_command(tmp_path / "elsewhere", registry)
