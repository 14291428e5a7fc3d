"""Random vibration: simulated output PSD of a linear system against |H|^2 S_xx (SPEC 5)."""

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import SDOFSystem, VoigtModel, library
from idkit.responses.random_vibration import (
    FLAT_LEVELS,
    flat_input_psds,
    is_linear_system,
    random_response,
    settle_records_for,
)
from idkit.signal.psd import PsdProfile

# Default analysis: one 20 s record per Hann segment, the three segments (2/3 overlap) being
# the periodic record shifted by thirds, so the cross terms of neighbouring lines cancel and
# the Welch PSD of a linear system is |H|^2 S_xx on the line grid smoothed by the Hann kernel
# (1/6, 2/3, 1/6), without random scatter (the record of 16000 samples is not divisible by 3:
# the cancellation leaves about 1e-4). What remains is the integrator: trapezoidal warping
# lowers |H|^2 by (omega h)^2 / 3 at most, h = 1 / 3200 s: 1.3 % at 100 Hz, 0.02 % at 10 Hz.
HANN_LINE_KERNEL = (1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0)
BIN_TOLERANCE_LOW = 1e-3  # 1-10 Hz, including the resonance: warping 0.02 % + cancellation 1e-4
BIN_TOLERANCE_ALL = 0.015  # 1-99 Hz: warping up to 1.3 %
RMS_TOLERANCE = 0.02  # output RMS vs RMS of |H|^2 S_xx


def _hann_smoothed(psd):
    out = np.array(psd, dtype=float)
    out[1:-1] = np.convolve(psd, HANN_LINE_KERNEL[::-1], mode="valid")
    return out


def _half_power_damping(freq, psd):
    """Damping ratio from the half-power band of the highest peak (linear interpolation)."""
    k = int(np.argmax(psd))
    half = 0.5 * psd[k]
    lo = k - int(np.argmax(psd[k::-1] <= half))  # first bin at or below half, going down
    hi = k + int(np.argmax(psd[k:] <= half))
    f_lo = np.interp(half, [psd[lo], psd[lo + 1]], [freq[lo], freq[lo + 1]])
    f_hi = np.interp(half, [psd[hi], psd[hi - 1]], [freq[hi], freq[hi - 1]])
    return (f_hi - f_lo) / (2.0 * freq[k])


@pytest.fixture(scope="module")
def linear_result():
    mass, omega0, zeta = 5.0, 2 * np.pi * 5.0, 0.1
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    return random_response(system, PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0), seed=7, n_realizations=30)


def test_linear_output_psd_agrees_with_transfer_function(linear_result):
    result = linear_result
    assert result.is_linear and result.n_realizations == 30
    assert result.nperseg == 16000 and result.freq[1] == pytest.approx(0.05, rel=1e-12)
    expected = _hann_smoothed(result.linear_output_psd)
    low = (result.freq >= 1) & (result.freq <= 10)
    everywhere = (result.freq >= 1) & (result.freq <= 99)
    assert np.abs(result.output_psd[low] / expected[low] - 1).max() < BIN_TOLERANCE_LOW
    assert np.abs(result.output_psd[everywhere] / expected[everywhere] - 1).max() < BIN_TOLERANCE_ALL
    assert result.output_rms == pytest.approx(result.linear_output_rms, rel=RMS_TOLERANCE)
    # the input is the target flat level (deterministic line amplitudes, same cancellation)
    band = (result.freq >= 1) & (result.freq <= 99)
    assert np.abs(result.input_psd[band] / 1e-3 - 1).max() < BIN_TOLERANCE_LOW
    assert result.input_rms == pytest.approx(PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0).rms(), rel=RMS_TOLERANCE)
    cumulative = result.output_cumulative_rms
    assert cumulative[-1] == pytest.approx(result.output_rms, rel=1e-12) and np.all(np.diff(cumulative) >= 0)


