"""Quantitative claims of the reference study that idkit reproduces with the study's own
parameter sets (``idkit.models.library``). The full list, with the claims idkit does not
reproduce and why, is ``docs/study-numbers.md``; claims already tested elsewhere (elastomer
resonance ordering, hybrid linear resonance, the 1/2 subharmonic of Table A.1, the transport
masses) are not repeated here.

Tolerances come from the thesis's own precision (half a unit of the last printed digit), the
grid a value is read from, or a closed-form bound; every input is deterministic.
"""

import numpy as np
import pytest

from idkit.models import HybridSystem, SDOFSystem, library
from idkit.models.maxwell import GeneralizedMaxwell
from idkit.responses.linear import complex_stiffness, linear_resonance, loss_factor
from idkit.responses.shock import shock_sweep
from idkit.simulate import harmonic_response
from idkit.studies.transport import transport_systems

A1_MASS = 8.0
A1_STUCK = 9e3  # k_wr0 (g1) + k_1 + k_2, N/m
A1_OMEGA0 = np.sqrt(A1_STUCK / A1_MASS)  # rad/s, 5.34 Hz
A1_SLIP_1 = 8.3 / 3e3  # deflection at which Jenkin element 1 slips, m
A1_SLIP_2 = 14.6 / 3e3  # ... element 2, m


def _transport(name):
    return {item.name: item.system for item in transport_systems()}[name]


def test_table_a1_drops_are_linear_up_to_0_09_m_s_and_fully_slipping_from_0_16_m_s():
    """Thesis 3.4.3, fig. 3.21a: linear up to 0.09 m/s, both elements slip above 0.15 m/s.

    Closed form: element 1 slips at Fc1/k1 = 2.77 mm, reached at v1 = omega0 Fc1/k1 = 0.093
    m/s; element 2 at 4.87 mm, reached at v2 = 0.158 m/s (energy balance over the piecewise
    linear force). Below v1 the rest shock level is omega0 |v0| up to the 0.24 % viscous
    damping (tolerance 1 %); 10 % above v1 slip lowers it by more than 2 %. At v2 the
    peak deflection is Fc2/k2 within 1 % (the viscous damping removes < 0.5 % of the energy).
    """
    v1 = A1_OMEGA0 * A1_SLIP_1
    energy = (0.5 * A1_STUCK * A1_SLIP_1**2 + 0.5 * 6e3 * (A1_SLIP_2**2 - A1_SLIP_1**2)
              + 8.3 * (A1_SLIP_2 - A1_SLIP_1))  # stored up to the slip of element 2, J
    v2 = np.sqrt(2 * energy / A1_MASS)
    assert v1 == pytest.approx(0.09, abs=0.005) and v2 == pytest.approx(0.16, abs=0.005)
    for name in ("system_a1_symmetric", "system_a1_asymmetric"):
        sweep = shock_sweep(library.get(name), impact_velocity=[-0.97 * v1, -1.1 * v1, -v2], workers=1)
        ratio = sweep.rest_shock_level / (A1_OMEGA0 * sweep.impact_speed)
        assert ratio[0] == pytest.approx(1.0, abs=0.01), name
        assert ratio[1] < 0.98, name
        if name == "system_a1_symmetric":
            assert sweep.peak_compression[2, 0] == pytest.approx(A1_SLIP_2, rel=0.01)


def test_table_a1_asymmetric_tension_governs_from_about_0_9_m_s():
    """Thesis 3.4.3, fig. 3.21b: compression critical below about 0.9 m/s, tension above.

    idkit's crossing is at 0.885 m/s; tolerance half a unit of the printed digit (+-0.05 m/s),
    sharper than the 0.6 / 1.5 m/s bracket of tests/responses/test_shock.py.
    """
    sweep = shock_sweep(library.get("system_a1_asymmetric"), impact_velocity=[-0.85, -0.95], workers=1)
    assert list(sweep.governing_phase) == ["compression", "tension"]


