"""`python -m graspframe`: the same command line as `graspframe`."""

from graspframe.cli import _console_script

if __name__ == "__main__":
    _console_script()
