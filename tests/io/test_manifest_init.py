"""``idkit data init``: a manifest from files plus what the user states, checked before writing."""

from __future__ import annotations

import json

import numpy as np
import pytest

from idkit.datasets import realdata_dir
from idkit.errors import DataError
from idkit.io import load_measurement_set
from idkit.io.manifest_init import init_manifest
from tests.cli.hostile import check, run_main

MR = realdata_dir("mr_damper_labcontrol")


def write_loops(path, amplitude_mm=4.0, unit="mm"):
    time = np.linspace(0.0, 20.0, 2001)
    deflection = amplitude_mm * np.sin(2 * np.pi * time / 5.0)
    force = 30.0 * deflection + 5.0 * np.sign(np.cos(2 * np.pi * time / 5.0))
    rows = "\n".join(f"{t!r},{x!r},{f!r}" for t, x, f in zip(time.tolist(), deflection.tolist(), force.tolist()))
    path.write_text(f"time [s],deflection [{unit}],force [N]\n{rows}\n")
    return path


def test_manifest_lists_the_files_with_the_stated_metadata_and_loads(tmp_path):
    for name in ("loops_a.csv", "loops_b.csv"):
        write_loops(tmp_path / name)
    manifest = init_manifest(tmp_path, kind="quasi_static", metadata={"isolator": "mount", "split": "fit"},
                             name="bench")
    assert [e.id for e in manifest.entries] == ["loops_a", "loops_b"]
    loaded = load_measurement_set(tmp_path)
    assert {m.info.isolator for m in loaded.measurements} == {"mount"}
    # the deflection unit came from the header: 4 mm -> 4e-3 m
    assert loaded.measurements[0].deflection.max() == pytest.approx(4e-3, rel=1e-3)


def test_nothing_is_written_when_a_file_does_not_read_as_stated(tmp_path):
    write_loops(tmp_path / "good.csv")
    write_loops(tmp_path / "bad.csv", unit="furlong")
    with pytest.raises(DataError, match=r"bad.csv.*furlong"):
        init_manifest(tmp_path, kind="quasi_static")
    assert not (tmp_path / "manifest.json").exists()


def test_existing_manifest_is_kept_unless_appending_or_forced(tmp_path):
    write_loops(tmp_path / "a.csv")
    init_manifest(tmp_path, kind="quasi_static")
    before = (tmp_path / "manifest.json").read_bytes()
    with pytest.raises(DataError, match="exists"):
        init_manifest(tmp_path, kind="quasi_static")
    assert (tmp_path / "manifest.json").read_bytes() == before
    write_loops(tmp_path / "b.csv")
    appended = init_manifest(tmp_path, kind="quasi_static", append=True, metadata={"split": "validation"})
    assert [(e.id, e.info.split) for e in appended.entries] == [("a", None), ("b", "validation")]


def test_drops_need_their_height(tmp_path):
    (tmp_path / "drop.csv").write_text("time [s],deflection [m],a_top_1 [g],a_top_2 [g]\n0,0,0,0\n0.001,0,0,0\n")
    with pytest.raises(DataError, match="drop_height_m"):
        init_manifest(tmp_path, kind="drop")


@pytest.mark.parametrize("pattern", ["", "/etc/*", ".", "../*.csv", "sub/../*.csv"])
def test_files_pattern_must_stay_inside_the_folder(tmp_path, pattern):
    """'' was taken as 'every file', '/etc/*' and '.' raised pathlib's NotImplementedError / IndexError."""
    (tmp_path / "set").mkdir()
    write_loops(tmp_path / "set" / "a.csv")
    write_loops(tmp_path / "outside.csv")
    with pytest.raises(DataError, match=r"files: found .*expected a glob pattern relative to the folder"):
        init_manifest(tmp_path / "set", kind="quasi_static", files=pattern)
    assert not (tmp_path / "set" / "manifest.json").exists()
    outcome = run_main(["data", "init", tmp_path / "set", "--kind", "quasi_static", "--files", pattern],
                       inputs=[tmp_path], must_not_exist=[tmp_path / "set" / "manifest.json"])
    check(outcome, "error", ["files: found", "relative to the folder"], case="data-init-files-outside")


def test_stated_values_that_would_not_be_used_are_refused(tmp_path):
    """A mapping for .mat files with only CSV files, or a name on append, were dropped without a word."""
    write_loops(tmp_path / "a.csv")
    with pytest.raises(DataError, match=r"mat_columns: found time but no .mat file among the 1 listed"):
        init_manifest(tmp_path, kind="quasi_static", mat_columns={"time": "Tout [s]"})
    assert not (tmp_path / "manifest.json").exists()
    init_manifest(tmp_path, kind="quasi_static", name="bench")
    write_loops(tmp_path / "b.csv")
    with pytest.raises(DataError, match=r"name: found 'renamed' with append"):
        init_manifest(tmp_path, kind="quasi_static", append=True, name="renamed")
    assert load_measurement_set(tmp_path).ids == ("a",)


