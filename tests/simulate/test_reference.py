"""Sanity of the solve_ivp reference path (idkit.simulate.reference) on problems with known answers."""


import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import (
    BoucWenModel,
    CoulombSpringSystem,
    GeneralizedMaxwell,
    HybridSystem,
    IwanModel,
    SDOFSystem,
    VoigtModel,
    library,
)
from idkit.simulate import BaseMotion
from idkit.simulate.reference import _derivatives, _layout, harmonic_reference, solve_ivp_reference

MASS = 2.0  # kg
STIFFNESS = 2000.0  # N/m, natural frequency 5.03 Hz with MASS
DAMPING = 6.0  # N s/m, damping ratio 0.047
VOIGT = SDOFSystem(MASS, VoigtModel(k=STIFFNESS, damping=DAMPING))


def _damped_free_vibration(t, y0):
    omega_n = np.sqrt(STIFFNESS / MASS)
    zeta = DAMPING / (2.0 * np.sqrt(STIFFNESS * MASS))
    omega_d = omega_n * np.sqrt(1.0 - zeta**2)
    return y0 * np.exp(-zeta * omega_n * t) * (np.cos(omega_d * t) + zeta * omega_n / omega_d * np.sin(omega_d * t))


@pytest.mark.parametrize("method", ["BDF", "Radau", "LSODA"])
def test_voigt_free_vibration_matches_analytic(method):
    # Linear SDOF from an initial deflection of 1 mm: the closed-form damped cosine.
    # Tolerance 1e-6 of the amplitude: rtol = 1e-9 over ~5 cycles accumulates a phase
    # error of order 1e-8; 1e-6 leaves room for the interpolation of solve_ivp's
    # dense output at t_eval, and is still 1000x below any modelling effect.
    y0 = 1e-3
    t = np.linspace(0.0, 1.0, 2001)
    run = solve_ivp_reference(VOIGT, t, initial_deflection=[y0], method=method, rtol=1e-9, atol=1e-14)
    assert run.flags[0] == 0 and run.reasons == ("ok",)
    np.testing.assert_allclose(run.displacement[0, 0], _damped_free_vibration(t, y0), rtol=0, atol=1e-6 * y0)
    # isolator force k y + c ydot and absolute acceleration -(force)/m (base at rest)
    expected_force = STIFFNESS * run.deflection[0, 0] + DAMPING * run.velocity[0, 0]
    np.testing.assert_allclose(run.isolator_force[0, 0], expected_force, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(run.acceleration[0, 0], -expected_force / MASS, rtol=1e-12, atol=1e-12)


def test_voigt_harmonic_matches_transmissibility():
    # Steady state of a linear system: X_1 = H(f) * (-i A), H = k* / (k* - m w^2).
    # 24 periods at 4 Hz: the transient decays as exp(-zeta w_n t) = exp(-1.5 * 6 s) ~ 1e-4
    # relative; tolerance 5e-4 of |X_1| covers that and the solver error (rtol 1e-9).
    freq, amplitude = 4.0, 1e-3
    result = harmonic_reference(VOIGT, freq, amplitude, n_periods=24, rtol=1e-9)
    expected = VOIGT.transmissibility(freq) * (-1j * amplitude)
    assert abs(result.harmonic(1) - expected) < 5e-4 * abs(expected)
    assert abs(result.hosidf(1) - VOIGT.transmissibility(freq)) < 5e-4 * abs(expected) / amplitude
    # A linear system has no higher harmonics and no bias; what is left is the decaying
    # transient at the natural frequency leaking into every bin (~1e-4 of X_1 after 6 s,
    # measured 1.4e-5 for the bias), so the bound is the same 5e-4.
    for order in (0, 0.5, 2, 3):
        assert abs(result.harmonic(order)) < 5e-4 * abs(expected)
    assert result.change < 1e-3


def test_base_given_as_acceleration_equals_base_given_as_displacement():
    # The same harmonic floor motion given as displacement (evaluated exactly) and as
    # acceleration (integrated as two extra ODE states, with the extra Jacobian columns).
    # Both solves run at rtol 1e-10, so they must agree to ~1e-8 of the response;
    # tolerance 1e-7 of the base amplitude.
    freq, amplitude = 6.0, 2e-3
    omega = 2 * np.pi * freq
    system = library.get("hybrid_symmetric")
    t = np.linspace(0.0, 0.5, 501)
    as_displacement = BaseMotion.harmonic(freq, amplitude)
    as_acceleration = BaseMotion.from_function(lambda s: -amplitude * omega**2 * np.sin(omega * s),
                                               quantity="acceleration", initial_velocity=amplitude * omega)
    runs = [solve_ivp_reference(system, t, base=base, rtol=1e-10, atol=1e-14, method="LSODA")
            for base in (as_displacement, as_acceleration)]
    np.testing.assert_allclose(runs[1].displacement, runs[0].displacement, rtol=0, atol=1e-7 * amplitude)
    np.testing.assert_allclose(runs[1].deflection, runs[0].deflection, rtol=0, atol=1e-7 * amplitude)


def _all_element_systems():
    wire_rope = IwanModel(g1=3e3, g2=4e4, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6], c_visc=1.3)
    elastomer = GeneralizedMaxwell(k0=1e3, k=[5.4e2, 1.2e4], rate=[1.0, 480.0], m_eff=0.1)
    bouc_wen = BoucWenModel(k1=1e3, k2=2e4, k3=1e5, alpha=5e3, beta=2e3, gamma=1e3, n=1.5, b=2.0, c=10.0,
                            c_visc=0.5)
    return {
        "hybrid_iwan": HybridSystem(2.0, elastomer, 0.02, wire_rope),
        "hybrid_bouc_wen": HybridSystem(2.0, elastomer, 0.02, bouc_wen),
        "coulomb": CoulombSpringSystem(mass=10.0, stiffness=9000.0, friction_force=1000.0, damping=10.0),
    }


