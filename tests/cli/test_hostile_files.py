"""Hostile input files through the real CLI: every file error is idkit's own, formats are strict.

Issue 13, items 3 and 4. Each case builds a broken file in ``tmp_path`` from a valid one
(a measurement set written by :func:`idkit.io.write_measurement_set`, a model file written
by ``idkit library``), runs the command that reads it through :func:`idkit.cli.main.main`
and asserts: exit status 2, a message naming the file and what was found and expected, no
traceback, inputs byte-identical, no output created. Refusals happen at load time, so the
cases are fast; one valid ("ok") control per command shows the valid file is accepted.
"""

from __future__ import annotations

import gzip
import io
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
import scipy.io

from tests.cli.hostile import check, run_main
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, write_measurement_set
from idkit.models import IwanModel, library, save_model

QS_FILE = "quasi_static/qs_1.csv"
ROOT = os.geteuid() == 0 if hasattr(os, "geteuid") else False
as_root = pytest.mark.skipif(ROOT, reason="root reads files whatever their permissions")


def _loops(amplitudes, samples: int) -> np.ndarray:
    phase = np.linspace(0, 2 * np.pi * len(amplitudes), samples)
    envelope = np.repeat(amplitudes, samples // len(amplitudes))
    envelope = np.concatenate([envelope, np.full(samples - envelope.size, amplitudes[-1])])
    return envelope * np.sin(phase)


@pytest.fixture(scope="module")
def valid_set(tmp_path_factory) -> Path:
    """A small valid measurement set: two quasi-static wire-rope records (ids qs_1, qs_2)."""
    folder = tmp_path_factory.mktemp("valid") / "set"
    truth = IwanModel(g1=3e3, g2=4e4, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6])
    rng = np.random.default_rng(3)
    measurements = []
    for repetition, amplitudes in ((1, [4e-3, 2e-3, 1e-3]), (2, [12e-3, 8e-3, 4e-3])):
        x = _loops(np.array(amplitudes), 600)
        force = truth.force(x) + 0.05 * rng.standard_normal(x.size)
        info = MeasurementInfo(id=f"qs_{repetition}", isolator="wire_rope", repetition=repetition,
                               split="fit", sample_rate_hz=50.0)
        measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x,
                                                   force=force, info=info))
    write_measurement_set(folder, measurements, name="hostile-files base set")
    return folder


@pytest.fixture
def dataset(valid_set, tmp_path) -> Path:
    """A fresh copy of the valid set, to be broken by one case."""
    return Path(shutil.copytree(valid_set, tmp_path / "set"))


@pytest.fixture(scope="module")
def valid_model(tmp_path_factory) -> Path:
    """A valid model file (Table 7.3 elastomer, Maxwell order 2) written by ``idkit library``."""
    path = tmp_path_factory.mktemp("model") / "elastomer.json"
    check(run_main(["library", "table_7_3_elastomer", "-o", path]), "ok", case="library -o model")
    return path


@pytest.fixture
def model(valid_model, tmp_path) -> Path:
    return Path(shutil.copy(valid_model, tmp_path / "model.json"))


def _manifest(folder: Path) -> dict:
    return json.loads((folder / "manifest.json").read_text(encoding="utf-8"))


def _write_manifest(folder: Path, document: dict | str) -> None:
    text = document if isinstance(document, str) else json.dumps(document, indent=1)
    (folder / "manifest.json").write_text(text, encoding="utf-8")


def _inspect(target: Path, tmp_path: Path, inputs, words, *, case: str, kind: str = "error"):
    outcome = run_main(["inspect", target], inputs=inputs)
    check(outcome, kind, words, case=case)


def _fit(dataset: Path, tmp_path: Path, words, *, case: str, model: str = "iwan",
         kind: str = "error", extra=()):
    output = tmp_path / "out.json"
    outcome = run_main(["fit", model, dataset, "-o", output, *extra], inputs=[dataset],
                       must_not_exist=[] if kind == "ok" else [output], watch=[tmp_path])
    check(outcome, kind, words, case=case)
    return outcome


