"""Modified Iwan model with deflection-dependent slip forces (idkit.models.iwan_modulated)."""

import itertools

import numpy as np
import pytest

from idkit.errors import ParameterError
from idkit.models import (
    IwanModel,
    ModulatedIwanModel,
    SDOFSystem,
    load_model,
    save_model,
)
from idkit.simulate import BaseMotion, simulate

PLAIN = {"g1": 1.84e4, "g2": 2.45e5, "g3": -4.57e5, "k": [1.88e5, 9.09e3], "fc": [15.5, 10.3]}


def _path(amplitudes, points=400):
    """Deflection path from 0 through reversals at the given amplitudes (m), piecewise linear."""
    corners = np.concatenate([[0.0], amplitudes])
    return np.concatenate([np.linspace(a, b, points)[1:] for a, b in itertools.pairwise(corners)])


def test_zero_modulation_is_the_plain_iwan_model_to_round_off():
    # the limits are multiplied by exactly 1.0 and the tangent gains exactly 0: bit-for-bit equality
    path = _path([0.012, -0.015, 0.008, -0.004])
    plain = IwanModel(**PLAIN, c_visc=4.0)
    modulated = ModulatedIwanModel(**PLAIN, c_visc=4.0, slip_modulation=0.0, slip_length=3e-3)
    np.testing.assert_array_equal(modulated.force(path), plain.force(path))
    t = np.arange(0.0, 0.4, 1e-4)
    base = BaseMotion.harmonic(12.0, 8e-3)
    fast = [simulate(SDOFSystem(2.98, model), t, base=base, gravity=True) for model in (plain, modulated)]
    np.testing.assert_array_equal(fast[0].acceleration, fast[1].acceleration)
    np.testing.assert_array_equal(fast[0].isolator_force, fast[1].isolator_force)


@pytest.mark.parametrize(("a", "b"), [(0.4, 0.0), (0.0, 0.5), (0.3, 0.4)])
def test_virgin_loading_follows_the_analytic_slip_force(a, b):
    # one element loaded monotonically from rest: F = min(k y, s(y) fc) in tension and
    # max(k y, -s(y) fc) in compression, s = 1 - a t + b t^2, exact while
    # (|a| + 2 |b|) fc / (k y_ref) < 1 (module docstring)
    model = ModulatedIwanModel(g1=0.0, k=[2e4], fc=[10.0], slip_modulation=a, slip_growth=b, slip_length=4e-3)
    assert model.stop_operator_exact
    for end in (0.02, -0.02):
        y = np.linspace(0.0, end, 2001)
        t = np.tanh(y / 4e-3)
        expected = np.sign(end) * np.minimum(2e4 * np.abs(y), 10.0 * (1.0 - a * t + b * t * t))
        np.testing.assert_allclose(model.force(y), expected, rtol=1e-12, atol=1e-12)


def test_loops_widen_alike_in_tension_and_compression_with_the_symmetric_term():
    model = ModulatedIwanModel(**PLAIN, slip_growth=0.5, slip_length=4e-3)
    path = _path([0.01, -0.01, 0.01, -0.01])
    force = model.force(path) - model.spring_force(path)  # the hysteretic part
    up, down = slice(2 * 399, 3 * 399), slice(3 * 399, 4 * 399)

    def width_at(y):
        return (force[up][np.argmin(np.abs(path[up] - y))] - force[down][np.argmin(np.abs(path[down] - y))])

    # at +-5 mm both branches have travelled 5 mm or more since their reversal, beyond every
    # element's slip travel (2 s fc / k <= 3.3 mm): width 2 s(y) sum fc, s = 1 + 0.5 tanh(1.25)^2
    # on both sides; the nearest grid point is within 0.025 mm, where s changes by 1.1e-3
    expected = 2.0 * (1.0 + 0.5 * np.tanh(1.25) ** 2) * sum(PLAIN["fc"])
    assert width_at(0.005) == pytest.approx(expected, rel=3e-3)
    assert width_at(-0.005) == pytest.approx(expected, rel=3e-3)


