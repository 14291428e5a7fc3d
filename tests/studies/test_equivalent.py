"""Equivalent stiffness and loss factor per cycle: closed forms of a Jenkin element and a
Kelvin element, and the model paired with the measurement cycle by cycle."""

import numpy as np
import pytest
from matplotlib.figure import Figure

from idkit.io import QuasiStaticMeasurement
from idkit.models import GeneralizedMaxwell, IwanModel
from idkit.plot.equivalent import plot_equivalent_linearization
from idkit.studies.equivalent import equivalent_linearization


def _record(amplitudes_m, period_s=10.0, samples_per_cycle=4000):
    """Cycles at growing amplitude from an unloaded start (the SPEC 3 protocol)."""
    pieces = [a * np.sin(2 * np.pi * np.arange(3 * samples_per_cycle) / samples_per_cycle) for a in amplitudes_m]
    x = np.concatenate(pieces)
    t = np.arange(x.size) * period_s / samples_per_cycle
    return t, x


def test_one_jenkin_element_gives_its_closed_form():
    # spring 1e5 N/m, slip 20 N (slips at 0.2 mm); parallel spring 0: a parallelogram loop
    k, fc = 1e5, 20.0
    jenkin = IwanModel(g1=0.0, g2=0.0, g3=0.0, k=[k], fc=[fc])
    t, x = _record([1e-3, 2e-3, 4e-3])
    measurement = QuasiStaticMeasurement(time=t, deflection=x, force=jenkin.force(x))
    result = equivalent_linearization([measurement], jenkin)
    # cycles wholly at one amplitude (the cycle that steps up to the next amplitude is not closed)
    steady = np.isclose(result.amplitude_m[:, None], [1e-3, 2e-3, 4e-3], rtol=1e-6).any(axis=1)
    assert steady.sum() >= 5
    X = result.amplitude_m[steady]
    # 4000 samples a cycle: the sampled extremes and the trapezoid area are exact to ~(2 pi/4000)^2 = 2.5e-6
    np.testing.assert_allclose(result.secant_stiffness_n_per_m[steady], fc / X, rtol=1e-4)
    np.testing.assert_allclose(result.loss_factor[steady], 4 * (X - fc / k) / (np.pi * X), rtol=1e-4)
    # the model is the generating law: paired cycle by cycle, identical
    np.testing.assert_allclose(result.model_loss_factor, result.loss_factor, rtol=1e-12)


@pytest.mark.parametrize("period_s", [2.0, 10.0])
def test_kelvin_element_gives_its_ellipse(period_s):
    k, c = 2e4, 300.0
    kelvin = GeneralizedMaxwell(k0=k, k=[1e9], rate=[1e9 / c])  # a dashpot c in parallel, to 1e-5
    t, x = _record([3e-3], period_s=period_s)
    measurement = QuasiStaticMeasurement(time=t, deflection=x, force=k * x + c * np.gradient(x, t))
    result = equivalent_linearization([measurement], kelvin)
    w = 2 * np.pi / period_s
    steady = slice(1, None)  # the first cycle starts at rest
    np.testing.assert_allclose(result.secant_stiffness_n_per_m[steady], np.hypot(k, c * w), rtol=1e-3)
    np.testing.assert_allclose(result.loss_factor[steady], c * w / np.hypot(k, c * w), rtol=1e-3)
    np.testing.assert_allclose(result.model_loss_factor[steady], result.loss_factor[steady], rtol=1e-3)


def test_plot_labels_both_panels():
    jenkin = IwanModel(g1=1e3, g2=0.0, g3=0.0, k=[1e5], fc=[20.0])
    t, x = _record([1e-3, 2e-3])
    result = equivalent_linearization([QuasiStaticMeasurement(time=t, deflection=x, force=jenkin.force(x))],
                                      jenkin)
    stiffness_ax, loss_ax = plot_equivalent_linearization(result, axes=Figure().subplots(2, 1))
    assert "[N/m]" in stiffness_ax.get_ylabel() and "[-]" in loss_ax.get_ylabel()
    assert "[mm]" in loss_ax.get_xlabel() and len(stiffness_ax.lines) == 2


