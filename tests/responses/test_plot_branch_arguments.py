"""``plot_branch`` refuses quantities that are not a harmonic of the branch, and does not draw
round-off on its log axis (``quantity=0.5`` on a period-1 branch drew 1e-15..1e-9 as a curve)."""

import numpy as np
import pytest

from idkit.errors import ParameterError
from idkit.models import IwanModel, SDOFSystem, VoigtModel
from idkit.plot.branches import HARMONIC_FLOOR, plot_branch
from idkit.responses import continue_in_frequency

MASS, OMEGA_N = 1.0, 2 * np.pi * 10.0


@pytest.fixture(scope="module")
def linear_branch():
    system = SDOFSystem(MASS, VoigtModel(k=MASS * OMEGA_N**2, damping=0.1 * MASS * OMEGA_N))
    return continue_in_frequency(system, 1e-3, (8.0, 12.0))


@pytest.mark.parametrize("quantity", [0.5, 1.5, 0, -1, 7, 1e300, np.nan, "abc", "1", None, True])
def test_bad_quantity_is_refused_naming_it(linear_branch, quantity):
    with pytest.raises(ParameterError, match=r"quantity: found .*expected 'ratio'.*a harmonic order"):
        plot_branch(linear_branch, quantity)


def test_a_harmonic_that_is_round_off_everywhere_is_refused(linear_branch):
    """A linear system has no second harmonic: the orbits give 1e-15..1e-9 of the first."""
    ratio = np.abs(linear_branch.hosidf(2)) / np.abs(linear_branch.hosidf(1))
    assert ratio.max() < HARMONIC_FLOOR
    with pytest.raises(ParameterError, match=r"harmonic 2 is below 1e-06 of the first harmonic at every point"):
        plot_branch(linear_branch, 2)
    for quantity in ("ratio", 1, np.float64(1.0)):
        line = plot_branch(linear_branch, quantity).lines[0]
        assert np.all(np.asarray(line.get_ydata()) > 0.1)


def test_a_real_harmonic_is_drawn_where_it_is_above_round_off():
    """A Duffing spring (a never-slipping Jenkin element keeps it smooth) has a third harmonic."""
    stiffness = MASS * OMEGA_N**2
    system = SDOFSystem(MASS, IwanModel(g1=0.9 * stiffness, k=[0.1 * stiffness], fc=[1e6], g3=1e3 * stiffness,
                                        c_visc=0.1 * MASS * OMEGA_N))
    branch = continue_in_frequency(system, 1e-3, (8.0, 12.0))
    ax = plot_branch(branch, 3)
    drawn = np.concatenate([np.asarray(line.get_ydata(), dtype=float) for line in ax.lines])
    third = np.abs(branch.hosidf(3)) / np.abs(branch.hosidf(1))
    assert third.min() > HARMONIC_FLOOR and np.all(np.isfinite(drawn))
