"""The generator's chain stepper against idkit's models and simulator (independent methods)."""

from __future__ import annotations

import numpy as np
import pytest

from idkit.models import IwanModel, SDOFSystem
from idkit.synth.chain import LINK_WIRE_ROPE, LINK_WIRE_ROPE_MODULATED, link_force_path, pack_links, run_chain
from idkit.synth.truth import default_wire_rope
from idkit.simulate import free_fall


def _plain_iwan_link(model: IwanModel, kind=LINK_WIRE_ROPE):
    """A wire-rope link (either kind) with constant slip forces (no modulation) and no bottoming =
    an Iwan model."""
    scalars = [model.g1, model.g2, model.g3, model.c_visc, 0.0, 1.0, 0.0, 1.0]
    return (kind, scalars, list(model.k), list(model.fc))


@pytest.mark.parametrize("kind", [LINK_WIRE_ROPE, LINK_WIRE_ROPE_MODULATED])
def test_link_force_equals_iwan_stop_operator_when_slip_forces_are_constant(kind):
    model = IwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3])
    kinds, scalars, ks, bs, ns = pack_links([_plain_iwan_link(model, kind)])
    x = 4e-3 * np.sin(np.linspace(0, 6 * np.pi, 3001)) * np.linspace(0.2, 1, 3001)
    time = np.linspace(0, 30, x.size)
    force, _ = link_force_path(kinds[0], scalars[0], ks[0], bs[0], ns[0], np.zeros(2), x, time)
    assert np.allclose(force, model.force(x), rtol=0, atol=1e-9)


def test_wire_rope_truth_loops_are_wider_in_compression_than_in_tension():
    truth = default_wire_rope()
    kinds, scalars, ks, bs, ns = pack_links([truth.link()])

    def width(center):
        x = center + 1e-3 * np.sin(np.linspace(-np.pi / 2, 4.5 * np.pi, 4001))
        path = np.concatenate([np.linspace(0, x[0], 200), x])
        force, _ = link_force_path(kinds[0], scalars[0], ks[0], bs[0], ns[0],
                                   np.zeros(ks.shape[1]), path, np.linspace(0, 100, path.size))
        last = slice(path.size - 1600, None)  # the last whole cycle
        return -np.trapezoid(force[last], path[last])  # dissipated energy per cycle, J

    assert width(-8e-3) > 1.3 * width(0.0) > 1.3 ** 2 * width(8e-3)


def test_chain_free_fall_matches_the_fast_simulator_for_a_plain_iwan_isolator():
    """Conditioned free fall (no gravity, base fixed) of an SDOF Iwan system: the chain with
    a base link vs idkit.simulate.free_fall (Newmark): peak acceleration and compression."""
    model = IwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3],
                      c_visc=4.0)
    mass, v0, step, duration = 4.33, -0.8, 1e-5, 0.2
    n_steps = int(round(duration / step))
    run = run_chain([mass], [_plain_iwan_link(model)], time_step=step, n_steps=n_steps,
                    x0=[0.0], v0=[v0])
    reference = free_fall(SDOFSystem(mass, model), impact_velocity=[v0], duration=duration,
                          time_step=step)
    assert np.abs(run.acceleration[0]).max() == pytest.approx(
        np.abs(reference.acceleration[0, 0]).max(), rel=2e-3)
    assert run.deflection[0].min() == pytest.approx(reference.deflection[0, 0].min(), rel=2e-3)
