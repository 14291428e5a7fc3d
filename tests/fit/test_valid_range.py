"""The Iwan fit can be asked to keep the parallel spring valid over a deflection range."""

import numpy as np
import pytest

from idkit.errors import FitError
from idkit.fit import fit_iwan
from idkit.models import IwanModel


def loops(model, amplitudes, points=400):
    phase = np.linspace(0, 4 * np.pi, points)
    return [(a * np.sin(phase), model.force(a * np.sin(phase))) for a in amplitudes]


def test_valid_range_keeps_the_spring_stiffness_non_negative():
    # a truth whose cubic softening makes the spring negative-stiff at -24 mm, seen only up to 8 mm
    truth = IwanModel(g1=2e4, g2=2e5, g3=-6e6, k=[1.5e5, 1e4], fc=[15.0, 8.0])
    assert truth.valid_deflection_range()[0] > -0.025
    small, large = loops(truth, [0.5e-3, 1e-3, 2e-3]), loops(truth, [4e-3, 8e-3])
    free = fit_iwan(small, large, order=2, seed=1)
    bounded = fit_iwan(small, large, order=2, seed=1, valid_range=(-0.03, 0.03))
    assert free.model.valid_deflection_range()[0] > -0.03  # the unconstrained fit follows the truth
    lower, upper = bounded.model.valid_deflection_range()
    assert lower <= -0.03 and upper >= 0.03
    # the constraint costs accuracy only where the data cannot tell (a few % at most here)
    assert bounded.error_large < free.error_large + 0.05
    assert bounded.settings.valid_range == (-0.03, 0.03)


@pytest.mark.parametrize("bad", [(0.01, 0.03), (-0.03, -0.01), (np.nan, 0.03)])
def test_bad_valid_range_is_refused(bad):
    truth = IwanModel(g1=2e4, k=[1e5], fc=[10.0])
    with pytest.raises(FitError, match="valid_range"):
        fit_iwan(loops(truth, [1e-3]), loops(truth, [5e-3]), order=1, valid_range=bad)