def _simulate(model_path: Path, tmp_path: Path, words, *, case: str, kind: str = "error"):
    output = tmp_path / "drop.csv"
    outcome = run_main(["simulate", "drop", model_path, "--mass", "1", "--height", "0.01",
                        "--duration", "0.05", "-o", output],
                       inputs=[model_path] if model_path.is_file() else [],
                       must_not_exist=[] if kind == "ok" else [output], watch=[tmp_path])
    check(outcome, kind, words, case=case)


def _mat_bytes(*, compression: bool = False) -> bytes:
    buffer = io.BytesIO()
    time = np.arange(200) / 50.0
    x = 4e-3 * np.sin(2 * np.pi * time)
    scipy.io.savemat(buffer, {"Tout": time, "x_F": np.column_stack([x * 1e3, 10.0 * x * 1e3])},
                     do_compression=compression)
    return buffer.getvalue()


def _mat_set(folder: Path, raw: bytes) -> None:
    """Replace the set's manifest by one listing a single .mat entry with these bytes."""
    (folder / "run.mat").write_bytes(raw)
    _write_manifest(folder, {"measurements": [{
        "id": "run", "kind": "quasi_static", "file": "run.mat", "isolator": "wire_rope",
        "mat_columns": {"time": "Tout [s]", "deflection": "x_F[:,0] [mm]",
                        "force": "x_F[:,1] [N]"}}]})


# ---------------------------------------------------------------- valid controls ("ok")

def test_ok_inspect_valid_set(dataset, tmp_path):
    _inspect(dataset, tmp_path, [dataset], ["2 measurements"], case="ok: inspect valid set",
             kind="ok")


def test_ok_fit_iwan_valid_set(dataset, tmp_path):
    outcome = _fit(dataset, tmp_path, [], case="ok: fit iwan valid set", kind="ok",
                   extra=["--order", "2"])  # the truth's order: at its noise floor
    assert (tmp_path / "out.json").is_file(), outcome.stderr


def test_ok_simulate_valid_model(model, tmp_path):
    _simulate(model, tmp_path, [], case="ok: simulate drop valid model", kind="ok")


def test_ok_utf8_byte_order_marks_are_accepted(dataset, model, tmp_path):
    manifest = dataset / "manifest.json"
    manifest.write_bytes(b"\xef\xbb\xbf" + manifest.read_bytes())
    data = dataset / QS_FILE
    data.write_bytes(b"\xef\xbb\xbf" + data.read_bytes())
    _inspect(dataset, tmp_path, [dataset], ["2 measurements"], case="ok: UTF-8 BOMs in set",
             kind="ok")
    model.write_bytes(b"\xef\xbb\xbf" + model.read_bytes())
    _simulate(model, tmp_path, [], case="ok: UTF-8 BOM in model file", kind="ok")


def test_ok_a_symlink_inside_the_set_folder(dataset, tmp_path):
    (dataset / "quasi_static" / "qs_1.csv").rename(dataset / "store.csv")
    (dataset / QS_FILE).symlink_to(dataset / "store.csv")
    _inspect(dataset, tmp_path, [dataset], ["2 measurements"],
             case="ok: symlink inside the set folder", kind="ok")


def test_ok_set_folder_reached_through_a_symlink(dataset, tmp_path):
    link = tmp_path / "linked_set"
    link.symlink_to(dataset, target_is_directory=True)
    _inspect(link, tmp_path, [dataset], ["2 measurements"],
             case="ok: set folder is a symlink", kind="ok")


# ------------------------------------------------- item 3: data files (CSV, gzip, .mat)

def _gzip_set(dataset: Path) -> Path:
    """Turn entry qs_1 into a .csv.gz file; returns its path."""
    target = dataset / "quasi_static" / "qs_1.csv.gz"
    target.write_bytes(gzip.compress((dataset / QS_FILE).read_bytes(), mtime=0))
    (dataset / QS_FILE).unlink()
    document = _manifest(dataset)
    document["measurements"][0]["file"] = "quasi_static/qs_1.csv.gz"
    _write_manifest(dataset, document)
    return target


