"""Cache entries (graspframe/common/cache.py): checked whenever they are read, a damaged one
reported in one warning line and rebuilt, published whole, correct with several
processes writing and reading the same entry at once."""

from __future__ import annotations

import errno
import json
import logging
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from graspframe.common.cache import ENTRY_FILE, cache_dir, read_entry, write_entry
from graspframe.common.errors import OutputError

VALUES = {"method": "hull", "sizes": [1.5, 2.0]}
FILES = {"piece_000.obj": b"v 0 0 0\n" * 100, "picture.png": b"\x89PNG" + bytes(range(256))}


@pytest.fixture
def folder(tmp_path: Path, monkeypatch) -> Path:
    """Where one entry goes, in a cache of the test's own."""
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))
    return cache_dir("things") / "key"


def test_an_entry_reads_back_as_written(folder: Path, caplog):
    assert read_entry(folder) is None  # none yet: no warning
    written = write_entry(folder, VALUES, FILES)
    entry = read_entry(folder)
    assert entry == written
    assert entry.values == VALUES
    assert list(entry.files) == list(FILES)
    assert {name: path.read_bytes() for name, path in entry.files.items()} == FILES
    # A data file's name carries its hash; nothing else is left beside the entry.
    assert entry.files["piece_000.obj"].name.startswith("piece_000-")
    assert sorted(p.name for p in folder.parent.iterdir()) == ["key"]
    assert not caplog.messages


def _cut_short(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _garbage(path: Path) -> None:
    path.write_bytes(os.urandom(len(path.read_bytes())))


def _changed_value(path: Path) -> None:  # still JSON of the format: only its hash tells
    index = json.loads(path.read_text())
    index["values"]["method"] = "coacd"
    path.write_text(json.dumps(index))


def _old_format(path: Path) -> None:
    path.write_text(json.dumps({"method": "hull", "files": ["piece_000.obj"]}))


DAMAGES = {
    "entry.json missing": (ENTRY_FILE, Path.unlink, "entry.json: No such file or directory"),
    "entry.json cut short": (ENTRY_FILE, _cut_short, "entry.json is not JSON"),
    "entry.json garbage": (ENTRY_FILE, _garbage, "entry.json is not JSON"),
    "entry.json of another format": (ENTRY_FILE, _old_format, "entry.json is not of format"),
    "a value changed": (ENTRY_FILE, _changed_value, "entry.json does not match its hash"),
    "a data file cut short": ("piece_000.obj", _cut_short, "does not match its hash"),
    "a data file garbage": ("picture.png", _garbage, "does not match its hash"),
    "a data file missing": ("picture.png", Path.unlink, "No such file or directory"),
}


@pytest.mark.parametrize("damage", list(DAMAGES))
def test_a_damaged_entry_is_reported_in_one_line_and_rebuilt(folder: Path, damage, caplog):
    written = write_entry(folder, VALUES, FILES)
    name, damage_it, why = DAMAGES[damage]
    damage_it(folder / ENTRY_FILE if name == ENTRY_FILE else written.files[name])
    with caplog.at_level(logging.WARNING, logger="graspframe.common.cache"):
        assert read_entry(folder) is None
    (warning,) = caplog.messages
    assert warning.startswith(f"cache entry {folder} is damaged (")
    assert why in warning and warning.endswith("); rebuilding it")
    caplog.clear()
    rebuilt = write_entry(folder, VALUES, FILES)
    assert rebuilt == written  # the same files at the same paths
    assert read_entry(folder) == written and not caplog.messages


def test_a_file_where_the_entry_folder_goes_is_replaced(folder: Path, caplog):
    folder.write_bytes(b"half a folder")
    with caplog.at_level(logging.WARNING, logger="graspframe.common.cache"):
        assert read_entry(folder) is None
    assert "is damaged (entry.json: Not a directory)" in caplog.text
    assert write_entry(folder, VALUES, FILES).values == VALUES


def test_a_failed_write_leaves_no_entry_and_says_why(folder: Path, monkeypatch):
    def no_space(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", no_space)  # where a full disk shows at the latest
    with pytest.raises(OutputError, match="No space left on device") as error:
        write_entry(folder, VALUES, FILES)
    assert str(error.value).startswith("cannot write ")
    assert list(folder.parent.iterdir()) == []  # no entry, no staging folder
    monkeypatch.undo()
    assert read_entry(folder) is None


WRITER = """
import sys
from pathlib import Path
from graspframe.common.cache import write_entry
folder, tag = Path(sys.argv[1]), sys.argv[2]
for round in range(int(sys.argv[3])):
    content = (tag * 50_000).encode()  # each writer's own: the entries differ
    entry = write_entry(folder, {"tag": tag}, {"data.bin": content, "note.txt": tag.encode()})
    assert entry.values == {"tag": tag}, entry
    assert entry.files["data.bin"].read_bytes() == content
"""


def test_processes_writing_one_entry_at_once_each_leave_a_whole_entry(folder: Path, caplog):
    """Four processes write the same entry, each with its own content, while this one
    reads it: every read finds no entry or a whole one, never a damaged one."""
    seen: list[str] = []  # "none", or the tag of a whole entry, or what was wrong
    stop = threading.Event()

    def read() -> None:
        while not stop.is_set():
            entry = read_entry(folder)
            if entry is None:
                seen.append("none")
                continue
            tag = entry.values["tag"]
            # The files the entry named still hold its content, whatever came since.
            data = entry.files["data.bin"].read_bytes()
            note = entry.files["note.txt"].read_bytes()
            whole = data == (tag * 50_000).encode() and note == tag.encode()
            seen.append(tag if whole else f"entry {tag} with other files")

    reader = threading.Thread(target=read)
    with caplog.at_level(logging.WARNING, logger="graspframe.common.cache"):
        reader.start()
        writers = [
            subprocess.Popen([sys.executable, "-c", WRITER, str(folder), tag, "15"])
            for tag in "abcd"
        ]
        codes = [writer.wait(timeout=120) for writer in writers]
        stop.set()
        reader.join()
    assert codes == [0, 0, 0, 0]
    assert not caplog.messages, caplog.text
    assert set(seen) <= {"none", *"abcd"}, set(seen)
    assert set(seen) & set("abcd")  # whole entries were read while they were written
    final = read_entry(folder)
    assert final is not None and final.values["tag"] in "abcd"
    # No staging folder or temporary file is left behind.
    assert [p.name for p in folder.parent.iterdir()] == ["key"]
    assert not [p for p in folder.iterdir() if p.name.startswith(".")]
