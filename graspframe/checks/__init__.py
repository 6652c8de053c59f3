"""`graspframe check-hand` and the checks it runs: the description and its model
(`contracts`), the open and closed preshapes without self-collision (`self_collision`),
grasps held by the hand alone (`grasps`), and the report (`hand`). `graspframe.testing`
turns the same checks into assertions for plugin authors' tests."""

from graspframe.common.moved_modules import forward_old_names

# `graspframe.checks` was one module (now `graspframe.checks.hand`): its names still
# import from here, with a DeprecationWarning.
__getattr__ = forward_old_names(__name__, "graspframe.checks.hand")