def test_cli_writes_a_manifest_that_loads(tmp_path):
    write_loops(tmp_path / "a.csv")
    outcome = run_main(["data", "init", tmp_path, "--kind", "quasi_static", "--isolator", "mount",
                        "--top-mass", "2.5"], inputs=[tmp_path / "a.csv"])
    check(outcome, "ok")
    document = json.loads((tmp_path / "manifest.json").read_text())
    assert document["measurements"][0]["top_mass_kg"] == 2.5
    refused = run_main(["data", "init", tmp_path, "--kind", "quasi_static"], inputs=[tmp_path])
    check(refused, "error", ["manifest", "exists", "--append", "--force"], case="data-init-existing")


@pytest.mark.skipif(MR is None, reason="../shared/realdata/mr_damper_labcontrol is not present")
def test_mat_files_need_their_columns_stated(tmp_path):
    import shutil

    shutil.copy(MR / "data" / "ensaio.A.1.mat", tmp_path / "ensaio.A.1.mat")
    with pytest.raises(DataError, match="mat_column|columns stated"):
        init_manifest(tmp_path, kind="quasi_static")
    manifest = init_manifest(tmp_path, kind="quasi_static", metadata={"sample_rate_hz": 100.0},
                             mat_columns={"time": "Tout [s]", "deflection": "x_F[:,0] [mm]",
                                          "v_rel": "x_F[:,1] [mm/s]", "force": "x_F[:,2] [N]"})
    assert manifest.entries[0].id == "ensaio.A.1"
    record = load_measurement_set(tmp_path).measurements[0]
    assert 8e-3 < 0.5 * np.ptp(record.deflection) < 1.1e-2


def _write_shaker(path, rate_hz=200.0):
    """0.5 s of base and top velocities sampled at ``rate_hz`` (Nyquist rate_hz / 2)."""
    time = np.arange(int(rate_hz) // 2) / rate_hz
    v_base, v_top = 1e-3 * np.sin(2 * np.pi * 10.0 * time), 2e-3 * np.sin(2 * np.pi * 10.0 * time + 0.3)
    rows = "\n".join(f"{t!r},{b!r},{v!r}" for t, b, v in zip(time.tolist(), v_base.tolist(), v_top.tolist()))
    path.write_text(f"time [s],v_base [m/s],v_top [m/s]\n{rows}\n")
    return path


@pytest.mark.parametrize("kind, excitation, accepted", [
    ("white_noise", {"band_hz": [1.0, 1e300]}, False),   # was written as stated
    ("white_noise", {"band_hz": [1.0, 250.0]}, False),
    ("white_noise", {"band_hz": [1.0, 200.0]}, True),   # up to the Nyquist frequency
    ("stepped_sine", {"freq_hz": 1e300}, False),         # was written as stated
    ("stepped_sine", {"freq_hz": 200.0}, False),         # at Nyquist a sine has no resolved phase
    ("stepped_sine", {"freq_hz": 199.0}, True),
])
def test_excitation_beyond_the_nyquist_frequency_is_refused(tmp_path, kind, excitation, accepted):
    _write_shaker(tmp_path / "run.csv", rate_hz=400.0)
    if accepted:
        init_manifest(tmp_path, kind=kind, metadata={"excitation": excitation})
        return
    key = "freq_hz" if kind == "stepped_sine" else "band_hz"
    with pytest.raises(DataError, match=rf"run.csv.*: excitation {key}: found .*, expected .* the Nyquist frequency") \
            as raised:
        init_manifest(tmp_path, kind=kind, metadata={"excitation": excitation})
    assert "200 Hz of its 400 Hz samples" in str(raised.value)
    assert not (tmp_path / "manifest.json").exists()


def test_repetition_beyond_json_exact_integers_is_refused(tmp_path):
    """``--repetition 1e300`` wrote a 301-digit integer into the manifest."""
    from idkit.io.info import MeasurementInfo

    write_loops(tmp_path / "a.csv")
    outcome = run_main(["data", "init", tmp_path, "--kind", "quasi_static", "--repetition", "1e300"],
                       inputs=[tmp_path / "a.csv"], must_not_exist=[tmp_path / "manifest.json"])
    check(outcome, "error", ["--repetition", "found '1e300'", "9007199254740991"], case="data-init-repetition-1e300")
    with pytest.raises(DataError, match=r"repetition: found an integer of 301 digits, expected a whole number from 1"):
        MeasurementInfo(repetition=10**300)
    assert MeasurementInfo(repetition=2**53 - 1).repetition == 2**53 - 1