def test_table_a1_symmetric_resonance_falls_with_amplitude_and_friction_damps_only_in_between():
    """Thesis 3.4.1, figs. 3.7-3.10: the resonance falls from about 5 Hz as the amplitude
    grows; friction damps the resonance only at intermediate amplitudes.

    Small amplitude: all stuck, 5.34 Hz; 1 m: all slipping, towards sqrt(g1/m) = 3.08 Hz.
    Peaks read on a log grid of 3.7 % steps: tolerance one step. Damping: the stuck peak
    (viscous only, Q ~ 200) and the stretched 1 m loops are far higher than the 3 mm one.
    """
    system = library.get("system_a1_symmetric")
    freq = np.geomspace(2.5, 6.0, 25)
    peaks = {}
    for amplitude in (1e-5, 3e-3, 1.0):
        response = harmonic_response(system, freq, amplitude, start="linear", workers=1)
        assert response.converged.all()
        h1 = np.abs(response.hosidf(1))
        peaks[amplitude] = (freq[np.argmax(h1)], h1.max())
    assert peaks[1e-5][0] == pytest.approx(A1_OMEGA0 / (2 * np.pi), rel=0.037)
    assert peaks[1.0][0] == pytest.approx(np.sqrt(3e3 / A1_MASS) / (2 * np.pi), rel=0.037)
    assert peaks[1e-5][0] > peaks[3e-3][0] > peaks[1.0][0]
    assert peaks[3e-3][1] < 0.1 * peaks[1e-5][1] and peaks[3e-3][1] < 0.3 * peaks[1.0][1]


def test_table_a1_symmetric_global_slip_from_about_0_1_m_and_no_even_harmonics():
    """Thesis 3.4.1, fig. 3.11 and A.3: global slip from about 1e-1 m; even harmonics zero.

    At 1 Hz (the lowest map frequency, where the deflection is smallest) the stuck deflection
    is x_b / ((f0/f)^2 - 1): element 1 slips from x_b = 2.77 mm x 27.5 = 0.076 m. At 0.06 m the
    response is linear (3rd harmonic at round-off, < 1e-5), at 0.2 m it slips (> 1e-2). A
    symmetric isolator has no even harmonics: |H2| below 1e-3 |H3| once settled to 1e-7.
    """
    system = library.get("system_a1_symmetric")
    response = harmonic_response(system, 1.0, [0.06, 0.2], tolerance=1e-7, start="linear", workers=1)
    assert response.converged.all()
    h2, h3 = np.abs(response.hosidf(2)), np.abs(response.hosidf(3))
    assert h3[0] < 1e-5 and h3[1] > 1e-2
    assert h2[1] < 1e-3 * h3[1]


def test_table_a1_asymmetric_superharmonic_peaks_at_half_and_third_of_the_resonance():
    """Thesis 3.4.2, figs. 3.15-3.16: peaks at 1/2 of the resonance in the 2nd harmonic and at
    1/3 in the 3rd, amplitude independent because the rope is still stuck.

    Stuck at 1e-4 and 1e-3 m (deflection < 2.77 mm below 3 Hz), the quadratic / cubic spring
    terms force the 2nd / 3rd harmonic, which resonates when 2f or 3f = f0 = 5.34 Hz (viscous
    Q ~ 200, half-width ~0.3 %). A peak: the value at f0/n exceeds the values 3 % either side
    by 2x (measured: 10x and more).
    """
    system = library.get("system_a1_asymmetric")
    f0 = A1_OMEGA0 / (2 * np.pi)
    for amplitude in (1e-4, 1e-3):
        for divisor, order in ((2, 2), (3, 3)):
            freq = f0 / divisor * np.array([0.97, 1.0, 1.03])
            response = harmonic_response(system, freq, amplitude, tolerance=1e-6, start="linear",
                                         max_periods=20000, workers=1)
            assert response.converged.all()
            h = np.abs(response.hosidf(order))
            assert h[1] > 2 * max(h[0], h[2]), (amplitude, divisor, h)


def test_table_b1_damping_at_resonance_and_damping_band_edges():
    """Thesis 4.3.1, figs. 4.3-4.4: the 5 kg resonance lies in the high-damping range of the
    low and medium variants and in the low-damping range of the high one; the damping region
    of the low variant ends at about 1e4 Hz, that of the high variant at about 1e8 Hz.

    Loss factor at the resonance: 0.92 / 0.87 / 0.14 (thresholds 0.5 and 0.2). Band edge:
    highest frequency with eta > 0.1 (9.3e3 and 9.3e7 Hz), within a factor 1.5 of the printed
    decade (the thesis reads it off a log axis).
    """
    eta = {v: linear_resonance(library.get(f"system_b1_{v}")).loss_factor for v in ("low", "medium", "high")}
    assert eta["low"] > 0.5 and eta["medium"] > 0.5 and eta["high"] < 0.2
    freq = np.geomspace(1e-3, 1e10, 3000)
    for variant, edge in (("low", 1e4), ("high", 1e8)):
        damped = freq[loss_factor(complex_stiffness(library.get(f"table_b1_{variant}"), freq)) > 0.1]
        assert edge / 1.5 < damped[-1] < edge * 1.5, variant