@pytest.mark.parametrize("zeta", [0.07, 0.03])
def test_damping_ratio_is_recovered_from_the_default_output_psd(zeta):
    """Half-power damping of the default output PSD (0.05 Hz) against the transfer function.

    With the half-power band B = 2 zeta f0 and the line step df, the estimate deviates by
    second-order terms in df / B: the Hann kernel (variance df^2 / 3) widens B by
    2 (df / B)^2; interpolating each half-power crossing linearly adds at most
    (df / B)^2 / 2 (curvature of |H|^2 there); a peak missed by up to df / 2 lowers the
    half level by up to (df / B)^2. Tolerance: the sum, 3.5 (df / B)^2 (1.8 % at zeta = 0.07,
    9.7 % at 0.03; the thesis's floor zeta = 4 df / (2 f0) = 0.02 gives 22 %). The reference
    is the half-power damping of the exact |H|^2 on a 1e-4 Hz grid, which itself differs
    from zeta by second order in zeta (numerator 1 + (2 zeta r)^2, asymmetry): within 4 zeta^2.
    """
    mass, f0 = 15.0, 5.0
    omega0 = 2 * np.pi * f0
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    result = random_response(system, PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0), seed=11)
    step = result.freq[1] - result.freq[0]
    assert step == pytest.approx(0.05, rel=1e-12)
    fine = np.arange(1.0, 20.0, 1e-4)
    reference = _half_power_damping(fine, np.abs(system.transmissibility(fine)) ** 2)
    assert reference == pytest.approx(zeta, abs=4 * zeta**2)
    estimate = _half_power_damping(result.freq, result.output_psd)
    bandwidth = 2 * reference * f0
    assert estimate == pytest.approx(reference, rel=3.5 * (step / bandwidth) ** 2)


def test_reproducible_with_a_seed_and_different_without():
    system = library.get("system_b1_medium")
    profile = PsdProfile([1.0, 10.0, 100.0], [1e-4, 1e-3, 1e-4])
    first = random_response(system, profile, seed=3, n_realizations=2, oversample=1)
    again = random_response(system, profile, seed=3, n_realizations=2, oversample=1)
    other = random_response(system, profile, seed=4, n_realizations=2, oversample=1)
    assert np.array_equal(first.output_psd, again.output_psd)
    assert not np.allclose(first.output_psd, other.output_psd)
    assert {"freq [Hz]", "output_psd [(m/s^2)^2/Hz]", "linear_output_psd [(m/s^2)^2/Hz]"} <= set(first.to_dataframe())


def test_nonlinear_systems_are_labelled_and_flat_levels():
    assert not is_linear_system(library.get("hybrid_asymmetric"))
    assert is_linear_system(library.get("system_b1_high"))
    profiles = flat_input_psds()
    assert tuple(profiles) == FLAT_LEVELS
    assert np.allclose(profiles[1e-4](np.array([0.05, 0.1, 50.0, 100.0, 101.0])), [0.0, 1e-4, 1e-4, 1e-4, 0.0],
                       rtol=1e-12, atol=0.0)


# The frequency method is the expectation of the time method's estimate for a linear system;
# they differ by the integrator's trapezoidal warping, (omega h)^2 / 3 with h = 1 / 3200 s:
# 1.3 % at 100 Hz (BIN_TOLERANCE_ALL), and by the 1e-4 left of the cross-term cancellation.
# The output RMS is dominated by the 5 Hz resonance, where warping is 3e-5 for the oscillator;
# a Maxwell element's internal state is integrated with the same scheme: 1e-3 allows for it.
FREQUENCY_RMS_TOLERANCE = 1e-3


def test_frequency_method_is_the_expected_time_estimate(linear_result):
    system = SDOFSystem(5.0, VoigtModel(k=5.0 * (2 * np.pi * 5.0) ** 2, damping=2 * 0.1 * 5.0 * 2 * np.pi * 5.0))
    profile = PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0)
    expected = random_response(system, profile, seed=7, method="frequency")
    assert expected.method == "frequency" and expected.n_realizations == 0 and expected.flags.size == 0
    assert np.array_equal(expected.freq, linear_result.freq)
    band = (expected.freq >= 1) & (expected.freq <= 99)
    low = (expected.freq >= 1) & (expected.freq <= 10)
    ratio = linear_result.output_psd / np.where(band, expected.output_psd, 1.0)
    assert np.abs(ratio[low] - 1).max() < BIN_TOLERANCE_LOW
    assert np.abs(ratio[band] - 1).max() < BIN_TOLERANCE_ALL
    assert np.abs(linear_result.input_psd[band] / expected.input_psd[band] - 1).max() < BIN_TOLERANCE_LOW
    assert expected.output_rms == pytest.approx(linear_result.output_rms, rel=FREQUENCY_RMS_TOLERANCE)