def test_loops_are_wider_in_compression_when_the_modulation_is_positive():
    model = ModulatedIwanModel(**PLAIN, slip_modulation=0.35, slip_length=6e-3)
    path = _path([0.01, -0.01, 0.01, -0.01])
    force = model.force(path)
    up = slice(2 * 399, 3 * 399)  # the last cycle: -10 mm -> 10 mm (upper branch) ...
    down = slice(3 * 399, 4 * 399)  # ... and back (lower branch)

    def width_at(y):
        return (force[up][np.argmin(np.abs(path[up] - y))] - force[down][np.argmin(np.abs(path[down] - y))])

    # slip scale 1.35 tanh(...) larger in compression: 1 - 0.35 tanh(-8/6) vs 1 - 0.35 tanh(8/6)
    assert width_at(-0.008) > 1.5 * width_at(0.008)


def test_shrinking_limit_clips_the_element_force():
    model = ModulatedIwanModel(g1=0.0, k=[1e6], fc=[10.0], slip_modulation=0.5, slip_length=1e-3)
    # slip at y = -2 mm (limit 10 (1 + 0.5 tanh 2)), then move to tension without reversal of
    # the element's sign: the limit shrinks to 10 (1 - 0.5 tanh 2) and the force follows it
    y = np.concatenate([np.linspace(0.0, -2e-3, 50), np.linspace(-2e-3, 2e-3, 400)[1:]])
    forces = model.jenkin_forces(y)[:, 0]
    assert forces[-1] == pytest.approx(10.0 * (1.0 - 0.5 * np.tanh(2.0)), rel=1e-12)
    assert np.all(np.abs(forces) <= 10.0 * (1.0 - 0.5 * np.tanh(y / 1e-3)) * (1 + 1e-12))


@pytest.mark.parametrize(("a", "b"), [(0.3, 0.0), (0.0, 0.5), (0.3, 0.4)])
def test_kernel_force_equals_the_quasi_static_operator_along_the_simulated_path(a, b):
    # the simulator's constitutive update is the model's operator applied to the deflection it
    # produced; same rule, same samples: agreement to round-off of the force (1e-9 relative)
    model = ModulatedIwanModel(**PLAIN, slip_modulation=a, slip_growth=b, slip_length=5e-3)
    t = np.arange(0.0, 0.5, 5e-5)
    run = simulate(SDOFSystem(2.98, model), t, base=BaseMotion.harmonic(9.0, 1.2e-2))
    assert run.ok.all()
    y = run.deflection[0, 0]
    np.testing.assert_allclose(run.isolator_force[0, 0], model.force(y), rtol=0, atol=1e-9 * 40.0)


def test_parameters_and_model_file(tmp_path):
    model = ModulatedIwanModel(**PLAIN, c_visc=4.0, slip_modulation=-0.2, slip_growth=0.3, slip_length=7e-3)
    assert model.params()["slip_modulation"] == -0.2 and model.params()["slip_growth"] == 0.3
    # a parameter set written before the symmetric term (no slip_growth) reads as b = 0
    older = {name: value for name, value in model.params().items() if name != "slip_growth"}
    assert ModulatedIwanModel.from_params(older).slip_growth == 0.0
    assert ModulatedIwanModel.from_params(model.params()) == model
    assert model.with_vector(model.to_vector()) == model
    path = tmp_path / "rope.json"
    save_model(model, path)
    assert load_model(path) == model
    assert model.plain() == IwanModel(**PLAIN, c_visc=4.0)


@pytest.mark.parametrize("options, word", [
    ({"slip_modulation": 1.0}, "slip_modulation"),
    ({"slip_modulation": -1.5}, "slip_modulation"),
    ({"slip_length": 0.0}, "slip_length"),
    ({"slip_modulation": float("nan")}, "slip_modulation"),
    ({"slip_growth": -1.0}, "slip_growth"),  # s(+-inf) = 0
    ({"slip_modulation": 0.8, "slip_growth": -0.5}, "slip_growth"),  # s = -0.3 at t = 1
])
def test_bad_parameters_are_named(options, word):
    with pytest.raises(ParameterError, match=word):
        ModulatedIwanModel(**PLAIN, **options)