@pytest.mark.parametrize("name", ["hybrid_iwan", "hybrid_bouc_wen", "coulomb"])
def test_analytic_jacobian_matches_finite_differences(name):
    # Central differences of the compiled right-hand side at random states where every
    # tanh is in its transition (velocities ~ v_eps, Jenkin forces around Fc). Relative
    # step 1e-7 gives a truncation + round-off error of ~1e-6 of the largest entry of a
    # column; tolerance 1e-4 of that column scale.
    system = _all_element_systems()[name]
    layout = _layout(system)
    n = layout.n_states
    eps, veps = 0.05, 0.01
    rng = np.random.default_rng(7)
    for _ in range(5):
        state = np.concatenate([
            rng.normal(0, 2e-3, layout.ndof),  # m
            rng.normal(0, 2 * veps, layout.ndof),  # m/s
            layout.j_fc * rng.uniform(-1.05, 1.05, layout.j_fc.size),  # N, across the saturation
            rng.normal(0, 1e-3, layout.m_k.size),  # m
            rng.normal(0, 1.0, layout.b_zy.size),  # N
        ])
        xb, vb = 1e-3, 0.5 * veps

        def evaluate(s, want_jacobian=False, xb=xb, vb=vb):
            rate, jac, dxb, dvb = np.zeros(n), np.zeros((n, n)), np.zeros(n), np.zeros(n)
            _derivatives(s, xb, vb, *layout.arrays(), eps, veps, 0.0, want_jacobian, rate, jac, dxb, dvb,
                         np.zeros(layout.ndof))
            return rate, jac, dxb, dvb

        _, jac, dxb, dvb = evaluate(state, True)
        columns = []
        for index in range(n):
            step = 1e-7 * max(abs(state[index]), 1e-4 if index < 2 * layout.ndof else 1e-2)
            plus, minus = state.copy(), state.copy()
            plus[index] += step
            minus[index] -= step
            columns.append((evaluate(plus)[0] - evaluate(minus)[0]) / (2 * step))
        numeric = np.array(columns).T
        scale = np.maximum(np.abs(numeric).max(axis=0), 1e-12)
        assert np.all(np.abs(jac - numeric) <= 1e-4 * scale), name
        for which, analytic, value in (("x_b", dxb, xb), ("v_b", dvb, vb)):
            step = 1e-7 * max(abs(value), 1e-3)
            args_plus = {"xb": xb + step} if which == "x_b" else {"vb": vb + step}
            args_minus = {"xb": xb - step} if which == "x_b" else {"vb": vb - step}
            numeric_base = (evaluate(state, **args_plus)[0] - evaluate(state, **args_minus)[0]) / (2 * step)
            assert np.all(np.abs(analytic - numeric_base) <= 1e-4 * max(np.abs(numeric_base).max(), 1e-12)), which


