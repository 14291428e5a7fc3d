"""Identification of the Iwan model with deflection-dependent slip forces (idkit.fit.iwan_modulated)."""

import itertools

import numpy as np
import pytest

from idkit.errors import FitError
from idkit.fit import prepare_loops
from idkit.fit.iwan_modulated import (
    fit_iwan_modulated,
    loop_model_table,
    modulated_set_errors,
)
from idkit.models import IwanModel, ModulatedIwanModel

TRUE = ModulatedIwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3],
                          slip_modulation=0.35, slip_length=6e-3)
NOISE_N = 0.05  # force noise, N (the bundled quasi-static records' level)


def _record(model, amplitude, rng, cycles=2, points=300):
    """Loops of one amplitude (m) from the unloaded state, with white force noise."""
    corners = [0.0] + [amplitude * (-1) ** i for i in range(2 * cycles + 1)]
    x = np.concatenate([np.linspace(a, b, points)[1:] for a, b in itertools.pairwise(corners)])
    x = np.concatenate([[0.0], x])
    return x, model.force(x) + NOISE_N * rng.standard_normal(x.size)


def _sets(model, seed):
    rng = np.random.default_rng(seed)
    small = [prepare_loops(*_record(model, a, rng), name=f"s{a * 1e3:g}mm") for a in (0.3e-3, 1e-3, 2e-3)]
    large = [prepare_loops(*_record(model, a, rng), name=f"l{a * 1e3:g}mm") for a in (5e-3, 10e-3, 15e-3)]
    return small, large


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_modulation_parameters_come_back_within_their_standard_errors(seed):
    small, large = _sets(TRUE, seed)
    result = fit_iwan_modulated(small, large, order=2)
    assert result.success, result.report()
    # 4 standard errors: a two-sided normal check that fails with probability 6e-5 per parameter
    # when the reported stderr is right (the data here are the model plus white noise)
    for name in ("slip_modulation", "slip_length"):
        value, stderr = result.parameters.set_index("name").loc[name, ["value", "stderr"]]
        assert abs(value - TRUE.params()[name]) < 4.0 * stderr, result.report()
        assert stderr < 0.1 * abs(TRUE.params()[name])  # resolved, not just consistent
    # the modulated model explains the loops better than the plain one it started from
    assert result.error_large < 0.5 * np.mean(result.plain_large_errors)


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_loops_without_modulation_say_the_modulation_is_not_resolved(seed):
    # "resolved" needs (a, b) 4 joint standard errors from (0, 0): p = 6.3e-5 per seed here
    small, large = _sets(TRUE.plain(), seed)
    result = fit_iwan_modulated(small, large, order=2)
    assert not result.success
    assert any("not resolved" in reason for reason in result.reasons)


def test_set_errors_of_the_true_model_are_the_noise_level():
    small, large = _sets(TRUE, 4)
    errors = modulated_set_errors(TRUE, small + large)
    # relative RMS of the noise: 0.05 N over each set's RMS force (> 5 N for every set here)
    assert np.all(errors < 2 * NOISE_N / np.array([np.sqrt(np.mean(s.force**2)) for s in small + large]))


def test_bad_arguments_are_named():
    small, large = _sets(TRUE, 5)
    with pytest.raises(FitError, match="modulation_starts"):
        fit_iwan_modulated(small, large, plain=TRUE.plain(), modulation_starts=[1.2])
    with pytest.raises(FitError, match="plain"):
        fit_iwan_modulated(small, large, plain="iwan")
    with pytest.raises(FitError, match="small"):
        fit_iwan_modulated([], large, plain=IwanModel(g1=1e4, k=[1e5], fc=[10.0]))


def test_order_table_has_a_row_per_model():
    small, large = _sets(TRUE, 6)
    table = loop_model_table(small, large, order=2, boucwen=False)
    assert list(table.summary["model"]) == ["iwan", "iwan_modulated"]
    iwan, modulated = table.summary["mean large [%]"]
    assert modulated < iwan


