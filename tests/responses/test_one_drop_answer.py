"""One answer per question: a drop gives the same peaks in the CLI, the sweep, the validator
and the measured-record reduction (issue "one concept, one place").

All of them reduce a record with :func:`idkit.signal.drop.drop_phase_peaks` on the grid of
:func:`idkit.responses.shock.default_shock_grid`, so the numbers must agree exactly (to the
round-off of a CSV round trip, 1e-12 relative), not within a tolerance.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from idkit.cli.main import main
from idkit.io import DropMeasurement, MeasurementInfo
from idkit.models import HybridSystem, IwanModel, SDOFSystem, VoigtModel, save_model
from idkit.responses.shock import shock_sweep
from idkit.signal.drop import drop_phase_peaks, process_drop
from idkit.simulate import free_fall
from idkit.validate import validate_drops

HEIGHTS = [0.02, 0.08]
TOP_MASS = 4.0


def rope():
    """An asymmetric wire rope (the quadratic term makes tension and compression differ)."""
    return IwanModel(g1=3e3, g2=4e4, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6], c_visc=5.0)


def test_cli_prints_the_sweep(tmp_path):
    path = save_model(rope(), tmp_path / "rope.json")
    out = tmp_path / "drops.csv"
    code = main(["simulate", "drop", str(path), "--mass", str(TOP_MASS), "--height", *map(str, HEIGHTS),
                 "-o", str(out)])
    assert code == 0
    printed = pd.read_csv(out)
    expected = shock_sweep(SDOFSystem(TOP_MASS, rope()), drop_height=HEIGHTS).to_dataframe()
    numeric = expected.select_dtypes("number").columns
    np.testing.assert_allclose(printed[numeric].to_numpy(float), expected[numeric].to_numpy(float), rtol=1e-12)


def _records_of(sweep, system):
    """Measured-looking drops built from the sweep's own simulated records (no noise)."""
    records = []
    for index, height in enumerate(HEIGHTS):
        accel = sweep.top_acceleration[index]
        records.append(DropMeasurement(
            time=sweep.time, deflection=_total(sweep, system, index),
            a_top_1=accel, a_top_2=accel,
            info=MeasurementInfo(id=f"drop-{height}", top_mass_kg=TOP_MASS, drop_height_m=height,
                                 intermediate_mass_kg=float(system.masses[1])
                                 if isinstance(system, HybridSystem) else None)))
    return records


def _total(sweep, system, index):
    """The top mass's travel relative to the base (deflection summed over the isolators)."""
    run = free_fall(system, impact_velocity=sweep.impact_velocity[index:index + 1], duration=sweep.duration,
                    time_step=sweep.time_step)
    return run.deflection[0].sum(axis=0)


@pytest.mark.parametrize("kind", ["sdof", "hybrid"])
def test_validator_simulates_exactly_the_sweep(kind):
    if kind == "sdof":
        system = SDOFSystem(TOP_MASS, rope())
        models = {"isolator": rope()}
    else:
        elastomer = VoigtModel(k=2e4, damping=20.0)
        system = HybridSystem(TOP_MASS, elastomer, 0.5, rope())
        models = {"upper": elastomer, "lower": rope()}
    sweep = shock_sweep(system, drop_height=HEIGHTS)
    result = validate_drops(_records_of(sweep, system), **models)
    table = result.metrics
    np.testing.assert_array_equal(table["peak accel compression simulated [m/s^2]"],
                                  sweep.peak_acceleration_compression)
    np.testing.assert_array_equal(table["peak accel tension simulated [m/s^2]"], sweep.peak_acceleration_tension)
    np.testing.assert_array_equal(table["peak compression simulated [m]"], sweep.travel_compression)


def test_measured_reduction_is_the_sweeps_reduction():
    """process_drop without smoothing, on a simulated record, reads the sweep's peaks."""
    system = SDOFSystem(TOP_MASS, rope())
    sweep = shock_sweep(system, drop_height=HEIGHTS)
    for index in range(len(HEIGHTS)):
        deflection = _total(sweep, system, index)
        # the record starts at impact; a rigid pre-impact sample at rest defines the reference
        time = np.r_[sweep.time[0] - sweep.time_step, sweep.time] + sweep.time_step
        record = process_drop(time, np.r_[deflection[0], deflection], np.r_[0.0, sweep.top_acceleration[index]],
                              relative_velocity=np.r_[0.0, np.gradient(deflection, sweep.time)], window=1,
                              deflection_reference=deflection[0])
        assert record.peak_acceleration_compression == sweep.peak_acceleration_compression[index]
        assert record.peak_acceleration_tension == sweep.peak_acceleration_tension[index]
        assert record.max_compression == sweep.travel_compression[index]


def test_phase_peaks_of_a_sine_are_the_analytic_ones():
    """One compression half-wave then one tension half-wave of an undamped oscillator."""
    omega, amplitude = 2 * np.pi * 8.0, 3e-3
    time = np.linspace(0.0, 2 * np.pi / omega, 4001)
    deflection = -amplitude * np.sin(omega * time) * np.where(time < np.pi / omega, 1.0, 0.5)
    acceleration = -omega**2 * deflection
    peaks = drop_phase_peaks(deflection, acceleration)
    # sampled peaks of a sine on 4000 points per period: within 1 - cos(pi/4000) ~ 3e-7
    assert peaks.compression == pytest.approx(amplitude, rel=1e-6)
    assert peaks.tension == pytest.approx(0.5 * amplitude, rel=1e-6)
    assert peaks.acceleration_compression == pytest.approx(omega**2 * amplitude, rel=1e-6)
    assert peaks.acceleration_tension == pytest.approx(0.5 * omega**2 * amplitude, rel=1e-6)
    assert float(peaks.rest_shock_level) == peaks.acceleration_compression


def test_the_rig_option_of_shock_sweep_is_the_rig_reduced_by_the_one_phase_rule():
    from idkit.models import SDOFSystem, library
    from idkit.responses.shock import shock_sweep
    from idkit.signal.drop import drop_phase_peaks
    from idkit.simulate import drop_rig

    system = SDOFSystem(4.33, library.get("table_7_1_wire_rope"))
    sweep = shock_sweep(system, drop_height=[0.03, 0.1], drop_model="rig", bottom_mass=7.88, duration=0.2)
    run = drop_rig(system, bottom_mass=7.88, drop_height=[0.03, 0.1], duration=0.2)
    peaks = drop_phase_peaks(run.deflection, run.top_acceleration, start=run.impact_index)
    assert sweep.drop_model == "rig" and sweep.ok.all()
    np.testing.assert_array_equal(sweep.peak_acceleration_compression, peaks.acceleration_compression)
    np.testing.assert_array_equal(sweep.peak_acceleration_tension, peaks.acceleration_tension)
    np.testing.assert_array_equal(sweep.travel_compression, peaks.compression)
    np.testing.assert_array_equal(sweep.impact_velocity, run.impact_velocity)