def test_table_b1_rest_shock_level_is_proportional_with_the_resonance_as_slope():
    """Thesis 4.3.2, fig. 4.5: the elastomer's rest shock level is proportional to |v0| with a
    slope near the (damped) eigenfrequency (eq. 3.23 for the undamped case).

    Linear model: proportional to 1e-9. Damping lowers the slope below 2 pi f_res (eq. 3.23 is
    the undamped bound); measured 0.90-0.92: asserted within 15 %.
    """
    for variant in ("low", "medium", "high"):
        system = library.get(f"system_b1_{variant}")
        sweep = shock_sweep(system, impact_velocity=[-0.5, -1.0], workers=1)
        slope = sweep.rest_shock_level / sweep.impact_speed
        assert slope[0] == pytest.approx(slope[1], rel=1e-9)
        assert 0.85 < slope[1] / (2 * np.pi * linear_resonance(system).freq) < 1.0, variant


def test_hybrid_wire_rope_stays_linear_in_drops_up_to_0_3_m_s_then_deflects_most():
    """Thesis 5.3.3, fig. 5.16: in drops the hybrid's wire rope behaves linearly up to 0.3
    m/s; at higher speeds it deflects more than the elastomer.

    The rope slips at Fc1/k1 = 2.77 mm; idkit reaches it at 0.31 m/s. Below, the rest shock
    level is proportional to |v0| (to 1e-6; the elastomer is linear); at 0.35 m/s it is
    more than 1 % below. At 0.2 m/s the stuck rope (9e3 N/m) deflects less than the
    softer elastomer, at 1 m/s more.
    """
    sweep = shock_sweep(library.get("hybrid_symmetric"), impact_velocity=[-0.2, -0.3, -0.35, -1.0], workers=1)
    slope = sweep.rest_shock_level / sweep.impact_speed
    assert slope[1] == pytest.approx(slope[0], rel=1e-6)
    assert slope[2] < 0.99 * slope[0]
    assert sweep.peak_compression[1, 1] < A1_SLIP_1 < sweep.peak_compression[2, 1]
    upper, lower = sweep.peak_compression[:, 0], sweep.peak_compression[:, 1]
    assert lower[0] < upper[0] and lower[3] > upper[3]


def test_hybrid_low_frequency_damping_region_near_1_hz():
    """Thesis 5.3.1, fig. 5.7: the small-amplitude hybrid stiffness has a damping region around
    1 Hz (the elastomer, soft against the stuck rope). idkit's loss-factor maximum: 0.62 Hz,
    within a factor 2 of the printed "around 1 Hz" (read off a 1e-2-1e6 Hz log axis). It
    does not depend on the rope's viscous c; the second region the thesis puts near 1e4 Hz
    does (docs/study-numbers.md) and is not asserted."""
    hybrid = library.get("hybrid_symmetric")
    freq = np.geomspace(1e-2, 30.0, 2000)
    eta = loss_factor(hybrid.series_stiffness(freq))
    assert 0.5 < freq[np.argmax(eta)] < 2.0


def test_table_7_3_resonances_need_the_printed_tau_read_as_rates():
    """Thesis 6.3.2 / 7.2.1, SPEC 1.4: the identified elastomer on 0.99 and 6.40 kg resonates
    at about 19 and 7.5 Hz (measured; SPEC: 19.5 and 7.8 Hz for the model). With the printed
    tau read as rates (1/s), idkit's 19.46 / 7.82 Hz are within SPEC's half unit (0.5 %) and
    within 5 % of the measured read-off (fit error 9.4 %, Table 7.2); read as seconds they
    would be 24.9 / 10.4 Hz, 28-39 % off.
    """
    printed = library.get("table_7_3_elastomer")
    tau_misread = GeneralizedMaxwell(k0=printed.k0, k=printed.k, rate=1.0 / np.asarray(printed.rate), m_eff=printed.m_eff)
    for mass, spec, measured in ((0.99, 19.5, 19.0), (6.40, 7.8, 7.5)):
        freq = linear_resonance(SDOFSystem(mass, printed)).freq
        assert freq == pytest.approx(spec, rel=5e-3) and freq == pytest.approx(measured, rel=0.05)
        assert abs(linear_resonance(SDOFSystem(mass, tau_misread)).freq / measured - 1) > 0.25


def test_table_7_hybrid_shaker_resonance_near_20_hz():
    """Thesis 6.4.2 / F.3: the hybrid on the shaker (0.99 kg top, 0.14 kg intermediate)
    resonates near 20 Hz at low input, and the model describes it accurately. idkit
    (Table 7.1 + 7.3, m_eff included): 18.7 Hz. Tolerance 10 %: "20 Hz" is a one-digit
    read-off of a measured map, and the elastomer model misses the FRFs by 9.4 % RMS."""
    hybrid = HybridSystem(0.99, library.get("table_7_3_elastomer"), 0.14, library.get("table_7_1_wire_rope"))
    assert linear_resonance(hybrid).freq == pytest.approx(20.0, rel=0.1)


