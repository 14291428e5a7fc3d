"""Fits of measurement sets on a small synthetic set written with idkit.io; bad input; measurement-level checks."""

import numpy as np
import pytest

from idkit.errors import DataError, FitError
from idkit.fit import fit_iwan_measurements, fit_maxwell_measurements, loop_sets, transmissibility_sets
from idkit.models import IwanModel
from tests.fit.small_set import ELASTOMER, TRUTH_IWAN, write_small_set


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    return write_small_set(tmp_path_factory.mktemp("set"))


def test_measurement_level_results_on_the_small_set(dataset):
    from idkit.io import load_measurement_set

    data = load_measurement_set(dataset)
    loops = loop_sets(data)
    assert [s.name for s in loops.small] == ["qs_small_1", "qs_small_2"]
    assert loops.small_repetitions == (1, 2)
    fit = fit_iwan_measurements(data, order=2, isolator="wire_rope")  # the set also holds elastomer loops
    # the records change amplitude mid-cycle, so the cycled start state is approximate (errors of a few %);
    # the parameters themselves come back: noise 0.05 N on loops of ~100 N
    for name in ("g1", "k_1", "k_2"):
        assert fit.model.params()[name] == pytest.approx(TRUTH_IWAN.params()[name], rel=0.02)
    for name in ("fc_1", "fc_2"):  # slip forces absorb the start-state mismatch
        assert fit.model.params()[name] == pytest.approx(TRUTH_IWAN.params()[name], rel=0.20)
    assert fit.result.error_large < 0.10
    # the loops span 0.3 to 12 mm (one sine cycle per amplitude): where the model is identified
    smallest, largest = fit.loop_amplitude_range
    assert (smallest, largest) == fit.data.amplitude_range()
    assert smallest == pytest.approx(0.3e-3, rel=0.02) and largest == pytest.approx(12e-3, rel=0.02)
    assert fit.provenance_dict()["loop_amplitude_range_m"] == [smallest, largest]
    assert f"loop amplitudes {1e3 * smallest:.3g} to {1e3 * largest:.3g} mm" in fit.report()
    maxwell = fit_maxwell_measurements(data)
    assert maxwell.k0.k0 == pytest.approx(ELASTOMER.k0, rel=1e-3)
    assert maxwell.result.error < 0.02
    assert maxwell.model.k[1] == pytest.approx(ELASTOMER.k[1], rel=0.05)
    assert maxwell.result.parameters["k0"].stderr == maxwell.k0.stderr


def test_bad_frfs_raise_fit_error_and_a_bad_split_a_data_error(dataset):
    """Orders are declared (idkit.checks): tests/test_checks.py feeds them their bad values."""
    from idkit.io import load_measurement_set
    from idkit.fit import TransmissibilitySet, fit_maxwell

    frfs, _ = transmissibility_sets(load_measurement_set(dataset))
    broken = [TransmissibilitySet(f.mass, f.freq, np.where(f.freq > 50, 0, f.transmissibility), f.name)
              for f in frfs]
    with pytest.raises(FitError, match="found 0 at"):
        fit_maxwell(broken, k0=1e4)
    nan = [TransmissibilitySet(f.mass, f.freq, np.where(f.freq > 50, np.nan, f.transmissibility), f.name)
           for f in frfs]
    with pytest.raises(FitError, match="finite"):
        fit_maxwell(nan, k0=1e4)
    with pytest.raises(DataError, match="split"):  # the selection is io's (idkit.io.provenance): a data error
        loop_sets(load_measurement_set(dataset), split="train")


def test_a_model_invalid_inside_the_data_sets_deflections_is_not_a_success():
    """The spring of TRUTH-like g3 < 0 turns negative at -x0; records reaching beyond fail the check."""
    from types import SimpleNamespace

    from idkit.fit.data_set_checks import valid_over_the_data

    model = IwanModel(g1=3e3, g2=0.0, g3=-3e7, k=[3e3], fc=[8.0])  # g1 + 3 g3 x^2 < 0 beyond 5.77 mm
    lower, upper = model.valid_deflection_range()

    def record(low, high, isolator="wire_rope"):
        return SimpleNamespace(deflection=np.array([low, 0.0, high]), info=SimpleNamespace(isolator=isolator))

    inside = [record(0.9 * lower, 0.9 * upper)]
    assert valid_over_the_data(model, inside, "wire_rope") == ()
    beyond = inside + [record(1.1 * lower, 0.0)]  # a drop compressing past the root
    (reason,) = valid_over_the_data(model, beyond, "wire_rope")
    assert "negative-stiff" in reason and f"{1e3 * 1.1 * lower:.4g}" in reason
    other_isolator = inside + [record(2 * lower, 0.0, isolator="elastomer")]
    assert valid_over_the_data(model, other_isolator, "wire_rope") == ()


