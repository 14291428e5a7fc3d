"""SPEC 6 tuning rules of the transport-tool study."""

import numpy as np
import pytest

from idkit.studies.transport import RK_VALUES, transport_systems, tuning_table
from idkit.errors import ParameterError


def test_every_system_meets_its_tuning_rule():
    systems = transport_systems()
    omega = 2 * np.pi * 5.0
    assert [s.kind for s in systems] == ["reference", "elastomer", "wire_rope"] + ["hybrid"] * len(RK_VALUES)
    reference, elastomer, wire_rope, *hybrids = systems
    assert reference.system.mass == 15.0
    voigt = reference.system.isolator
    # reference: undamped natural frequency 5 Hz, damping ratio 0.07
    assert np.sqrt(voigt.k / 15.0) == pytest.approx(omega, rel=1e-12)
    assert voigt.damping / (2 * np.sqrt(voigt.k * 15.0)) == pytest.approx(0.07, rel=1e-12)
    # elastomer: |k*(5 Hz)| = moving mass * omega^2
    k_el = abs(elastomer.system.isolator.complex_stiffness(5.0))
    assert k_el == pytest.approx(elastomer.system.moving_mass * omega**2, rel=1e-12)
    # wire rope: stuck stiffness
    assert wire_rope.system.isolator.stuck_stiffness == pytest.approx(wire_rope.system.mass * omega**2, rel=1e-12)
    for item, r_k in zip(hybrids, RK_VALUES):
        system = item.system
        achieved = system.lower.g1 / abs(system.upper.complex_stiffness(5.0))
        assert achieved == pytest.approx(r_k, rel=1e-6)
        assert abs(system.series_stiffness(5.0)) == pytest.approx(system.masses[0] * omega**2, rel=1e-12)
        assert system.intermediate_mass == pytest.approx(0.01 * system.mass, rel=1e-12)
        assert system.lower == wire_rope.system.isolator  # wire rope unchanged


def test_tuned_resonances_are_near_5_hz():
    """Small-amplitude transmissibility peaks near 5 Hz (damping shifts the peak by a few %)."""
    freq = np.linspace(3.0, 7.0, 4001)
    for item in transport_systems():
        peak = freq[np.argmax(np.abs(item.system.transmissibility(freq)))]
        assert peak == pytest.approx(5.0, rel=0.06), item.name


def test_tuning_table_and_bad_input():
    table = tuning_table(transport_systems())
    assert len(table) == 10
    np.testing.assert_allclose(table["r_k achieved [-]"].dropna(), RK_VALUES, rtol=1e-6)
    with pytest.raises(ParameterError, match="r_k"):
        transport_systems(r_k_values=[0.0])
    with pytest.raises(ParameterError, match="target_freq"):
        transport_systems(target_freq=-5)
