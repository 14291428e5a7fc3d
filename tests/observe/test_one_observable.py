"""One answer per question: inspect, fit and validate see the same loops and the same H1.

The agreements below are exact (``np.array_equal``): the three callers run the same
function on the same record, so any difference would be a second definition.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.fit import fit_maxwell, loop_sets, transmissibility_sets
from idkit.fit.elastomer_data import elastomer_data
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, WhiteNoiseMeasurement, write_measurement_set
from idkit.io import load_measurement_set
from idkit.io.manifest import MANIFEST_NAME
from idkit.io.selection import select_measurements
from idkit.models import IwanModel, library
from idkit.observe.quasi_static import prepare_loops, process_quasi_static
from idkit.observe.white_noise import FRF_RESOLUTION_HZ, frf_from_white_noise
from idkit.signal.cycles import noise_level, reversal_threshold
from idkit.validate import validate_frf

ELASTOMER = library.get("table_7_3_elastomer")
WIRE_ROPE = IwanModel(g1=3e3, k=[3e3, 3e3], fc=[8.3, 14.6])


def _growing_loops(seed: int) -> QuasiStaticMeasurement:
    """Loops from 0.1 mm to 10 mm amplitude (the smallest is 1 % of the range) with 2 um noise."""
    rng = np.random.default_rng(seed)
    amplitudes = np.array([0.1e-3, 0.3e-3, 1e-3, 3e-3, 10e-3])
    phase = np.linspace(0.0, 2 * np.pi * amplitudes.size, 6000)
    x = np.repeat(amplitudes, 1200) * np.sin(phase)
    force = WIRE_ROPE.force(x)
    x = x + 2e-6 * rng.standard_normal(x.size)
    info = MeasurementInfo(id=f"qs_{seed}", isolator="wire_rope", split="fit", sample_rate_hz=50.0)
    return QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=force, info=info)


def _white_noise(mass: float, seed: int, fs: float = 1000.0, n: int = 32768) -> WhiteNoiseMeasurement:
    rng = np.random.default_rng(seed)
    base = rng.standard_normal(n)
    freq = np.fft.rfftfreq(n, 1 / fs)
    stiffness = ELASTOMER.complex_stiffness(np.maximum(freq, 1e-3))
    h = stiffness / (stiffness - (mass + ELASTOMER.m_eff) * (2 * np.pi * freq) ** 2)
    top = np.fft.irfft(np.fft.rfft(base) * h, n) + 0.01 * rng.standard_normal(n)
    info = MeasurementInfo(id=f"wn_{mass:g}_{seed}", isolator="elastomer", top_mass_kg=mass, split="fit",
                           repetition=seed, sample_rate_hz=fs)
    return WhiteNoiseMeasurement(time=np.arange(n) / fs, v_base=base, v_top=top, info=info)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_inspect_and_the_fit_cut_a_record_at_the_same_reversals(seed):
    """The smallest loop (0.1 mm, 1 % of the range) lies below the former fit threshold (2 % of the
    range) and far above the noise-based one (10 x 2 um): both paths now keep all of it."""
    record = _growing_loops(seed)
    inspected = process_quasi_static(record)
    fitted = prepare_loops(record.deflection, record.force, points_per_set=None, name=record.id)
    reversals = inspected.cycles.reversals
    assert inspected.min_excursion == reversal_threshold(record.deflection)
    assert inspected.min_excursion < 0.02 * np.ptp(record.deflection)  # the old fit rule would lose loops
    assert np.array_equal(fitted.reversals, reversals - reversals[0])
    assert np.array_equal(fitted.deflection, record.deflection[reversals[0]: reversals[-1] + 1])
    assert reversals.size == 10  # every peak and valley of the five loops, the 0.1 mm one included
    resampled = prepare_loops(record.deflection, record.force, points_per_set=600, name=record.id)
    assert resampled.reversals.size - 1 == inspected.cycles.branch_start.size  # same branches
    assert noise_level(record.deflection) < 1e-5


def test_loop_sets_of_a_set_cut_each_record_as_inspect_does(tmp_path):
    records = [_growing_loops(seed) for seed in (1, 2)]
    small = QuasiStaticMeasurement(time=records[0].time, deflection=0.3 * records[0].deflection,
                                   force=WIRE_ROPE.force(0.3 * records[0].deflection),
                                   info=MeasurementInfo(id="qs_small", isolator="wire_rope", split="fit"))
    data = loop_sets(records + [small], points_per_set=None)
    for prepared in data.small + data.large:
        record = {r.id: r for r in records + [small]}[prepared.name]
        reversals = process_quasi_static(record).cycles.reversals
        assert np.array_equal(prepared.reversals, reversals - reversals[0])


def test_inspect_fit_and_validation_estimate_the_identical_h1():
    run = _white_noise(3.0, seed=4)
    inspected = frf_from_white_noise(run, band=(1.0, 100.0))
    (fitted,), _ = transmissibility_sets([run], band=(1.0, 100.0))
    validated = validate_frf([run], isolator=ELASTOMER)  # the defaults: one resolution for all three
    curve = validated.details["curves"][run.id]
    assert np.array_equal(inspected.freq, fitted.freq) and np.array_equal(inspected.h1, fitted.transmissibility)
    assert np.array_equal(curve["freq [Hz]"].to_numpy(), inspected.freq)
    assert np.array_equal(curve["H1 measured"].to_numpy(), inspected.h1)
    # FRF_RESOLUTION_HZ lines from the time column: 4000-sample segments at 1000 Hz
    assert FRF_RESOLUTION_HZ == 0.25
    assert inspected.estimate.nperseg == 4000 and inspected.freq[1] - inspected.freq[0] == 0.25


def test_a_band_above_nyquist_is_clipped_with_a_warning_and_a_note():
    run = _white_noise(3.0, seed=5, fs=150.0, n=8192)
    with pytest.warns(UserWarning, match="Nyquist"):
        frf = frf_from_white_noise(run, band=(1.0, 100.0))
    assert frf.band == (1.0, 75.0) and frf.freq[-1] <= 75.0
    assert len(frf.notes) == 1 and "clipped to 75 Hz" in frf.notes[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # inside Nyquist: no warning, no note
        assert frf_from_white_noise(run, band=(1.0, 50.0)).notes == ()


def test_velocity_signals_come_first():
    run = _white_noise(3.0, seed=6)
    with_acceleration = WhiteNoiseMeasurement(time=run.time, v_base=run.v_base, v_top=run.v_top,
                                              a_base=2 * run.v_base, a_top=run.v_top, info=run.info)
    assert frf_from_white_noise(with_acceleration).signals == "velocity"


def test_selection_is_typed_and_reuses_the_set_hashes(tmp_path):
    runs = [_white_noise(mass, seed=7) for mass in (1.0, 3.0)]
    loops = [QuasiStaticMeasurement(time=np.arange(800) / 50.0, deflection=1e-3 * np.sin(np.linspace(0, 8, 800)),
                                    force=1.4e4 * 1e-3 * np.sin(np.linspace(0, 8, 800)),
                                    info=MeasurementInfo(id="qs_el", isolator="elastomer", split="fit"))]
    write_measurement_set(tmp_path / "set", runs + loops, name="selection")
    loaded = load_measurement_set(tmp_path / "set")
    chosen, provenance = select_measurements(loaded, kind="white_noise", isolator="elastomer", split="all")
    hashes = loaded.select(kind="white_noise").hashes()
    assert [m.id for m in chosen] == [r.id for r in runs]
    assert provenance.files == {name: digest for name, digest in hashes.items() if name != MANIFEST_NAME}
    assert provenance.manifest_sha256 == loaded.manifest_sha256 and provenance.selection["split"] is None
    _, listed = select_measurements(runs + loops, kind="quasi_static", isolator="elastomer", split="fit")
    assert listed.ids == ("qs_el",) and listed.folder is None
    with pytest.raises(DataError, match="expected a measurement"):
        select_measurements([runs[0], (1.0, 2.0)], kind="white_noise", isolator=None, split=None)
    with pytest.raises(DataError, match="expected a MeasurementSet"):
        select_measurements("data/elastomer", kind="white_noise", isolator=None, split=None)
    with pytest.raises(DataError, match=r"available \(kind, isolator, split\)"):
        select_measurements(loaded, kind="drop", isolator=None, split=None)


def test_elastomer_data_selects_once_and_the_fit_carries_the_k0_uncertainty():
    runs = [_white_noise(mass, seed) for mass in (1.0, 3.0) for seed in (1, 2)]
    x = 1.5e-3 * np.sin(np.linspace(0, 12 * np.pi, 1200))
    rng = np.random.default_rng(0)
    loops = [QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x,
                                    force=ELASTOMER.k0 * x + 0.05 * rng.standard_normal(x.size),
                                    info=MeasurementInfo(id=f"qs_el_{r}", isolator="elastomer", split="fit"))
             for r in (1, 2)]
    data = elastomer_data(runs + loops)
    assert [s.name for s in data] == [r.id for r in runs] and len(data) == 4
    assert data.repetitions == (1, 2, 1, 2)
    assert data.provenance.ids == ("qs_el_1", "qs_el_2", *(r.id for r in runs))
    assert data.k0 == data.k0_estimate.k0 and data.k0_stderr == data.k0_estimate.stderr > 0
    # k0 within 4 stderr of the truth: the force noise (0.05 N on 21 N) is the only error
    assert abs(data.k0 - ELASTOMER.k0) < 4 * data.k0_stderr
    result = fit_maxwell(list(data.frfs), k0=data.k0, k0_stderr=data.k0_stderr, order=2)
    assert result.params["k0"].stderr == data.k0_stderr and not result.params["k0"].vary
    given = elastomer_data(runs + loops, k0=1.4e4)
    assert given.k0_estimate is None and given.loops == () and given.provenance.ids == tuple(r.id for r in runs)
