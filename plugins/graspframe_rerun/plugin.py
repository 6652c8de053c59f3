"""The rerun recorder as an observer: one recording per run that asks for it; and its
viewer, for `graspframe review`."""

from __future__ import annotations

from typing import TYPE_CHECKING

from graspframe.plugin_system import hookimpl
from graspframe_rerun.viewer import RerunViewer

if TYPE_CHECKING:
    from graspframe_rerun.recording import RunRecording

_recordings: dict[str, RunRecording] = {}


@hookimpl
def graspframe_register_viewers(register):
    register(RerunViewer)


@hookimpl
def graspframe_run_started(run):
    if run.params.get("record", False):
        # rerun (0.4 s to import) loads with the first run that is recorded.
        from graspframe_rerun.recording import RunRecording

        _recordings[run.run_id] = RunRecording(run)


@hookimpl
def graspframe_run_event(run, event):
    recording = _recordings.get(run.run_id)
    if recording is not None:
        recording.handle(event.kind, event.sim_time, event.data)


@hookimpl
def graspframe_run_finished(run, result):
    recording = _recordings.pop(run.run_id, None)
    if recording is None:
        return None
    recording.finish(result.status, result.error, result.score)
    return {"recording": str(recording.path)}