def _corrupt_deflate(raw: bytes) -> bytes:
    broken = bytearray(raw)
    for offset in range(20, min(len(broken) - 8, 400), 7):
        broken[offset] ^= 0xA5
    return bytes(broken)


def test_gzip_corrupted_deflate_stream_in_a_set(dataset, tmp_path):
    target = _gzip_set(dataset)
    target.write_bytes(_corrupt_deflate(target.read_bytes()))
    _fit(dataset, tmp_path, ["qs_1.csv.gz", "not a valid gzip file", "expected gzip"],
         case="gzip corrupted deflate (fit)")


def test_gzip_corrupted_deflate_stream_lone_file(dataset, tmp_path):
    target = _gzip_set(dataset)
    lone = tmp_path / "lone.csv.gz"
    lone.write_bytes(_corrupt_deflate(target.read_bytes()))
    _inspect(lone, tmp_path, [lone], ["lone.csv.gz", "not a valid gzip file"],
             case="gzip corrupted deflate (inspect lone file)")


def test_gzip_truncated(dataset, tmp_path):
    target = _gzip_set(dataset)
    target.write_bytes(target.read_bytes()[: len(target.read_bytes()) // 2])
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv.gz", "not a valid gzip file", "ended"],
             case="gzip truncated")


def test_gzip_name_but_plain_text(dataset, tmp_path):
    target = _gzip_set(dataset)
    target.write_bytes(gzip.decompress(target.read_bytes()))
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv.gz", "not a valid gzip file"],
             case="gzip name, plain text inside")


def test_gzip_bad_crc(dataset, tmp_path):
    target = _gzip_set(dataset)
    raw = target.read_bytes()
    target.write_bytes(raw[:-8] + bytes(8))
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv.gz", "not a valid gzip file", "CRC"],
             case="gzip bad CRC")


def test_csv_empty_file(dataset, tmp_path):
    (dataset / QS_FILE).write_bytes(b"")
    _fit(dataset, tmp_path, ["qs_1.csv", "empty file", "expected a header"], case="csv 0 bytes")


def test_csv_not_utf8(dataset, tmp_path):
    data = dataset / QS_FILE
    data.write_bytes(data.read_bytes().replace(b"force [N]", b"force [N\xe9]"))
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv", "not UTF-8", "expected UTF-8"],
             case="csv non-UTF-8 byte")


def test_csv_utf16(dataset, tmp_path):
    data = dataset / QS_FILE
    data.write_bytes(data.read_text(encoding="utf-8").encode("utf-16"))
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv", "UTF-16", "expected UTF-8"],
             case="csv UTF-16 with BOM")


def test_csv_truncated_mid_row(dataset, tmp_path):
    data = dataset / QS_FILE
    raw = data.read_bytes()
    data.write_bytes(raw[: raw.rindex(b",")])
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv", "data row 600", "expected 3 fields"],
             case="csv truncated mid-row")


def test_data_file_is_a_folder(dataset, tmp_path):
    (dataset / QS_FILE).unlink()
    (dataset / QS_FILE).mkdir()
    _fit(dataset, tmp_path, ["qs_1.csv", "is a folder", "expected a file"],
         case="data file is a folder")


def test_data_file_is_a_fifo(dataset, tmp_path):
    (dataset / QS_FILE).unlink()
    os.mkfifo(dataset / QS_FILE)
    outcome = run_main(["inspect", dataset], timeout_s=20)
    check(outcome, "error", ["qs_1.csv", "not a regular file"], case="data file is a FIFO")


def test_lone_file_is_a_fifo(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    check(run_main(["inspect", fifo], timeout_s=20), "error", ["pipe.csv", "not a regular file"],
          case="inspect a FIFO")


def test_data_file_dangling_symlink(dataset, tmp_path):
    (dataset / QS_FILE).unlink()
    (dataset / QS_FILE).symlink_to(dataset / "gone.csv")
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv", "not found"],
             case="data file dangling symlink")


