"""Atomic writes: parallel writers never leave a partial or mixed file."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from graspframe.common.files import atomic_output, atomic_write, temporary_path

SIZE = 1 << 20  # 1 MiB per write: large enough for writes to overlap
ROUNDS = 20


def test_temporary_name_is_unique_and_beside_the_target(tmp_path: Path):
    target = tmp_path / "result.json"
    names = {temporary_path(target) for _ in range(100)}
    assert len(names) == 100
    assert all(name.parent == tmp_path and name.name.startswith(".result.json.") for name in names)


def test_parallel_writers_leave_one_whole_content(tmp_path: Path):
    target = tmp_path / "result.json"
    contents = [bytes([ord("a") + i]) * SIZE for i in range(2)]
    atomic_write(target, contents[0])
    seen: list[bytes] = []
    stop = threading.Event()

    def write(content: bytes) -> None:
        for _ in range(ROUNDS):
            atomic_write(target, content)

    def read() -> None:
        while not stop.is_set():
            seen.append(target.read_bytes())

    reader = threading.Thread(target=read)
    writers = [threading.Thread(target=write, args=(c,)) for c in contents]
    reader.start()
    for w in writers:
        w.start()
    for w in writers:
        w.join()
    stop.set()
    reader.join()

    assert seen
    assert all(data in contents for data in seen)
    assert target.read_bytes() in contents
    assert [p.name for p in tmp_path.iterdir()] == ["result.json"]


def test_a_failed_write_keeps_the_old_file(tmp_path: Path):
    target = tmp_path / "summary.md"
    atomic_write(target, "old\n")
    with pytest.raises(RuntimeError), atomic_output(target) as stream:
        stream.write(b"half")
        raise RuntimeError("interrupted")
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["summary.md"]
