"""Part characteristics against the closed forms of a Jenkin element and a Maxwell part."""

import numpy as np
import pytest

from idkit.catalogue.characteristics import CYCLE_FREQ_HZ, part_characteristics
from idkit.models import GeneralizedMaxwell, IwanModel


def test_one_jenkin_element_gives_the_parallelogram_loop_values():
    stiffness, slip = 1e5, 10.0  # slip displacement 0.1 mm
    model = IwanModel(g1=0.0, k=[stiffness], fc=[slip])
    amplitudes = np.array([0.5e-3, 2e-3])
    curves = part_characteristics("jenkin", "wire_rope", model, amplitudes_m=amplitudes, n_draws=0)
    # k_eq = fc / X, eta = 4 (X - fc/k) / (pi X); the loop is sampled at 400 points per cycle, so its
    # corners and area are exact to the trapezoid over a piecewise-linear path: 1e-3
    assert curves.secant_stiffness == pytest.approx(slip / amplitudes, rel=1e-3)
    assert curves.loss_factor == pytest.approx(4 * (amplitudes - slip / stiffness) / (np.pi * amplitudes), rel=1e-3)


def test_a_maxwell_part_gives_its_complex_stiffness_and_the_bands_hold_the_mean():
    model = GeneralizedMaxwell(k0=1e4, k=[5e3], rate=[50.0])
    covariance = np.diag([500.0**2, 300.0**2])
    curves = part_characteristics("body", "elastomer", model, ("k0", "k_1"), covariance, n_draws=30, seed=2,
                                  amplitudes_m=np.array([1e-3]))
    dynamic = model.complex_stiffness(CYCLE_FREQ_HZ)
    # the second cycle from rest still carries the start transient of the 50 1/s element,
    # exp(-50 x 0.2 s) = 5e-5: 1e-3
    assert curves.secant_stiffness[0] == pytest.approx(abs(dynamic), rel=1e-3)
    # an ellipse encloses pi X^2 Im k*: eta_eq = Im k* / |k*| (sin of the loss angle, the secant
    # definition of idkit.studies.equivalent; Im k* / Re k* is its tangent)
    assert curves.loss_factor[0] == pytest.approx(dynamic.imag / abs(dynamic), rel=1e-3)
    low, high = curves.transmissibility_band
    assert np.all(low <= curves.transmissibility * (1 + 1e-9)) and np.all(curves.transmissibility <= high * (1 + 1e-9))
