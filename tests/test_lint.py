"""The code base is ruff clean and formatted, and vulture finds no dead code (rules and
settings in pyproject.toml; false positives in tests/vulture_whitelist.py)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).parents[1]


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