def test_frequency_method_of_a_maxwell_system_and_auto():
    system = library.get("system_b1_medium")  # generalized Maxwell elastomer: linear
    profile = PsdProfile([1.0, 10.0, 100.0], [1e-4, 1e-3, 1e-4])
    simulated = random_response(system, profile, seed=5, n_realizations=4)
    expected = random_response(system, profile, seed=5, method="auto")
    assert expected.method == "frequency" and simulated.method == "time"
    band = (expected.freq >= 1) & (expected.freq <= 99)
    assert np.abs(simulated.output_psd[band] / expected.output_psd[band] - 1).max() < BIN_TOLERANCE_ALL
    assert expected.output_rms == pytest.approx(simulated.output_rms, rel=FREQUENCY_RMS_TOLERANCE)


def test_frequency_method_refuses_nonlinear_systems_and_auto_simulates_them():
    hybrid = library.get("hybrid_asymmetric")
    profile = PsdProfile.flat(1e-6, f_lo=0.1, f_hi=100.0)
    with pytest.raises(SimulationError, match="method='frequency'.*nonlinear"):
        random_response(hybrid, profile, seed=1, method="frequency")
    # at 1e-6 it stays stuck (solved in the frequency domain, next tests); at 1e-2 it slips
    loud = PsdProfile.flat(1e-2, f_lo=0.1, f_hi=100.0)
    auto = random_response(hybrid, loud, seed=1, n_realizations=1, method="auto", freq_step=0.5, fs=400.0)
    assert auto.method == "time" and auto.n_realizations == 1
    quiet = random_response(hybrid, profile, seed=1, n_realizations=1, method="auto", freq_step=0.5, fs=400.0)
    assert quiet.method == "frequency (stays stuck)"


def test_linear_start_is_settled_and_a_rest_start_is_not():
    """A lightly damped linear system (zeta = 0.005 at 5 Hz: time constant 6.4 s, a 20 s
    record leaves e^-3 = 5 % of a start-up transient) analysed without settling records.

    From the small-amplitude steady state the run is periodic from the first sample but for
    the integrator: the trapezoidal rule puts the discrete resonance (omega0 h)^2 / 12 =
    8e-6 (relative) off the exact one, which near a resonance of damping ratio zeta changes
    the steady state by about that over zeta, 1.6e-3; the settling error must stay within
    twice that. Its PSD is the frequency method's within the bin tolerance above. From
    rest the transient is still there: a settling error of order 1.
    """
    h = 1.0 / 3200.0
    mass, omega0, zeta = 15.0, 2 * np.pi * 5.0, 0.005
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    profile = PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0)
    linear = random_response(system, profile, seed=2, n_realizations=4, start="linear", settle_records=0)
    rest = random_response(system, profile, seed=2, n_realizations=4, start="rest", settle_records=0)
    expected = random_response(system, profile, seed=2, method="frequency")
    warping = (omega0 * h) ** 2 / 12.0
    assert linear.settling_error.shape == (4,) and linear.settling_error.max() < 2 * warping / zeta
    assert rest.settling_error.min() > 0.1
    band = (expected.freq >= 1) & (expected.freq <= 99)
    assert np.abs(linear.output_psd[band] / expected.output_psd[band] - 1).max() < BIN_TOLERANCE_ALL
    assert np.abs(rest.output_psd[band] / expected.output_psd[band] - 1).max() > 0.1


