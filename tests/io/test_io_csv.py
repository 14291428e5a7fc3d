"""CSV measurements: reading each kind, unit conversion, provenance, writing."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.io import (
    DropMeasurement,
    Excitation,
    MeasurementInfo,
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
    file_sha256,
    read_csv_measurement,
    write_csv_measurement,
)


def _write(path: Path, text: str | bytes) -> Path:
    path.write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
    return path


QS_TEXT = ("time [ms],deflection [mm],force [daN]\n"
           "0,-1.5,-2.0\n10,0.0,0.5\n20,1.5,2.5\n")


def test_quasi_static_read_converts_to_si(tmp_path):
    path = _write(tmp_path / "qs_small_1.csv", QS_TEXT)
    m = read_csv_measurement(path, "quasi_static")
    assert isinstance(m, QuasiStaticMeasurement)
    np.testing.assert_array_equal(m.time, [0.0, 0.01, 0.02])
    np.testing.assert_array_equal(m.deflection, [-1.5 / 1000, 0.0, 1.5 / 1000])
    np.testing.assert_array_equal(m.force, [-20.0, 5.0, 25.0])
    assert m.v_rel is None
    assert m.info.id == "qs_small_1"
    assert m.source.path == path
    assert m.source.sha256 == file_sha256(path)
    assert m.source.column_label("force") == "force [daN]"
    assert list(m.to_dataframe().columns) == ["time [s]", "deflection [m]", "force [N]"]


def test_arrays_are_read_only(tmp_path):
    m = read_csv_measurement(_write(tmp_path / "a.csv", QS_TEXT), "quasi_static")
    with pytest.raises(ValueError, match="read-only"):
        m.force[0] = 1.0


def test_columns_in_any_order_bom_crlf_spaces_and_trailing_blank_lines(tmp_path):
    text = ("\ufeffforce [N] , time [s],deflection [m]\r\n"
            " 1.0 ,0.0, 0.001\r\n2.0,0.5,0.002\r\n\r\n\r\n")
    m = read_csv_measurement(_write(tmp_path / "b.csv", text), "quasi_static")
    np.testing.assert_array_equal(m.force, [1.0, 2.0])
    np.testing.assert_array_equal(m.time, [0.0, 0.5])


def test_cr_only_line_ends_read_like_lf(tmp_path):
    """Classic-Mac files (a lone CR ends every line) give the same values and row numbers."""
    lf = read_csv_measurement(_write(tmp_path / "lf.csv", QS_TEXT), "quasi_static")
    cr = read_csv_measurement(_write(tmp_path / "cr.csv", QS_TEXT.replace("\n", "\r")), "quasi_static")
    for name in ("time", "deflection", "force"):
        np.testing.assert_array_equal(getattr(cr, name), getattr(lf, name))
    broken = QS_TEXT.replace("20,1.5", "20,x").replace("\n", "\r")
    with pytest.raises(DataError, match=r"column 'deflection \[mm\]': data row 3 .*file line 4\): found 'x'"):
        read_csv_measurement(_write(tmp_path / "bad.csv", broken), "quasi_static")


@pytest.mark.parametrize("encoding", ["utf-16-le", "utf-16-be", "utf-32-le", "utf-32-be"])
def test_wide_text_without_byte_order_mark_is_named_not_utf8(tmp_path, encoding):
    # was: "header cell 't\x00i\x00m\x00e...' is not of the form 'name [unit]'"
    path = _write(tmp_path / "wide.csv", QS_TEXT.encode(encoding))
    with pytest.raises(DataError, match=f"file '.*wide.csv': not UTF-8 text .*{encoding.upper()} without a "
                                        "byte-order mark"):
        read_csv_measurement(path, "quasi_static")


@pytest.mark.parametrize("deflection, force, words", [
    # read as 0.0 without a word
    ("1e-3", "1e-400", ("column 'force [N]': data row 2 .*found '1e-400', which is nonzero but below "
                        "float64's smallest magnitude")),
    ("1e-3", "-0.00000000000000000001e-310", "found '-0.00000000000000000001e-310', which is nonzero"),
    # was "found inf"
    ("1e-3", "1e400", "column 'force [N]': data row 2 .*found '1e400', which is beyond float64's largest"),
    ("1e-3", "1" + "0" * 400, "column 'force [N]': data row 2 .*beyond float64's largest"),
])
def test_numbers_float64_cannot_hold_are_refused_with_row_and_column(tmp_path, deflection, force, words):
    text = f"time [s],deflection [m],force [N]\n0,0,0\n0.1,{deflection},{force}\n"
    with pytest.raises(DataError, match=words.replace("[N]", r"\[N\]").replace("(", r"\(")):
        read_csv_measurement(_write(tmp_path / "u.csv", text), "quasi_static")


@pytest.mark.parametrize("cells, words", [
    ("5e-324,1", r"column 'deflection \[mm\]': data row 2 .*found 5e-324 mm, which is 0.0 m in SI"),
    ("1,1e306", r"column 'force \[kN\]': data row 2 .*found 1e\+306 kN, which is inf N in SI"),
])
def test_values_the_unit_conversion_would_underflow_or_overflow_are_refused(tmp_path, cells, words):
    text = f"time [s],deflection [mm],force [kN]\n0,0,0\n0.1,{cells}\n"
    with pytest.raises(DataError, match=words):
        read_csv_measurement(_write(tmp_path / "c.csv", text), "quasi_static")


def test_zeros_and_the_smallest_numbers_are_kept(tmp_path):
    text = "time [s],deflection [m],force [N]\n0,0e-400,-0.0\n0.1,5e-324,-1e-320\n"
    m = read_csv_measurement(_write(tmp_path / "z.csv", text), "quasi_static")
    np.testing.assert_array_equal(m.deflection, [0.0, 5e-324])
    np.testing.assert_array_equal(m.force, [-0.0, -1e-320])


def test_gzip_file_is_read_and_hashed_as_stored(tmp_path):
    path = _write(tmp_path / "c.csv.gz", gzip.compress(QS_TEXT.encode(), mtime=0))
    m = read_csv_measurement(path, "quasi_static")
    assert m.info.id == "c"
    assert m.source.sha256 == file_sha256(path)
    np.testing.assert_array_equal(m.force, [-20.0, 5.0, 25.0])


def test_white_noise_accepts_velocities_or_accelerations(tmp_path):
    v = read_csv_measurement(_write(tmp_path / "v.csv", "time [s],v_base [mm/s],v_top [m/s]\n"
                                    "0,1,0.1\n0.001,2,0.2\n"), "white_noise")
    assert isinstance(v, WhiteNoiseMeasurement)
    np.testing.assert_array_equal(v.v_base, [0.001, 0.002])
    a = read_csv_measurement(_write(tmp_path / "a.csv", "time [s],a_base [g],a_top [m/s^2]\n"
                                    "0,1,0.1\n0.001,2,0.2\n"), "white_noise")
    np.testing.assert_allclose(a.a_base, [9.80665, 2 * 9.80665])
    assert a.v_base is None


def test_stepped_sine_needs_frequency_from_info(tmp_path):
    path = _write(tmp_path / "p.csv", "time [s],v_base [m/s],v_top [m/s],u_in [V]\n"
                  "0,0,0,0.1\n0.001,0.1,0.2,0.1\n")
    with pytest.raises(DataError, match="without a frequency"):
        read_csv_measurement(path, "stepped_sine")
    info = MeasurementInfo(id="p", excitation=Excitation(freq=20.0, amplitude=0.01,
                                                         amplitude_quantity="velocity"))
    m = read_csv_measurement(path, "stepped_sine", info=info)
    assert isinstance(m, SteppedSineMeasurement)
    assert m.freq == 20.0 and m.nominal_amplitude == 0.01
    assert m.x_base is None
    np.testing.assert_array_equal(m.u_in, [0.1, 0.1])


def test_drop_in_thousands_of_g(tmp_path):
    path = _write(tmp_path / "d.csv", "time [us],deflection [mm],a_top_1 [1000g],a_top_2 [g]\n"
                  "0,0,0.001,1\n1,-0.1,0.002,2\n")
    m = read_csv_measurement(path, "drop")
    assert isinstance(m, DropMeasurement)
    np.testing.assert_allclose(m.a_top_1, m.a_top_2)
    np.testing.assert_allclose(m.a_top_mean, [9.80665, 2 * 9.80665])
    np.testing.assert_array_equal(m.time, [0.0, 1e-6])


@pytest.mark.parametrize(("declared_hz", "ok"), [(100.0, True), (100.9, True), (99.1, True),
                                                (101.5, False), (98.0, False), (200.0, False)])
def test_declared_sample_rate_checked_within_one_percent(tmp_path, declared_hz, ok):
    text = "time [s],deflection [m],force [N]\n" + "".join(
        f"{k / 100!r},0,0\n" for k in range(20))
    path = _write(tmp_path / "r.csv", text)
    info = MeasurementInfo(id="r", sample_rate_hz=declared_hz)
    if ok:
        read_csv_measurement(path, "quasi_static", info=info)
    else:
        with pytest.raises(DataError, match="tolerance 1%"):
            read_csv_measurement(path, "quasi_static", info=info)


def test_unknown_kind(tmp_path):
    with pytest.raises(DataError, match="a.csv': kind: found 'sweep', expected one of 'quasi_static'"):
        read_csv_measurement(_write(tmp_path / "a.csv", QS_TEXT), "sweep")


def test_missing_file_is_data_error(tmp_path):
    with pytest.raises(DataError, match="not found"):
        read_csv_measurement(tmp_path / "nope.csv", "quasi_static")


def test_successful_read_leaves_file_byte_identical(tmp_path):
    path = _write(tmp_path / "a.csv", QS_TEXT)
    before = (file_sha256(path), path.stat().st_mtime_ns, path.stat().st_mode)
    read_csv_measurement(path, "quasi_static")
    assert (file_sha256(path), path.stat().st_mtime_ns, path.stat().st_mode) == before


# --- constructors check their inputs too -------------------------------------------------

def test_constructor_rejects_length_mismatch():
    with pytest.raises(DataError, match="found 2 values, expected 3 \\(as many as time\\)"):
        QuasiStaticMeasurement(time=[0.0, 1.0, 2.0], deflection=[0.0, 1.0, 2.0], force=[0.0, 1.0])


def test_constructor_rejects_non_finite_with_1_based_sample():
    with pytest.raises(DataError, match=r"sample 2 \(1-based\): found nan"):
        QuasiStaticMeasurement(time=[0.0, 1.0], deflection=[0.0, np.nan], force=[0.0, 1.0])


def test_constructor_rejects_2d_and_text():
    with pytest.raises(DataError, match="expected 1-D"):
        QuasiStaticMeasurement(time=[[0.0, 1.0]], deflection=[0.0, 1.0], force=[0.0, 1.0])
    with pytest.raises(DataError, match="not numbers"):
        QuasiStaticMeasurement(time=["a", "b"], deflection=[0.0, 1.0], force=[0.0, 1.0])


def test_constructor_copies_input():
    force = np.array([0.0, 1.0])
    m = QuasiStaticMeasurement(time=[0.0, 1.0], deflection=[0.0, 1.0], force=force)
    force[0] = 5.0
    assert m.force[0] == 0.0


def test_white_noise_needs_a_complete_pair():
    with pytest.raises(DataError, match="no response columns"):
        WhiteNoiseMeasurement(time=[0.0, 1.0])


@pytest.mark.parametrize("kwargs", [
    {"top_mass_kg": -1.0}, {"top_mass_kg": float("nan")}, {"drop_height_m": 0.0},
    {"repetition": 1.5}, {"repetition": True}, {"split": "test"}, {"sample_rate_hz": float("inf")},
    {"isolator": ""},
])
def test_info_rejects_bad_values(kwargs):
    with pytest.raises(DataError):
        MeasurementInfo(id="x", **kwargs)


@pytest.mark.parametrize("kwargs", [
    {"freq": -1.0}, {"amplitude": 1.0}, {"amplitude": 1.0, "amplitude_quantity": "force"},
    {"band": (10.0, 1.0)}, {"band": (1.0,)},
])
def test_excitation_rejects_bad_values(kwargs):
    with pytest.raises(DataError):
        Excitation(**kwargs)


# --- writer ---------------------------------------------------------------------------------

def _qs() -> QuasiStaticMeasurement:
    t = np.linspace(0.0, 1.0, 11)
    return QuasiStaticMeasurement(time=t, deflection=1e-3 * np.sin(t), force=0.1 + np.cos(t),
                                  info=MeasurementInfo(id="w"))


def test_writer_round_trips_bit_for_bit(tmp_path):
    m = _qs()
    path = write_csv_measurement(m, tmp_path / "w.csv")
    back = read_csv_measurement(path, "quasi_static")
    for name, values in m.signals().items():
        assert np.array_equal(getattr(back, name), values)
    assert path.read_text().splitlines()[0] == "time [s],deflection [m],force [N]"


def test_writer_gzip_is_reproducible(tmp_path):
    a = write_csv_measurement(_qs(), tmp_path / "a.csv.gz")
    b = write_csv_measurement(_qs(), tmp_path / "b.csv.gz")
    assert a.read_bytes() == b.read_bytes()
    assert np.array_equal(read_csv_measurement(a, "quasi_static").force, _qs().force)


def test_writer_with_units(tmp_path):
    path = write_csv_measurement(_qs(), tmp_path / "u.csv",
                                 units={"force": "daN", "deflection": "mm"})
    assert path.read_text().splitlines()[0] == "time [s],deflection [mm],force [daN]"
    back = read_csv_measurement(path, "quasi_static")
    np.testing.assert_allclose(back.force, _qs().force, rtol=1e-15)
    with pytest.raises(DataError, match="unknown unit"):
        write_csv_measurement(_qs(), tmp_path / "v.csv", units={"force": "mm"})
    with pytest.raises(DataError, match="does not have"):
        write_csv_measurement(_qs(), tmp_path / "v.csv", units={"v_top": "m/s"})


def test_writer_refuses_to_overwrite_and_leaves_no_temp_files(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("precious input\n")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        write_csv_measurement(_qs(), path)
    assert path.read_text() == "precious input\n"
    write_csv_measurement(_qs(), path, overwrite=True)
    assert path.read_text().startswith("time [s]")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.csv"]
