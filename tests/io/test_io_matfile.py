"""read_mat: column specs with units, shapes, errors."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io

from idkit.errors import DataError
from idkit.io import MatColumn, MeasurementInfo, file_sha256, read_mat
from idkit.io.matfile import parse_mat_column

COLUMNS = {"time": "t [s]", "deflection": "x_F[:,0] [mm]", "force": "x_F[:,2] [N]"}


@pytest.fixture
def mat_path(tmp_path):
    t = np.arange(20) * 0.01
    path = tmp_path / "loop.mat"
    scipy.io.savemat(path, {"t": t[None, :], "x_F": np.column_stack([t, 2 * t, 3 * t]),
                            "label": "text", "cube": np.zeros((2, 2, 2))})
    return path


def test_read_mat_converts_and_records_provenance(mat_path):
    before = (file_sha256(mat_path), mat_path.stat().st_mtime_ns)
    m = read_mat(mat_path, "quasi_static", columns=COLUMNS,
                 info=MeasurementInfo(id="loop", sample_rate_hz=100.0))
    np.testing.assert_array_equal(m.deflection, np.arange(20) * 0.01 / 1000)
    np.testing.assert_array_equal(m.force, 3 * (np.arange(20) * 0.01))
    assert m.source.sha256 == before[0]
    assert (file_sha256(mat_path), mat_path.stat().st_mtime_ns) == before
    assert m.source.column_label("deflection") == "x_F[:,0] [mm]"


@pytest.mark.parametrize(("columns", "match"), [
    ({**COLUMNS, "force": "x_F[:,2]"}, "unit missing"),
    ({**COLUMNS, "force": "x_F[:,2] [tonf]"}, "unknown unit 'tonf'"),
    ({**COLUMNS, "force": "F [N]"}, "variable 'F' not in the file"),
    ({**COLUMNS, "force": "x_F[:,5] [N]"}, "column 5 \\(0-based\\)"),
    ({**COLUMNS, "force": "x_F [N]"}, "expected a vector"),
    ({**COLUMNS, "force": "cube [N]"}, "expected a vector"),
    ({**COLUMNS, "force": "label [N]"}, "expected real numbers"),
    ({**COLUMNS, "force": "x_F(:,3) [N]"}, "column spec"),
    ({"time": "t [s]", "deflection": "x_F[:,0] [mm]"}, "lacks \\['force'\\]"),
    ({**COLUMNS, "temperature": "t [K]"}, "unknown \\['temperature'\\]"),
    # AttributeError ('items') before
    (None, "columns: found NoneType, expected a mapping"),
    (["t [s]", "x_F[:,0] [mm]", "x_F[:,2] [N]"], "columns: found list, expected a mapping"),
])
def test_read_mat_errors(mat_path, columns, match):
    with pytest.raises(DataError, match=match):
        read_mat(mat_path, "quasi_static", columns=columns)


def test_length_mismatch_and_nan_in_mat(tmp_path):
    path = tmp_path / "bad.mat"
    scipy.io.savemat(path, {"t": np.arange(5.0), "x": np.array([0.0, 1.0, np.nan, 3.0, 4.0]),
                            "f": np.arange(4.0)})
    with pytest.raises(DataError, match=r"column 'x \[m\]': sample 3 \(1-based\): found nan"):
        read_mat(path, "quasi_static", columns={"time": "t [s]", "deflection": "x [m]",
                                                 "force": "t [N]"})
    with pytest.raises(DataError, match="found 4 values, expected 5"):
        read_mat(path, "quasi_static", columns={"time": "t [s]", "deflection": "t [m]",
                                                 "force": "f [N]"})


def _read_force(path, spec):
    return read_mat(path, "quasi_static", columns={"time": "t [s]", "deflection": "d [m]", "force": spec})


def test_integers_float64_would_round_are_refused_by_variable_and_sample(tmp_path):
    path = tmp_path / "ints.mat"
    scipy.io.savemat(path, {
        "t": np.arange(4.0), "d": np.zeros(4),
        "big": np.array([0, 1, 2**53 + 1, 3], dtype=np.int64),               # read as 2^53 without a word
        "umax": np.array([0, 1, 2**64 - 1, 3], dtype=np.uint64),
        "exact": np.array([0, -(2**63), 2**62, 2**53], dtype=np.int64),      # powers of two: exact
        "small": np.array([0, 1, 2**31 - 1, -(2**31)], dtype=np.int32),
    })
    with pytest.raises(DataError, match=r"column 'big \[N\]': variable 'big' \(int64\) sample 3 \(1-based\): "
                                        r"found 9007199254740993, which float64 cannot hold exactly"):
        _read_force(path, "big [N]")
    with pytest.raises(DataError, match=r"variable 'umax' \(uint64\) sample 3 .*found 18446744073709551615"):
        _read_force(path, "umax [N]")
    np.testing.assert_array_equal(_read_force(path, "exact [N]").force, [0.0, -(2.0**63), 2.0**62, 2.0**53])
    np.testing.assert_array_equal(_read_force(path, "small [N]").force, [0.0, 1.0, 2.0**31 - 1, -(2.0**31)])


def test_values_the_unit_conversion_would_overflow_are_refused(tmp_path):
    path = tmp_path / "huge.mat"
    scipy.io.savemat(path, {"t": np.arange(4.0), "d": np.zeros(4), "f": np.array([0.0, 1.0, 1e306, 3.0])})
    # was a RuntimeWarning and "found inf"
    with pytest.raises(DataError, match=r"column 'f \[kN\]': sample 3 \(1-based\): found 1e\+306 kN, which is "
                                        r"inf N in SI"):
        _read_force(path, "f [kN]")


def test_not_a_mat_file(tmp_path):
    path = tmp_path / "x.mat"
    path.write_bytes(b"not a mat file at all")
    with pytest.raises(DataError, match="not a readable MATLAB"):
        read_mat(path, "quasi_static", columns=COLUMNS)
    path.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(100))
    with pytest.raises(DataError, match="v7.3"):
        read_mat(path, "quasi_static", columns=COLUMNS)


def test_parse_mat_column():
    assert parse_mat_column("x_F[:, 2] [mm/s]", where="t") == MatColumn("x_F", 2, "mm/s")
    assert parse_mat_column("Tout [s]", where="t") == MatColumn("Tout", None, "s")
    assert parse_mat_column("Tout", where="t") == MatColumn("Tout", None, None)
