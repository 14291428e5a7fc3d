"""``idkit shock``: shock records straight in, tables and figures out, bad input named."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from idkit.io import read_shock_csv
from idkit.observe import condition_shock, shock_pulses
from tests.cli.hostile import check, run_main

FS = 100_000.0


def write_record(path, *, amplitude_g=200.0, offset_g=1.0, unit="g", tests=2, header=None):
    time = np.arange(int(0.02 * FS)) / FS
    pulse = np.where((time >= 0.004) & (time <= 0.007), np.sin(np.pi * (time - 0.004) / 0.003), 0.0)
    columns = [offset_g + amplitude_g * (1 + 0.2 * k) * pulse for k in range(tests)]
    lines = [header or ",".join(["time [s]"] + [f"shot_{k + 1} [{unit}]" for k in range(tests)])]
    lines += [",".join(repr(float(v)) for v in row) for row in zip(time, *columns)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_records_in_tables_and_figures_out(tmp_path):
    response = write_record(tmp_path / "payload.csv", amplitude_g=300.0)
    fixture = write_record(tmp_path / "fixture.csv")
    out = tmp_path / "shock"
    outcome = run_main(["shock", response, "--input", fixture, "-o", out], inputs=[response, fixture])
    check(outcome, "ok")
    pulses = pd.read_csv(out / "pulses.csv")
    expected = shock_pulses(condition_shock(read_shock_csv(response)).record)
    np.testing.assert_allclose(pulses.loc[pulses.channel == "payload", "peak [m/s^2]"], expected.peak, rtol=1e-12)
    # offset of 1 g removed; half-sine dv = 2 A tau / pi
    np.testing.assert_allclose(pulses.loc[pulses.channel == "payload", "velocity_change [m/s]"],
                               2 * 300 * 9.80665 * np.array([1.0, 1.2]) * 0.003 / np.pi, rtol=2e-3)
    ratio = pd.read_csv(out / "ratio_payload.csv")
    np.testing.assert_allclose(ratio.filter(like="test_").to_numpy(), 1.5, rtol=1e-9)
    for name in ("payload_srs.png", "payload_srs.svg", "fixture_pulses.png", "payload_ratio.svg"):
        assert (out / name).stat().st_size > 0
    assert "velocity_change" in outcome.stdout


def test_points_apply_to_the_default_band(tmp_path):
    """``--points`` without ``--freq-min/--freq-max`` sets the number of natural frequencies of the default band."""
    from idkit.observe.shock import default_srs_band

    path = write_record(tmp_path / "payload.csv")
    out = tmp_path / "shock"
    check(run_main(["shock", path, "--points", "7", "-o", out], inputs=[path]), "ok")
    spectra = pd.read_csv(out / "spectra.csv")
    np.testing.assert_array_equal(spectra.loc[spectra.test == spectra.test.iloc[0], "freq [Hz]"],
                                  default_srs_band(read_shock_csv(path), 7))


@pytest.mark.parametrize("case, header, words", [
    ("unknown-unit", "time [s],shot_1 [furlong/s^2]", ["furlong/s^2", "shot_1", "accepted"]),
    ("missing-unit", "time [s],shot_1", ["shot_1", "unit missing"]),
    ("no-time-column", "t_ms [ms],shot_1 [g]", ["column 1", "time"]),
])
def test_bad_files_are_named(tmp_path, case, header, words):
    path = write_record(tmp_path / "bad.csv", header=header, tests=1)
    outcome = run_main(["shock", path], inputs=[path])
    check(outcome, "error", ["bad.csv", *words], case=f"shock-{case}")


def test_band_above_the_sample_rate_is_refused(tmp_path):
    path = write_record(tmp_path / "slow.csv")
    outcome = run_main(["shock", path, "--freq-min", "10", "--freq-max", "20000"], inputs=[path])
    check(outcome, "error", ["slow.csv", "too slowly", "20000 Hz"], case="shock-band-too-high")


def test_output_over_an_input_is_refused(tmp_path):
    path = write_record(tmp_path / "in.csv")
    outcome = run_main(["shock", path, "-o", tmp_path], inputs=[path], must_not_exist=[])
    check(outcome, "error", ["-o"], case="shock-output-over-input")


@pytest.mark.parametrize("as_input", [False, True])
def test_two_records_of_one_channel_are_refused(tmp_path, as_input):
    """Two files named payload.csv: the second's figures replaced the first's, the tables held 'payload' twice."""
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first = write_record(tmp_path / "a" / "payload.csv", amplitude_g=300.0)
    second = write_record(tmp_path / "b" / "payload.csv")
    out = tmp_path / "shock"
    argv = ["shock", first, *(["--input"] if as_input else []), second, "-o", out]
    outcome = run_main(argv, inputs=[first, second], must_not_exist=[out], watch=[tmp_path])
    check(outcome, "error", ["channel 'payload' given twice", str(first), str(second)], case="shock same channel")


def test_a_missing_sample_is_refused_not_spread_over_the_record(tmp_path):
    """A row removed from a 100 kHz record was analysed at 1 / median step (spectra, velocity change)."""
    record = write_record(tmp_path / "payload.csv")
    lines = record.read_text().splitlines(keepends=True)
    record.write_text("".join(lines[:501] + lines[502:]))  # data row 501 (t = 5 ms) removed
    outcome = run_main(["shock", record], inputs=[record])
    check(outcome, "error", ["payload.csv", "column 'time [s]'", "data row 501", "2 x the median step 1e-05 s",
                             "expected uniform sampling"])


@pytest.mark.parametrize("freq_min, samples", [("1e-300", "1e+305"), ("1e-4", "1e+09")])
def test_a_residual_window_beyond_the_step_limit_is_refused(tmp_path, freq_min, samples):
    """--freq-min 1e-300 ended in numpy's 'Maximum allowed dimension exceeded' traceback (one period of
    the lowest natural frequency is padded after the record: 1e305 samples)."""
    record = write_record(tmp_path / "payload.csv")
    outcome = run_main(["shock", record, "--freq-min", freq_min, "--freq-max", "1000"], inputs=[record])
    check(outcome, "error", [f"lowest natural frequency {float(freq_min):g} Hz", f"{samples} samples at 100000 Hz",
                             "expected at most 1e+08", ">= 0.001 Hz"])


@pytest.mark.parametrize("lowpass", ["1e-300", "10"])
def test_a_lowpass_below_one_over_the_record_length_is_refused(tmp_path, lowpass):
    """--lowpass 10 on a 20 ms record with a 1 ms, 100 m/s^2 half sine reported a peak of 0.42 m/s^2 lasting the
    whole record, exit 0 (only the mean and trend survive); --lowpass 1e-300 ended in a LinAlgError traceback."""
    record = write_record(tmp_path / "payload.csv")
    outcome = run_main(["shock", record, "--lowpass", lowpass], inputs=[record])
    check(outcome, "error", [f"lowpass_hz: found {float(lowpass)!r}", "below 1 / record length = 50.025 Hz",
                             "expected a cut-off in [50.025, 50000) Hz"])


def test_idkit_drop_records_are_read_as_shock_records():
    """A drop record of a measurement set: its two top-mass accelerometers are the record's
    tests, its id the channel; it starts at impact, so no pre-trigger offset is removed."""
    from pathlib import Path

    from idkit.io.discover import load_measurements
    from idkit.io.shock_csv import read_shock_file
    from idkit.studies.shock import analyse_shock

    drop = Path(__file__).resolve().parents[2] / "data" / "wire_rope" / "drop" / "drop_wr_4.33kg_04cm_1.csv.gz"
    (record,) = load_measurements(drop)[1]
    shock = read_shock_file(drop)
    assert shock.channel == record.id and shock.source.column_label("test 2") == "a_top_2 [m/s^2]"
    np.testing.assert_array_equal(shock.accel, np.column_stack([record.a_top_1, record.a_top_2]))
    outcome = run_main(["shock", drop, "--points", "8"], inputs=[drop])
    check(outcome, "ok", [record.id, "offset none"])
    pulses = analyse_shock([shock], n_points=8, offset="none").pulses[0]
    # offset none: the peak is the recorded sample of largest magnitude of each accelerometer
    np.testing.assert_allclose(pulses.peak, [np.abs(record.a_top_1).max(), np.abs(record.a_top_2).max()],
                               rtol=1e-12)
