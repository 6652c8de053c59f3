"""graspframe: map one image of a human grasp onto a robot hand on an arm, and score it."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("graspframe")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

__all__ = ["__version__"]
