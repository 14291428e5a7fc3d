"""Force histories: the scores against closed forms, the grouping, bad input."""

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.io import MeasurementInfo, QuasiStaticMeasurement
from idkit.observe.histories import (
    ForceHistory,
    dissipated_energy,
    histories_from_records,
    normalised_rms_error,
    strong_motion_window,
)


def test_normalised_rms_error_is_one_for_zero_and_zero_for_the_measurement():
    measured = np.sin(np.linspace(0.0, 20.0, 500))
    assert normalised_rms_error(np.zeros(500), measured) == pytest.approx(1.0)
    assert normalised_rms_error(measured, measured) == 0.0
    assert normalised_rms_error(1.1 * measured, measured) == pytest.approx(0.1)


def test_dissipated_energy_of_a_dashpot_cycle_is_pi_c_omega_a_squared():
    """F = c v on x = A sin(w t) over one period: pi c w A^2; trapezoids on 4001 samples: 1e-5 relative."""
    c, w, a = 300.0, 2 * np.pi * 1.5, 4e-3
    t = np.linspace(0.0, 2 * np.pi / w, 4001)
    x = a * np.sin(w * t)
    assert dissipated_energy(x, c * a * w * np.cos(w * t)) == pytest.approx(np.pi * c * w * a**2, rel=1e-5)


def test_strong_motion_window_of_a_burst_of_constant_rate():
    """Constant |v| from 2 s to 8 s: the cumulative integral is linear there, 5 % at 2.3 s and 95 % at 7.7 s
    (to a sample, 0.01 s)."""
    t = np.linspace(0.0, 10.0, 1001)
    x = np.clip(t, 2.0, 8.0)
    window = strong_motion_window(t, x)
    assert t[window.start] == pytest.approx(2.3, abs=0.011)
    assert t[window.stop - 1] == pytest.approx(7.7, abs=0.011)


def record(ident, amplitude, frequency, seconds=8.0):
    t = np.arange(0.0, seconds, 0.01)
    x = amplitude * np.sin(2 * np.pi * frequency * t)
    return QuasiStaticMeasurement(time=t, deflection=x, force=1e4 * x, info=MeasurementInfo(id=ident))


def test_repetitions_share_a_group_and_other_levels_do_not():
    histories = histories_from_records([record("a1", 5e-3, 0.5), record("a2", 5.2e-3, 0.5), record("b", 10e-3, 0.5),
                                        record("c", 5e-3, 2.0)])
    groups = {h.name: h.group for h in histories}
    assert groups["a1"] == groups["a2"] and len({groups["a1"], groups["b"], groups["c"]}) == 3
    assert histories[3].cycle_rate == pytest.approx(2.0, rel=2e-3)  # reversals read to a sample (0.01 s in 7.5 s)


def test_bad_histories_are_refused_naming_the_record():
    t = np.arange(100) * 0.01
    with pytest.raises(DataError, match="'r1' force: found nan"):
        ForceHistory("r1", t, np.sin(t), np.where(t > 0.5, np.nan, 1.0))
    with pytest.raises(DataError, match="'r2' deflection: found a constant record"):
        ForceHistory("r2", t, np.zeros(100), np.ones(100))
    with pytest.raises(DataError, match="found the id 'a' twice"):
        histories_from_records([record("a", 1e-3, 1.0), record("a", 2e-3, 1.0)])


def test_records_of_two_isolators_need_the_isolator_named():
    from idkit.observe.histories import force_histories

    first, second = record("a", 1e-3, 1.0), record("b", 2e-3, 1.0)
    second = QuasiStaticMeasurement(time=second.time, deflection=second.deflection, force=second.force,
                                    info=MeasurementInfo(id="b", isolator="elastomer"))
    first = QuasiStaticMeasurement(time=first.time, deflection=first.deflection, force=first.force,
                                   info=MeasurementInfo(id="a", isolator="wire_rope"))
    with pytest.raises(DataError, match="isolators elastomer, wire_rope"):
        force_histories([first, second], split=None)
    assert [h.name for h in force_histories([first, second], isolator="elastomer", split=None)[0]] == ["b"]
