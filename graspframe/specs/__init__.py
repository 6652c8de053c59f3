"""Hand and arm specs: a robot described in a TOML file, no Python needed.

A spec names a URDF as its vendor ships it and adds what graspframe needs and the file
lacks: frames given as offsets from existing links (palm frame, palm pad, fingertips,
flange), the real fingers, drives, couplings and, for a hand, the preshape table.
`load_spec(path)` reads one and returns a `HandDescription` or an `ArmDescription`, the
same object a Python plugin registers; every command that takes a hand or an arm name
also takes a spec path (`graspframe run --hand my_hand.toml`).

Paths in a spec are relative to the spec file; `~` and `${ENV}` are expanded (an unset
variable is an error naming it). Angles are in radians, or in degrees under a key ending
in `_deg`. Every table accepts only its own keys: a misspelt key is an error listing the
accepted ones. The format is documented key by key in docs/specs.md.

The modules: `reader.py` (typed access to a spec's values), `model.py` (what hands and
arms say alike: packages, frames, joints, drive), `hands.py`, `arms.py`.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from graspframe.common.errors import DescriptionError
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.specs.arms import read_arm
from graspframe.specs.hands import read_hand
from graspframe.specs.reader import SpecReader

SPEC_SUFFIX = ".toml"
KINDS = ("hand", "arm")

__all__ = ["is_spec_path", "load_spec"]


def is_spec_path(name: str) -> bool:
    """Whether a name given where a robot name is expected is a spec file path."""
    return name.lower().endswith(SPEC_SUFFIX)


def load_spec(path: Path | str) -> HandDescription | ArmDescription:
    """The hand or arm a spec file describes (DescriptionError, one line, for anything
    wrong with it)."""
    path = Path(path).expanduser()
    if not path.is_file():
        raise DescriptionError(f"spec file not found: {path}")
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise DescriptionError(f"spec {path.name} is not valid TOML: {exc}") from exc
    reader = SpecReader(path)
    kind = data.get("kind")
    if kind not in KINDS:
        raise reader.fail(f"'kind' must be one of {', '.join(KINDS)}, got {kind!r}")
    return read_hand(reader, data) if kind == "hand" else read_arm(reader, data)
