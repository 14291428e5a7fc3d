"""The Iwan family rule (idkit.fit.family.choose_iwan_family) and the default valid range."""

import itertools

import numpy as np
import pytest

from idkit.errors import DataError, FitError
from idkit.fit import fit_iwan, prepare_loops
from idkit.fit.data_set_checks import data_valid_range
from idkit.fit.family import choose_iwan_family
from idkit.fit import fit_iwan_measurements
from idkit.fit.model_form import FLOOR_MARGIN
from idkit.io import MeasurementInfo, QuasiStaticMeasurement
from idkit.models import IwanModel, ModulatedIwanModel

PLAIN = IwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3])
# slip forces 1.8x wider in compression than in tension at 10 mm: no plain Iwan follows that
MODULATED = ModulatedIwanModel.from_iwan(PLAIN, slip_modulation=0.6, slip_length=4e-3)
NOISE_N = 0.05


def _sets(model, seed):
    rng = np.random.default_rng(seed)

    def record(amplitude, name):
        corners = [0.0] + [amplitude * (-1) ** i for i in range(5)]
        x = np.concatenate([[0.0], *(np.linspace(a, b, 300)[1:] for a, b in itertools.pairwise(corners))])
        return prepare_loops(x, model.force(x) + NOISE_N * rng.standard_normal(x.size), name=name)

    return ([record(a, f"s{a * 1e3:g}") for a in (0.3e-3, 1e-3, 2e-3)],
            [record(a, f"l{a * 1e3:g}") for a in (5e-3, 10e-3, 15e-3)])


def _floor_check(fit):
    """The measurement-level rule with the known noise as the floor (relative noise < 0.1 %)."""
    return tuple(f"{group} above the floor" for group, error in (("small", fit.error_small),
                                                                  ("large", fit.error_large))
                 if error > FLOOR_MARGIN + 1e-3)


@pytest.mark.parametrize("seed", [0, 1])
def test_loops_with_modulated_slip_bring_in_the_modulated_family(seed):
    small, large = _sets(MODULATED, seed)
    plain = {order: fit_iwan(small, large, order=order, seed=seed) for order in (2, 3)}
    assert _floor_check(plain[2])  # the plain form misses the loops by more than the margin
    chosen, rows, modulated = choose_iwan_family(small, large, plain, floor_check=_floor_check)
    assert chosen is modulated and chosen.settings.family == "modulated" and chosen.success
    assert isinstance(chosen.model, ModulatedIwanModel) and chosen.model.order == 2  # lowest order within
    assert list(rows["order"]) == [2] and list(rows["family"]) == ["modulated"]  # stopped there
    # the generating modulation comes back within 4 standard errors (noise-only data)
    value, stderr = chosen.params["slip_modulation"].value, chosen.params["slip_modulation"].stderr
    assert abs(value - 0.6) < 4 * stderr


def test_loops_a_plain_model_explains_keep_the_plain_family_without_the_stage():
    small, large = _sets(PLAIN, 2)
    plain = {2: fit_iwan(small, large, order=2, seed=0)}
    chosen, rows, modulated = choose_iwan_family(small, large, plain, floor_check=_floor_check)
    assert chosen is plain[2] and rows is None and modulated is None
    # forced: the stage runs, says the modulation is not resolved, and is kept with that reason
    forced, rows, _ = choose_iwan_family(small, large, plain, family="modulated", floor_check=_floor_check)
    assert forced.settings.family == "modulated" and not forced.success
    assert any("not resolved" in reason for reason in forced.reasons)


def _record(deflection, ident="r1", isolator="wire_rope"):
    x = np.asarray(deflection, float)
    return QuasiStaticMeasurement(info=MeasurementInfo(id=ident, isolator=isolator, sample_rate_hz=1.0),
                                  time=np.arange(x.size, dtype=float), deflection=x, force=1e4 * x)


def test_data_valid_range_spans_every_record_of_the_isolator_and_straddles_zero():
    # 1.25 x the extremes of the isolator's records (VALID_RANGE_MARGIN)
    records = [_record([-2e-3, 1e-3]), _record([-8e-3, 0.0], "r2"),
               _record([-50e-3, 40e-3], "r3", isolator="elastomer")]
    assert data_valid_range(records, isolator="wire_rope") == pytest.approx((-10e-3, 1.25e-3))
    assert data_valid_range(records, isolator=None) == pytest.approx((-62.5e-3, 50e-3))
    low, high = data_valid_range([_record([1e-3, 4e-3])])  # one-sided data: the other side is -1e-3 x
    assert low == pytest.approx(-5e-6) and high == pytest.approx(5e-3)
    with pytest.raises(DataError, match="no record of isolator 'bouc'"):
        data_valid_range(records, isolator="bouc")


def test_bad_valid_range_is_named():
    """family is declared (idkit.checks): tests/test_checks.py feeds it its bad values."""
    with pytest.raises(FitError, match="valid_range: found 'loops'"):
        fit_iwan_measurements([_record(np.linspace(-1e-3, 1e-3, 50))], valid_range="loops", isolator=None)
