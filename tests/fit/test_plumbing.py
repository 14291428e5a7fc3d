"""The shared pieces of the fitters: laws, optimiser status, results like lmfit's, units from the models."""

from __future__ import annotations

import math

import numpy as np
import pytest

from idkit.fit import fit_boucwen, fit_iwan, fit_maxwell, fit_voigt
from idkit.fit._optim import CONVERGED, INFEASIBLE, MAX_EVALS, nelder_mead, sqp
from idkit.models import BoucWenModel, GeneralizedMaxwell, HybridSystem, IwanModel, SDOFSystem, VoigtModel, library
from idkit.models.laws import (
    hybrid_transmissibility,
    jenkin_step,
    kernel_array,
    lowest_spring_stiffness,
    polynomial_spring_force,
    polynomial_spring_stiffness,
    sdof_transmissibility,
    stop_operator,
)

ELASTOMER = library.get("table_7_3_elastomer")
FREQ = np.linspace(1.0, 100.0, 199)


# --------------------------------------------------------------------------- laws


def test_sdof_law_is_what_the_system_and_the_fit_objective_use():
    system = SDOFSystem(3.0, ELASTOMER)
    law = sdof_transmissibility(ELASTOMER.complex_stiffness(FREQ), 3.0 + ELASTOMER.m_eff, 2 * np.pi * FREQ)
    assert np.array_equal(system.transmissibility(FREQ), law)  # the system calls the law: bit for bit


def test_hybrid_law_matches_an_independent_linear_solve():
    """Cramer's rule against numpy's LU solve of the same 2x2 dynamic-stiffness system;
    1e-10 relative: both are exact up to rounding of a system whose condition stays below 1e5."""
    upper = ELASTOMER
    lower = IwanModel(g1=3e3, k=[3e3, 3e3], fc=[8.3, 14.6])
    system = HybridSystem(mass=3.0, upper=upper, intermediate_mass=0.03, lower=lower)
    omega = 2 * np.pi * FREQ
    k_u, k_l = upper.small_amplitude_stiffness(FREQ), lower.small_amplitude_stiffness(FREQ)
    m_top, m_in = system.masses
    independent = []
    for w, ku, kl in zip(omega, k_u, k_l):
        matrix = np.array([[ku - m_top * w**2, -ku], [-ku, ku + kl - m_in * w**2]])
        independent.append(np.linalg.solve(matrix, np.array([0.0, kl]))[0])
    law = hybrid_transmissibility(k_u, k_l, m_top, m_in, omega)
    assert np.allclose(law, independent, rtol=1e-10, atol=0)
    assert np.array_equal(system.transmissibility(FREQ), law)


def test_jenkin_step_is_the_stop_operator_one_step_at_a_time():
    rng = np.random.default_rng(0)
    x = np.cumsum(rng.normal(0, 1e-3, 500))
    k, fc = np.array([2e3, 5e3, 1e4]), np.array([1.0, 4.0, 20.0])
    history = stop_operator(kernel_array(x), k, fc, np.zeros(3))
    state = np.zeros(3)
    for i in range(1, x.size):
        total = jenkin_step(state, k, fc, x[i] - x[i - 1])
        assert np.array_equal(state, history[i]) and total == pytest.approx(history[i].sum(), rel=1e-15)


def test_spring_laws_agree_with_the_model_and_the_lowest_stiffness_is_the_minimum():
    model = IwanModel(g1=3e3, g2=-4e5, g3=2e7, k=[1e3], fc=[1.0])
    x = np.linspace(-0.02, 0.02, 2001)
    assert np.array_equal(model.spring_force(x), polynomial_spring_force(x, 3e3, -4e5, 2e7))
    stiffness = polynomial_spring_stiffness(x, 3e3, -4e5, 2e7)
    assert np.array_equal(model.spring_stiffness(x), stiffness)
    lowest = lowest_spring_stiffness(3e3, -4e5, 2e7, -0.02, 0.02)
    # the analytic minimum at the vertex x = -g2 / (3 g3) = 6.67 mm: g1 - g2^2 / (3 g3)
    assert lowest == pytest.approx(3e3 - 4e5**2 / (3 * 2e7), rel=1e-12)
    # the grid (20 um spacing) cannot go below it and misses it by at most 3 g3 h^2 = 0.024 N/m
    assert lowest <= stiffness.min() <= lowest + 3 * 2e7 * (2e-5) ** 2


# --------------------------------------------------------------------------- optimiser status