def test_data_file_symlink_loop(dataset, tmp_path):
    (dataset / QS_FILE).unlink()
    (dataset / QS_FILE).symlink_to(dataset / QS_FILE)
    _inspect(dataset, tmp_path, [], ["qs_1.csv", "cannot be read"], case="data file symlink loop")


@as_root
def test_data_file_permission_denied(dataset, tmp_path):
    (dataset / QS_FILE).chmod(0)
    try:
        _inspect(dataset, tmp_path, [], ["qs_1.csv", "cannot be read", "permission"],
                 case="data file permission denied")
    finally:
        (dataset / QS_FILE).chmod(0o644)


def test_mat_valid_control(dataset, tmp_path):
    _mat_set(dataset, _mat_bytes())
    _inspect(dataset, tmp_path, [dataset], ["1 measurements"], case="ok: valid .mat entry",
             kind="ok")


def test_mat_empty_file(dataset, tmp_path):
    _mat_set(dataset, b"")
    _fit(dataset, tmp_path, ["run.mat", "empty file", "expected a MATLAB .mat file"],
         case=".mat 0 bytes")


@pytest.mark.parametrize("keep", [10, 127, 300, -40])
def test_mat_truncated(dataset, tmp_path, keep):
    raw = _mat_bytes()
    _mat_set(dataset, raw[:keep])
    _inspect(dataset, tmp_path, [dataset], ["run.mat", "expected"],
             case=f".mat truncated to {keep} bytes")


def test_mat_header_without_variables(dataset, tmp_path):
    _mat_set(dataset, _mat_bytes()[:128])
    _inspect(dataset, tmp_path, [dataset], ["run.mat", "without any variable", "truncated"],
             case=".mat header only")


def test_mat_corrupted_compressed_variable(dataset, tmp_path):
    raw = _mat_bytes(compression=True)
    broken = bytearray(raw)
    for offset in range(160, len(broken), 11):
        broken[offset] ^= 0x5A
    _mat_set(dataset, bytes(broken))
    _inspect(dataset, tmp_path, [dataset], ["run.mat", "not a readable MATLAB .mat file"],
             case=".mat corrupted compressed variable")


def test_mat_text_file(dataset, tmp_path):
    _mat_set(dataset, b"time,force\n1,2\n" * 20)
    _inspect(dataset, tmp_path, [dataset], ["run.mat", "not a readable MATLAB .mat file"],
             case=".mat that is text")


# ----------------------------------------------------------- item 3: the manifest itself

def test_manifest_is_a_folder(dataset, tmp_path):
    (dataset / "manifest.json").unlink()
    (dataset / "manifest.json").mkdir()
    _fit(dataset, tmp_path, ["manifest.json", "is a folder", "expected a file"],
         case="manifest is a folder")


def test_manifest_empty(dataset, tmp_path):
    (dataset / "manifest.json").write_bytes(b"")
    _fit(dataset, tmp_path, ["manifest.json", "empty file", "expected a JSON object"],
         case="manifest 0 bytes")


def test_manifest_not_utf8(dataset, tmp_path):
    manifest = dataset / "manifest.json"
    manifest.write_bytes(manifest.read_bytes().replace(b"hostile-files", b"hostile\xff"))
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "not UTF-8", "byte"],
             case="manifest non-UTF-8 byte")


def test_manifest_utf16(dataset, tmp_path):
    manifest = dataset / "manifest.json"
    manifest.write_bytes(manifest.read_text(encoding="utf-8").encode("utf-16"))
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "UTF-16", "expected UTF-8"],
             case="manifest UTF-16")


def test_manifest_truncated(dataset, tmp_path):
    manifest = dataset / "manifest.json"
    manifest.write_bytes(manifest.read_bytes()[:-30])
    _fit(dataset, tmp_path, ["manifest.json", "invalid JSON", "line"], case="manifest truncated")