def test_runs_that_have_not_settled_are_continued_from_their_state():
    """The zeta = 0.005 system above from rest without settling records: the start-up transient
    decays by e^-3 per 20 s record, so continuing each run from its own state until its settling
    error is below 0.05 takes one or two records, after which its PSD is the frequency method's
    within the bin tolerance. Continuing every run by exactly two records (a limit no run meets)
    is the same computation as settling two records uninterrupted: each continuation repeats
    its run bit for bit (tests/simulate/test_continuation_state.py), but the two calls' time
    grids have different lengths, whose mean spacings can differ in the last bit, so the
    comparison allows 1e-8. A run still above the limit at the cap is listed, not hidden."""
    mass, omega0, zeta = 15.0, 2 * np.pi * 5.0, 0.005
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    profile = PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0)
    settled = random_response(system, profile, seed=2, n_realizations=4, settle_records=0, settle_until=0.05)
    assert settled.settling_error.max() <= 0.05
    assert settled.extra_records.shape == (4,) and 1 <= settled.extra_records.min() <= settled.extra_records.max() <= 3
    expected = random_response(system, profile, seed=2, method="frequency")
    band = (expected.freq >= 1) & (expected.freq <= 99)
    assert np.abs(settled.output_psd[band] / expected.output_psd[band] - 1).max() < BIN_TOLERANCE_ALL
    continued = random_response(system, profile, seed=2, n_realizations=4, settle_records=0, settle_until=1e-12,
                                max_extra_records=2)
    uninterrupted = random_response(system, profile, seed=2, n_realizations=4, settle_records=2)
    assert np.all(continued.extra_records == 2)
    # the cap was reached with every run above 1e-12: said, not hidden
    np.testing.assert_array_equal(continued.unsettled_runs, np.arange(4))
    assert "4 of 4 runs not settled to 1e-12 after 2 extra records" in continued.report()
    assert settled.unsettled_runs.size == 0 and "not settled" not in settled.report()
    np.testing.assert_allclose(continued.output_psd, uninterrupted.output_psd, rtol=1e-8,
                               atol=1e-8 * uninterrupted.output_psd.max())
    np.testing.assert_allclose(continued.settling_error, uninterrupted.settling_error, rtol=1e-6, atol=1e-9)
    assert np.all(uninterrupted.extra_records == 0)


def test_settle_records_for_follows_the_time_constant():
    """Five time constants 1 / (zeta 2 pi f0) in records of 20 s. The half-power zeta of |H|^2
    is zeta to first order (within 4 zeta^2, i.e. 4 zeta relative, see above); the grid step
    (1e-4 Hz) adds 2e-4 relative at zeta = 0.07. A stuck wire rope (no damping) gets the cap."""
    mass, omega0, zeta = 15.0, 2 * np.pi * 5.0, 0.07
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    analytic = 5.0 / (zeta * omega0) * 0.05
    assert settle_records_for(system) == pytest.approx(analytic, rel=4 * zeta + 2e-4)
    assert settle_records_for(system, max_records=0.05) == 0.05
    assert settle_records_for(library.get("system_a1_asymmetric")) == 1.0


def test_a_fraction_of_a_record_settles_a_damped_system():
    """0.25 record (5 s) is 11 time constants of the zeta = 0.07 system: the transient is left
    at e^-11 = 2e-5 and the estimate is the frequency method's within the bin tolerances."""
    mass, omega0, zeta = 15.0, 2 * np.pi * 5.0, 0.07
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    profile = PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0)
    result = random_response(system, profile, seed=4, n_realizations=3, settle_records=0.25)
    expected = random_response(system, profile, seed=4, method="frequency")
    assert result.settle_records == 0.25 and result.settling_error.max() < 1e-3
    low = (expected.freq >= 1) & (expected.freq <= 10)
    band = (expected.freq >= 1) & (expected.freq <= 99)
    assert np.abs(result.output_psd[low] / expected.output_psd[low] - 1).max() < BIN_TOLERANCE_LOW
    assert np.abs(result.output_psd[band] / expected.output_psd[band] - 1).max() < BIN_TOLERANCE_ALL


def _stuck_wire_rope(friction_n=(20.0, 10.0), g2=0.0):
    """A 5 Hz Iwan SDOF (15 kg, stuck stiffness 15 (2 pi 5)^2 N/m, zeta 0.03 from c_visc)."""
    from idkit.models import IwanModel

    mass, omega0 = 15.0, 2 * np.pi * 5.0
    stuck = mass * omega0**2
    return SDOFSystem(mass, IwanModel(g1=0.55 * stuck, g2=g2, g3=0.0, k=[0.3 * stuck, 0.15 * stuck],
                                      fc=list(friction_n), c_visc=2 * 0.03 * mass * omega0))


