"""Three-stage Iwan fit: recovery on synthetic loops, backends, start, bad input."""

import numpy as np
import pytest

from idkit.errors import FitError
from idkit.fit import fit_iwan, iwan_set_errors, iwan_start, prepare_loops
from idkit.models import IwanModel, library

NOISE = 0.01  # force noise std as a fraction of each set's RMS force
SMALL_AMPLITUDES = (0.1e-3, 0.3e-3, 1e-3, 2e-3, 4e-3)  # m (SPEC 3: small loops 0.05-4.5 mm)
LARGE_AMPLITUDES = (6e-3, 10e-3, 15e-3)  # m (large loops 1-15 mm)
NOISE_SEEDS = (20240601, 4, 17)  # independent noise realisations; every test holds for each
# Recovery: |fitted - true| <= Z_MAX x the reported standard error. The Gauss-Newton
# stderr approximates the spread of this (not least-squares) objective: over 30 noise
# seeds the z-scores of the seven parameters had standard deviations 0.9-1.3 and never
# exceeded 3.6, so 4.5 sigma is a bound that a correct fit keeps for any seed.
Z_MAX = 4.5
# Information content at 1 % force noise: the stderr itself must be small, or the test
# above would pass a fit that determines nothing. Measured stderr / |true value| over 30
# seeds (it depends on the noise level, not its realisation): 0.06 % for g1, k_1, fc_1;
# 0.25 % for k_2, fc_2; 0.4 % for g2; 26 % for g3 (its force is small below 15 mm).
# The caps are about 3x those.
MAX_REL_STDERR = {"g1": 0.002, "k_1": 0.002, "fc_1": 0.002, "k_2": 0.01, "fc_2": 0.01, "g2": 0.015, "g3": 0.8}
NOISE_FLOOR_FACTOR = 1.05  # fitted error <= 1.05 x the error of the true model on the same data
BACKEND_REL_TOL = 1e-3  # nlopt and scipy Nelder-Mead parameters agree to 0.1 %
ULP_REL_TOL = 1e-3  # parameters from data perturbed by one ulp agree to 0.1 % (CPU independence)


def _truth() -> IwanModel:
    table = library.get("table_7_1_wire_rope")
    return IwanModel(g1=table.g1, g2=table.g2, g3=table.g3, k=table.k, fc=table.fc)  # quasi-static: no c_visc


def _loop_record(model, amplitude, rng, cycles=2, samples_per_cycle=400):
    """Sine loops from the unloaded origin, force with NOISE x RMS white noise."""
    phase = np.linspace(0.0, 2 * np.pi * (cycles + 0.25), int(samples_per_cycle * (cycles + 0.25)))
    deflection = amplitude * np.sin(phase)
    force = model.force(deflection)
    force = force + NOISE * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    return deflection, force


@pytest.fixture(scope="module", params=NOISE_SEEDS, ids=lambda seed: f"seed{seed}")
def loops(request):
    rng = np.random.default_rng(request.param)
    truth = _truth()
    small = [_loop_record(truth, a, rng) for a in SMALL_AMPLITUDES]
    large = [_loop_record(truth, a, rng) for a in LARGE_AMPLITUDES]
    return truth, small, large


@pytest.fixture(scope="module")
def fits(loops):
    _, small, large = loops
    return {backend: fit_iwan(small, large, order=2, backend=backend) for backend in ("nlopt", "scipy")}


@pytest.mark.parametrize("backend", ["nlopt", "scipy"])
def test_recovers_table_7_1_parameters_within_their_standard_errors(fits, loops, backend):
    truth = loops[0].params()
    result = fits[backend]
    assert result.success, result.reasons
    parameters = result.parameters
    assert parameters["c_visc"].vary is False
    assert parameters["k_1"].user_data["unit"] == "N/m"
    for name, max_rel in MAX_REL_STDERR.items():
        stderr = parameters[name].stderr
        assert stderr is not None and 0 < stderr < max_rel * abs(truth[name]), name
        assert abs(parameters[name].value - truth[name]) < Z_MAX * stderr, name


@pytest.mark.parametrize("backend", ["nlopt", "scipy"])
def test_error_reaches_the_noise_floor(fits, loops, backend):
    truth, small, large = loops
    result = fits[backend]
    small_sets = [prepare_loops(x, f) for x, f in small]
    large_sets = [prepare_loops(x, f) for x, f in large]
    floor_small = float(np.mean(iwan_set_errors(truth, small_sets)))
    floor_large = float(np.mean(iwan_set_errors(truth, large_sets)))
    assert floor_small == pytest.approx(NOISE, rel=0.2)  # the data carry the intended noise
    assert result.error_small <= NOISE_FLOOR_FACTOR * floor_small
    assert result.error_large <= NOISE_FLOOR_FACTOR * floor_large
    # each stage improves on its start and the history is complete
    assert [s.name for s in result.stages] == ["stage 1", "stage 2", "stage 3"]
    assert [s.data for s in result.stages] == ["small", "large", "all"]
    assert all(s.mean_error <= s.start_error for s in result.stages)
    assert result.stages[0].params["g2"] == 0.0 and result.stages[0].params["g3"] == 0.0
    assert result.stages[2].params["g1"] == result.stages[1].params["g1"]  # globals fixed in stage 3
    assert result.stages[2].free == ("k_1", "k_2", "fc_1", "fc_2")


