"""Floquet classification of orbits that attract nothing: an undamped system's multipliers lie on
the unit circle, so its periodic orbit is neutral, not stable (it was called stable, and a harmonic
map reported the orbit of an undamped oscillator that never settles as its steady state)."""

import numpy as np
import pytest

from idkit.models import IwanModel, SDOFSystem, VoigtModel
from idkit.responses import harmonic_map, periodic_response
from idkit.responses.periodic import STABILITY_MARGIN, classify_multipliers

MASS, F_N = 1.0, 10.0  # kg, Hz
OMEGA_N = 2 * np.pi * F_N


def _voigt(zeta):
    return SDOFSystem(MASS, VoigtModel(k=MASS * OMEGA_N**2, damping=2 * zeta * MASS * OMEGA_N))


def _decay(zeta, freq):
    """|mu| of a Voigt oscillator over one excitation period: exp(-zeta omega_n T)."""
    return np.exp(-zeta * OMEGA_N / freq)


@pytest.mark.parametrize("freq", [3.0, 30.0, 300.0])
def test_undamped_orbit_is_neutral_not_stable(freq):
    orbit = periodic_response(_voigt(0.0), freq, 1e-3)
    assert orbit.converged[0]
    # average-acceleration Newmark conserves the energy of a linear undamped oscillator
    np.testing.assert_allclose(np.abs(orbit.multipliers[0]), 1.0, atol=1e-9)
    assert orbit.instability[0] == "neutral" and not orbit.stable[0]
    assert "neutral" in orbit.report()


@pytest.mark.parametrize("zeta, freq", [(1e-3, 30.0), (1e-3, 300.0), (1e-2, 3.0)])
def test_damped_orbit_is_stable_when_its_decay_exceeds_the_margin(zeta, freq):
    assert 1.0 - _decay(zeta, freq) > 2 * STABILITY_MARGIN  # the cases resolve the decay
    orbit = periodic_response(_voigt(zeta), freq, 1e-3)
    step = 1.0 / (freq * orbit.steps_per_period[0])  # Newmark's period error is O((omega_n h)^2)
    np.testing.assert_allclose(np.abs(orbit.multipliers[0]), _decay(zeta, freq), rtol=(OMEGA_N * step) ** 2)
    assert orbit.stable[0] and orbit.instability[0] == "stable"


def test_the_margin_widens_to_the_closing_tolerance():
    """A decay of 2.1e-4 a period is resolved at the default tolerance, not by an orbit closed to 1e-3."""
    zeta, freq = 1e-3, 300.0
    assert STABILITY_MARGIN < 1.0 - _decay(zeta, freq) < 1e-3
    assert periodic_response(_voigt(zeta), freq, 1e-3).instability[0] == "stable"
    assert periodic_response(_voigt(zeta), freq, 1e-3, tolerance=1e-3).instability[0] == "neutral"


def test_friction_memory_at_plus_one_is_not_neutral():
    """Sticking memory (a multiplier exactly +1: a family of orbits) with a damped mode is stable;
    a pair on the circle or a multiplier of -1 is neutral; outside is unstable."""
    assert classify_multipliers([1.0, 0.9 + 0.1j, 0.9 - 0.1j]) == (True, "stable")
    assert classify_multipliers([1.0, 0.6 + 0.8j, 0.6 - 0.8j]) == (False, "neutral")
    assert classify_multipliers([-1.0, 0.5]) == (False, "neutral")
    assert classify_multipliers([1.0 + 2 * STABILITY_MARGIN, 0.5]) == (False, "fold")
    # an Iwan rope whose Jenkin element never slips, and a damped mode: its memory's multiplier is +1
    rope = SDOFSystem(2.0, IwanModel(g1=4e3, k=[1e3], fc=[1e6], c_visc=20.0))
    orbit = periodic_response(rope, 5.0, 1e-3)
    assert abs(orbit.multipliers[0, 0] - 1.0) < 1e-9 and np.all(np.abs(orbit.multipliers[0, 1:]) < 0.5)
    assert orbit.stable[0] and orbit.instability[0] == "stable"


def test_harmonic_map_does_not_report_a_neutral_orbit_as_the_steady_state():
    """Before: converged 'ok' by shooting at 30 Hz, though the time run never settles there."""
    result = harmonic_map(_voigt(0.0), [30.0], [1e-3])
    assert not result.converged[0, 0]
    assert "neutral" in str(result.reasons[0, 0])
