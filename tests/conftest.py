"""Shared fixtures."""

from __future__ import annotations

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
