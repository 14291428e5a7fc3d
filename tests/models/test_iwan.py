"""Quasi-static Iwan model: analytic invariants of the exact stop operator."""

import numpy as np
import pytest

from idkit.models import IwanModel, jenkin_force, library


def triangle(amplitude, n_cycles=3, points_per_quarter=400):
    """Deflection history 0 -> +A -> -A -> +A ... (piecewise linear, m)."""
    path = [np.linspace(0.0, amplitude, points_per_quarter, endpoint=False)]
    for _ in range(n_cycles):
        path.append(np.linspace(amplitude, -amplitude, 2 * points_per_quarter, endpoint=False))
        path.append(np.linspace(-amplitude, amplitude, 2 * points_per_quarter, endpoint=False))
    return np.concatenate(path + [[amplitude]])


def test_jenkin_corners_at_plus_minus_fc():
    x = triangle(5e-3)
    force = jenkin_force(x, stiffness=3e3, friction_force=8.3)
    assert force.max() == pytest.approx(8.3, abs=0)
    assert force.min() == pytest.approx(-8.3, abs=0)
    # elastic branch slope equals k right after every reversal
    reversal = np.argmax(x)
    slope = (force[reversal + 1] - force[reversal]) / (x[reversal + 1] - x[reversal])
    assert slope == pytest.approx(3e3, rel=1e-12)


def test_stuck_and_slipping_slopes():
    model = library.get("table_a1_symmetric")
    x = np.linspace(0, 20e-3, 4001)
    force = model.force(x)
    slopes = np.diff(force) / np.diff(x)
    assert slopes[0] == pytest.approx(model.stuck_stiffness, rel=1e-12)  # all stuck: g1 + sum k
    assert slopes[-1] == pytest.approx(model.g1, rel=1e-12)  # all slipping: g1
    # slip onsets at fc_i / k_i: slope drops by k_i there
    onset = np.array(model.fc) / np.array(model.k)
    middle = (onset[0] + onset[1]) / 2
    assert slopes[np.searchsorted(x, middle)] == pytest.approx(model.g1 + model.k[1], rel=1e-12)


def test_masing_property_of_symmetric_model():
    """Unloading from a reversal (x_r, F_r) follows F_r - 2 F_backbone((x_r - x)/2)."""
    model = IwanModel.symmetric(k_wr0=3e3, k=[3e3, 5e3, 2e3], fc=[8.3, 14.6, 4.0])
    amplitude = 6e-3
    x_load = np.linspace(0, amplitude, 601)
    x_unload = np.linspace(amplitude, -amplitude, 1201)
    force = model.force(np.concatenate([x_load, x_unload[1:]]))
    f_reversal = force[600]
    unloading = force[600:]
    backbone = model.force(np.linspace(0, 2 * amplitude, 1201) / 2)  # F_bb((x_r - x)/2)
    expected = f_reversal - 2 * backbone
    np.testing.assert_allclose(unloading, expected, rtol=0, atol=1e-9 * abs(f_reversal))


def test_asymmetric_soft_hardening_shape():
    model = library.get("table_a1_asymmetric")
    amplitude = 15e-3
    x = triangle(amplitude, n_cycles=2)
    force = model.force(x)
    # asymmetry: tension peak exceeds compression peak (g2 > 0)
    assert force.max() > abs(force.min()) * 1.05
    # hardening: tangent stiffness on the loading branch grows toward the tip (g3 > 0)
    tip = np.argmax(x)
    branch_slopes = np.diff(force[tip - 300 : tip]) / np.diff(x[tip - 300 : tip])
    assert branch_slopes[-1] > branch_slopes[len(branch_slopes) // 2] > 0
    # the symmetric sibling has equal peaks
    symmetric = library.get("table_a1_symmetric").force(x)
    assert symmetric.max() == pytest.approx(-symmetric.min(), rel=1e-12)


@pytest.mark.parametrize("amplitude", [2e-3, 5e-3, 20e-3])
def test_loop_area_equals_dissipated_energy(amplitude):
    """Per steady cycle each slipping Jenkin dissipates 4 Fc (X - Fc/k); the spring none."""
    model = library.get("table_a1_asymmetric")
    x = triangle(amplitude, n_cycles=3, points_per_quarter=2000)
    force = model.force(x)
    start = 4000 + 8000  # after the first loading quarter and one full cycle
    cycle = slice(start, start + 8001)
    area = np.trapezoid(force[cycle], x[cycle])
    k, fc = np.array(model.k), np.array(model.fc)
    slipping = k * amplitude > fc
    dissipated = np.sum(4 * fc[slipping] * (amplitude - fc[slipping] / k[slipping]))
    # trapezoid on a piecewise-linear loop sampled every A/2000 is exact except at
    # slip onsets inside a step: error <= sum Fc * step
    assert area == pytest.approx(dissipated, abs=float(np.sum(fc)) * amplitude / 2000)


def test_negative_stiffness_range_of_table_7_1():
    lower, upper = library.get("table_7_1_wire_rope").valid_deflection_range()
    assert lower == pytest.approx(-0.0343, abs=5e-4)  # SPEC 1.2: about -34 mm
    assert upper > 0.3
    assert library.get("table_a1_symmetric").valid_deflection_range() == (-np.inf, np.inf)
