"""Issue-10 loop targets on the first truth: the bundled wire rope (truth "a"), CLI defaults.

Truth "a" (:func:`idkit.synth.truth_models`) is an order-30 Iwan law whose loop width
follows the deflection (wider in compression) plus a bottoming spring; a plain Iwan model of
any order misses its loops by ~4 % (the order table flattens at 4.2 % / 4.1 %), so the
default family rule must bring in the slip-modulated model. Targets (issue 10), each a
physical statement:

* loop error within 2 percentage points of what the generating force law scores on the
  same loop sets under the same objective (7.1) from the same start state: the sensor noise
  (0.05 N) and load-cell offset give the truth's own floor (0.2-0.7 % here);
* stuck stiffness within 20 % of ``g1 + sum k_i`` of the truth;
* tangent stiffness at 90 % of the largest loop amplitude, either way, within 10 %;
* the fitted spring non-negative-stiff over every deflection of the set (drops reach -41 mm,
  beyond the loops' 16 mm);
* parameters agree to 1e-3 when every force sample is moved by one ulp (the fit is a
  property of the data, not of rounding).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from idkit.fit import fit_iwan_measurements
from idkit.fit.iwan_modulated import modulated_set_errors
from idkit.io import load_measurement_set
from idkit.models import ModulatedIwanModel
from idkit.synth import truth_models

DATA = Path(__file__).resolve().parents[2] / "data" / "wire_rope"
ROPE, _ = truth_models("a")

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not (DATA / "manifest.json").exists(),
                                 reason="bundled data set data/ not generated in this checkout")]


@pytest.fixture(scope="module")
def rope_set():
    return load_measurement_set(DATA)


@pytest.fixture(scope="module")
def rope_fit(rope_set):
    return fit_iwan_measurements(rope_set)  # the CLI's defaults: order and family "auto", valid range "data"


def _truth_loop_error(loop_set) -> float:
    """Error (7.1) of the generating law on a set loaded monotonically from zero to its first
    point (every bundled loop record starts unloaded)."""
    ramp = np.linspace(0.0, loop_set.deflection[0], 200)
    force = ROPE.quasi_static_force(np.concatenate([ramp, loop_set.deflection[1:]]))[ramp.size - 1:]
    return float(np.sqrt(np.sum((force - loop_set.force) ** 2) / np.sum(loop_set.force**2)))


def test_the_family_rule_brings_in_the_modulation_and_the_fit_succeeds(rope_fit):
    assert rope_fit.success, rope_fit.reasons
    assert isinstance(rope_fit.model, ModulatedIwanModel) and rope_fit.result.settings.family == "modulated"
    table = rope_fit.order_table
    plain = table[table["family"] == "plain"]
    # the plain family flattens ~4 points above the modulated one: the form, not the order, misses
    assert plain["error_small_percent"].min() > 2.0 + table.loc[table["recommended"], "error_small_percent"].iloc[0]
    # wider loops in compression: a > 0 (the truth's width grows by up to 35 % over ~6 mm)
    assert 0.1 < rope_fit.model.slip_modulation < 0.6
    assert rope_fit.model.c_visc > 0  # from the stepped-sine resonance, never silently 0


def test_loop_errors_within_2_points_of_the_truth(rope_fit):
    sets = list(rope_fit.data.small) + list(rope_fit.data.large)
    assert all(s.starts_unloaded for s in sets)
    fitted = modulated_set_errors(rope_fit.result.model, sets)
    truth = np.array([_truth_loop_error(s) for s in sets])
    assert np.all(truth < 0.01)  # the truth's floor: noise and offset only
    assert np.all(fitted - truth <= 0.02), (fitted, truth)


def test_stuck_stiffness_within_20_percent(rope_fit):
    model = rope_fit.model
    assert model.g1 + sum(model.k) == pytest.approx(ROPE.stuck_stiffness, rel=0.20)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_tangent_stiffness_at_large_amplitude_within_10_percent(rope_fit, side):
    large = max(float(np.max(np.abs(s.deflection))) for s in rope_fit.data.large)
    path = side * np.linspace(0.0, 0.91 * large, 9101)
    at, step = 9000, 90  # 0.90 x the amplitude, +-1 % of the stroke

    def tangent(force):
        return (force[at + step] - force[at - step]) / (path[at + step] - path[at - step])

    assert tangent(rope_fit.model.force(path)) == pytest.approx(tangent(ROPE.quasi_static_force(path)), rel=0.10)


def test_spring_positive_over_every_deflection_of_the_set(rope_fit, rope_set):
    lower, upper = rope_fit.model.valid_deflection_range()
    seen = [m.deflection for m in rope_set.measurements if getattr(m, "deflection", None) is not None]
    assert lower < min(d.min() for d in seen) and max(d.max() for d in seen) < upper


def test_parameters_agree_when_the_forces_move_by_one_ulp(rope_fit, rope_set):
    import dataclasses

    def nudged(measurement):
        if measurement.kind != "quasi_static":
            return measurement
        return dataclasses.replace(measurement, force=np.nextafter(measurement.force, np.inf))

    records = [nudged(m) for m in rope_set.measurements]
    assert any(not np.array_equal(a.force, b.force) for a, b in zip(records, rope_set.measurements)
               if a.kind == "quasi_static")
    again = fit_iwan_measurements(records)
    assert type(again.model) is type(rope_fit.model) and again.model.order == rope_fit.model.order
    first, second = rope_fit.model.params(), again.model.params()
    for name, value in first.items():
        assert second[name] == pytest.approx(value, rel=1e-3, abs=1e-12), name


def _every_value_one_ulp_up(measurement):
    """The record with every floating-point sample (not the time base) moved one ulp up."""
    import dataclasses

    moved = {f.name: np.nextafter(getattr(measurement, f.name), np.inf) for f in dataclasses.fields(measurement)
             if f.name != "time" and isinstance(getattr(measurement, f.name), np.ndarray)
             and getattr(measurement, f.name).dtype.kind == "f"}
    return dataclasses.replace(measurement, **moved)


def test_elastomer_parameters_agree_when_every_sample_moves_by_one_ulp():
    # the bundled elastomer (truth "a"), CLI defaults (order and loss constraint "auto", k0
    # with relaxation): measured 3e-7 either way, against the 1e-3 target
    from idkit.fit import fit_maxwell_measurements

    records = load_measurement_set(DATA.parent / "elastomer").measurements
    first = fit_maxwell_measurements(records)
    again = fit_maxwell_measurements([_every_value_one_ulp_up(m) for m in records])
    assert again.success == first.success and again.model.params().keys() == first.model.params().keys()
    for name, value in first.model.params().items():
        assert again.model.params()[name] == pytest.approx(value, rel=1e-3, abs=1e-12), name
