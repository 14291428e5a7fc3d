"""Measurement-level processing: simulated truth, generated data and the real MR-damper loops."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from idkit.observe.quality import find_clipping, summarize_measurements
from idkit.observe.white_noise import frf_from_white_noise
from idkit.observe.stepped_sine import hosidf_from_stepped_sine, stepped_sine_sweep
from idkit.signal.cycles import noise_level
from idkit.observe.drop import process_drop_measurement
from idkit.observe.quasi_static import process_quasi_static
from idkit.errors import DataError
from idkit.io import DropMeasurement, Excitation, MeasurementInfo, SteppedSineMeasurement, WhiteNoiseMeasurement, read_csv_measurement, read_manifest
from idkit.datasets import read_mr_damper
from idkit.datasets import realdata_dir
from idkit.models import GeneralizedMaxwell, IwanModel, SDOFSystem
from idkit.simulate import STANDARD_GRAVITY, free_fall, simulate

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.mark.parametrize("seed", [3, 7])
def test_h1_of_a_simulated_linear_system_is_within_coherence_based_bounds(seed):
    """Elastomer (Table 7.3) on 0.99 kg, random base acceleration, noise on the output only:
    |H1 / H - 1| below 6 random errors eps (Bendat & Piersol 9.90) plus a 3 % bias.

    The bias is the time step's: the average-acceleration step at h = 1 ms shifts a
    frequency by (w h)^2 / 12 = 3.3 % at 100 Hz. The random part is Rayleigh with scale
    eps (P(> 6 eps) = 1.5e-8 per line); over 12 noise seeds the largest excess over the
    bias was 4.3 eps, so 4 eps (the former bound) failed one seed in twelve.
    """
    rng = np.random.default_rng(seed)
    fs, seconds = 1000.0, 60.0
    time = np.arange(int(fs * seconds) + 1) / fs
    system = SDOFSystem(0.99, GeneralizedMaxwell(k0=1.40e4, k=[3.49e3, 1.07e4], rate=[46.6, 841.0],
                                                 m_eff=0.163))
    spectrum = np.fft.rfft(rng.standard_normal(time.size))
    spectrum[np.fft.rfftfreq(time.size, 1 / fs) < 1.0] = 0.0  # no drift of the base velocity
    base_accel = 5.0 * np.fft.irfft(spectrum, time.size)
    response = simulate(system, time, base_acceleration=base_accel[None, :])
    from idkit.simulate.base_motion import integrate_acceleration

    _, base_velocity = integrate_acceleration(base_accel, 1.0 / fs)
    top_velocity = response.velocity[0, 0] + base_velocity
    top_velocity = top_velocity + 0.002 * np.std(top_velocity) * rng.standard_normal(time.size)
    run = WhiteNoiseMeasurement(time=time, v_base=base_velocity, v_top=top_velocity,
                                info=MeasurementInfo(id="sim", top_mass_kg=0.99))
    frf = frf_from_white_noise(run, band=(2.0, 100.0), resolution_hz=0.5)  # 2000-sample segments
    exact = system.transmissibility(frf.freq)
    error = np.abs(frf.h1 / exact - 1)
    assert np.all(error < 6 * frf.estimate.random_error + 0.03)
    assert frf.min_coherence > 0.9 and frf.top_mass_kg == 0.99


def test_hosidf_of_a_synthetic_point_recovers_harmonics_and_input_distortion():
    rng = np.random.default_rng(3)
    fs, freq = 2000.0, 12.5
    t = np.arange(1600) / fs
    w = 2 * np.pi * freq
    v_base = 0.01 * (np.sin(w * t) + 0.01 * np.sin(2 * w * t + 0.4) + 0.007 * np.sin(3 * w * t))
    v_top = 0.02 * np.sin(w * t - 0.5) + 0.001 * np.sin(3 * w * t + 1.0)
    noise = 1e-5
    info = MeasurementInfo(id="p", isolator="x", top_mass_kg=1.0,
                           excitation=Excitation(freq=freq, amplitude=0.01, amplitude_quantity="velocity"))
    point = hosidf_from_stepped_sine(SteppedSineMeasurement(
        time=t, v_base=v_base + noise * rng.standard_normal(t.size),
        v_top=v_top + noise * rng.standard_normal(t.size), info=info), n_harmonics=3)
    tolerance = 1e-3  # ~ 10 standard errors of 1e-5 noise on 1600 samples, relative to 0.01
    assert abs(point.hosidf[0]) == pytest.approx(2.0, abs=tolerance * 2)
    assert np.angle(point.hosidf[0]) == pytest.approx(-0.5, abs=tolerance)
    assert abs(point.hosidf[2]) == pytest.approx(0.1, abs=tolerance)
    assert point.input_distortion == pytest.approx([0.01, 0.007], abs=tolerance)
    sweep = stepped_sine_sweep([point_measurement(freq=f) for f in (5.0, 10.0, 20.0)])
    flat = next(iter(sweep.flatness.values()))
    assert flat.ratio == pytest.approx(2.0, rel=1e-6)
    assert len(sweep.to_dataframe()) == 3


def point_measurement(freq):
    t = np.arange(2000) / 2000.0
    amplitude = 0.01 * (freq / 5.0) ** 0.5
    return SteppedSineMeasurement(
        time=t, v_base=amplitude * np.sin(2 * np.pi * freq * t),
        v_top=amplitude * np.sin(2 * np.pi * freq * t),
        info=MeasurementInfo(id=f"p{freq:g}", isolator="x", top_mass_kg=1.0,
                             excitation=Excitation(freq=freq, amplitude=0.01,
                                                   amplitude_quantity="velocity")))


def test_drop_processor_recovers_the_peaks_of_a_simulated_drop():
    """Table 7.1 wire rope, 4.33 kg, 5 cm conditioned free fall (simulated at 100 kHz),
    recorded at 2 kHz after 40 samples of free fall. Peak acceleration within 3 % (sampling and
    the 5-sample forward-backward average lose ~2 (w T)^2), peak compression within 1 %,
    measured impact velocity within the documented smoothing bias 10 (w0 T)^2 + 1 %."""
    model = IwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3],
                      c_visc=4.0)
    mass, height = 4.33, 0.05
    fine = free_fall(SDOFSystem(mass, model), drop_height=[height], duration=0.3, time_step=1e-5)
    every = 50  # 2 kHz
    lead = 40
    deflection = np.concatenate([np.zeros(lead), fine.deflection[0, 0, ::every]])
    v_rel = np.concatenate([np.zeros(lead), fine.velocity[0, 0, ::every]])
    accel = np.concatenate([np.zeros(lead), fine.acceleration[0, 0, ::every]])
    time = np.arange(deflection.size) / 2000.0
    drop = DropMeasurement(time=time, deflection=deflection, a_top_1=accel, a_top_2=accel,
                           v_rel=v_rel, info=MeasurementInfo(id="sim", drop_height_m=height,
                                                             top_mass_kg=mass))
    result = process_drop_measurement(drop)
    compressed = fine.deflection[0, 0] < 0
    true_peak = np.abs(fine.acceleration[0, 0][compressed]).max()
    assert result.result.peak_acceleration_compression == pytest.approx(true_peak, rel=0.03)
    assert result.result.max_compression == pytest.approx(-fine.deflection[0, 0].min(), rel=0.01)
    v0 = -np.sqrt(2 * STANDARD_GRAVITY * height)
    assert result.impact_velocity_from_height == pytest.approx(v0, rel=1e-12)
    omega_t = np.sqrt(model.stuck_stiffness / mass) / 2000.0
    assert abs(result.impact_velocity / v0 - 1) < 10 * omega_t**2 + 0.01
    assert result.result.impact_index == pytest.approx(lead, abs=1)


def _bundled(name, kind):
    if not (DATA / name / "manifest.json").exists():
        pytest.skip("bundled data/ not generated")
    manifest = read_manifest(DATA / name)
    records = [read_csv_measurement(DATA / name / e.file, e.kind, info=e.info)
               for e in manifest.entries if e.kind == kind]
    assert records, f"data/{name} holds no {kind} record: the checks below would pass on nothing"
    return records


def test_quasi_static_processing_of_the_bundled_wire_rope_finds_the_programmed_loops():
    truth = json.loads((DATA / "truth" / "wire_rope.json").read_text())["measurements"]
    for loops in _bundled("wire_rope", "quasi_static"):
        result = process_quasi_static(loops, large_threshold=4.6e-3, points_per_branch=50)
        programmed = np.repeat(truth[loops.id]["amplitudes_m"], 4)  # +A, -A, +A, -A each
        turning = np.abs(loops.deflection[result.cycles.reversals])
        assert turning.size == programmed.size
        # 50 Hz sampling misses a turning point by up to one sample of travel: at most about
        # 5 x the mean hand speed / 50 Hz (jerks, fast spells); noise adds a few um
        travel = 5 * truth[loops.id]["mean_speed_m_per_s"] / 50.0
        assert np.all(turning <= programmed + 5e-6) and np.all(turning >= programmed - travel)
        assert result.n_cycles == (programmed.size - 1) // 2  # consecutive branch pairs
        n_branches = result.cycles.branch_start.size
        assert result.loops.deflection.size == n_branches * 49 + 1
        assert result.deflection_noise == pytest.approx(1e-6, rel=0.2)


def test_drop_processing_of_the_bundled_drops_recovers_the_true_peaks():
    """Generated drops (noise, bounce, relaxation) vs the noise-free simulated truth:
    rest shock level within 8 %, peak compression (from the unloaded zero) within 5 %."""
    for name in ("wire_rope", "elastomer", "hybrid"):
        truth = json.loads((DATA / "truth" / f"{name}.json").read_text())["measurements"]
        for drop in _bundled(name, "drop")[::5]:
            result = process_drop_measurement(drop)
            record = truth[drop.id]
            assert result.peak_acceleration == pytest.approx(record["peak_acceleration_m_per_s2"],
                                                             rel=0.08)
            lowest = result.result.deflection_reference - result.result.max_compression
            assert -lowest == pytest.approx(record["max_compression_m"], rel=0.05)


def test_summary_flags_clipping_and_non_flat_input():
    sweep = [point_measurement(freq=f) for f in (5.0, 10.0, 20.0)]
    t = np.arange(400) / 2000.0
    clipped = np.clip(np.sin(2 * np.pi * 10 * t), -0.8, 0.8)
    sweep.append(SteppedSineMeasurement(
        time=t, v_base=np.sin(2 * np.pi * 10 * t), v_top=clipped,
        info=MeasurementInfo(id="clipped", excitation=Excitation(freq=10.0))))
    summary = summarize_measurements(sweep)
    kinds = {(w.measurement_id, w.kind) for w in summary.warnings}
    assert ("clipped", "clipped") in kinds
    assert any(kind == "non_flat_input" for _, kind in kinds)
    assert "warning" in summary.report() and len(summary.to_dataframe()) == 4
    assert find_clipping(np.sin(np.linspace(0, 6, 100))) == (0, pytest.approx(np.nan, nan_ok=True))
    assert noise_level(np.zeros(10)) == 0.0
    with pytest.raises(DataError, match="expected QuasiStaticMeasurement"):
        process_quasi_static(sweep[0])


def test_mr_damper_cycle_count_matches_the_documented_excitation():
    """Real MR-damper loops (mr_damper_labcontrol). The test log Ensaios.ods documents no cycle
    count; its entry Ensaio1 gives F = 0.833 Hz and stroke 24.42 mm, and SOURCE.txt 30 s records.
    The file data_simulation_4.1 is that test (stroke 24.7 mm, 30 s, 0.83 Hz): the sine starts
    after the damper rests at its lower end, so the documented count is the number of whole
    excitation periods in the moving part, floor(0.833 Hz x (30 s - t_start)) = 23."""
    folder = realdata_dir("mr_damper_labcontrol")
    if folder is None:
        pytest.skip("real data folder 'mr_damper_labcontrol' not found (set IDKIT_REALDATA or "
                    "place shared/realdata beside the repository)")
    path = folder / "data" / "data_simulation_4.1_MRdamper.mat"
    if not path.exists():
        pytest.skip(f"{path.name} not in {folder}")
    loops = read_mr_damper(path)
    documented_freq, documented_stroke = 0.833, 24.42e-3  # Ensaios.ods, Ensaio1
    x = loops.deflection
    start = loops.time[np.flatnonzero(np.abs(x - x[0]) > 1e-4)[0]]
    expected = int(np.floor(documented_freq * (loops.time[-1] - start)))
    result = process_quasi_static(loops)
    assert result.n_cycles == expected == 23
    periods = np.diff(loops.time[result.cycles.cycle_start])
    assert np.median(periods) == pytest.approx(1 / documented_freq, rel=0.02)
    assert 2 * np.median(result.amplitude) == pytest.approx(documented_stroke, rel=0.03)


def test_loop_amplitude_range_is_half_the_travel_between_reversals():
    """Branch amplitudes of a path through known reversals (cut at its first and last reversal,
    as loop_set cuts a record): half the travel between consecutive reversals; the range spans
    every set."""
    from idkit.observe.quasi_static import LoopData, LoopSet

    def loop(turns, name):
        path = np.concatenate([np.linspace(a, b, 20, endpoint=False) for a, b in zip(turns[:-1], turns[1:])]
                              + [[turns[-1]]])
        reversals = np.append(np.arange(len(turns) - 1) * 20, path.size - 1)
        return LoopSet(deflection=path, force=3e3 * path, reversals=reversals, name=name)

    small = loop([5e-5, -5e-5, 1e-4, -1e-4], "small")  # branches 5e-5, 7.5e-5, 1e-4
    large = loop([2e-3, -2e-3, 1.5e-3], "large")  # 2e-3, 1.75e-3
    np.testing.assert_allclose(small.branch_amplitudes, [5e-5, 7.5e-5, 1e-4], rtol=1e-12)
    np.testing.assert_allclose(large.branch_amplitudes, [2e-3, 1.75e-3], rtol=1e-12)
    data = LoopData(small=(small,), large=(large,), small_repetitions=(1,), large_repetitions=(1,), amplitudes={},
                    threshold=8e-3, provenance=None)
    assert data.amplitude_range() == pytest.approx((5e-5, 2e-3), rel=1e-12)