@pytest.mark.parametrize("backend", ["nlopt", "scipy"])
def test_nelder_mead_status_comes_from_the_optimiser(backend):
    bounds = (np.full(2, -5.0), np.full(2, 5.0))

    def bowl(u):
        return float((u[0] - 1.0) ** 2 + 10 * (u[1] + 2.0) ** 2)

    done = nelder_mead(bowl, [0.0, 0.0], step=0.5, bounds=bounds, backend=backend, max_evals=2000, xtol=1e-9,
                       ftol=1e-14, restarts=1)
    assert done.status == CONVERGED and done.success
    assert np.allclose(done.x, [1.0, -2.0], atol=1e-6)  # xtol 1e-9 on a bowl of curvature 2-20
    stopped = nelder_mead(bowl, [0.0, 0.0], step=0.5, bounds=bounds, backend=backend, max_evals=12, xtol=1e-9,
                          ftol=1e-14, restarts=2)
    assert stopped.status == MAX_EVALS and not stopped.success and stopped.evaluations >= 12


class _NeverFeasible:
    """min z^2 subject to 0.5 - z <= 0 and z - 0.25 <= 0 (no point meets both)."""

    names = ["z"]
    evaluations = 0
    n_constraints = 2

    def objective(self, z, with_gradient=True):
        self.evaluations += 1
        return float(z[0] ** 2), (np.array([2 * z[0]]) if with_gradient else None)

    def constraints(self, z):
        return np.array([0.5 - z[0], z[0] - 0.25]), np.array([[-1.0], [1.0]])


@pytest.mark.parametrize("backend", ["nlopt", "scipy"])
def test_sqp_that_never_meets_the_constraints_says_infeasible(backend):
    run = sqp(_NeverFeasible(), [0.9], backend=backend, max_evals=50, ftol=1e-12)
    assert run.status == INFEASIBLE and not run.success and run.x[0] == 0.9  # the start kept


# --------------------------------------------------------------------------- results


def _iwan_loops():
    truth = IwanModel(g1=3e3, k=[6e3], fc=[10.0])
    x = np.sin(np.linspace(0, 4 * np.pi, 400))
    return [(a * x, truth.force(a * x)) for a in (1e-3, 2e-3)], [(8e-3 * x, truth.force(8e-3 * x))]


def _frfs():
    sets = []
    for mass in (1.0, 3.0):
        h = sdof_transmissibility(ELASTOMER.complex_stiffness(FREQ), mass + ELASTOMER.m_eff, 2 * np.pi * FREQ)
        sets.append((mass, FREQ, h))
    return sets


def _lmfit_like(result) -> None:
    assert result.params is result.parameters
    assert isinstance(result.success, bool) and isinstance(result.message, str) and result.message
    assert result.nfev >= result.evaluations > 0
    assert math.isfinite(result.chisqr) and math.isfinite(result.aic)
    assert "[[Variables]]" in result.fit_report()


def _units_are_the_models(result, model) -> None:
    declared = {spec.name: spec.unit for spec in model.param_specs()}
    for name, parameter in result.params.items():
        if name in declared:
            assert parameter.user_data["unit"] == declared[name], name


def test_iwan_result_reads_like_lmfit_with_the_models_units():
    small, large = _iwan_loops()
    result = fit_iwan(small, large, order=1)
    _lmfit_like(result)
    _units_are_the_models(result, result.model)
    assert all(stage.status in ("converged", "stalled") for stage in result.stages)
    limited = fit_iwan(small, large, order=1, max_evals=30)
    assert any(stage.status == MAX_EVALS for stage in limited.stages)
    assert not limited.success and any("evaluation limit" in reason for reason in limited.reasons)


def test_maxwell_and_voigt_results_read_like_lmfit_with_the_models_units():
    maxwell = fit_maxwell(_frfs(), k0=ELASTOMER.k0, k0_stderr=50.0, order=2)
    _lmfit_like(maxwell)
    _units_are_the_models(maxwell, maxwell.model)
    assert maxwell.status == CONVERGED and maxwell.params["k0"].stderr == 50.0
    assert isinstance(maxwell.model, GeneralizedMaxwell)
    voigt = fit_voigt(_frfs(), k0=ELASTOMER.k0)
    _units_are_the_models(voigt, voigt.model)
    assert isinstance(voigt.model, VoigtModel) and voigt.status in ("converged", "stalled")


def test_boucwen_result_shares_the_loop_result_base():
    truth = BoucWenModel(k1=2e3, k2=0, k3=0, alpha=2e4, beta=6e3, gamma=2e3, n=1.0)
    x = np.sin(np.linspace(0, 4 * np.pi, 401))
    result = fit_boucwen([(1e-3 * x, truth.force(1e-3 * x))], [(4e-3 * x, truth.force(4e-3 * x))],
                         global_max_evals=300)
    _lmfit_like(result)
    _units_are_the_models(result, result.model)
    iwan = fit_iwan(*_iwan_loops(), order=1)
    assert list(result.to_dataframe().columns) == list(iwan.to_dataframe().columns)
    assert result.success == (not result.reasons)
    assert result.params["z_max"].user_data["unit"] == "N"