@as_root
def test_manifest_permission_denied(dataset, tmp_path):
    (dataset / "manifest.json").chmod(0)
    try:
        _fit(dataset, tmp_path, ["manifest.json", "cannot be read"],
             case="manifest permission denied")
    finally:
        (dataset / "manifest.json").chmod(0o644)


def test_dataset_missing(tmp_path):
    output = tmp_path / "out.json"
    check(run_main(["fit", "iwan", tmp_path / "nope", "-o", output], must_not_exist=[output]),
          "error", ["DATASET: found", "nope' (not found)"], case="fit: dataset missing")


# --------------------------------------------------------------- item 3: model files

def test_model_missing(tmp_path):
    _simulate(tmp_path / "absent.json", tmp_path, ["model file", "absent.json", "not found"],
              case="model file missing")
    assert "Errno" not in run_main(["simulate", "drop", tmp_path / "absent.json"]).stderr


def test_model_is_a_folder(tmp_path):
    folder = tmp_path / "model.json"
    folder.mkdir()
    _simulate(folder, tmp_path, ["model file", "model.json", "is a folder", "expected a file"],
              case="model path is a folder")


def test_model_below_a_regular_file(model, tmp_path):
    _simulate(model / "inner.json", tmp_path, ["model file", "inner.json", "not found"],
              case="model path below a file")


def test_model_not_utf8(model, tmp_path):
    model.write_bytes(model.read_bytes().replace(b"idkit.models.library", b"idkit\xe9models"))
    _simulate(model, tmp_path, ["model file", "model.json", "not UTF-8", "byte"],
              case="model file non-UTF-8 byte")


def test_model_utf16(model, tmp_path):
    model.write_bytes(model.read_text(encoding="utf-8").encode("utf-16"))
    _simulate(model, tmp_path, ["model file", "UTF-16", "expected UTF-8"], case="model UTF-16")


def test_model_empty(model, tmp_path):
    model.write_bytes(b"")
    _simulate(model, tmp_path, ["model file", "model.json", "empty file"], case="model 0 bytes")


def test_model_truncated(model, tmp_path):
    model.write_bytes(model.read_bytes()[:-40])
    _simulate(model, tmp_path, ["model file", "model.json", "invalid JSON", "line"],
              case="model truncated JSON")


def test_model_is_a_fifo(tmp_path):
    fifo = tmp_path / "model.json"
    os.mkfifo(fifo)
    _simulate(fifo, tmp_path, ["model file", "not a regular file"], case="model FIFO")


@as_root
def test_model_permission_denied(model, tmp_path):
    model.chmod(0)
    try:
        _simulate(model, tmp_path, ["model file", "cannot be read"], case="model permission denied")
    finally:
        model.chmod(0o644)


def test_model_deeply_nested(model, tmp_path):
    document = json.loads(model.read_text(encoding="utf-8"))
    text = json.dumps(document)[:-1] + ', "provenance": ' + "[" * 100000 + "]" * 100000 + "}"
    model.write_text(text, encoding="utf-8")
    _simulate(model, tmp_path, ["model file", "model.json"], case="model nested 1e5 deep")


# ----------------------------------------------------- item 4: strict manifests

def _raw_entry_edit(dataset: Path, old: str, new: str) -> None:
    manifest = dataset / "manifest.json"
    text = manifest.read_text(encoding="utf-8")
    assert old in text
    manifest.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_manifest_duplicate_key_in_entry(dataset, tmp_path):
    _raw_entry_edit(dataset, '"repetition": 1,', '"repetition": 1, "repetition": 3,')
    _fit(dataset, tmp_path, ["manifest.json", "measurements[0]", "'repetition' given twice", "1 and 3"],
         case="manifest key twice in one entry")


def test_manifest_duplicate_key_at_top_level(dataset, tmp_path):
    _raw_entry_edit(dataset, '"name": ', '"name": "first", "name": ')
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "'name' given twice"],
             case="manifest top-level key twice")


