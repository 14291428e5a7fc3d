"""The admissible Bouc-Wen parameter space (BoucWenModel Notes): hardening laws included."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from idkit.errors import ParameterError
from idkit.models import BoucWenModel
from idkit.models.boucwen import check_boucwen_shape
from idkit.models.laws import boucwen_z_history


def _model(beta, gamma, n=1.0):
    return BoucWenModel(k1=5e4, k2=0.0, k3=0.0, alpha=5e4, beta=beta, gamma=gamma, n=n)


@pytest.mark.parametrize("beta, gamma, n", [
    (800.0, -1100.0, 1.0),     # the Noel & Schoukens benchmark: hardening
    (800.0, -1100.0, 0.5),
    (800.0, -1100.0, 1.5),     # hardening, n > 1: valid below its escape deflection
    (500.0, -500.0, 2.0),      # linear loading
    (300.0, 200.0, 1.0),       # class I
    (-100.0, 400.0, 1.0),      # class II
])
def test_admissible_laws_are_accepted(beta, gamma, n):
    assert _model(beta, gamma, n).beta == beta


@pytest.mark.parametrize("beta, gamma", [(-100.0, -200.0), (0.0, -300.0), (0.0, 0.0), (-300.0, 300.0)])
def test_ratcheting_laws_are_refused_with_the_condition(beta, gamma):
    with pytest.raises(ParameterError, match=r"beta \+ gamma .* expected .*beta > 0"):
        _model(beta, gamma)


def _loop_peaks(beta, gamma, n, cycles=40):
    """Peak |z| per cycle of a 1 mm harmonic deflection."""
    x = 1e-3 * np.sin(np.linspace(0.0, 2 * np.pi * cycles, 400 * cycles + 1))
    z = boucwen_z_history(x, 5e4, beta, gamma, n, 0.0, 4)
    return np.abs(z[:-1]).reshape(cycles, 400).max(axis=1)


@pytest.mark.parametrize("n", [0.5, 1.0])
def test_beta_decides_between_a_closed_loop_and_ratcheting(n):
    """The Notes' map: hardening cycles converge iff beta > 0. With beta > 0 the last cycles repeat
    to 1e-6 after 40 cycles (geometric convergence, ratio (alpha + 300 Z^n)/(alpha + 1900 Z^n) per half
    cycle: 0.82 for n = 0.5, 0.73 for n = 1);
    with beta < 0 (ratio > 1) the peak keeps growing, by more than 1 % over the last 5 cycles."""
    closed = _loop_peaks(800.0, -1100.0, n)
    assert abs(closed[-1] - closed[-2]) < 1e-6 * closed[-1]
    ratchet = _loop_peaks(-200.0, -100.0, n)
    assert ratchet[-1] > 1.01 * ratchet[-6]


def test_escape_deflection_is_the_integral_of_the_loading_law():
    """x_escape = int_0^inf dz / (alpha + |beta + gamma| z^n), by quadrature to 1e-10."""
    model = _model(800.0, -1100.0, 1.5)
    integral, _ = quad(lambda z: 1.0 / (5e4 + 300.0 * z ** 1.5), 0.0, math.inf, epsabs=0.0, epsrel=1e-12)
    assert model.escape_deflection == pytest.approx(integral, rel=1e-8)
    assert math.isinf(_model(800.0, -1100.0, 1.0).escape_deflection)
    assert math.isinf(_model(300.0, 200.0, 2.0).escape_deflection)


def test_check_names_the_values():
    with pytest.raises(ParameterError, match="found beta \\+ gamma = -300"):
        check_boucwen_shape(-100.0, -200.0, 1.0, model="BoucWenModel")


def test_a_step_many_relaxation_lengths_long_is_integrated_not_lost():
    """A yield travel z_max / alpha of 10 um sampled in 1.3 mm steps: four fixed Runge-Kutta
    sub-steps of 0.32 mm are 32 relaxation lengths each, far past the explicit scheme's
    stability (about 2.8), and z overflowed to NaN, returned as a force. The sub-steps now
    follow the relaxation length: z stays within z_max and equals z along the same piecewise
    linear path sampled 1000x finer (the law is rate independent: z depends on the path
    only) to 1e-5 of z_max (RK4 at a quarter relaxation length a sub-step errs by about
    0.25^5 / 120 = 8e-6 of the relaxing part, at most 2 z_max, and the error relaxes with it;
    5.6e-7 measured). A step beyond even the most sub-steps (5 m here) is an error naming the
    sample, not NaN."""
    from idkit.errors import SimulationError

    model = BoucWenModel(k1=3e4, k2=1e6, k3=0.0, alpha=1e5, beta=8e4, gamma=2e4, n=2)
    assert model.yield_travel == pytest.approx(1e-5, rel=1e-12)
    z_max = (model.alpha / (model.beta + model.gamma)) ** (1.0 / model.n)
    coarse = 0.01 * np.sin(np.linspace(0.0, 2.0 * np.pi, 50))
    z = model.hysteretic_force(coarse)
    fine = np.interp(np.linspace(0.0, coarse.size - 1.0, 1000 * (coarse.size - 1) + 1), np.arange(coarse.size), coarse)
    assert np.all(np.abs(z) <= z_max * (1.0 + 1e-9))
    np.testing.assert_allclose(z, model.hysteretic_force(fine)[::1000], rtol=0.0, atol=1e-5 * z_max)
    with pytest.raises(SimulationError, match=r"diverged at deflection sample 1 \(a step of 5 m.*1e-05 m"):
        model.force([0.0, 5.0])
