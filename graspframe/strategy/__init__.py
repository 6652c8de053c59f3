"""The method's grasp strategy (docs/method.md, 3-4): plan, execute, human references."""
