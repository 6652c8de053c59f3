"""The cache: results computed once and reused by later runs, each entry checked when read
and rebuilt when damaged.

The cache folder is GRASPFRAME_CACHE_DIR (default ~/.cache/graspframe), one folder per
kind of entry ("decompositions", "human_references"). An entry is a folder
`<kind>/<key>/` holding its data files and, written last, `entry.json`:

    {
      "format": "graspframe.cache_entry/1",
      "values": {...},                  # the entry's own JSON values
      "files": [{"name": "piece_000.obj", "file": "piece_000-<hash>.obj", "sha256": "..."}],
      "sha256": "..."                   # of format, values and files (canonical JSON)
    }

Reading checks the whole entry: entry.json is JSON of this format and matches its own
hash, and every data file is there and matches its hash. A damaged entry (a process
killed while writing, a full disk, a changed byte) is reported in one warning line
naming it and read as absent, so its caller builds it again.

Writing: the entry is built in a private staging folder beside it and published by
renaming that folder (atomic), so an entry folder is whole from the moment it exists.
When a folder is already there (a damaged entry, or one another process has just
published), the files are moved into it one by one, entry.json last. A data file's name
carries its hash: a name always stands for the same content, so a process that holds the
paths of an entry's files keeps whole files while another one rewrites the entry, and two
processes building the same entry at once each leave an entry.json that names files it
wrote.
"""

from __future__ import annotations

import errno
import hashlib
import json
import logging
import os
import shutil
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from graspframe.common.errors import OutputError
from graspframe.common.files import atomic_write, make_folder, os_reason, temporary_path

log = logging.getLogger(__name__)

CACHE_ENV = "GRASPFRAME_CACHE_DIR"
ENTRY_FORMAT = "graspframe.cache_entry/1"
ENTRY_FILE = "entry.json"
STORED_HASH_CHARACTERS = 16  # of a data file's SHA-256 in its stored name


def cache_dir(kind: str) -> Path:
    """The cache folder of one kind of entry ("decompositions", "human_references"),
    created on demand, under GRASPFRAME_CACHE_DIR (default ~/.cache/graspframe)."""
    root = Path(os.environ.get(CACHE_ENV, Path.home() / ".cache" / "graspframe"))
    return make_folder(root / kind, "cache folder")


@dataclass(frozen=True)
class CacheEntry:
    """A whole cache entry.

    folder: where it lies; values: its own JSON values; files: each data file's path, by
    the name it was written under, in the order it was written.
    """

    folder: Path
    values: dict[str, Any]
    files: dict[str, Path]


class DamagedEntry(Exception):
    """Why a cache entry cannot be trusted (inside this module: a damaged entry is rebuilt,
    never reported as an error)."""


def _sha256(content: bytes) -> str:
    return hashlib.sha256(content).hexdigest()


def _seal(body: dict[str, Any]) -> str:
    """The hash of an entry.json's content besides its own hash."""
    return _sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode())


def _stored_name(name: str, digest: str) -> str:
    """The file name of a data file: its name with part of its hash ("piece_000-<hash>.obj")."""
    path = Path(name)
    return f"{path.stem}-{digest[:STORED_HASH_CHARACTERS]}{path.suffix}"


def _read_bytes(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except OSError as error:
        raise DamagedEntry(f"{path.name}: {os_reason(error)}") from None


def _checked(folder: Path) -> CacheEntry:
    """The entry in `folder`; DamagedEntry saying what is wrong unless it is whole."""
    text = _read_bytes(folder / ENTRY_FILE)
    try:
        index = json.loads(text)
    except (UnicodeDecodeError, ValueError):
        raise DamagedEntry(f"{ENTRY_FILE} is not JSON") from None
    if not isinstance(index, dict) or index.get("format") != ENTRY_FORMAT:
        raise DamagedEntry(f"{ENTRY_FILE} is not of format {ENTRY_FORMAT}")
    body = {key: value for key, value in index.items() if key != "sha256"}
    if index.get("sha256") != _seal(body):
        raise DamagedEntry(f"{ENTRY_FILE} does not match its hash")
    files = {}
    for record in index["files"]:
        path = folder / record["file"]
        if _sha256(_read_bytes(path)) != record["sha256"]:
            raise DamagedEntry(f"{path.name} does not match its hash")
        files[record["name"]] = path
    return CacheEntry(folder, index["values"], files)


def read_entry(folder: Path) -> CacheEntry | None:
    """The entry in `folder` when it is whole; None when there is none, and None after
    one warning line naming it and what is wrong when it is damaged."""
    if not os.path.lexists(folder):
        return None
    try:
        return _checked(folder)
    except DamagedEntry as damage:
        log.warning("cache entry %s is damaged (%s); rebuilding it", folder, damage)
        return None


def write_entry(folder: Path, values: dict[str, Any], files: Mapping[str, bytes]) -> CacheEntry:
    """Write the entry `folder` (in a kind's cache folder) with its JSON `values` and data
    `files` (name -> content), replacing a damaged one; returns it as a reader sees it
    (its values as JSON gives them back). OutputError when it cannot be written."""
    staging = temporary_path(folder)
    make_folder(staging, "cache entry folder")
    try:
        records = []
        for name, content in files.items():
            digest = _sha256(content)
            stored = _stored_name(name, digest)
            atomic_write(staging / stored, content)
            records.append({"name": name, "file": stored, "sha256": digest})
        body = {"format": ENTRY_FORMAT, "values": values, "files": records}
        text = json.dumps({**body, "sha256": _seal(body)}, indent=1)
        atomic_write(staging / ENTRY_FILE, text)
        _publish(staging, folder)
    except OSError as error:
        raise OutputError(f"cannot write cache entry {folder}: {os_reason(error)}") from error
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    # Another process may have written the same entry since: its entry.json names its own
    # files, and these stay as they are (a name always stands for the same content).
    files_written = {record["name"]: folder / record["file"] for record in records}
    return CacheEntry(folder, json.loads(text)["values"], files_written)


def _publish(staging: Path, folder: Path) -> None:
    """Move the whole entry in `staging` to `folder`: by one rename when there is none,
    else file by file, entry.json last."""
    if os.path.lexists(folder) and not folder.is_dir():  # damaged: not even a folder
        folder.unlink(missing_ok=True)
    try:
        os.rename(staging, folder)
        return
    except OSError as error:
        if error.errno not in (errno.EEXIST, errno.ENOTEMPTY):
            raise
    for path in staging.iterdir():
        if path.name != ENTRY_FILE:
            os.replace(path, folder / path.name)
    os.replace(staging / ENTRY_FILE, folder / ENTRY_FILE)
