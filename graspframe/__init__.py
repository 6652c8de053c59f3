"""graspframe: map one image of a human grasp onto a robot hand on an arm, and score it.

One package per floor of docs/architecture.md, lowest first: `common`, `model_files`,
`hal`, `robot_models`, `plugin_system` and `specs`, `motion` and `metrics`, `pictures`,
`vision` and `perception`, `strategy`, `checks`, `run` and `experiments`, `cli`;
`testing` is for plugin authors' tests.
"""

from importlib.metadata import PackageNotFoundError, version

from graspframe.common import moved_modules

try:
    __version__ = version("graspframe")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

moved_modules.install()

__all__ = ["__version__"]