def test_manifest_duplicate_key_nested(dataset, tmp_path):
    _raw_entry_edit(dataset, '"split": "fit"', '"split": "fit", "excitation": '
                    '{"band_hz": [1, 10], "band_hz": [1, 20]}')
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "'band_hz' given twice"],
             case="manifest nested key twice")


def test_manifest_same_file_twice(dataset, tmp_path):
    document = _manifest(dataset)
    document["measurements"][1]["file"] = QS_FILE
    _write_manifest(dataset, document)
    _fit(dataset, tmp_path, ["manifest.json", "entry 2", "qs_2", "same data file as entry 1",
                             "one entry per data file"], case="same data file twice")


def test_manifest_same_file_other_spelling(dataset, tmp_path):
    document = _manifest(dataset)
    document["measurements"][1]["file"] = "quasi_static/./qs_1.csv"
    _write_manifest(dataset, document)
    _inspect(dataset, tmp_path, [dataset], ["same data file as entry 1"],
             case="same data file, other spelling")


def test_manifest_same_file_through_symlink(dataset, tmp_path):
    (dataset / "quasi_static" / "qs_2.csv").unlink()
    (dataset / "quasi_static" / "qs_2.csv").symlink_to("qs_1.csv")
    _inspect(dataset, tmp_path, [dataset], ["qs_2.csv", "same data file as entry 1"],
             case="same data file through a symlink")


def test_data_file_symlink_outside_the_set(dataset, tmp_path):
    outside = tmp_path / "elsewhere.csv"
    shutil.copy(dataset / QS_FILE, outside)
    (dataset / QS_FILE).unlink()
    (dataset / QS_FILE).symlink_to(outside)
    _fit(dataset, tmp_path, ["qs_1.csv", "elsewhere.csv", "outside the set's folder"],
         case="data file symlink outside the set")


def test_data_folder_symlinked_outside_the_set(dataset, tmp_path):
    outside = tmp_path / "outside_qs"
    shutil.move(dataset / "quasi_static", outside)
    (dataset / "quasi_static").symlink_to(outside, target_is_directory=True)
    _inspect(dataset, tmp_path, [dataset], ["qs_1.csv", "outside_qs", "outside the set's folder"],
             case="data folder symlinked outside the set")


def test_manifest_path_escape_refused(dataset, tmp_path):
    document = _manifest(dataset)
    document["measurements"][0]["file"] = "../set/quasi_static/qs_1.csv"
    _write_manifest(dataset, document)
    _inspect(dataset, tmp_path, [dataset], ["'../set/quasi_static/qs_1.csv'", "no '..'"],
             case="manifest path with ..")


def test_manifest_control_character_in_path(dataset, tmp_path):
    document = _manifest(dataset)
    document["measurements"][0]["file"] = "quasi_static/qs\u0000_1.csv"
    _write_manifest(dataset, document)
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "no control characters"],
             case="manifest NUL in path")


@pytest.mark.parametrize(("key", "value", "words"), [
    ("top_mass_kg", "true", ["top_mass_kg", "True", "expected a finite real number"]),
    ("repetition", "true", ["repetition", "True", "expected a whole number"]),
    ("bottom_mass_kg", "false", ["bottom_mass_kg", "False", "expected a finite real number"]),
    ("top_mass_kg", "NaN", ["measurements[0].top_mass_kg", "NaN", "expected a finite"]),
    ("top_mass_kg", "-Infinity", ["-Infinity", "expected a finite"]),
    ("top_mass_kg", "1e400", ["1e400", "overflows to infinity"]),
    ("top_mass_kg", '"4.2"', ["top_mass_kg", "'4.2'", "expected a finite real number"]),
])
def test_manifest_number_fields(dataset, tmp_path, key, value, words):
    _raw_entry_edit(dataset, '"repetition": 1,', f'"repetition": 1, "{key}": {value},'
                    if key != "repetition" else f'"repetition": {value},')
    _fit(dataset, tmp_path, ["manifest.json", *words], case=f"manifest {key} = {value}")