def test_valid_range_keeps_the_spring_stiffness_non_negative_beyond_the_loops():
    # a softening cubic that turns negative-stiff at -20 mm; the loops reach 15 mm, drops 30 mm
    truth = ModulatedIwanModel(g1=1.84e4, g2=2.45e5, g3=-1.2e7, k=[1.88e5, 9.09e3], fc=[15.5, 10.3],
                               slip_modulation=0.35, slip_length=6e-3)
    assert truth.valid_deflection_range()[0] > -0.03
    small, large = _sets(truth, 7)
    result = fit_iwan_modulated(small, large, plain=truth.plain(), valid_range=(-0.03, 0.03))
    lower, upper = result.model.valid_deflection_range()
    assert lower <= -0.03 * (1 - 1e-6) and upper >= 0.03 * (1 - 1e-6)
    with pytest.raises(FitError, match="valid_range"):
        fit_iwan_modulated(small, large, plain=truth.plain(), valid_range=(0.01, 0.03))


@pytest.mark.parametrize(("cycled", "a", "b"), [(False, 0.3, 0.25), (True, 0.3, 0.25), (False, 0.8, -0.17)])
def test_stage_jacobian_equals_central_differences(cycled, a, b):
    """The forward sensitivities of the stop operator against central differences of the
    residuals. Away from a clipping switch the residuals are smooth in every coordinate, so the
    difference quotient with step h agrees to O(h^2) (h = 1e-6: ~1e-10 of a column's scale);
    a step that moves an element across its limit at some point gives a kink, which the
    random start avoids with probability ~1 (2500 points, 1e-6 relative steps). Tolerance
    1e-6 of the column's largest entry. ``(a, b) = (0.8, -0.17)`` puts the slip scale's lowest
    value (0.03) under the stage's 0.05 margin: its barrier row is active."""
    from idkit.fit.iwan_modulated import _stage_residuals

    small, large = _sets(TRUE, 5)
    sets = small + large
    x_all = np.concatenate([s.deflection for s in sets])
    f_all = np.concatenate([s.force for s in sets])
    offsets = np.concatenate([[0], np.cumsum([s.deflection.size for s in sets])]).astype(np.int64)
    inv_norms = np.array([1.0 / np.linalg.norm(s.force) for s in sets])
    flags = np.full(len(sets), cycled)
    grid = np.linspace(-0.03, 0.03, 61)  # wide enough that the barrier is active at its ends
    n, g1_ref, x_ref = 2, 1.84e4, 15e-3
    u = np.array([np.log(1.7e4), 0.2, -5.0, np.log(1.5e5), np.log(8e3), np.log(14.0), np.log(9.0), a, b,
                  np.log(5e-3)])
    rows = x_all.size + grid.size + 1

    def run(v, want=True):
        residual, jacobian = np.empty(rows), np.empty((rows, u.size))
        _stage_residuals(v, n, g1_ref, x_ref, x_all, f_all, offsets, inv_norms, flags, grid, want, residual, jacobian)
        return residual, jacobian

    residual, jacobian = run(u)
    assert np.any(residual[x_all.size:-1] > 0)  # the spring barrier's rows are exercised
    assert (residual[-1] > 0) == (1 - abs(a) + min(b, 0) < 0.05)  # the slip scale's, when below its margin
    step = 1e-6
    for column in range(u.size):
        up, down = u.copy(), u.copy()
        up[column] += step
        down[column] -= step
        numeric = (run(up)[0] - run(down)[0]) / (2 * step)
        scale = np.max(np.abs(jacobian[:, column]))
        assert scale > 0
        np.testing.assert_allclose(jacobian[:, column], numeric, rtol=0, atol=1e-6 * scale)
    # the residuals do not depend on whether the Jacobian was asked for
    np.testing.assert_array_equal(run(u, False)[0], residual)


