"""The bodies of the `graspframe` commands, one module each; graspframe/cli.py holds the
typer app, every command's options and help, and the small commands.

`vision` (classify), `evaluate` (options -> sweep, the sweep with its
progress and tables), `review` (a recorded run in a plugin's viewer), `run_summary`
(what `run` prints at the end), `plugin_commands` (the commands plugins add, such as
hog_knn's `db build`).
"""
