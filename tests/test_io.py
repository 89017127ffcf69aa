"""Atomic output: written whole, and on disk (fsync) before and after the rename."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from tetherheli import _io


@pytest.fixture
def events(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    log: list[str] = []
    fsync, replace = os.fsync, os.replace

    def spy_fsync(fd: int) -> None:
        log.append("fsync dir" if stat.S_ISDIR(os.fstat(fd).st_mode) else "fsync file")
        fsync(fd)

    def spy_replace(a, b) -> None:
        log.append("rename")
        replace(a, b)

    monkeypatch.setattr(_io.os, "fsync", spy_fsync)
    monkeypatch.setattr(_io.os, "replace", spy_replace)
    return log


def test_file_synced_before_rename_and_folder_after(tmp_path: Path, events: list[str]):
    _io.atomic_write_text(tmp_path / "a.txt", "one\n")
    assert events == ["fsync file", "rename", "fsync dir"]
    events.clear()
    with _io.atomic_open(tmp_path / "b.csv") as fh:
        fh.write("x\n")
    assert events == ["fsync file", "rename", "fsync dir"]
    events.clear()
    with _io.atomic_path(tmp_path / "c.gif") as tmp:  # for writers that take a file name
        assert tmp.parent == tmp_path and tmp.suffix == ".gif"
        tmp.write_bytes(b"GIF")
    assert events == ["fsync file", "rename", "fsync dir"]
    assert (tmp_path / "a.txt").read_text() == "one\n" and (tmp_path / "b.csv").read_text() == "x\n"
    assert (tmp_path / "c.gif").read_bytes() == b"GIF"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.csv", "c.gif"]


def test_failed_write_leaves_the_old_file(tmp_path: Path, events: list[str]):
    target = tmp_path / "r.csv"
    target.write_text("old\n")
    with pytest.raises(RuntimeError), _io.atomic_open(target) as fh:
        fh.write("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old\n" and events == []
    assert [p.name for p in tmp_path.iterdir()] == ["r.csv"]


def test_failed_path_write_leaves_the_old_file(tmp_path: Path, events: list[str]):
    target = tmp_path / "a.gif"
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError), _io.atomic_path(target) as tmp:
        tmp.write_bytes(b"half")
        raise RuntimeError("boom")
    assert target.read_bytes() == b"old" and events == []
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"]
