"""The method's experiments (METHOD.md section 6): sweeps of grasp runs, summaries, plots."""