def test_backends_agree(fits):
    nlopt_params, scipy_params = fits["nlopt"].model.params(), fits["scipy"].model.params()
    for name in ("g1", "g2", "k_1", "k_2", "fc_1", "fc_2"):
        assert nlopt_params[name] == pytest.approx(scipy_params[name], rel=BACKEND_REL_TOL), name
    assert fits["nlopt"].error_small == pytest.approx(fits["scipy"].error_small, abs=1e-5)


@pytest.mark.parametrize("backend", ["nlopt", "scipy"])
def test_data_perturbed_by_one_ulp_give_the_same_parameters(fits, loops, backend):
    """A fit that rounding can steer (a flat direction, a knife-edge stop) differs by CPU."""
    _, small, large = loops
    up = [(x, np.nextafter(f, np.inf)) for x, f in small], [(x, np.nextafter(f, np.inf)) for x, f in large]
    perturbed = fit_iwan(*up, order=2, backend=backend).model.params()
    for name, value in fits[backend].model.params().items():
        assert perturbed[name] == pytest.approx(value, rel=ULP_REL_TOL), name


def test_an_element_the_small_loops_never_slip_is_fixed_by_the_large_ones():
    """fc_2 of an element that slips only beyond the small loops comes back (stage 3 on all loops).

    Element 2 slips at 14.6 N / 3e3 N/m = 4.9 mm, beyond the 4 mm small loops: on the
    small loops alone its slip force is undetermined (their error is flat in fc_2).
    """
    truth = IwanModel(g1=3e3, g2=4e4, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6])
    rng = np.random.default_rng(8)
    small = [_loop_record(truth, a, rng) for a in (0.3e-3, 1e-3, 2e-3, 4e-3)]
    large = [_loop_record(truth, a, rng) for a in (4e-3, 8e-3, 12e-3)]
    result = fit_iwan(small, large, order=2)
    assert result.success, result.reasons
    for name in ("k_1", "k_2", "fc_1", "fc_2"):
        parameter = result.parameters[name]
        assert abs(parameter.value - truth.params()[name]) < Z_MAX * parameter.stderr, name
    # stage 3 does not undo stage 2: the large loops stay at the noise floor of the truth
    floor_large = float(np.mean(iwan_set_errors(truth, [prepare_loops(x, f) for x, f in large])))
    assert result.error_large <= NOISE_FLOOR_FACTOR * floor_large


def test_report_and_table(fits):
    result = fits["nlopt"]
    text = result.report()
    assert "stage 2 (large loops" in text and "fc_2" in text and "N/m^3" in text
    table = result.to_dataframe()
    assert set(table["stage"]) == {"stage 1", "stage 2", "stage 3", "final"}
    # stage 1 on the small sets, stage 2 on the large, stage 3 on all, final on all
    assert len(table) == 3 * len(SMALL_AMPLITUDES) + 3 * len(LARGE_AMPLITUDES)


def test_automatic_start_is_read_off_the_loops(loops):
    """The start's loop-level numbers are read directly (5 %); the element split is a seed.

    The stiff element (k_1 = 1.9e5 N/m) slips after 0.17 mm of travel, which only the
    first points of the two smallest loops resolve; its start value scattered over
    1.0-1.4 x the truth across 30 noise seeds, and the fit recovers it from there.
    """
    truth, small, large = loops
    start = iwan_start([prepare_loops(x, f) for x, f in small], [prepare_loops(x, f) for x, f in large], 2)
    assert start.stuck_stiffness == pytest.approx(truth.stuck_stiffness, rel=0.05)
    assert start.half_height == pytest.approx(truth.fc.sum(), rel=0.05)
    assert start.g1 == pytest.approx(truth.g1, rel=0.05)
    soft, stiff = sorted(start.model.k)
    assert soft == pytest.approx(min(truth.k), rel=0.1)
    assert 0.5 < stiff / max(truth.k) < 2.0


@pytest.mark.parametrize("order", [1, 3])
def test_any_order_fits_and_stays_positive(loops, order):
    _, small, large = loops
    result = fit_iwan(small, large, order=order)
    assert result.model.order == order
    assert np.all(result.model.k > 0) and np.all(result.model.fc > 0) and result.model.g1 > 0
    if order == 1:  # one element cannot follow two slip travels: clearly above the noise
        assert 2 * NOISE < result.error_small < 0.25
    else:  # an extra element costs nothing on the fit
        assert result.error_small < 1.1 * NOISE
    # a redundant element leaves a flat direction: whatever happens there is named, never a crash
    assert result.success == (not result.reasons)


