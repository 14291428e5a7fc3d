"""A small synthetic measurement set (wire-rope loops, elastomer loops and white noise) written with idkit.io.

Shared by the fit, CLI and plot tests: an order-2 Iwan truth with 0.05 N force noise and the
Table 7.3 elastomer's exact transmissibility on three top masses, two repetitions each.
"""

import numpy as np

from idkit.io import MeasurementInfo, QuasiStaticMeasurement, WhiteNoiseMeasurement, write_measurement_set
from idkit.models import IwanModel, library

TRUTH_IWAN = IwanModel(g1=3e3, g2=4e4, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6])
ELASTOMER = library.get("table_7_3_elastomer")


def sine_loops(amplitudes, samples=1500):
    """Deflection in m: one sine cycle per amplitude (m), ``samples`` points in all."""
    phase = np.linspace(0, 2 * np.pi * len(amplitudes), samples)
    envelope = np.repeat(amplitudes, samples // len(amplitudes))
    envelope = np.concatenate([envelope, np.full(samples - envelope.size, amplitudes[-1])])
    return envelope * np.sin(phase)


def white_noise(mass, repetition, rng, fs=1000.0, n=16384):
    """A white-noise run on ``mass`` (kg): base velocity noise, top velocity through the exact transmissibility."""
    base = rng.standard_normal(n)
    freq = np.fft.rfftfreq(n, 1 / fs)
    stiffness = ELASTOMER.complex_stiffness(np.maximum(freq, 1e-3))
    h = stiffness / (stiffness - (mass + ELASTOMER.m_eff) * (2 * np.pi * freq) ** 2)
    top = np.fft.irfft(np.fft.rfft(base) * h, n)
    time = np.arange(n) / fs
    info = MeasurementInfo(id=f"wn_{mass:.2f}_{repetition}", isolator="elastomer", top_mass_kg=mass,
                           repetition=repetition, split="fit", sample_rate_hz=fs)
    return WhiteNoiseMeasurement(time=time, v_base=base, v_top=top, info=info)


def write_small_set(folder):
    """Write the set into ``folder`` (created); returns it."""
    rng = np.random.default_rng(8)
    measurements = []
    for repetition in (1, 2):
        for kind, amplitudes in (("small", [4e-3, 2e-3, 1e-3, 0.3e-3]), ("large", [12e-3, 8e-3, 4e-3])):
            x = sine_loops(np.array(amplitudes))
            force = TRUTH_IWAN.force(x) + 0.05 * rng.standard_normal(x.size)
            info = MeasurementInfo(id=f"qs_{kind}_{repetition}", isolator="wire_rope", repetition=repetition,
                                   split="fit", sample_rate_hz=50.0)
            measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=force,
                                                       info=info))
        x = sine_loops(np.array([1e-3, 2e-3]), 800)
        info = MeasurementInfo(id=f"qs_el_{repetition}", isolator="elastomer", repetition=repetition, split="fit",
                               sample_rate_hz=50.0)
        measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x,
                                                   force=ELASTOMER.k0 * x + 0.01 * rng.standard_normal(x.size),
                                                   info=info))
        for mass in (0.99, 3.0, 6.4):
            measurements.append(white_noise(mass, repetition, rng))
    write_measurement_set(folder, measurements, name="cli test")
    return folder


