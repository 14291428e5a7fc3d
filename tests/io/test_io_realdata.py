"""Adapters for shared/realdata (skipped when the folder is absent)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.io import file_sha256, load_measurement_set
from idkit.datasets import read_afrl_accel, read_boucwen_benchmark, read_mr_damper, read_prony_reference, read_pyvisco_complex_modulus, read_pyvisco_shift_factors
from idkit.datasets import realdata_dir


def test_realdata_dir_honours_env(monkeypatch, tmp_path):
    monkeypatch.setenv("IDKIT_REALDATA", str(tmp_path))
    assert realdata_dir() == tmp_path.resolve()
    assert realdata_dir("absent") is None


def test_pyvisco_master_curve_and_isotherms(realdata):
    folder = realdata("pyvisco_dma")
    master = read_pyvisco_complex_modulus(folder / "examples" / "freq_user_master.csv")
    assert master.quantity == "modulus" and master.freq.size == 206
    assert master.freq[0] == 1e-12 and master.freq[-1] == pytest.approx(1e14)
    assert master.storage[0] == pytest.approx(88.79651575665739e6, rel=1e-15)
    assert np.all(np.diff(master.freq) > 0)
    raw = read_pyvisco_complex_modulus(folder / "examples" / "freq_user_raw.csv")
    assert raw.freq.size == 210 and raw.temperature is not None
    assert raw.temperature.min() == pytest.approx(223.15, abs=0.1)
    shifts = read_pyvisco_shift_factors(folder / "examples" / "freq_user_master__shift_factors.csv")
    assert shifts.temperature.size == 21
    assert shifts.reference_temperature == pytest.approx(268.15)  # Tref -5 C
    reduced = raw.master_curve(shifts)
    # the shifted isotherms span the master curve's range of reduced frequency
    assert reduced.freq.min() == pytest.approx(0.1 * 10 ** -11.7, rel=1e-9)
    assert reduced.freq.max() == pytest.approx(100 * 10 ** 12.75, rel=1e-9)


@pytest.mark.parametrize(("relpath", "n_terms", "e0_pa"), [
    ("freq_master/prony_terms.MPL", 27, None),
    ("freq_raw/prony_terms.MPL", 34, None),
    ("time_master/prony_terms.MPL", 31, None),
    ("time_master/prony_terms_KPf_MD.csv", 31, 1739.03e6),
])
def test_prony_references(realdata, relpath, n_terms, e0_pa):
    path = realdata("pyvisco_dma") / "verification" / relpath
    prony = read_prony_reference(path)
    assert prony.alpha.size == prony.tau.size == n_terms
    assert np.all(np.diff(prony.tau) > 0) and 0 < prony.alpha.sum() < 1
    assert prony.instantaneous_modulus == e0_pa
    assert list(prony.to_dataframe().columns)[:2] == ["alpha [-]", "tau [s]"]
    if e0_pa is None:
        with pytest.raises(DataError, match="instantaneous_modulus"):
            _ = prony.moduli
    else:
        np.testing.assert_allclose(prony.moduli.sum() + prony.equilibrium_modulus, e0_pa)


_PRONY_HEAD = "TB,PRON,_MATL   ,   1,   2,SHEA\n"


@pytest.mark.parametrize(("tbdata", "expected"), [
    # a blank field leaves its location (ANSYS): the values after it keep their places
    ("TBDATA,1,0.25,,0.5\nTBDATA,2,1e-3\nTBDATA,4,2e-2\n", ([0.25, 0.5], [1e-3, 2e-2])),
    ("TBDATA,1,0.25,1e-3,0.5,2e-2,\n", ([0.25, 0.5], [1e-3, 2e-2])),  # a trailing comma adds nothing
])
def test_ansys_prony_blank_fields_keep_their_locations(tmp_path, tbdata, expected):
    path = tmp_path / "prony_terms.MPL"
    path.write_text(_PRONY_HEAD + tbdata)
    prony = read_prony_reference(path)
    assert prony.alpha.tolist() == expected[0] and prony.tau.tolist() == expected[1]


def test_ansys_prony_blank_field_never_filled_is_refused(tmp_path):
    """Before, the blank was dropped and every later value slid one location down, read without a word."""
    path = tmp_path / "prony_terms.MPL"
    path.write_text(_PRONY_HEAD + "TBDATA,1,0.25,,1e-3,0.5,2e-2\n")
    with pytest.raises(DataError, match="TB,PRON declares 2 terms; found TBDATA indices 1..5 \\(4 values\\)"):
        read_prony_reference(path)


def test_both_time_master_prony_files_agree(realdata):
    folder = realdata("pyvisco_dma") / "verification" / "time_master"
    ansys = read_prony_reference(folder / "prony_terms.MPL", instantaneous_modulus=1739.03e6)
    pyvisco = read_prony_reference(folder / "prony_terms_KPf_MD.csv")
    np.testing.assert_allclose(ansys.alpha, pyvisco.alpha, rtol=1e-6)
    np.testing.assert_allclose(ansys.tau, pyvisco.tau, rtol=1e-6)
    assert ansys.equilibrium_modulus == pytest.approx(pyvisco.equilibrium_modulus, rel=1e-6)


def test_mr_damper_loop(realdata):
    path = realdata("mr_damper_labcontrol") / "data" / "ensaio10.2.mat"
    before = (file_sha256(path), path.stat().st_mtime_ns)
    loop = read_mr_damper(path)
    assert loop.kind == "quasi_static" and loop.n_samples == 3001
    assert loop.info.sample_rate_hz == pytest.approx(100.0)
    assert np.abs(loop.deflection).max() == pytest.approx(12.4e-3, rel=0.01)  # mm -> m
    assert 250 < np.abs(loop.force).max() < 350  # N
    # v_rel is the time derivative of the position (same length unit per second)
    slope = np.gradient(loop.deflection, loop.time)
    assert np.corrcoef(slope, loop.v_rel)[0, 1] > 0.99
    assert np.std(slope) / np.std(loop.v_rel) == pytest.approx(1.0, rel=0.01)
    assert (file_sha256(path), path.stat().st_mtime_ns) == before
    assert loop.source.sha256 == before[0]


def test_mr_damper_through_a_manifest_in_tmp(realdata, tmp_path):
    """The same file as a .mat manifest entry (copied into tmp, never into the repo; a
    symlink leading out of the set's folder is refused)."""
    source = realdata("mr_damper_labcontrol") / "data" / "ensaio1.mat"
    (tmp_path / "ensaio1.mat").write_bytes(source.read_bytes())
    (tmp_path / "manifest.json").write_text(json.dumps({"measurements": [{
        "id": "ensaio1", "kind": "quasi_static", "isolator": "mr_damper", "file": "ensaio1.mat",
        "sample_rate_hz": 100.0,
        "mat_columns": {"time": "Tout [s]", "deflection": "x_F[:,0] [mm]",
                        "v_rel": "x_F[:,1] [mm/s]", "force": "x_F[:,2] [N]"}}]}))
    from_manifest = load_measurement_set(tmp_path).get("ensaio1")
    direct = read_mr_damper(source)
    assert np.array_equal(from_manifest.force, direct.force)
    assert from_manifest.source.sha256 == direct.source.sha256
    (tmp_path / "ensaio1.mat").unlink()
    (tmp_path / "ensaio1.mat").symlink_to(source)
    with pytest.raises(DataError, match="outside the set's folder"):
        load_measurement_set(tmp_path)


@pytest.mark.parametrize(("k", "channel", "peak_kgn"), [
    (1, "pcb_1", (20, 30)), (4, "pcb_4", (75, 90)), (6, "fixture_bottom", (10, 15))])
def test_afrl_accelerations(realdata, k, channel, peak_kgn):
    record = read_afrl_accel(realdata("droptower_shock_afrl") / f"accel_{k}.csv")
    assert record.channel == channel
    assert record.accel.shape == (5000, 5) and record.n_tests == 5
    assert record.sample_rate_hz == pytest.approx(1e6, rel=1e-9)
    peak = np.abs(record.accel).max() / 9806.65
    assert peak_kgn[0] < peak < peak_kgn[1]
    assert list(record.to_dataframe().columns)[:2] == ["time [s]", "test_1 [m/s^2]"]


def test_boucwen_benchmark(realdata):
    data = read_boucwen_benchmark(realdata("boucwen_benchmark") / "bouc-wen.mat")
    assert data.sample_rate_hz == 750.0
    assert data.train_force.size == data.train_displacement.size == 40960
    assert data.test_multisine_force.size == 8192
    assert data.test_sinesweep_displacement.size == 153000
    assert np.sqrt(np.mean(data.train_force ** 2)) == pytest.approx(50.0, rel=0.05)  # RMS 50 N
    assert data.time(3)[-1] == pytest.approx(2 / 750)


@pytest.mark.parametrize("u, message", [
    (np.array([[0], [2**53 + 1], [5]], dtype=np.int64), r"'u'.*9007199254740993.*cannot hold exactly"),
    (np.array([["a"], ["b"], ["c"]]), r"variable 'u' has dtype <U1, expected real numbers"),
])
def test_boucwen_benchmark_refuses_values_float64_would_change(tmp_path, u, message):
    """The benchmark adapter cast every variable straight to float64: an int64 beyond 2^53 was
    rounded without a word (read_mat refuses it) and text raised numpy's own error."""
    from scipy.io import savemat

    vector = np.zeros((3, 1))
    path = tmp_path / "bouc-wen.mat"
    savemat(path, {"u": u, "y": vector, "uval_multisine": vector, "yval_multisine": vector,
                   "uval_sinesweep": vector, "yval_sinesweep": vector})
    with pytest.raises(DataError, match=message):
        read_boucwen_benchmark(path)
    savemat(path, {"u": np.array([[0], [2**53], [5]], dtype=np.int64), "y": vector, "uval_multisine": vector,
                   "yval_multisine": vector, "uval_sinesweep": vector, "yval_sinesweep": vector})
    assert read_boucwen_benchmark(path).train_force[1] == 2.0**53  # exactly representable: read as is
