"""The one output writer: atomic files, the folder swap, and recovery after a killed run."""

import os
import subprocess
import sys

import pytest

from idkit.atomic import atomic_output_folder, recover_leftovers, replace_folder, write_text_atomic
from idkit.errors import OutputError


def _folder(path, text):
    path.mkdir()
    (path / "content.txt").write_text(text)
    return path


def _dead_pid() -> int:
    process = subprocess.Popen([sys.executable, "-c", "pass"])
    process.wait()
    return process.pid


def test_failed_second_rename_puts_the_old_folder_back(tmp_path, monkeypatch):
    target, staging = _folder(tmp_path / "out", "old"), _folder(tmp_path / ".out.partial.1.ab", "new")
    real = os.rename

    def rename(source, destination):
        if os.fspath(source) == os.fspath(staging):
            raise OSError(5, "Input/output error", os.fspath(source))
        real(source, destination)

    monkeypatch.setattr("idkit.atomic.os.rename", rename)
    with pytest.raises(OSError):
        replace_folder(staging, target)
    assert (target / "content.txt").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".out.partial.1.ab", "out"]  # no aside copy left


def test_an_error_while_building_keeps_the_old_folder_and_removes_the_staging(tmp_path):
    target = _folder(tmp_path / "out", "old")
    with pytest.raises(KeyboardInterrupt):
        with atomic_output_folder(target, force=True) as staging:
            (staging / "content.txt").write_text("half")
            raise KeyboardInterrupt
    assert (target / "content.txt").read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_a_complete_folder_replaces_the_old_one(tmp_path):
    target = _folder(tmp_path / "out", "old")
    with atomic_output_folder(target, force=True) as staging:
        (staging / "content.txt").write_text("new")
    assert (target / "content.txt").read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_recovery_restores_an_aside_copy_and_removes_stale_staging(tmp_path):
    dead = _dead_pid()
    _folder(tmp_path / f".out.old.{dead}.0a1b", "old")
    _folder(tmp_path / f".out.partial.{dead}.0a1c", "new, complete")
    running = _folder(tmp_path / f".out.partial.{os.getpid()}.0a1d", "another run still writing")
    recover_leftovers(tmp_path / "out")
    assert (tmp_path / "out" / "content.txt").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == [running.name, "out"]


def test_recovery_keeps_a_present_folder_and_removes_the_aside_copy(tmp_path):
    _folder(tmp_path / "out", "new")
    _folder(tmp_path / f".out.old.{_dead_pid()}.0a1b", "old")
    recover_leftovers(tmp_path / "out")
    assert (tmp_path / "out" / "content.txt").read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_text_files_are_written_whole_and_failures_name_the_path(tmp_path):
    path = write_text_atomic(tmp_path / "a.txt", "é\n")
    assert path.read_bytes() == "é\n".encode()
    with pytest.raises(FileExistsError):
        write_text_atomic(path, "x")
    with pytest.raises(OutputError, match="missing"):
        write_text_atomic(tmp_path / "missing" / "b.txt", "x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]