def test_parameters_stay_inside_the_search_box_and_a_bound_is_not_a_success():
    """Loops without any slip: slip forces stay finite and the fit names what it cannot see."""
    x = np.concatenate([a * np.sin(np.linspace(0, 4.5 * np.pi, 600)) for a in (1e-3, 2e-3, 5e-3)])
    force = 2e4 * x  # a linear spring: no element is ever seen slipping
    result = fit_iwan([(x[:1200], force[:1200])], [(x[1200:], force[1200:])], order=2)
    assert np.all(np.isfinite(result.model.k)) and np.all(np.isfinite(result.model.fc))
    # the force law is reproduced; which degenerate representation (elements never slipping,
    # or slipping at once with vanishing fc) the simplex lands on is not determined by the data
    assert result.error_small < 1e-3 and result.error_large < 1e-3
    assert not result.success
    assert any("never slips" in reason or "search bound" in reason for reason in result.reasons)
    assert "not a success" in result.report()


def test_compiled_objective_matches_the_model_force():
    """Independent check of the fused kernel against IwanModel.force (virgin state)."""
    model = IwanModel(g1=2e3, g2=1e5, g3=-3e5, k=[5e4, 4e3], fc=[5.0, 7.0])
    phase = np.linspace(0, 5 * np.pi, 701)
    deflection = 3e-3 * np.sin(phase) * np.linspace(0.5, 1.0, phase.size) + 5e-4 * np.sin(0.2 * phase)
    measured = model.force(deflection) * 1.02
    loop_set = prepare_loops(deflection, measured, points_per_set=None)
    first = int(np.flatnonzero(np.isclose(deflection, loop_set.deflection[0]))[0])
    reference = model.force(deflection)[first : first + loop_set.deflection.size]
    expected = np.sqrt(np.sum((reference - loop_set.force) ** 2) / np.sum(loop_set.force**2))
    # "virgin": unloaded at x = 0, loaded to the first point. The record's own history
    # reaches the first reversal through the same path only if no element reversed
    # before it, which holds here (the record rises monotonically to its first peak).
    assert iwan_set_errors(model, [loop_set], initial_state="virgin")[0] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize(
    ("small", "match"),
    [
        ([(np.linspace(0, 1e-3, 10), np.linspace(0, 3, 10))], "found 10 points, expected at least 20"),
        ([(np.linspace(0, 1e-3, 100), np.linspace(0, 3, 100))], "reversal"),
        ([(np.full(100, np.nan), np.ones(100))], "found nan at index 0"),
        ([(np.sin(np.linspace(0, 9, 100)), np.ones(99))], "expected equal counts"),
        ([], "found no data set"),
        ([(np.zeros(100), np.ones(100))], "constant record"),
    ],
)
def test_bad_loops_raise_fit_error(loops, small, match):
    with pytest.raises(FitError, match=match):
        fit_iwan(small, loops[2])


def test_too_few_points_per_set_raise_fit_error(loops):
    """order, backend, initial_state and stage2_starts are declared (idkit.checks): tests/test_checks.py."""
    _, small, large = loops
    with pytest.raises(FitError, match="points_per_set: found 5"):
        fit_iwan(small, large, points_per_set=5)


def test_order_table_recommends_the_generating_order():
    """Loops of the order-2 Table 7.1 rope: order 1 misses, order 3 gains nothing, the rule picks 2."""
    from idkit.fit import iwan_order_table

    rng = np.random.default_rng(NOISE_SEEDS[0])
    truth = _truth()
    small = [_loop_record(truth, a, rng) for a in SMALL_AMPLITUDES]
    large = [_loop_record(truth, a, rng) for a in LARGE_AMPLITUDES]
    table = iwan_order_table(small, large, orders=(1, 2, 3)).set_index("order")
    assert table.loc[1, "error_small_percent"] > 2 * table.loc[2, "error_small_percent"]
    assert table.loc[3, "error_small_percent"] > 0.9 * table.loc[2, "error_small_percent"]
    assert table["recommended"].tolist() == [False, True, False]
    assert table.loc[2, "stuck_stiffness [N/m]"] == pytest.approx(truth.stuck_stiffness, rel=0.01)
    # the smallest loop (0.1 mm) already slips the stiff element a little: its secant lies below
    assert 0.5 * truth.stuck_stiffness < table.loc[2, "smallest_loop_secant [N/m]"] < truth.stuck_stiffness
    low, high = truth.valid_deflection_range()
    assert table.loc[2, "spring_negative_below [m]"] == pytest.approx(low, rel=0.05)


def test_stage_2_keeps_the_best_of_several_starts(loops):
    """More starts can only lower stage 2's objective; each one costs evaluations."""
    _, small, large = loops
    poor = IwanModel(g1=1e3, k=[1e6, 1e3], fc=[50.0, 1.0])  # far from the loops: local minima are likely
    one = fit_iwan(small, large, order=2, start=poor, stage2_starts=1)
    four = fit_iwan(small, large, order=2, start=poor, stage2_starts=4)
    assert four.stages[1].mean_error <= one.stages[1].mean_error
    assert four.stages[1].evaluations > one.stages[1].evaluations
    assert four.settings.stage2_starts == 4 and one.settings.stage2_starts == 1