def test_as_iwan_result_keeps_the_modulated_model_and_the_stage_history():
    small, large = _sets(TRUE, 6)
    result = fit_iwan_modulated(small, large, order=2)
    converted = result.to_iwan_result()
    assert converted.model is result.model and converted.settings.family == "modulated"
    assert [stage.name for stage in converted.stages] == ["stage 1", "stage 2", "stage 3", "modulation"]
    assert converted.success == result.success
    for name in ("slip_modulation", "slip_length", "k_1", "fc_2"):
        assert converted.params[name].stderr == pytest.approx(result.stderr(name), rel=1e-12)
    assert converted.params["c_visc"].vary is False
    assert "Slip-modulated Iwan fit, order 2" in converted.report()
    # a refit started from the modulated model (one start, its own a) stays at that optimum
    again = fit_iwan_modulated(small, large, plain=result.model)
    assert again.starts == ((pytest.approx(result.model.slip_modulation), pytest.approx(result.model.slip_growth)),)
    assert again.error_small == pytest.approx(result.error_small, rel=1e-6)
    with pytest.raises(FitError, match="settings"):
        again.to_iwan_result()


def test_exact_and_difference_jacobians_reach_the_same_optimum():
    # the optimum is a property of the residuals, not of how their Jacobian is formed: the two
    # stages agree to the solver's tolerance on the loop errors (1e-6 relative)
    small, large = _sets(TRUE, 7)
    plain = fit_iwan_modulated(small, large, order=2).plain
    exact = fit_iwan_modulated(small, large, plain=plain)
    differences = fit_iwan_modulated(small, large, plain=plain, jacobian="2-point")
    np.testing.assert_allclose(differences.small_errors, exact.small_errors, rtol=1e-6)
    np.testing.assert_allclose(differences.large_errors, exact.large_errors, rtol=1e-6)


def test_set_errors_and_forces_of_a_modulated_model_carry_its_modulation():
    # iwan_set_errors / iwan_set_forces (report plots, tests) once scored a modulated model as
    # the plain one: with its slip modulation they are the modulation stage's own numbers
    from idkit.fit import iwan_set_errors, iwan_set_forces

    small, large = _sets(TRUE, 8)
    sets = small + large
    widening = ModulatedIwanModel.from_iwan(TRUE.plain(), slip_modulation=0.35, slip_growth=0.5, slip_length=6e-3)
    for model in (TRUE, widening):
        np.testing.assert_array_equal(iwan_set_errors(model, sets), modulated_set_errors(model, sets))
        # from the virgin state: loaded in one step from zero to the set's first point
        forces = iwan_set_forces(model, sets, initial_state="virgin")
        path = np.concatenate([[0.0], sets[-1].deflection])
        np.testing.assert_allclose(forces[-1], model.force(path)[1:], rtol=0, atol=1e-9)
    assert np.all(iwan_set_errors(TRUE, large) < 0.5 * iwan_set_errors(TRUE.plain(), large))


@pytest.mark.parametrize("seed", [9, 10])
def test_continuation_in_the_order_reaches_the_noise_at_the_truths_order(seed):
    # a slip-modulated order-2 truth with both terms: the chain from a plain order-1 fit adds
    # one element (a split of the first) and stops where accept() says; order 2 reaches the
    # noise (0.05 N on loops of 10-300 N: error (7.1) ~0.1 %, the truth itself scores that)
    from idkit.fit.iwan_modulated import fit_modulated_orders, split_element

    truth = ModulatedIwanModel.from_iwan(TRUE.plain(), slip_modulation=0.3, slip_growth=0.4, slip_length=6e-3)
    small, large = _sets(truth, seed)
    floor = np.concatenate([modulated_set_errors(truth, small), modulated_set_errors(truth, large)])
    fits = fit_modulated_orders(small, large, IwanModel(g1=2e4, k=[1.9e5], fc=[20.0]), max_order=3,
                                points_per_set=None, accept=lambda fit: fit.model.order == 2)
    assert sorted(fits) == [1, 2]  # stopped at the accepted order
    second = fits[2]
    # its history is the chain's: the order-1 stage, then its own, started from the split model
    assert [stage.name for stage in second.history] == ["modulation"]
    assert second.stage_name == "modulation, order 2 (order 1 with element 1 split)"
    assert second.stage_result().start_error == pytest.approx(
        float(np.mean(modulated_set_errors(split_element(fits[1].model, 0), small + large))), rel=1e-12)
    assert second.success, second.report()
    errors = np.concatenate([second.small_errors, second.large_errors])
    assert np.all(errors < floor + 0.002), (errors, floor)  # within 0.2 point of the truth's own score
    for name in ("slip_modulation", "slip_growth"):
        value, stderr = second.parameters.set_index("name").loc[name, ["value", "stderr"]]
        assert abs(value - truth.params()[name]) < 4.0 * stderr, second.report()


