"""Writing files so that a reader never sees a partial one, and saying in one line why a
write failed.

`atomic_write` writes to a temporary file with a unique name in the target's folder,
flushes it to disk, then renames it over the target (`os.replace`, atomic on one file
system). Processes and threads writing the same path at once each use their own
temporary file, so the target is always one writer's whole content. A write that fails
(no space left, no permission, a file where a folder is needed) leaves the target as it
was, removes the temporary file and raises an OutputError naming the path and the cause.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import BinaryIO

from graspframe.common.errors import DescriptionError, OutputError

# The mesh files graspframe reads (trimesh, COLLADA through pycollada): an object's
# (hal/objects.py) and a robot's collision meshes (convex.py's `load_mesh` reads both).
MESH_SUFFIXES = (".obj", ".stl", ".dae", ".glb", ".gltf", ".ply")


def mesh_file(path: Path | str, what: str) -> Path:
    """`path` when it names an existing file of one of the MESH_SUFFIXES formats (the
    file is not read); a DescriptionError naming `what` (e.g. "mesh file", "object
    'mug': mesh_path") otherwise."""
    path = Path(path)
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise DescriptionError(
            f"{what} {path}: unknown format {path.suffix or '(no suffix)'!r}; mesh files "
            f"are {', '.join(MESH_SUFFIXES)}"
        )
    if not path.is_file():
        raise DescriptionError(f"{what} {path} does not exist; give the path of a mesh file")
    return path


def temporary_path(path: Path) -> Path:
    """A hidden name beside `path`, unique to this process and call."""
    return path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex}.tmp")


def os_reason(error: OSError) -> str:
    """The cause of a failed file operation in words ("No space left on device")."""
    return error.strerror or str(error)


def make_folder(path: Path | str, what: str = "folder") -> Path:
    """Create the folder `path` and its parents (fine when it exists); an OutputError
    naming `what` and the cause when it cannot be created."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"cannot create {what} {path}: {os_reason(error)}") from error
    return path


@contextmanager
def atomic_output(path: Path | str) -> Iterator[BinaryIO]:
    """A binary stream whose content replaces `path` when the block ends without an
    exception; on an exception the target is untouched and the temporary file removed.
    The parent folder must exist. An OSError while writing (in the block too: writing
    to the stream) becomes an OutputError naming `path` and the cause."""
    path = Path(path)
    tmp = temporary_path(path)
    try:
        with open(tmp, "xb") as stream:
            yield stream
            stream.flush()
            os.fsync(stream.fileno())
        os.replace(tmp, path)
    except BaseException as error:
        with suppress(OSError):  # e.g. no temporary file: its folder is not one
            tmp.unlink(missing_ok=True)
        if isinstance(error, OSError):
            raise OutputError(f"cannot write {path}: {os_reason(error)}") from error
        raise


def atomic_write(path: Path | str, data: bytes | str) -> Path:
    """Replace `path` with `data` (str is written as UTF-8) atomically; returns the path.
    OutputError (path and cause) when it cannot be written."""
    content = data.encode() if isinstance(data, str) else data
    with atomic_output(path) as stream:
        stream.write(content)
    return Path(path)
