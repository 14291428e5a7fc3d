"""Generalized Maxwell and Bouc-Wen force laws against closed-form solutions."""

import numpy as np
import pytest

from idkit.models import BoucWenModel, GeneralizedMaxwell, SDOFSystem, VoigtModel, library


def test_maxwell_ramp_matches_closed_form():
    """Constant-rate deflection r = v t: u_i = v / rate_i (1 - exp(-rate_i t))."""
    model = GeneralizedMaxwell(k0=1e3, k=[2e3, 5e3], rate=[10.0, 400.0])
    time = np.linspace(0, 0.5, 50)  # coarse on purpose: the update is exact for linear r
    velocity = 0.01
    force = model.force(velocity * time, time)
    expected = model.k0 * velocity * time + np.sum(
        np.array(model.k) * velocity / np.array(model.rate)
        * (1 - np.exp(-np.outer(time, model.rate))), axis=1)
    np.testing.assert_allclose(force, expected, rtol=1e-12, atol=1e-12)


def test_maxwell_time_domain_steady_state_matches_complex_stiffness():
    model = library.get("table_7_3_elastomer")
    freq = 20.0
    time = np.arange(0, 2.0, 1 / (freq * 2048))
    x = 1e-3 * np.sin(2 * np.pi * freq * time)
    force = model.force(x, time)
    last = time >= 1.0  # 20 periods; slowest rate 46.6 1/s has decayed by exp(-46)
    basis = np.exp(2j * np.pi * freq * time[last])
    coefficient = 2 * np.mean(force[last] * np.conj(basis))
    expected = model.complex_stiffness(freq) * (-1j * 1e-3)
    # the exponential update is exact for piecewise-linear x: the residual is the
    # linear-interpolation error of a sine at 2048 points per period, O(1e-6)
    assert abs(coefficient / expected - 1) < 1e-5


def test_complex_stiffness_limits_and_rate_naming():
    model = GeneralizedMaxwell.from_dampers(k0=1e3, k=[2e3, 5e3], damping=[20.0, 5.0])
    np.testing.assert_allclose(model.rate, [100.0, 1000.0])
    np.testing.assert_allclose(model.tau, [0.01, 0.001])
    assert model.complex_stiffness(0.0) == pytest.approx(1e3)
    assert model.complex_stiffness(1e9).real == pytest.approx(model.instantaneous_stiffness, rel=1e-6)
    same = GeneralizedMaxwell.from_time_constants(k0=1e3, k=[2e3, 5e3], tau=[0.01, 0.001])
    assert same == model
    voigt = VoigtModel(k=1e4, damping=50.0)
    assert voigt.loss_factor(10.0) == pytest.approx(2 * np.pi * 10 * 50 / 1e4)
    assert voigt.damping_ratio(10.0) == pytest.approx(voigt.loss_factor(10.0) / 2)


def test_table_7_3_resonances_read_as_rates():
    """SPEC 1.4: with rates in 1/s the identified model resonates at ~19.5 Hz and ~7.8 Hz."""
    elastomer = library.get("table_7_3_elastomer")
    freq = np.linspace(2, 40, 38001)
    for mass, resonance in ((0.99, 19.5), (6.40, 7.8)):
        peak = freq[np.argmax(np.abs(SDOFSystem(mass, elastomer).transmissibility(freq)))]
        assert peak == pytest.approx(resonance, abs=0.15)


def test_boucwen_loading_branch_matches_closed_form():
    """n = 1, loading with z >= 0: dz/dx = alpha - (gamma + beta) z."""
    model = BoucWenModel(k1=0.0, k2=0.0, k3=0.0, alpha=5e3, beta=300.0, gamma=200.0, n=1.0)
    x = np.linspace(0, 0.02, 2001)
    z = model.hysteretic_force(x)
    rate = model.beta + model.gamma
    np.testing.assert_allclose(z, model.alpha / rate * (1 - np.exp(-rate * x)), rtol=1e-8, atol=1e-10)
    # force law with asymmetry factor and polynomial
    full = BoucWenModel(k1=1e3, k2=2e4, k3=1e5, alpha=5e3, beta=300.0, gamma=200.0, n=1.0, b=2.0, c=10.0)
    elastic = x * (1e3 + 2e4 * np.abs(x) + 1e5 * x**2)
    np.testing.assert_allclose(full.force(x), 2.0 ** (10.0 * x) * (elastic + z), rtol=1e-8)
