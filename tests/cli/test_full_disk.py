"""A disk that fills (or a file-size limit) while ``idkit simulate`` writes: the error names the file."""

from __future__ import annotations

import errno
import os

import pytest

from idkit import _numba_cache
from tests.cli.hostile import check, run_main

GRID = ["--freq", "5", "--amplitude", "1e-4", "--harmonics", "1", "--quiet"]


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = tmp_path_factory.mktemp("model") / "elastomer.json"
    check(run_main(["library", "system_b1_medium", "-o", path]), "ok")
    return path


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EFBIG])
def test_a_table_write_that_fills_the_disk_names_the_file_and_leaves_nothing(model, tmp_path, monkeypatch, code):
    from idkit import atomic

    def full(descriptor):
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(atomic.os, "fsync", full)  # the write reached the disk and did not fit
    grid = tmp_path / "grid.csv"
    outcome = run_main(["simulate", "harmonic", model, *GRID, "-o", grid], inputs=[model], must_not_exist=[grid],
                       watch=[tmp_path])
    check(outcome, "error", [f"cannot write '{grid}': {os.strerror(code)}; nothing written"])


def test_an_os_error_without_a_file_names_the_commands_outputs(model, tmp_path, monkeypatch):
    from idkit import atomic

    def too_large(path, text, **options):
        raise OSError(errno.EFBIG, "File too large")  # as a library write deep down reports it: no file name

    monkeypatch.setattr(atomic, "write_text_atomic", too_large)
    grid = tmp_path / "grid.csv"
    outcome = run_main(["simulate", "harmonic", model, *GRID, "-o", grid], inputs=[model], must_not_exist=[grid])
    check(outcome, "error", [f"File too large (while running; this command writes -o '{grid}')"])


class _FullCache:
    """The parts of numba's cache file :func:`idkit._numba_cache.locked_save` uses, on a full disk."""

    def __init__(self, folder):
        self._index_path = str(folder / "kernel.nbi")
        self.index_saved = False

    def _load_index(self):
        return {}

    def _data_name(self, number):
        return f"kernel.{number}.nbc"

    def _save_data(self, name, data):
        raise OSError(errno.EFBIG, "File too large")

    def _save_index(self, overloads):
        self.index_saved = True


@pytest.mark.skipif(_numba_cache.fcntl is None, reason="the locked save needs fcntl (POSIX)")
def test_a_numba_cache_that_cannot_be_written_is_skipped_not_fatal(tmp_path):
    cache = _FullCache(tmp_path)
    with pytest.warns(RuntimeWarning, match="numba cache not written \\(File too large"):
        _numba_cache.locked_save(cache, ("signature",), b"machine code")
    assert not cache.index_saved  # an index never names data that were not written


def test_a_warning_reads_as_an_idkit_line(monkeypatch, capsys):
    import warnings

    from idkit.cli import main as cli_main

    def warns(args):
        warnings.warn("numba cache not written (File too large, in /cache)", RuntimeWarning, stacklevel=2)
        return 0

    monkeypatch.setattr(cli_main, "_cmd_library", warns)
    with warnings.catch_warnings():
        warnings.simplefilter("always")  # shown, not raised as the test suite's filter does
        assert cli_main.main(["library"]) == 0
    assert capsys.readouterr().err == "idkit: warning: numba cache not written (File too large, in /cache)\n"
