"""Loops as they come from a rig: centre drift and force offset detected, reported, removable."""

from __future__ import annotations

import numpy as np
import pytest

from idkit.datasets import read_mr_damper, realdata_dir
from idkit.io import MeasurementInfo, QuasiStaticMeasurement
from idkit.models import IwanModel
from idkit.observe.quality import summarize_measurements
from idkit.observe.quasi_static import cycle_statistics, loop_sets, remove_loop_offsets

ROPE = IwanModel(g1=3e3, g2=0.0, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6])


def rig_record(*, drift=0.0, offset=0.0, seed=0, amplitude=4e-3, name="qs"):
    """Hysteretic loops (symmetric rope) whose centre moves by ``drift`` m over the record
    and whose force reads ``offset`` N too high, with 0.1 % force noise."""
    rng = np.random.default_rng(seed)
    time = np.linspace(0.0, 60.0, 12001)
    relative = amplitude * np.sin(2 * np.pi * time / 10.0)
    force = ROPE.force(relative)
    centre = drift * time / time[-1]
    noisy = force + offset + rng.normal(0.0, 1e-3 * np.ptp(force), time.size)
    return QuasiStaticMeasurement(time=time, deflection=relative + centre, force=noisy,
                                  info=MeasurementInfo(id=name, isolator="wire_rope", split="fit"))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_drift_and_offset_are_measured(seed):
    record = rig_record(drift=2e-3, offset=40.0, seed=seed)
    stats = cycle_statistics(record)
    # centres move at the drift rate (a centre is the mean of a cycle's extremes, so it lags
    # the cycle's mid time by a fixed fraction of the period: only the slope is checked)
    slope = np.polyfit(stats.time, stats.center, 1)[0]
    assert slope == pytest.approx(2e-3 / 60.0, rel=0.02)
    # midline at the centre: the offset; noise sigma 0.1 % of ~200 N averaged over two branches
    assert stats.median_force_offset == pytest.approx(40.0, abs=1.0)
    kinds = summarize_measurements([record]).warnings
    assert {w.kind for w in kinds} == {"loop_drift", "force_offset"}


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_clean_symmetric_record_raises_nothing(seed):
    record = rig_record(seed=seed)
    stats = cycle_statistics(record)
    assert stats.findings() == []
    assert abs(stats.median_force_offset) < 1.0
    # loop energy of the known model is positive and the secant stiffness sits between
    # the spring's and the stuck stiffness at this amplitude
    assert np.all(stats.dissipated_energy > 0)
    assert np.all((stats.secant_stiffness > 3e3) & (stats.secant_stiffness < 3e3 + 6e3 + 3 * 3e5 * 16e-6))


def test_removal_centres_the_loops_and_keeps_the_input():
    record = rig_record(drift=2e-3, offset=40.0)
    before = record.deflection.copy()
    clean, correction = remove_loop_offsets(record)
    np.testing.assert_array_equal(record.deflection, before)
    after = cycle_statistics(clean)
    assert after.findings() == []
    assert correction.force_offset == pytest.approx(40.0, abs=1.0)
    assert "loop offsets removed" in clean.info.notes


def test_the_fit_pipeline_removes_only_when_asked_and_records_it():
    records = [rig_record(drift=1e-3, offset=30.0, amplitude=a, name=f"qs_{a}") for a in (2e-3, 1.2e-2)]
    plain = loop_sets(records, small_threshold=8e-3)
    cleaned = loop_sets(records, small_threshold=8e-3, remove_offsets=True)
    assert plain.offset_corrections == ()
    assert [c.measurement_id for c in cleaned.offset_corrections] == ["qs_0.002", "qs_0.012"]
    assert all(abs(c.force_offset - 30.0) < 1.5 for c in cleaned.offset_corrections)


MR = realdata_dir("mr_damper_labcontrol")


@pytest.mark.skipif(MR is None, reason="../shared/realdata/mr_damper_labcontrol is not present")
def test_mr_damper_loops_drift_and_carry_a_force_offset():
    """ensaio.A.1: the loop centre drifts from 9.4 to 5.9 mm and the force reads about +100 N."""
    record = read_mr_damper(MR / "data" / "ensaio.A.1.mat")
    stats = cycle_statistics(record)
    assert stats.center[0] == pytest.approx(9.4e-3, abs=0.1e-3)
    assert stats.center[-1] == pytest.approx(5.9e-3, abs=0.1e-3)
    assert 90.0 < stats.median_force_offset < 110.0
    warnings = summarize_measurements([record]).warnings
    assert {w.kind for w in warnings} >= {"loop_drift", "force_offset"}


def test_growing_amplitude_protocol_is_not_drift():
    """Cycles that span an amplitude step move their centre by half the step: not drift."""
    time = np.linspace(0.0, 60.0, 12001)
    level = np.repeat([1e-3, 2e-3, 4e-3], 4000)[: time.size]
    level = np.r_[level, np.full(time.size - level.size, 4e-3)]
    deflection = level * np.sin(2 * np.pi * time / 10.0)
    record = QuasiStaticMeasurement(time=time, deflection=deflection, force=ROPE.force(deflection),
                                    info=MeasurementInfo(id="steps"))
    assert cycle_statistics(record).findings() == []


def test_one_amplitude_test_is_one_group_and_different_amplitudes_still_need_a_threshold():
    same = [rig_record(amplitude=a, name=f"qs_{k}", seed=k) for k, a in enumerate((4.0e-3, 4.2e-3))]
    data = loop_sets(same, small_threshold=8e-3)
    assert data.single_amplitude and data.small == data.large
    different = [rig_record(amplitude=a, name=f"qs_{k}") for k, a in enumerate((1e-3, 4e-3))]
    with pytest.raises(Exception, match="no large-loop record"):
        loop_sets(different, small_threshold=8e-3)


def _amplitude_steps(offset_n: float) -> QuasiStaticMeasurement:
    """Loops of 1, 5 and 12 mm in turn (a quasi-static protocol), force offset by ``offset_n``."""
    turns = np.array([0, 1, -1, 1, -1, 5, -5, 5, -5, 12, -12, 12, -12, 0]) * 1e-3
    half = 0.5 * (1 - np.cos(np.linspace(0.0, np.pi, 201)[:-1]))
    x = np.concatenate([a + (b - a) * half for a, b in zip(turns[:-1], turns[1:])] + [turns[-1:]])
    t = np.arange(x.size) * 0.01
    return QuasiStaticMeasurement(time=t, deflection=x, force=offset_n + 1e4 * x + 2e3 * np.gradient(x, t))


def test_a_cycle_across_an_amplitude_step_does_not_make_the_force_offset_nan():
    # the cycle from the 1 mm to the 5 mm loops has its unloading branch short of its centre:
    # its midline is NaN, and the median of all cycles was NaN; remove_offsets then made every
    # force sample NaN and the fit blamed the file ("column 'force [N]': found nan")
    stats = cycle_statistics(_amplitude_steps(50.0))
    assert np.isnan(stats.force_offset).any()
    assert stats.median_force_offset == pytest.approx(50.0, abs=1e-9)
    clean, correction = remove_loop_offsets(_amplitude_steps(50.0))
    assert correction.force_offset == pytest.approx(50.0, abs=1e-9) and np.all(np.isfinite(clean.force))
