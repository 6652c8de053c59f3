"""Built-in graspframe plugin: records every run to a rerun file (runs/<id>/recording.rrd)."""
