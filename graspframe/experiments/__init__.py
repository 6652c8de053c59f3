"""The method's experiments (docs/experiments.md): sweeps of grasp runs, summaries, plots."""