def test_complex_stiffness_read_off_a_transmissibility_is_the_law():
    from idkit.models.laws import sdof_transmissibility
    from idkit.observe.white_noise import TransmissibilitySet
    from idkit.plot.equivalent import plot_complex_stiffness_comparison
    from idkit.studies.equivalent import MIN_DISTANCE_FROM_ONE, complex_stiffness_comparison

    law = GeneralizedMaxwell(k0=1.4e4, k=[3.5e3, 1.1e4], rate=[47.0, 840.0], m_eff=0.05)
    freq = np.linspace(1.0, 100.0, 397)
    frfs = [TransmissibilitySet(mass=m, freq=freq, transmissibility=sdof_transmissibility(
        law.complex_stiffness(freq), m + law.m_eff, 2 * np.pi * freq)) for m in (1.0, 2.5, 1.0)]
    result = complex_stiffness_comparison(frfs, law)
    assert result.mass_kg == (1.0, 2.5)  # one FRF per top mass
    for freq_hz, measured, model, mass in zip(result.freq_hz, result.measured, result.model, result.mass_kg):
        h = sdof_transmissibility(model, mass + law.m_eff, 2 * np.pi * freq_hz)
        kept = np.abs(h - 1) >= MIN_DISTANCE_FROM_ONE
        assert kept.sum() > 300 and np.all(np.isnan(measured[~kept]))
        # the exact inverse: round-off only (|H - 1| >= 0.2 bounds the amplification by 5 |H|)
        np.testing.assert_allclose(measured[kept], model[kept], rtol=1e-10)
    stiffness_ax, loss_ax = plot_complex_stiffness_comparison(result, axes=Figure().subplots(2, 1))
    assert len(stiffness_ax.lines) == 3 and "[N/m]" in stiffness_ax.get_ylabel()


def test_drop_shock_spectra_of_a_half_sine_pulse():
    # a half-sine of peak A over tau: an oscillator far above 1/tau follows it (maximax ~ A);
    # one far below sees an impulse dv = 2 A tau / pi and peaks at ~ w_n dv (5 % damping
    # shaves a few percent off)
    from idkit.io import DropMeasurement
    from idkit.io.info import MeasurementInfo
    from idkit.plot.equivalent import plot_drop_shock_spectra
    from idkit.studies.equivalent import drop_shock_spectra

    fs, tau, peak = 20000.0, 0.02, 300.0
    t = np.arange(0, 2.0, 1 / fs)
    drops = []
    for height, scale in ((0.05, 0.5), (0.1, 1.0)):
        a = np.where((t > 0.1) & (t < 0.1 + tau), scale * peak * np.sin(np.pi * (t - 0.1) / tau), 0.0)
        for mass in (2.0, 4.0) if height == 0.1 else (4.0,):
            info = MeasurementInfo(isolator="pad", top_mass_kg=mass, drop_height_m=height)
            drops.append(DropMeasurement(time=t, deflection=np.zeros_like(t), a_top_1=a, a_top_2=a, info=info))
    result = drop_shock_spectra(drops)
    assert result.top_mass_kg == 4.0 and result.height_m == (0.05, 0.1)  # the mass with most heights
    srs = result.acceleration[1]
    assert peak <= srs[-1] <= 1.1 * peak  # 1000 Hz oscillator on a 25 Hz pulse
    dv = 2 * peak * tau / np.pi
    np.testing.assert_allclose(srs[0], 2 * np.pi * 1.0 * dv, rtol=0.1)
    np.testing.assert_allclose(result.acceleration[0], 0.5 * srs, rtol=1e-9)  # linear in the record
    ax = plot_drop_shock_spectra(result, ax=Figure().subplots())
    assert len(ax.lines) == 2 and "[Hz]" in ax.get_xlabel()
    assert drop_shock_spectra([]) is None


def test_loop_residual_plot_draws_model_minus_measured():
    from idkit.fit.predictions import LoopFitPrediction, LoopPrediction
    from idkit.plot.equivalent import plot_loop_residuals

    x = np.linspace(-1e-3, 1e-3, 50)
    small = tuple(LoopPrediction(f"s{i}", x, 100 * x, 100 * x + 0.5) for i in range(8))
    large = (LoopPrediction("l1", 10 * x, 1e3 * x, 1e3 * x - 2.0),)
    small_ax, large_ax = plot_loop_residuals(LoopFitPrediction(small=small, large=large),
                                             axes=Figure().subplots(1, 2))
    assert len(small_ax.lines) == 6 + 1  # at most six sets a panel, plus the zero line
    np.testing.assert_allclose(small_ax.lines[0].get_ydata(), 0.5)
    np.testing.assert_allclose(large_ax.lines[0].get_ydata(), -2.0)
    assert "[N]" in small_ax.get_ylabel() and "[mm]" in large_ax.get_xlabel()