def test_transport_damping_ratios_and_intermediate_mass_resonances():
    """Thesis 8.2, fig. 8.1a: at small input the elastomer has the reference's damping ratio
    0.07 (eq. 4.5), the r_k = 0.1 hybrid 0.035, the wire rope < 0.02; the r_k = 0.1 hybrid's
    intermediate-mass resonance shows close to 100 Hz, that of r_k = 1.25 lies above 100 Hz.

    Damping from the -3 dB width of |H| (what a PSD shows). The thesis reads it from PSDs of
    0.05 Hz lines; test_random_vibration bounds that estimate's error by 3.5 (df / B)^2:
    7 % at zeta = 0.035, 2 % at 0.07; tolerances 7 % and 5 % (idkit: 0.0707, 0.0370).
    Second resonance: the second peak of |H| (idkit 108.6 and 209.5 Hz).
    """
    zeta = {name: linear_resonance(_transport(name), f_min=0.5, f_max=1e3).damping_ratio_half_power
            for name in ("elastomer", "hybrid r_k=0.1", "wire rope")}
    assert zeta["elastomer"] == pytest.approx(0.07, rel=0.05)
    assert zeta["hybrid r_k=0.1"] == pytest.approx(0.035, rel=0.07)
    assert zeta["wire rope"] < 0.02
    freq = np.geomspace(50.0, 500.0, 4001)
    for name, low, high in (("hybrid r_k=0.1", 100.0, 130.0), ("hybrid r_k=1.25", 100.0, 500.0)):
        magnitude = np.abs(_transport(name).transmissibility(freq))
        inner = np.flatnonzero((magnitude[1:-1] > magnitude[:-2]) & (magnitude[1:-1] > magnitude[2:])) + 1
        assert inner.size == 1 and low < freq[inner[0]] < high, name


def test_transport_drops_tension_from_0_14_m_s_and_hybrids_between_the_ropes_and_the_elastomer():
    """Thesis 8.3, fig. 8.2a: the wire-rope system's rest shock level moves to tension above
    0.14 m/s; the hybrids lie between the wire rope (lowest) and the elastomer, higher for
    higher r_k.

    idkit's crossing: 0.137 m/s; tolerance half a unit of the printed digit (+-0.005 m/s).
    Ordering at 0.05 and 0.2 m/s, where every system stays inside its valid range (the
    Table 7.1 rope reaches its negative-stiffness limit between 0.25 and 0.3 m/s, SPEC 1.2).
    """
    sweep = shock_sweep(_transport("wire rope"), impact_velocity=[-0.135, -0.145], workers=1)
    assert list(sweep.governing_phase) == ["compression", "tension"]
    names = ["wire rope"] + [f"hybrid r_k={r:g}" for r in (0.1, 0.2, 0.4, 0.6, 0.8, 1.0, 1.25)] + ["elastomer"]
    levels = np.array([shock_sweep(_transport(name), impact_velocity=[-0.05, -0.2], workers=1).rest_shock_level
                       for name in names])
    assert np.all(np.diff(levels, axis=0) > 0)


def test_table_7_1_drop_relaxation_matters_only_below_0_2_m_s_and_tension_takes_over_near_1_m_s():
    """Thesis F.1, fig. F.3 (4.33 kg on the Table 7.1 rope): relaxation (initial elongation m g)
    matters only up to 0.2 m/s; above about 1 m/s the model's tension peak exceeds the
    compression peak.

    Relaxation changes the rest shock level by 76 % at 0.05 m/s, 10 % at 0.1 m/s and < 1 %
    from 0.2 m/s on (asserted: > 5 % at 0.1, < 1 % at 0.2 and 0.5). Crossing: idkit 1.0-1.1
    m/s; asserted compression at 0.9, tension at 1.2 m/s (the thesis reads "up to 1 m/s").
    """
    system = SDOFSystem(4.33, library.get("table_7_1_wire_rope"))
    speeds = [-0.1, -0.2, -0.5, -0.9, -1.2]
    plain = shock_sweep(system, impact_velocity=speeds, workers=1)
    relaxed = shock_sweep(system, impact_velocity=speeds[:3], relaxation=True, workers=1)
    change = np.abs(relaxed.rest_shock_level / plain.rest_shock_level[:3] - 1)
    assert change[0] > 0.05 and change[1] < 0.01 and change[2] < 0.01
    assert list(plain.governing_phase[3:]) == ["compression", "tension"]