def test_manifest_version_true(dataset, tmp_path):
    _raw_entry_edit(dataset, '"version": 1', '"version": true')
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "version: found True", "one of 1"],
             case="manifest version true")


def test_manifest_band_with_boolean(dataset, tmp_path):
    _raw_entry_edit(dataset, '"split": "fit"', '"split": "fit", "excitation": '
                    '{"band_hz": [false, 10]}')
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "band", "found"],
             case="manifest band_hz with a boolean")


def test_manifest_name_not_a_string(dataset, tmp_path):
    _raw_entry_edit(dataset, '"name": "hostile-files base set"', '"name": ["a", "b"]')
    _inspect(dataset, tmp_path, [dataset], ["manifest.json", "name", "expected a string"],
             case="manifest name is a list")


# ------------------------------------------------------- item 4: strict model files

def _edit_model(model: Path, edit) -> None:
    document = json.loads(model.read_text(encoding="utf-8"))
    edit(document)
    model.write_text(json.dumps(document, indent=1), encoding="utf-8")


def _raw_model_edit(model: Path, old: str, new: str) -> None:
    text = model.read_text(encoding="utf-8")
    assert old in text
    model.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_model_duplicate_parameter(model, tmp_path):
    _raw_model_edit(model, '"k0": 14000.0,', '"k0": 14000.0, "k0": 1.0,')
    _simulate(model, tmp_path, ["model file", "model.params", "'k0' given twice", "14000.0 and 1.0"],
              case="model parameter twice")


def test_model_duplicate_top_level_key(model, tmp_path):
    _raw_model_edit(model, '"format_version": 1,', '"format_version": 1, "format_version": 1,')
    _simulate(model, tmp_path, ["model file", "'format_version' given twice"],
              case="model top-level key twice")


def test_model_duplicate_key_in_provenance(model, tmp_path):
    _raw_model_edit(model, '"source": ', '"name": "x", "source": ')
    _simulate(model, tmp_path, ["model file", "'name' given twice"],
              case="model provenance key twice")


def test_model_without_units(model, tmp_path):
    _edit_model(model, lambda d: d["model"].pop("units"))
    _simulate(model, tmp_path, ["model file", "'units' missing", "generalized_maxwell"],
              case="model without units")


def test_model_units_incomplete(model, tmp_path):
    _edit_model(model, lambda d: d["model"]["units"].pop("rate_2"))
    _simulate(model, tmp_path, ["model file", "units", "no unit for 'rate_2'"],
              case="model units missing one parameter")


def test_model_units_unknown_parameter(model, tmp_path):
    _edit_model(model, lambda d: d["model"]["units"].update(tau_1="s"))
    _simulate(model, tmp_path, ["model file", "units", "'tau_1'"], case="model units extra entry")


def test_model_units_not_si(model, tmp_path):
    _edit_model(model, lambda d: d["model"]["units"].update(k0="N/mm"))
    _simulate(model, tmp_path, ["model file", "units.k0", "'N/mm'", "'N/m'"],
              case="model unit not SI")


def test_model_unknown_key_in_model(model, tmp_path):
    _edit_model(model, lambda d: d["model"].update(comment="tuned by hand"))
    _simulate(model, tmp_path, ["model file", "unknown key(s) comment", "expected keys"],
              case="model unknown key inside model")


def test_model_unknown_top_level_key(model, tmp_path):
    _edit_model(model, lambda d: d.update(provenence={"seed": 1}))
    _simulate(model, tmp_path, ["model file", "unknown key(s) provenence"],
              case="model unknown top-level key")


@pytest.mark.parametrize(("value", "words"), [
    ("true", ["k0", "True", "bool", "expected a finite real number"]),
    ('"14000"', ["k0", "'14000'", "expected a finite real number"]),
    ("NaN", ["model.params.k0", "NaN", "expected a finite number"]),
    ("Infinity", ["Infinity", "expected a finite number"]),
    ("1e999", ["model.params.k0", "1e999", "overflows to infinity"]),
    ("null", ["k0", "None", "expected a finite real number"]),
])
def test_model_parameter_values(model, tmp_path, value, words):
    _raw_model_edit(model, '"k0": 14000.0', f'"k0": {value}')
    _simulate(model, tmp_path, ["model file", *words], case=f"model parameter k0 = {value}")