def test_continuation_stops_when_elements_stop_helping():
    # loops of an order-2 truth: order 2 explains them, order 3 and 4 cannot cut the error by
    # the order rule's tenth; patience=1 stops after the first such order, None goes on
    from idkit.fit.iwan_modulated import fit_modulated_orders

    small, large = _sets(TRUE, 11)
    start = IwanModel(g1=2e4, k=[1.9e5], fc=[20.0])
    patient = fit_modulated_orders(small, large, start, max_order=4, points_per_set=None, patience=1)
    assert sorted(patient) == [1, 2, 3]
    assert sorted(fit_modulated_orders(small, large, start, max_order=4, points_per_set=None, patience=None)) == [1, 2, 3, 4]


def test_standard_errors_match_the_spread_over_noise_realisations():
    """30 seeds of the same loops, 0.05 N force noise on every set (one load cell): the RMS of
    (fitted - true) / stderr per parameter lies in (0.55, 1.6), the central 99.9 % of
    sqrt(chi2_30 / 30) with a margin (tests/fit/test_uncertainty.py). Before (one pooled variance
    for all sets, whose relative noise differs ~10 x): k_1 1.80, fc_1 1.53, g1 0.53, a 0.45;
    0.91-1.16 with the sandwich, 0.89-1.07 with the offset step added."""
    truth = TRUE.params()
    z: dict = {}
    for seed in range(30):
        result = fit_iwan_modulated(*_sets(TRUE, seed), order=2)
        table = result.parameters.set_index("name")
        for name in truth:
            if name in table.index:
                z.setdefault(name, []).append((table.loc[name, "value"] - truth[name]) / table.loc[name, "stderr"])
    for name, values in z.items():
        rms = float(np.sqrt(np.mean(np.square(values))))
        assert 0.55 < rms < 1.6, f"{name}: rms z = {rms:.3f}"


OFFSET_SEEDS = range(8)


def _offset_sets(seed):
    """The loops of ``_sets(TRUE, .)`` with one load-cell zero error per set, N(0, 0.1 N)
    (idkit.synth's quasi-static records), which the fit holds at 0."""
    rng = np.random.default_rng(seed)

    def loops(amplitudes, prefix):
        out = []
        for a in amplitudes:
            x, f = _record(TRUE, a, rng)
            out.append(prepare_loops(x, f + 0.1 * rng.standard_normal(), name=f"{prefix}{a * 1e3:g}mm"))
        return out

    return loops((0.3e-3, 1e-3, 2e-3), "s"), loops((5e-3, 10e-3, 15e-3), "l")


def test_standard_errors_count_a_force_offset_per_loop_set():
    """A 0.1 N zero error per set does not average down over the set as the 0.05 N noise does.
    Before, the stderr described the noise only: over 30 seeds RMS z 2.0-8.3 (g2 7.6,
    slip_length 8.3). Now the Gauss-Newton step to the optimum with one offset per set free is
    added in quadrature (30 seeds: 0.77-0.96). Over these 8 seeds the RMS of a right stderr is
    sqrt(chi2_8 / 8), below 1.87 with probability 0.9995."""
    truth = TRUE.params()
    z: dict = {}
    for seed in OFFSET_SEEDS:
        table = fit_iwan_modulated(*_offset_sets(seed), order=2).parameters.set_index("name")
        for name in truth:
            if name in table.index:
                z.setdefault(name, []).append((table.loc[name, "value"] - truth[name]) / table.loc[name, "stderr"])
    assert set(z) == set(truth) - {"c_visc"}
    for name, values in z.items():
        rms = float(np.sqrt(np.mean(np.square(values))))
        assert rms < 1.87, f"{name}: rms z = {rms:.3f}"
