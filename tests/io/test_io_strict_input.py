"""Strict input reading (idkit.inputfiles) and the file errors of the readers: every problem
is a DataError naming the file, never an OSError, UnicodeDecodeError or zlib.error."""

from __future__ import annotations

import gzip
import io
import json
import os

import numpy as np
import pytest
import scipy.io

from idkit.errors import DataError, ModelFileError
from idkit.inputfiles import decode_utf8, load_json, read_input_bytes
from idkit.io import read_csv_measurement, read_mat
from idkit.io.matfile import load_mat_variables

CSV = b"time [s],deflection [mm],force [N]\n" + b"".join(
    f"{k / 50},{np.sin(k / 5):.6f},{10 * np.sin(k / 5):.5f}\n".encode() for k in range(200))


def _json(text: str, error=DataError):
    return load_json(text.encode("utf-8"), "file 'x.json'", error, expected="an object")


@pytest.mark.parametrize(("text", "fragments"), [
    ('{"a": 1, "a": 2}', ["key 'a' given twice", "found 1 and 2"]),
    ('{"m": [{"x": {"b": 1, "b": 1}}]}', ["at m[0].x (list positions 0-based)", "'b' given twice"]),
    ('{"p": {"k": NaN}}', ["at p.k", "NaN", "expected a finite number"]),
    ('{"p": [1, -Infinity]}', ["at p[1]", "-Infinity"]),
    ('{"p": 1e400}', ["at p", "1e400", "overflows to infinity"]),
    ('{"p": 1' + "0" * 400 + "}", ["at p", "integer of 401 digits"]),
    ('{"p": 1,}', ["invalid JSON at line 1, column"]),
    ("[" * 100000 + "]" * 100000, ["nested too deeply"]),
    ("  \n", ["empty file", "expected an object"]),
])
def test_load_json_refusals_name_file_and_key_path(text, fragments):
    with pytest.raises(DataError) as info:
        _json(text)
    message = str(info.value)
    assert message.startswith("file 'x.json': ")
    for fragment in fragments:
        assert fragment in message, message


def test_load_json_keeps_valid_documents_unchanged():
    document = {"a": [1, 2.5, -3e-300, 1e308], "b": {"c": None, "d": True, "e": "é"}}
    raw = b"\xef\xbb\xbf" + json.dumps(document, ensure_ascii=False).encode("utf-8")
    assert load_json(raw, "f", DataError, expected="x") == document


def test_error_class_is_the_callers():
    with pytest.raises(ModelFileError, match="given twice"):
        _json('{"a": 1, "a": 1}', ModelFileError)


@pytest.mark.parametrize(("raw", "fragment"), [
    ("é".encode("utf-16"), "UTF-16 text"),
    ("é".encode("utf-32"), "UTF-32 text"),
    (b"ok \xff", "not UTF-8 text (byte 3"),
    ("time [s]".encode("utf-16-le"), "not UTF-8 text (NUL bytes between the first characters: UTF-16-LE"),
    ("time [s]".encode("utf-32-be"), "UTF-32-BE without a byte-order mark"),
])
def test_decode_utf8_names_the_encoding_problem(raw, fragment):
    with pytest.raises(DataError, match=fragment.replace("(", r"\(")):
        decode_utf8(raw, "file 'a.csv'", DataError)


def test_read_input_bytes_refuses_anything_but_a_regular_file(tmp_path):
    (tmp_path / "folder").mkdir()
    (tmp_path / "file").write_bytes(b"x")
    os.mkfifo(tmp_path / "pipe")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    cases = {"missing": "not found", "folder": "is a folder", "pipe": "not a regular file",
             "file/below": "a part of the path is a file", "loop": "cannot be read"}
    for name, fragment in cases.items():
        with pytest.raises(DataError, match=fragment):
            read_input_bytes(tmp_path / name, f"file '{name}'", DataError)
    assert read_input_bytes(tmp_path / "file", "f", DataError) == b"x"


def test_corrupted_and_truncated_gzip_are_data_errors(tmp_path):
    packed = gzip.compress(CSV, mtime=0)
    rng = np.random.default_rng(11)
    path = tmp_path / "qs.csv.gz"
    for trial in range(60):
        broken = bytearray(packed)
        if trial % 2:
            broken = broken[: rng.integers(0, len(broken))]
        else:
            for offset in rng.integers(10, len(broken) - 8, size=3):
                broken[offset] ^= int(rng.integers(1, 256))
        path.write_bytes(bytes(broken))
        try:
            read_csv_measurement(path, "quasi_static")
        except DataError as error:
            assert "qs.csv.gz" in str(error)


def _mat(compression: bool) -> bytes:
    buffer = io.BytesIO()
    time = np.arange(300) / 50.0
    scipy.io.savemat(buffer, {"Tout": time, "x_F": np.column_stack([time, 2 * time])},
                     do_compression=compression)
    return buffer.getvalue()


@pytest.mark.parametrize("compression", [False, True])
def test_truncated_or_corrupted_mat_files_are_data_errors(tmp_path, compression):
    raw = _mat(compression)
    rng = np.random.default_rng(5)
    path = tmp_path / "run.mat"
    for trial in range(80):
        broken = bytearray(raw)
        if trial % 2:
            broken = broken[: rng.integers(0, len(broken))]
        else:
            for offset in rng.integers(0, len(broken), size=3):
                broken[offset] = int(rng.integers(0, 256))
        path.write_bytes(bytes(broken))
        try:
            read_mat(path, "quasi_static", columns={"time": "Tout [s]", "deflection": "x_F[:,0] [m]",
                                                     "force": "x_F[:,1] [N]"})
        except DataError as error:
            assert "run.mat" in str(error)


def test_empty_and_header_only_mat(tmp_path):
    (tmp_path / "empty.mat").write_bytes(b"")
    with pytest.raises(DataError, match="empty.mat': empty file"):
        load_mat_variables(tmp_path / "empty.mat")
    (tmp_path / "header.mat").write_bytes(_mat(False)[:128])
    with pytest.raises(DataError, match="without any variable"):
        load_mat_variables(tmp_path / "header.mat")


SHOCK_ROWS = ["time [ms],shot_1 [g]"] + [f"{k / 100},{(k % 7) / 10}" for k in range(40)]
SHOCK = "\n".join(SHOCK_ROWS) + "\n"


@pytest.mark.parametrize(("text", "fragments"), [
    # a sample row of empty cells, or an empty line, was dropped silently (the rows after it renumbered)
    ("\n".join(SHOCK_ROWS[:20] + [","] + SHOCK_ROWS[20:]), ["data row 20 ", "file line 21", "found an empty cell"]),
    ("\n".join(SHOCK_ROWS[:20] + [""] + SHOCK_ROWS[20:]), ["data row 20 ", "found an empty line"]),
    ("time [s],shot_1 [g]\n0," + "1" * 200000 + "\n1,0\n", ["not parseable as CSV", "field limit"]),
])
def test_shock_csv_never_drops_a_row(tmp_path, text, fragments):
    from idkit.io import read_shock_csv

    path = tmp_path / "fixture.csv"
    path.write_text(text)
    with pytest.raises(DataError, match="file '.*fixture.csv'") as info:
        read_shock_csv(path)
    for fragment in fragments:
        assert fragment in str(info.value)


def test_shock_csv_ignores_only_trailing_empty_lines(tmp_path):
    from idkit.io import read_shock_csv

    path = tmp_path / "fixture.csv"
    path.write_text(SHOCK + "\n\n")
    assert read_shock_csv(path).accel.shape == (40, 1)
