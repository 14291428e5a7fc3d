"""Linear frequency domain: complex stiffness, transmissibility, resonance, damping ratios."""

import numpy as np
import pytest

from idkit.responses.linear import (
    complex_stiffness,
    effective_stiffness,
    linear_frf,
    linear_resonance,
    loss_factor,
    stiffness_response,
)
from idkit.errors import SimulationError
from idkit.models import GeneralizedMaxwell, SDOFSystem, VoigtModel, library

EXACT = 1e-12  # closed forms evaluated two ways agree to round-off
RESONANCE_TOLERANCE = 1e-7  # relative: Brent refinement of the peak


def test_complex_stiffness_and_loss_factor_of_linear_models():
    freq = np.geomspace(0.1, 1e3, 30)
    s = 2j * np.pi * freq
    voigt = VoigtModel(k=2e3, damping=15.0)
    assert np.allclose(complex_stiffness(voigt, freq), 2e3 + 15.0 * s, rtol=EXACT)
    assert np.allclose(loss_factor(complex_stiffness(voigt, freq)), 2 * np.pi * freq * 15.0 / 2e3, rtol=EXACT)
    maxwell = library.get("table_b1_medium")
    expected = maxwell.k0 + np.sum(maxwell.k * maxwell.damping * s[:, None] / (maxwell.damping * s[:, None] + maxwell.k), axis=1)
    response = stiffness_response(maxwell, freq)
    assert np.allclose(response.stiffness, expected, rtol=EXACT)
    assert np.allclose(response.loss_factor, maxwell.loss_factor(freq), rtol=EXACT)
    assert np.allclose(np.tan(response.phase), response.loss_factor, rtol=1e-9)  # eq. 4.6
    # a stuck wire rope is a spring plus its small viscous damper
    wire_rope = library.get("table_a1_symmetric")
    assert np.allclose(complex_stiffness(wire_rope, freq), 9e3 + wire_rope.c_visc * s, rtol=EXACT)


def test_sdof_transmissibility_and_resonance_match_closed_forms():
    mass, omega0, zeta = 3.0, 2 * np.pi * 7.0, 0.08
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    freq = np.geomspace(0.5, 200.0, 60)
    r = 2 * np.pi * freq / omega0
    analytic = (1 + 2j * zeta * r) / (1 - r**2 + 2j * zeta * r)
    frf = linear_frf(system, freq)
    assert np.allclose(frf.transmissibility, analytic, rtol=1e-10)
    # peak of |H| of a base-excited Voigt system: r^2 = (sqrt(1 + 8 zeta^2) - 1) / (4 zeta^2)
    r_peak = np.sqrt((np.sqrt(1 + 8 * zeta**2) - 1) / (4 * zeta**2))
    assert frf.resonance.freq == pytest.approx(7.0 * r_peak, rel=RESONANCE_TOLERANCE)


def test_small_amplitude_hybrid_transmissibility_solves_the_two_mass_equations():
    system = library.get("hybrid_asymmetric")
    freq = np.array([1.0, 7.0, 30.0, 300.0])
    omega = 2 * np.pi * freq
    upper = system.upper.complex_stiffness(freq)
    lower = system.lower.small_amplitude_stiffness(freq)
    m_top, m_in = system.masses
    expected = []
    for w, ku, kl in zip(omega, upper, lower):
        matrix = np.array([[ku - m_top * w**2, -ku], [-ku, ku + kl - m_in * w**2]])
        expected.append(np.linalg.solve(matrix, [0.0, kl])[0])
    frf = linear_frf(system, freq)
    assert np.allclose(frf.transmissibility, expected, rtol=1e-10)
    assert np.allclose(frf.stiffness, 1 / (1 / upper + 1 / lower), rtol=EXACT)
    assert len(frf.component_stiffness) == 2
    assert {"freq [Hz]", "H_magnitude [-]", "isolator_1_loss_factor [-]"} <= set(frf.to_dataframe())


@pytest.mark.parametrize("isolator, mass", [
    (VoigtModel(k=1e4, damping=2 * 0.01 * np.sqrt(1e4 * 10.0)), 10.0),  # zeta = 1 %
    (GeneralizedMaxwell(k0=1e4, k=[1.5e3], rate=[60.0]), 10.0),  # eta(f0) about 0.07
    (library.get("table_b1_high"), 5.0),  # Table B.1 high: eta about 0.14
])
def test_half_power_damping_ratio_equals_half_the_loss_factor_for_light_damping(isolator, mass):
    resonance = linear_resonance(SDOFSystem(mass, isolator))
    assert resonance.loss_factor < 0.15
    # for light damping the two readings agree to a relative O(eta) (the loss factor varies over the band)
    assert resonance.damping_ratio_half_power == pytest.approx(resonance.damping_ratio_loss_factor,
                                                               rel=max(resonance.loss_factor, 2e-3))


def test_half_power_and_loss_factor_readings_part_for_heavy_damping():
    resonance = linear_resonance(library.get("system_b1_medium"))
    assert resonance.loss_factor > 0.8  # the medium elastomer damps its resonance heavily
    assert resonance.damping_ratio_half_power > 1.2 * resonance.damping_ratio_loss_factor


def test_effective_stiffness_and_input_checks():
    system = library.get("system_b1_low")
    assert np.allclose(effective_stiffness(system, [1.0, 10.0]), system.isolator.complex_stiffness([1.0, 10.0]))
    with pytest.raises(SimulationError, match="freq"):
        linear_frf(system, [0.0, 1.0])
    with pytest.raises(SimulationError, match="expected SDOFSystem"):
        linear_frf(system.isolator, [1.0])


@pytest.mark.parametrize("natural_hz", [1.5e-3, 15.0, 5e4])
def test_linear_frf_finds_a_resonance_far_outside_the_default_search_range(natural_hz):
    # the search was fixed to 0.01 Hz - 10 kHz: a 50 kHz part (0.01 kg on 1e9 N/m) reported
    # its resonance at 10 kHz, a 1.5 mHz one at 0.01 Hz, with the range end's |H|.
    # Closed form of the base-excited Voigt peak: r = sqrt(sqrt(1 + 8 z^2) - 1) / (2 z).
    mass, zeta = 0.5, 0.05
    omega = 2 * np.pi * natural_hz
    system = SDOFSystem(mass, VoigtModel(k=mass * omega**2, damping=2 * zeta * mass * omega))
    ratio = np.sqrt(np.sqrt(1 + 8 * zeta**2) - 1) / (2 * zeta)
    resonance = linear_frf(system, [1.0]).resonance
    assert resonance.freq == pytest.approx(ratio * natural_hz, rel=RESONANCE_TOLERANCE)
    assert resonance.peak_magnitude == pytest.approx(abs(system.transmissibility(ratio * natural_hz)), rel=EXACT)


@pytest.mark.parametrize("f_min, f_max", [(0.01, 2.0), (20.0, 1e4)])
def test_linear_resonance_refuses_a_peak_at_the_end_of_its_range(f_min, f_max):
    # a 5 Hz system searched in 0.01-2 Hz came back as "resonance at 2 Hz", half-power NaN
    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.2 * np.pi * 5))
    with pytest.raises(SimulationError, match="largest at the end of the search range"):
        linear_resonance(system, f_min=f_min, f_max=f_max)


@pytest.mark.parametrize("n_grid", [1, 2, 2.7, True, "4000"])
def test_linear_resonance_refuses_a_grid_that_cannot_hold_a_peak(n_grid):
    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.2 * np.pi * 5))
    with pytest.raises(SimulationError, match="n_grid: found"):
        linear_resonance(system, n_grid=n_grid)