def test_jenkin_rate_law_reduces_to_stop_operator():
    # Drive one Jenkin element of the compiled rate law along a prescribed deflection
    # history (a decaying sine reaching twice the yield deflection) and compare with the
    # exact stop operator (SPEC 1.1).
    from scipy.integrate import solve_ivp

    from idkit.models import jenkin_force

    stiffness, friction = 3e3, 8.3
    layout = _layout(SDOFSystem(1.0, IwanModel(g1=0.0, k=[stiffness], fc=[friction])))
    t = np.linspace(0.0, 2.0, 4001)
    amplitude = 6e-3  # m, twice the yield deflection friction/stiffness = 2.8 mm
    deflection = amplitude * np.sin(2 * np.pi * t) * (1 - 0.3 * t)
    exact = jenkin_force(deflection, stiffness, friction)
    errors = []
    for eps in (1e-2, 1e-3, 1e-4):
        def rate(s, force, eps=eps):
            ydot = amplitude * (2 * np.pi * np.cos(2 * np.pi * s) * (1 - 0.3 * s) - 0.3 * np.sin(2 * np.pi * s))
            state = np.array([0.0, ydot, force[0]])
            out = np.zeros(3)
            _derivatives(state, 0.0, 0.0, *layout.arrays(), eps, eps * 1.0, 0.0, False, out, np.zeros((3, 3)),
                         np.zeros(3), np.zeros(3), np.zeros(1))
            return out[2:]

        solution = solve_ivp(rate, (0, 2.0), [0.0], t_eval=t, method="LSODA", rtol=1e-10, atol=1e-10)
        errors.append(np.abs(solution.y[0] - exact).max() / friction)
    # The error shrinks with the smoothing width and is below 1 % of Fc at eps = 1e-4.
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-2


def test_negative_stiffness_is_flagged_like_the_fast_integrator():
    # Table 7.1 wire rope: local stiffness of the parallel spring turns negative near
    # -34 mm (SPEC 1.2). A hard drop crosses it; both paths stop with flag 1 and NaN after.
    # The crossing times agree within 1 ms (fast step 1e-5 s; the event is located by
    # the ODE solver to rtol).
    from idkit.simulate import simulate

    system = SDOFSystem(2.98, library.get("table_7_1_wire_rope"))
    t = np.arange(0, 0.1, 1e-5)
    reference = solve_ivp_reference(system, t, initial_velocity=[-3.0], rtol=1e-8, method="LSODA")
    fast = simulate(system, t, initial_velocity=[-3.0])
    assert reference.flags[0] == 1 == fast.flags[0]
    assert "negative local stiffness" in reference.reasons[0]
    assert abs(reference.flag_time[0] - fast.flag_time[0]) < 1e-3
    assert np.all(np.isnan(reference.displacement[0, 0, t > reference.flag_time[0] + 1e-5]))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"initial_deflection": [1e-3, 0.0]}, "initial_deflection"),
        ({"atol": [1e-9]}, "atol"),
    ],
)
def test_bad_arguments_are_named(kwargs, match):
    with pytest.raises(SimulationError, match=match):
        solve_ivp_reference(VOIGT, np.linspace(0, 0.1, 11), **kwargs)


def test_bad_system_is_named():
    with pytest.raises(SimulationError, match="system"):
        solve_ivp_reference(VOIGT.isolator, np.linspace(0, 0.1, 11))