def test_model_format_version_true(model, tmp_path):
    _raw_model_edit(model, '"format_version": 1', '"format_version": true')
    _simulate(model, tmp_path, ["model file", "format_version: found True"],
              case="model format_version true")


def test_system_mass_boolean(tmp_path):
    path = save_model(library.get("system_b1_low"), tmp_path / "system.json")
    _edit_model(path, lambda d: d["model"].update(mass=True))
    _simulate(path, tmp_path, ["model file", "model (kind 'sdof'): mass", "True", "expected a finite real number"],
              case="system mass true")


def test_system_unknown_key(tmp_path):
    path = save_model(library.get("system_b1_low"), tmp_path / "system.json")
    _edit_model(path, lambda d: d["model"].update(top_mass=5.0))
    _simulate(path, tmp_path, ["model file", "unknown key(s) top_mass", "sdof"],
              case="system unknown key")


def test_system_isolator_without_units(tmp_path):
    path = save_model(library.get("system_b1_low"), tmp_path / "system.json")
    _edit_model(path, lambda d: d["model"]["isolator"].pop("units"))
    _simulate(path, tmp_path, ["model file", "model.isolator", "'units' missing"],
              case="system isolator without units")


# ------------------------------------------------------------ other commands, same readers

def test_fit_maxwell_refuses_a_duplicate_key(dataset, tmp_path):
    _raw_entry_edit(dataset, '"split": "fit"', '"split": "fit", "split": "validation"')
    _fit(dataset, tmp_path, ["manifest.json", "'split' given twice"], model="maxwell",
         case="fit maxwell: manifest key twice")


def test_fit_maxwell_refuses_a_corrupt_gzip(dataset, tmp_path):
    target = _gzip_set(dataset)
    target.write_bytes(_corrupt_deflate(target.read_bytes()))
    _fit(dataset, tmp_path, ["qs_1.csv.gz", "not a valid gzip file"], model="maxwell",
         case="fit maxwell: corrupt gzip")


def test_fit_maxwell_refuses_a_symlink_outside(dataset, tmp_path):
    outside = tmp_path / "elsewhere.csv"
    shutil.copy(dataset / QS_FILE, outside)
    (dataset / QS_FILE).unlink()
    (dataset / QS_FILE).symlink_to(outside)
    _fit(dataset, tmp_path, ["qs_1.csv", "outside the set's folder"], model="maxwell",
         case="fit maxwell: symlink outside the set")


def test_inspect_lone_csv_not_utf8(dataset, tmp_path):
    lone = tmp_path / "lone.csv"
    lone.write_bytes((dataset / QS_FILE).read_bytes().replace(b"time [s]", b"t\xefme [s]"))
    _inspect(lone, tmp_path, [lone], ["lone.csv", "not UTF-8"], case="inspect lone csv non-UTF-8")


@pytest.mark.parametrize(("edit", "words"), [
    (lambda d: d["model"].pop("units"), ["'units' missing"]),
    (lambda d: d["model"]["params"].update(k_1=True), ["model.params.k_1", "True"]),
    (lambda d: d.update(notes="hand-edited"), ["unknown key(s) notes"]),
])
def test_simulate_harmonic_refuses_strict_model_rules(model, tmp_path, edit, words):
    _edit_model(model, edit)
    output = tmp_path / "harmonic.csv"
    outcome = run_main(["simulate", "harmonic", model, "--mass", "1", "--freq", "10",
                        "--amplitude", "1e-4", "-o", output], inputs=[model],
                       must_not_exist=[output], watch=[tmp_path])
    check(outcome, "error", ["model file", "model.json", *words],
          case=f"simulate harmonic: {words[0]}")
