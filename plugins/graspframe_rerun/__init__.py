"""Built-in graspframe plugin: records every run to a rerun file (runs/<id>/recording.rrd)
and shows it in the rerun viewer (`graspframe review`)."""