def test_frf_residual_plot_is_zero_on_the_generating_law_and_sees_a_wrong_one():
    from idkit.models.laws import sdof_transmissibility
    from idkit.observe.white_noise import TransmissibilitySet
    from idkit.plot.equivalent import plot_frf_residuals

    law = GeneralizedMaxwell(k0=1.4e4, k=[3.5e3, 1.1e4], rate=[47.0, 840.0], m_eff=0.05)
    freq = np.linspace(1.0, 100.0, 397)
    frfs = [TransmissibilitySet(mass=m, freq=freq, transmissibility=sdof_transmissibility(
        law.complex_stiffness(freq), m + law.m_eff, 2 * np.pi * freq)) for m in (1.0, 2.5)]
    ax = plot_frf_residuals(law, frfs, ax=Figure().subplots())
    assert len(ax.lines) == 2 and max(np.max(line.get_ydata()) for line in ax.lines) < 1e-12
    wrong = plot_frf_residuals(law.scaled(2.0), frfs, ax=Figure().subplots())
    assert min(np.max(line.get_ydata()) for line in wrong.lines) > 0.5  # stiffness x2 moves the resonance


def test_drop_shock_spectra_with_histories_add_the_model_and_the_impact():
    """The model's spectrum is that of its simulated record; the impact's is that of a velocity step
    dv = (1 + e) sqrt(2 g h), whose answer is known in closed form: the oscillator's relative motion
    z = -(dv / w_d) exp(-zeta w t) sin(w_d t), its absolute acceleration -(w^2 z + 2 zeta w z')."""
    from types import SimpleNamespace

    from idkit.gravity import STANDARD_GRAVITY
    from idkit.io import DropMeasurement
    from idkit.io.info import MeasurementInfo
    from idkit.studies.equivalent import drop_shock_spectra

    fs, tau, peak = 20000.0, 0.02, 300.0
    t = np.arange(0, 1.0, 1 / fs)
    a = np.where((t > 0.1) & (t < 0.1 + tau), peak * np.sin(np.pi * (t - 0.1) / tau), 0.0)
    drops = [DropMeasurement(time=t, deflection=np.zeros_like(t), a_top_1=a, a_top_2=a,
                             info=MeasurementInfo(id=f"d{h}", isolator="pad", top_mass_kg=4.0, drop_height_m=h))
             for h in (0.02, 0.08)]
    histories = SimpleNamespace(contact=SimpleNamespace(restitution=0.3), drops=tuple(
        SimpleNamespace(id=f"d{h}", simulated_time=t - 0.1, simulated_acceleration=2.0 * a) for h in (0.08,)))
    result = drop_shock_spectra(drops, histories=histories)
    assert result.height_m == (0.08,)  # the histories' drops only
    np.testing.assert_allclose(result.model_acceleration[0], 2.0 * result.acceleration[0], rtol=1e-9)
    dv = 1.3 * np.sqrt(2 * STANDARD_GRAVITY * 0.08)
    zeta, phase = 0.05, np.linspace(0.0, 2 * np.pi, 200001)  # w t over the first period, where the peak lies
    root = np.sqrt(1 - zeta**2)
    z = -np.exp(-zeta * phase / root) * np.sin(phase)  # in units of dv / w_d, time in 1 / w_d
    z_dot = -np.exp(-zeta * phase / root) * (np.cos(phase) - zeta / root * np.sin(phase))
    step_answer = float(np.max(np.abs(z / root**2 + 2 * zeta / root * z_dot))) * root  # in units of w dv
    ratio = result.input_acceleration[0] / (2 * np.pi * result.freq_hz * dv * step_answer)
    slow = result.freq_hz < fs / 100  # the impulse (two steps wide) is a step to these oscillators
    np.testing.assert_allclose(ratio[slow], 1.0, rtol=2e-3)
    # faster ones: the filter sees the response at the samples only, a peak missed by at most
    # (w_n T)^2 / 8 (idkit.signal.srs), and the impulse is a triangle two steps wide, whose spectrum
    # at w_n is sinc^2(w_n T / 2) of the step's
    half = np.pi * result.freq_hz / fs  # w_n T / 2
    lowest = (1 - (2 * half) ** 2 / 8) * (np.sin(half) / half) ** 2
    assert np.all((ratio >= lowest) & (ratio < 1 + 2e-3)), (ratio, lowest)