def test_a_run_that_stays_stuck_is_solved_in_the_frequency_domain_and_agrees_with_the_simulation():
    """At 1e-6 (m/s^2)^2/Hz the elements carry at most a few mN against slip forces of 10-20 N:
    the small-amplitude steady state is the nonlinear system's. "auto" then returns the
    frequency-domain estimate; a simulation from that steady state (settled by construction)
    agrees within the bin tolerances of the linear systems above."""
    from idkit.responses.small_amplitude import stays_stuck
    from idkit.signal.psd import synthesize_random

    system = _stuck_wire_rope()
    profile = PsdProfile.flat(1e-6, f_lo=0.1, f_hi=100.0)
    signals = synthesize_random(profile, seed=4, fs=3200.0, freq_step=0.05, n_realizations=4)
    assert stays_stuck(system, signals, 3200.0) == (True, "")
    auto = random_response(system, profile, seed=4, n_realizations=4, method="auto")
    assert auto.method == "frequency (stays stuck)" and not auto.is_linear
    simulated = random_response(system, profile, seed=4, n_realizations=4, start="linear", settle_records=0)
    assert simulated.settling_error.max() < 1e-3
    low = (auto.freq >= 1) & (auto.freq <= 10)
    band = (auto.freq >= 1) & (auto.freq <= 99)
    assert np.abs(simulated.output_psd[low] / auto.output_psd[low] - 1).max() < BIN_TOLERANCE_LOW
    assert np.abs(simulated.output_psd[band] / auto.output_psd[band] - 1).max() < BIN_TOLERANCE_ALL


def test_slip_a_nonlinear_spring_or_bouc_wen_keep_a_run_in_the_time_domain():
    from idkit.models import BoucWenModel
    from idkit.responses.small_amplitude import LINEARITY_TOLERANCE, stays_stuck
    from idkit.signal.psd import synthesize_random

    signals = synthesize_random(PsdProfile.flat(1e-2, f_lo=0.1, f_hi=100.0), seed=4, fs=3200.0, freq_step=0.05,
                                n_realizations=2)
    stuck, why = stays_stuck(_stuck_wire_rope(friction_n=(1e-3, 1e-3)), signals, 3200.0)
    assert not stuck and "Jenkin element 1 would slip" in why
    # g2 x / g1 at the ~30 mm the floor level gives is far above the tolerance
    stuck, why = stays_stuck(_stuck_wire_rope(g2=1e5), signals, 3200.0)
    assert not stuck and f"nonlinear by more than {LINEARITY_TOLERANCE:g}" in why
    bouc_wen = SDOFSystem(15.0, BoucWenModel(k1=2e3, k2=0, k3=0, alpha=2e4, beta=6e3, gamma=2e3, n=1.0))
    stuck, why = stays_stuck(bouc_wen, signals, 3200.0)
    assert not stuck and "Bouc-Wen" in why
    slipping = random_response(_stuck_wire_rope(friction_n=(1e-3, 1e-3)), PsdProfile.flat(1e-2, f_lo=0.1, f_hi=100.0),
                               seed=4, n_realizations=2, method="auto", settle_records=0.1)
    assert slipping.method == "time"


def test_floor_signals_are_reused_only_for_the_same_profile_seed_and_grid():
    from idkit.responses.small_amplitude import line_amplitudes, synthesized_records
    from idkit.signal.psd import synthesize_random

    quiet, loud = PsdProfile.flat(1e-6, f_lo=0.1, f_hi=100.0), PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0)
    first = synthesized_records(quiet, 5, 400.0, 0.5, 3)
    assert synthesized_records(PsdProfile.flat(1e-6, f_lo=0.1, f_hi=100.0), 5, 400.0, 0.5, 3) is first  # equal profile
    assert not first.flags.writeable
    np.testing.assert_array_equal(first, synthesize_random(quiet, seed=5, fs=400.0, freq_step=0.5, n_realizations=3))
    lines = line_amplitudes(first)
    assert line_amplitudes(first) is lines
    for other in (synthesized_records(quiet, 6, 400.0, 0.5, 3), synthesized_records(loud, 5, 400.0, 0.5, 3)):
        assert other is not first and not np.array_equal(other, first)
        assert line_amplitudes(other) is not lines
    more = synthesized_records(quiet, 5, 400.0, 0.5, 4)  # one more realization: a new set (its first three are these)
    assert more is not first and more.shape == (4, first.shape[1])


