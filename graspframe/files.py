"""Writing files so that a reader never sees a partial one; where cached files live.

`atomic_write` writes to a temporary file with a unique name in the target's folder,
flushes it to disk, then renames it over the target (`os.replace`, atomic on one file
system). Processes and threads writing the same path at once each use their own
temporary file, so the target is always one writer's whole content.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO

CACHE_ENV = "GRASPFRAME_CACHE_DIR"


def mesh_file(path: Path | str, suffixes: tuple[str, ...], what: str) -> Path:
    """`path` when it names an existing file with one of the `suffixes` (the file is not
    read); a DescriptionError naming `what` (e.g. "mesh file", "object 'mug': mesh_path")
    otherwise."""
    from graspframe.errors import DescriptionError

    path = Path(path)
    if path.suffix.lower() not in suffixes:
        raise DescriptionError(
            f"{what} {path}: unknown format {path.suffix or '(no suffix)'!r}; mesh files "
            f"are {', '.join(suffixes)}"
        )
    if not path.is_file():
        raise DescriptionError(f"{what} {path} does not exist; give the path of a mesh file")
    return path


def cache_dir(kind: str) -> Path:
    """The cache folder of one kind of file graspframe computes once and reuses
    ("decompositions", "human_references"), created on demand, under GRASPFRAME_CACHE_DIR
    (default ~/.cache/graspframe)."""
    root = Path(os.environ.get(CACHE_ENV, Path.home() / ".cache" / "graspframe"))
    path = root / kind
    path.mkdir(parents=True, exist_ok=True)
    return path


def temporary_path(path: Path) -> Path:
    """A hidden name beside `path`, unique to this process and call."""
    return path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex}.tmp")


@contextmanager
def atomic_output(path: Path | str) -> Iterator[BinaryIO]:
    """A binary stream whose content replaces `path` when the block ends without an
    exception; on an exception the target is untouched and the temporary file removed.
    The parent folder must exist."""
    path = Path(path)
    tmp = temporary_path(path)
    try:
        with open(tmp, "xb") as stream:
            yield stream
            stream.flush()
            os.fsync(stream.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def atomic_write(path: Path | str, data: bytes | str) -> Path:
    """Replace `path` with `data` (str is written as UTF-8) atomically; returns the path."""
    content = data.encode() if isinstance(data, str) else data
    with atomic_output(path) as stream:
        stream.write(content)
    return Path(path)
