"""Hostile variants of the shared real data, written to tmp_path (never into the repository).

Each variant is read correctly or refused with a named error; nothing is dropped or altered
silently. Skipped when ``../shared/realdata`` is absent.
"""

from __future__ import annotations

import numpy as np
import pytest

from idkit.datasets import read_afrl_accel
from idkit.errors import DataError


def _afrl_lines(realdata, k=1):
    lines = (realdata("droptower_shock_afrl") / f"accel_{k}.csv").read_text().splitlines(keepends=True)
    return lines[:2], lines[2:]


@pytest.mark.parametrize("row", [1, 2000, 4998])
def test_afrl_record_with_a_missing_sample_is_refused(realdata, tmp_path, row):
    """A removed row (a step of 2 us in a 1 MS/s record) was read, and the SRS, filter and velocity
    change ran at 1 / median step as if the samples were evenly spaced."""
    head, body = _afrl_lines(realdata)
    path = tmp_path / "accel_1.csv"
    path.write_text("".join(head + body[:row] + body[row + 1:]))
    with pytest.raises(DataError, match=rf"data row {row + 1} .*time step 2e-06 s.*2 x the median step 1e-06 s.*"
                                        r"expected uniform sampling"):
        read_afrl_accel(path)


def _boucwen_variables(realdata):
    scipy_io = pytest.importorskip("scipy.io")
    path = realdata("boucwen_benchmark") / "bouc-wen.mat"
    return scipy_io, {k: v for k, v in scipy_io.loadmat(path).items() if not k.startswith("__")}


@pytest.mark.parametrize("index", [0, 1000, 40959])
def test_boucwen_benchmark_nan_is_named_by_sample(realdata, tmp_path, index):
    """The message was only "found non-finite values": no sample, no count."""
    scipy_io, variables = _boucwen_variables(realdata)
    y = variables["y"].copy()
    y[0, index] = np.nan
    scipy_io.savemat(tmp_path / "bouc-wen.mat", {**variables, "y": y})
    from idkit.datasets import read_boucwen_benchmark

    with pytest.raises(DataError, match=rf"column 'y': sample {index + 1} \(1-based\): found nan, expected a finite "
                                        r"number \(1 non-finite value\(s\) in total\)"):
        read_boucwen_benchmark(tmp_path / "bouc-wen.mat")


def test_boucwen_benchmark_truncated_signal_names_both_lengths(realdata, tmp_path):
    """A training force three samples short said only "force and displacement lengths differ"."""
    scipy_io, variables = _boucwen_variables(realdata)
    scipy_io.savemat(tmp_path / "bouc-wen.mat", {**variables, "u": variables["u"][:-3]})
    from idkit.datasets import read_boucwen_benchmark

    with pytest.raises(DataError, match=r"train: found 40957 samples of 'u' \(force\) and 40960 of 'y' "
                                        r"\(displacement\), expected equal lengths"):
        read_boucwen_benchmark(tmp_path / "bouc-wen.mat")


def test_afrl_one_ulp_moves_the_shock_analysis_by_rounding_only(realdata, tmp_path):
    """Every nonzero acceleration of accel_1 moved by one ulp: peaks, velocity changes and the three spectra
    move by rounding, not by a changed pulse window or trigger (measured: 2.2e-16 peak, 1.3e-15 velocity
    change, 6e-13 spectra). Bound of the spectra: the recursive filters accumulate one rounding per sample
    of the padded record (5000 samples + one period of the lowest natural frequency, 1/T: 10000), eps each."""
    from idkit.studies.shock import analyse_shock

    head, body = _afrl_lines(realdata)
    rows = [line.strip().split(",") for line in body]
    moved = [",".join([row[0]] + [repr(float(np.nextafter(float(v), np.inf))) if float(v) != 0 else v
                                  for v in row[1:]]) + "\n" for row in rows]
    path = tmp_path / "accel_1.csv"
    path.write_text("".join(head + moved))
    fixture = read_afrl_accel(realdata("droptower_shock_afrl") / "accel_6.csv")
    before = analyse_shock([read_afrl_accel(realdata("droptower_shock_afrl") / "accel_1.csv")], input=fixture)
    after = analyse_shock([read_afrl_accel(path)], input=fixture)
    eps = np.finfo(float).eps
    a, b = before.pulse_table(), after.pulse_table()
    assert (a["time_of_peak [s]"] == b["time_of_peak [s]"]).all() and (a["duration [s]"] == b["duration [s]"]).all()
    for column in ("peak [m/s^2]", "velocity_change [m/s]", "offset_removed [m/s^2]"):
        np.testing.assert_allclose(b[column], a[column], rtol=16 * eps, atol=0)
    for s_before, s_after in zip(before.spectra[0].spectra, after.spectra[0].spectra):
        for name in ("absolute_acceleration", "pseudo_velocity", "relative_displacement"):
            np.testing.assert_allclose(getattr(s_after, name), getattr(s_before, name), rtol=10000 * eps, atol=0)


@pytest.mark.parametrize("value", ["3.0", None])
def test_pyvisco_shift_factor_repeated_temperature_is_refused(realdata, tmp_path, value):
    """A temperature given twice (62 C as -7.74 and 3.0) was read, and master_curve took the first row's
    shift factor without a word."""
    from idkit.datasets import read_pyvisco_shift_factors

    lines = (realdata("pyvisco_dma") / "examples" / "freq_user_master__shift_factors.csv").read_text().splitlines(
        keepends=True)
    head, body = lines[:2], lines[2:]
    temperature, log_a_t = (cell.strip() for cell in body[5].split(","))
    repeat = f"{temperature},{value if value is not None else log_a_t}\n"
    path = tmp_path / "shift_factors.csv"
    path.write_text("".join(head + body[:6] + [repeat] + body[6:]))
    with pytest.raises(DataError, match=rf"data row 7 .*temperature 335.15 K repeats data row 6 .*\(log_aT "
                                        rf"{log_a_t} there, {value or log_a_t} here\); expected one shift factor"):
        read_pyvisco_shift_factors(path)