def test_a_model_that_cannot_simulate_the_highest_drop_is_not_a_success():
    """The data set's most severe drop is simulated; a flagged run is a reason, a clean one is not."""
    from types import SimpleNamespace

    from idkit.fit.data_set_checks import survives_the_largest_drops

    def drop(height, mass=5.0):
        info = SimpleNamespace(drop_height_m=height, top_mass_kg=mass, isolator="wire_rope")
        return SimpleNamespace(kind="drop", info=info)

    softening = IwanModel(g1=3e3, g3=-3e7, k=[3e3], fc=[8.0])  # negative-stiff beyond 5.8 mm
    hardening = IwanModel(g1=3e3, g3=3e7, k=[3e3], fc=[8.0])
    records = [drop(0.01), drop(0.2)]  # 0.2 m compresses far beyond 5.8 mm
    (reason,) = survives_the_largest_drops(softening, records, "wire_rope")
    assert "highest drop (0.2 m on 5 kg)" in reason and "negative local stiffness" in reason
    assert survives_the_largest_drops(hardening, records, "wire_rope") == ()
    assert survives_the_largest_drops(softening, [drop(0.2)], "elastomer") == ()  # another isolator's drops


def test_sweeps_without_a_resonance_inside_leave_c_visc_0_and_say_why(monkeypatch):
    """A failed damping identification does not fail the loop fit; the fit says why c_visc is 0."""
    from pathlib import Path

    from idkit.fit import measurement_level
    from idkit.io import load_measurement_set

    def no_resonance(model, sweeps, level):
        raise FitError("level 0.12: the measured |H1| peaks at the edge of the sweep (3 Hz)")

    monkeypatch.setattr(measurement_level, "fit_viscous_damping", no_resonance)
    data = load_measurement_set(Path(__file__).resolve().parents[2] / "data" / "wire_rope")
    fit = fit_iwan_measurements(data, order=2)
    assert fit.damping is None and fit.model.c_visc == 0.0
    assert "peaks at the edge of the sweep" in fit.report()
    assert "peaks at the edge" in fit.provenance_dict()["viscous_damping"]


def test_loop_noise_floor_is_the_force_noise_over_the_force_rms():
    # white noise of a known standard deviation on a smooth loop: the median-based estimate
    # is within 3 % (its spread for 20000 samples is about 1 %)
    from idkit.fit.model_form import loop_noise_floor
    from idkit.io import MeasurementInfo, QuasiStaticMeasurement

    rng = np.random.default_rng(4)
    x = 5e-3 * np.sin(np.linspace(0, 8 * np.pi, 20000))
    clean = TRUTH_IWAN.force(x)
    record = QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x,
                                    force=clean + 0.05 * rng.standard_normal(x.size),
                                    info=MeasurementInfo(id="qs"))
    floor = loop_noise_floor([record])["qs"]
    assert floor == pytest.approx(0.05 / np.sqrt(np.mean(clean**2)), rel=0.03)


def test_a_loop_fit_far_above_its_noise_floor_is_not_a_success(dataset):
    # the order-2 truth with 0.05 N noise: order 2 reaches the floor; one element cannot
    # follow two slip forces and stays more than FLOOR_MARGIN above it, which is a reason
    from idkit.fit.model_form import FLOOR_MARGIN
    from idkit.io import load_measurement_set

    data = load_measurement_set(dataset)
    right = fit_iwan_measurements(data, order=2, damping_level=None, isolator="wire_rope")
    assert not any("noise floor" in reason for reason in right.reasons), right.reasons
    assert right.result.error_small < FLOOR_MARGIN and right.result.error_large < FLOOR_MARGIN
    wrong = fit_iwan_measurements(data, order=1, damping_level=None, isolator="wire_rope")
    assert wrong.result.error_small > 2 * FLOOR_MARGIN or wrong.result.error_large > 2 * FLOOR_MARGIN
    assert not wrong.success and any("above the noise floor" in reason for reason in wrong.reasons)