def _tuned_on_a_line(stiffness, freq_hz=5.0, fs=800.0, oversample=4, freq_step=0.05):
    """A mass whose undamped resonance with ``stiffness`` falls exactly (``k - m omega^2 == 0``
    in floating point) on a line of the floor signal's grid."""
    rate = fs * oversample
    lines = np.fft.rfftfreq(round(rate / freq_step), d=1.0 / rate)
    omega = 2.0 * np.pi * lines[np.argmin(np.abs(lines - freq_hz))]
    mass = stiffness / omega**2
    for _ in range(8):  # at most a few ulps from k / omega^2
        if stiffness - mass * omega**2 == 0.0:
            return mass
        mass = np.nextafter(mass, np.inf if stiffness - mass * omega**2 > 0 else -np.inf)
    raise AssertionError("no mass puts the resonance exactly on the line")


def test_an_undamped_resonance_on_a_line_is_not_a_bounded_stuck_state():
    """An undamped rope (c_visc = 0, as a fit that cannot see the damping leaves it) tuned to a
    line of the floor signal (the transport study tunes to 5 Hz, on its 0.05 Hz grid) has no
    small-amplitude steady state: its lines are infinite. It was taken for "stays stuck" (a NaN
    peak compares false), and the frequency-domain answer then failed with "psd must be
    finite". Now the run is simulated in time, and a linear start or a linear system's
    frequency-domain answer says why it cannot be had. No RuntimeWarning on the way."""
    import warnings

    from idkit.models import IwanModel
    from idkit.responses.small_amplitude import stays_stuck

    rope = IwanModel(g1=3e4, k=[3e4, 3e4], fc=[83.0, 146.0])
    system = SDOFSystem(_tuned_on_a_line(rope.stuck_stiffness), rope)
    floor = PsdProfile(np.array([1.0, 100.0]), np.array([1e-3, 1e-3]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        signals = np.fft.irfft(np.ones((1, 32001)) * 1e-3, n=64000)  # every line excited
        stuck, reason = stays_stuck(system, signals, 3200.0)
        assert not stuck and "unbounded" in reason and "at 5 Hz" in reason
        response = random_response(system, floor, seed=3, n_realizations=2, method="auto", workers=1)
        assert response.method == "time" and np.isfinite(response.output_psd).all()
        with pytest.raises(SimulationError, match="start='linear'.*unbounded.*5 Hz"):
            random_response(system, floor, seed=3, n_realizations=2, method="auto", start="linear", workers=1)
        voigt = VoigtModel(k=1e4, damping=0.0)
        with pytest.raises(SimulationError, match="unbounded.*undamped.*5 Hz.*method='time'"):
            random_response(SDOFSystem(_tuned_on_a_line(1e4), voigt), floor, seed=3, method="frequency")


def test_a_floor_profile_above_the_simulated_nyquist_frequency_is_refused_not_cut():
    # fs = 10 Hz (x 4 oversampling: a 20 Hz Nyquist frequency) with a 0.1-100 Hz floor ran
    # and reported an input RMS of 0.045 m/s^2 for a profile of 0.1 m/s^2: the band above
    # 20 Hz was dropped without a word
    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.1 * 2 * np.pi * 5))
    profile = PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0)
    with pytest.raises(SimulationError, match="reaching 100 Hz, expected none above oversample x fs / 2"):
        random_response(system, profile, seed=1, n_realizations=1, fs=10.0)
    # the profile's top exactly at the Nyquist frequency is kept whole (its line there is zero
    # in every realization, as at any fs)
    kept = random_response(system, profile, seed=1, n_realizations=1, fs=50.0, method="frequency")
    assert np.isfinite(kept.output_rms)


@pytest.mark.parametrize("arguments, words", [
    (dict(seed=-1), "seed: found -1"),
    (dict(seed=True), "seed: found True"),
    (dict(seed=1.5), "seed: found 1.5"),
])
def test_random_response_names_a_bad_argument(arguments, words):
    # numpy's "expected non-negative integer", "'dict' object is not callable", string
    # comparisons: errors that named nothing the caller wrote
    from idkit.errors import IdkitError

    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.1 * 2 * np.pi * 5))
    call = dict(input_psd=PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0), seed=1, n_realizations=1) | arguments
    with pytest.raises(IdkitError, match=words):
        random_response(system, **call)
