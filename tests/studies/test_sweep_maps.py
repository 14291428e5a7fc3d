"""Measured and model HOSIDFs of one setup (idkit.studies.sweep_maps) on a linear truth with a closed form."""

import numpy as np
import pytest

from idkit.io import MeasurementInfo, SteppedSineMeasurement
from idkit.io.info import Excitation
from idkit.models import VoigtModel
from idkit.plot import plot_sweep_bode, plot_sweep_maps
from idkit.studies.sweep_maps import MAP_ORDERS, sweep_maps

ZETA = 0.05
MASS, K, C = 3.0, 3.0 * (2 * np.pi * 12.0) ** 2, 2 * ZETA * 3.0 * 2 * np.pi * 12.0
#: model tolerance: the steady-state tolerance 1e-3 plus the trapezoidal rule's relative
#: frequency error (w0 h)^2 / 12 at the default 48 steps per resonance period, which moves
#: |H| near the resonance by up to that error over 2 zeta
MODEL_RTOL = 1e-3 + (2 * np.pi / 48) ** 2 / 12 / (2 * ZETA)
LEVELS = (0.005, 0.02, 0.08)  # base velocity amplitudes, m/s
FREQS = np.geomspace(4.0, 40.0, 7)


def transmissibility(freq):
    w = 2 * np.pi * freq
    return (K + 1j * C * w) / (K - MASS * w**2 + 1j * C * w)


def records(top_mass=MASS):
    """Steady-state sines written from the closed form: v_top = Re(T V_b e^{i w t})."""
    fs, out = 2000.0, []
    for level in LEVELS:
        for freq in FREQS:
            t = np.arange(int(round(fs * 8 / freq * 2))) / fs  # 16 periods
            w = 2 * np.pi * freq
            v_base = level * np.cos(w * t)
            v_top = np.real(transmissibility(freq) * level * np.exp(1j * w * t))
            out.append(SteppedSineMeasurement(
                time=t, v_base=v_base, v_top=v_top,
                info=MeasurementInfo(id=f"ss_{level}_{freq:.2f}", isolator="elastomer", top_mass_kg=top_mass,
                                     split="fit", excitation=Excitation(freq=float(freq), amplitude=level,
                                                                        amplitude_quantity="velocity"))))
    return out


@pytest.fixture(scope="module")
def maps():
    # a second setup with fewer records must be ignored (the most-recorded setup is shown)
    extra = records(top_mass=5.0)[:4]
    return sweep_maps(records() + extra, isolator=VoigtModel(k=K, damping=C), n_freq=9, n_amplitude=4)


def test_measured_first_harmonic_is_the_closed_form_and_higher_orders_vanish(maps):
    first = maps.order(1.0)
    assert maps.setup == "top mass 3 kg"
    assert len(first) == len(LEVELS) * FREQS.size
    expected = transmissibility(first["freq [Hz]"].to_numpy(float))
    # exact sines over whole periods: least squares returns them to rounding
    np.testing.assert_allclose(first["H measured"].to_numpy(complex), expected, rtol=1e-9)
    for order in (2.0, 3.0, 0.5):
        assert np.abs(maps.order(order)["H measured"].to_numpy(complex)).max() < 1e-9


def test_model_at_the_measured_points_and_on_the_grid_is_the_transmissibility(maps):
    first = maps.order(1.0)
    assert (maps.points["status"] == "ok").all()
    expected = transmissibility(first["freq [Hz]"].to_numpy(float))
    np.testing.assert_allclose(first["H model"].to_numpy(complex), expected, rtol=MODEL_RTOL)
    grid = maps.model
    assert grid.valid.all()
    np.testing.assert_allclose(grid.hosidf(1.0), transmissibility(grid.freq)[:, None] * np.ones(grid.amplitude.size),
                               rtol=MODEL_RTOL)
    # the grid spans exactly the measured frequencies and first-harmonic base amplitudes
    amplitude = first["base amplitude [m]"].to_numpy(float)
    assert grid.freq[0] == pytest.approx(FREQS[0]) and grid.freq[-1] == pytest.approx(FREQS[-1])
    assert grid.amplitude[0] == pytest.approx(amplitude.min()) and grid.amplitude[-1] == pytest.approx(amplitude.max())
    # a linear model has no other harmonic: what is left is the transient still decaying when
    # the steady-state criterion (every coefficient's change below 1e-3 of H1) was met
    first_magnitude = np.abs(first["H model"].to_numpy(complex))
    for order in (2.0, 3.0, 0.5):
        assert np.all(np.abs(maps.order(order)["H model"].to_numpy(complex)) < 1e-3 * first_magnitude)


def test_figures_show_every_order_and_every_level(maps):
    axes = plot_sweep_maps(maps)
    titles = [ax.get_title() for ax in axes.ravel()]
    assert len(titles) == len(MAP_ORDERS)
    assert titles[0].endswith("first harmonic") and titles[-1].endswith("1/2 subharmonic")
    magnitude_ax, phase_ax = plot_sweep_bode(maps)
    assert [text.get_text() for text in magnitude_ax.get_legend().get_texts()] == [f"{level:g} m/s" for level in LEVELS]
    assert "phase" in phase_ax.get_ylabel()
    # the phase of the model line at the highest frequency is the closed form's (unwrapped from 0)
    model_line = phase_ax.get_lines()[0]
    assert model_line.get_ydata()[-1] == pytest.approx(np.degrees(np.angle(transmissibility(FREQS[-1]))), abs=0.5)


def test_too_few_records_give_none():
    assert sweep_maps(records()[:2], isolator=VoigtModel(k=K, damping=C)) is None
    assert sweep_maps([], isolator=VoigtModel(k=K, damping=C)) is None
