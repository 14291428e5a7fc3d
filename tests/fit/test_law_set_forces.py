"""Loop sets of models without a packed loop kernel are scored by their own force law, with the
start states of the packed kernels (a subclass of IwanModel or BoucWenModel is never scored as
its parent)."""

import numpy as np

from idkit.fit import prepare_loops
from idkit.fit.loop_objective import boucwen_set_forces, iwan_set_errors, iwan_set_forces, law_set_forces
from idkit.models import BoucWenModel, IwanModel
from idkit.models.boucwen_pinched import PinchedBoucWenModel
from idkit.models.clearance import ClearanceIwanModel

PLAIN = IwanModel(g1=3e3, g2=1e4, k=[3e3, 1e4], fc=[8.0, 3.0])
# starts away from zero deflection, so the virgin and cycled start states differ
DEFLECTION = 4e-3 * np.sin(np.linspace(0.3, 4 * np.pi + 0.3, 801))


def test_the_law_path_reproduces_the_packed_iwan_kernel_in_every_start_state():
    """Same stop-operator updates in the same order: equal to round-off (measured: bit for bit)."""
    sets = [prepare_loops(DEFLECTION, PLAIN.force(DEFLECTION))]
    for state in ("virgin", "cycled", "auto"):
        np.testing.assert_allclose(law_set_forces(PLAIN, sets, initial_state=state)[0],
                                   iwan_set_forces(PLAIN, sets, initial_state=state)[0], rtol=0, atol=1e-12)


def test_a_clearance_model_is_scored_with_its_clearance_not_as_a_plain_iwan():
    clearance = ClearanceIwanModel(gap=1e-3, g1=3e3, g2=1e4, k=[3e3, 1e4], fc=[8.0, 3.0])
    sets = [prepare_loops(DEFLECTION, clearance.force(DEFLECTION))]
    x = sets[0].deflection  # the resampled branches the fit scores
    own_law = clearance.force(np.concatenate([[0.0], x]))[1:]  # loaded from the unloaded state
    forces = iwan_set_forces(clearance, sets, initial_state="virgin")[0]
    np.testing.assert_allclose(forces, own_law, rtol=0, atol=1e-12)
    assert np.max(np.abs(forces - iwan_set_forces(PLAIN, sets, initial_state="virgin")[0])) > 1.0  # dead zone
    assert iwan_set_errors(clearance, sets, initial_state="virgin")[0] == np.sqrt(
        np.sum((forces - sets[0].force) ** 2) / np.sum(sets[0].force ** 2))


def test_a_pinched_bouc_wen_model_is_scored_with_its_pinching():
    pinched = PinchedBoucWenModel(k1=2e4, k2=0.0, k3=0.0, alpha=1e3, beta=3e2, gamma=3e2, n=1.0, pinch=0.6,
                                  pinch_width=0.3)
    sets = [prepare_loops(DEFLECTION, pinched.force(DEFLECTION))]
    x = sets[0].deflection
    own_law = pinched.force(np.concatenate([[0.0], x]))[1:]
    forces = boucwen_set_forces(pinched, sets, initial_state="virgin")[0]
    np.testing.assert_allclose(forces, own_law, rtol=0, atol=1e-12 * np.max(np.abs(own_law)))
    plain = BoucWenModel(**{name: getattr(pinched, name) for name in ("k1", "k2", "k3", "alpha", "beta", "gamma",
                                                                       "n")})
    # the pinching's dip near z = 0 moves the force by a fraction of a newton on these 80 N loops
    assert np.max(np.abs(forces - boucwen_set_forces(plain, sets, initial_state="virgin")[0])) > 0.1
