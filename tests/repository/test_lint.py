"""The code base is ruff clean and formatted, vulture finds no dead code (rules and
settings in pyproject.toml; false positives in tests/vulture_whitelist.py), and no
module grows past 450 lines."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).parents[2]


def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", *args], cwd=ROOT, capture_output=True, text=True)


def test_ruff_clean():
    result = _run("ruff", "check", ".")
    assert result.returncode == 0, result.stdout + result.stderr


def test_ruff_formatted():
    result = _run("ruff", "format", "--check", ".")
    assert result.returncode == 0, result.stdout + result.stderr


def test_no_dead_code():
    # Paths, confidence and ignored names come from [tool.vulture].
    result = _run("vulture")
    assert result.returncode == 0, result.stdout + result.stderr


MAX_MODULE_LINES = 450  # a module past it holds more than one job: split it


def test_modules_are_at_most_450_lines():
    long = {
        path.relative_to(ROOT).as_posix(): len(path.read_text().splitlines())
        for folder in ("graspframe", "plugins")
        for path in (ROOT / folder).rglob("*.py")
        if len(path.read_text().splitlines()) > MAX_MODULE_LINES
    }
    assert not long, long
