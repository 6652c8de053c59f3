"""Shared fixtures."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import pytest

from graspframe.hal import HandDescription

from fakes import FAKE_HAND_URDF, make_fake_hand


@pytest.fixture
def fake_hand_urdf(tmp_path: Path) -> Path:
    path = tmp_path / "fake_hand.urdf"
    path.write_text(FAKE_HAND_URDF)
    return path


@pytest.fixture
def fake_hand(fake_hand_urdf: Path) -> HandDescription:
    return make_fake_hand(fake_hand_urdf)


# Real vendor models and scans, read where they lie (never copied into the project):
# GRASPFRAME_TEST_THIRD_PARTY, else the shared folder beside the repository (as CI has
# it), else /work/shared. The tests that need them skip when none is there.
def _third_party() -> Path:
    candidates = [
        Path(__file__).resolve().parents[2] / "shared" / "third_party",
        Path("/work/shared/third_party"),
    ]
    if os.environ.get("GRASPFRAME_TEST_THIRD_PARTY"):
        candidates.insert(0, Path(os.environ["GRASPFRAME_TEST_THIRD_PARTY"]))
    return next((c for c in candidates if c.is_dir()), candidates[0])


THIRD_PARTY = _third_party()
LEAP_HAND_SPEC = Path(__file__).resolve().parents[1] / "docs/examples/hands/leap_hand.toml"
PANDA_SPEC = Path(__file__).resolve().parents[1] / "docs/examples/arms/panda.toml"
JACO2_SPEC = Path(__file__).resolve().parents[1] / "docs/examples/arms/kinova_jaco2.toml"


# Set by .ci/run where the vendor files are present: a test that would skip for want of
# them fails instead, so that no vendor test passes in CI by skipping.
REQUIRE_THIRD_PARTY_ENV = "GRASPFRAME_REQUIRE_THIRD_PARTY"
THIRD_PARTY_SKIPS = ("third-party", "YCB scans")  # words of every such skip's reason


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if report.skipped and os.environ.get(REQUIRE_THIRD_PARTY_ENV) == "1":
        reason = str(report.longrepr[-1]) if isinstance(report.longrepr, tuple) else ""
        if any(words in reason for words in THIRD_PARTY_SKIPS):
            report.outcome = "failed"
            report.longrepr = f"{REQUIRE_THIRD_PARTY_ENV}=1, but the test skipped: {reason}"


def _vendor_dir(*parts: str) -> Path:
    if not THIRD_PARTY.joinpath(*parts).is_dir():
        pytest.skip("the third-party vendor models are not on this machine")
    return THIRD_PARTY.joinpath(*parts)


@pytest.fixture
def leap_hand_dir(monkeypatch) -> Path:
    """The vendor's LEAP hand folder, named by LEAP_HAND_DIR as the spec expects."""
    folder = _vendor_dir("hands", "leap_hand")
    monkeypatch.setenv("LEAP_HAND_DIR", str(folder))
    return folder


@pytest.fixture
def panda_description_dir(monkeypatch) -> Path:
    """The vendor's Panda description folder, named by PANDA_DESCRIPTION_DIR."""
    folder = _vendor_dir("arms", "panda", "example-robot-data", "robots", "panda_description")
    monkeypatch.setenv("PANDA_DESCRIPTION_DIR", str(folder))
    return folder


@pytest.fixture
def kinova_description_dir(monkeypatch) -> Path:
    """The vendor's Kinova description folder, named by KINOVA_DESCRIPTION_DIR."""
    folder = _vendor_dir(
        "arms", "kinova_jaco2", "example-robot-data", "robots", "kinova_description"
    )
    monkeypatch.setenv("KINOVA_DESCRIPTION_DIR", str(folder))
    return folder


@pytest.fixture
def ycb_scans() -> Path:
    """The folder of YCB scans (the set's layout), read in place."""
    return _vendor_dir("objects", "ycb")


def folder_state(folder: Path) -> dict[str, str]:
    """Everything under a vendor folder: relative path -> SHA-256 of a file's bytes, or
    "folder" for a folder. Equal before and after a test: no file was edited, added or
    removed, and nothing (not even an empty folder) was written beside the files."""
    return {
        str(path.relative_to(folder)): (
            hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else "folder"
        )
        for path in sorted(folder.rglob("*"))
    }
