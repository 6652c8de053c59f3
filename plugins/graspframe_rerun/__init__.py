"""Built-in graspframe plugin: records every run to a rerun file (runs/<id>/recording.rrd)
and shows it in the rerun viewer (`graspframe review`).

Only recording.py imports rerun, when a run asks to be recorded: loading the plugin does
not."""

RECORDING_SUFFIX = ".rrd"
RECORDING_FILE = f"recording{RECORDING_SUFFIX}"  # in the run folder
