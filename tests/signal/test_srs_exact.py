"""The three shock response spectra against an exact reference at pyroshock sample rates.

Reference: the oscillator ``z'' + 2 zeta w z' + w^2 z = -a(t)`` with ``a`` linear between the
samples (what ramp invariance, ISO 18431-4, makes exact) solved interval by interval in
40-digit decimal arithmetic (:mod:`decimal`, standard library): on each interval the
particular solution of a linear forcing ``p + q t`` is ``alpha + beta t``, and the rest decays
as the free damped oscillation from the interval's start. That is neither the complex-mode
filter of :mod:`idkit.signal.srs` (phi functions, one-pole recursion) nor scipy's first-order
hold (a float64 matrix exponential, which itself loses digits at these rates). At 40 digits
its own round-off stays far below the 1e-9 checked: the particular solution cancels against
the free part by at most ``(fs / 2 pi f_n)^2`` (6e5 here), leaving over 30 correct digits.
mpmath is not a dependency of idkit, hence :mod:`decimal` with a short sine/cosine series.
"""

from __future__ import annotations

from decimal import Decimal, localcontext

import numpy as np
import pytest

from idkit.signal.srs import relative_displacement_coefficients, shock_spectra

PRECISION = 40
PI = Decimal("3.14159265358979323846264338327950288419716939937510582097494")


def _sin_cos(angle: Decimal) -> tuple[Decimal, Decimal]:
    """Sine and cosine by their series after halving the angle below 1/2, then doubling back."""
    halvings = 0
    while abs(angle) > Decimal("0.5"):
        angle /= 2
        halvings += 1
    sine, cosine, term, n = Decimal(0), Decimal(0), Decimal(1), 0
    smallest = Decimal(10) ** -(PRECISION + 5)
    while abs(term) > smallest or n < 2:  # term = angle^n / n!
        if n % 4 == 0:
            cosine += term
        elif n % 4 == 1:
            sine += term
        elif n % 4 == 2:
            cosine -= term
        else:
            sine -= term
        n += 1
        term = term * angle / n
    for _ in range(halvings):
        sine, cosine = 2 * sine * cosine, cosine * cosine - sine * sine
    return sine, cosine


def exact_response(accel, fs: float, freq: float, damping_ratio: float) -> tuple[list, list]:
    """Relative displacement and absolute acceleration at the samples, as Decimals.

    The record starts from rest with the input ramping from 0 at ``-1/fs`` to ``accel[0]``,
    as a digital filter with zero initial state sees it.
    """
    with localcontext() as context:
        context.prec = PRECISION
        omega = 2 * PI * Decimal(float(freq))
        zeta = Decimal(float(damping_ratio))
        step = 1 / Decimal(float(fs))
        sigma = zeta * omega
        omega_d = omega * (1 - zeta * zeta).sqrt()
        decay = (-sigma * step).exp()
        sine, cosine = _sin_cos(omega_d * step)
        omega2 = omega * omega
        zz = decay * (cosine + sigma * sine / omega_d)  # free oscillation over one step
        zv = decay * sine / omega_d
        vz = -decay * omega2 * sine / omega_d
        vv = decay * (cosine - sigma * sine / omega_d)
        samples = [Decimal(0)] + [Decimal(float(value)) for value in accel]
        displacement, velocity = Decimal(0), Decimal(0)
        z_out, a_out = [], []
        for start, end in zip(samples[:-1], samples[1:]):
            slope = (end - start) / step  # a = start + slope t on this step
            beta = -slope / omega2
            alpha = (-start - 2 * sigma * beta) / omega2
            free_z, free_v = displacement - alpha, velocity - beta
            displacement = zz * free_z + zv * free_v + alpha + beta * step
            velocity = vz * free_z + vv * free_v + beta
            z_out.append(displacement)
            a_out.append(-(2 * sigma * velocity + omega2 * displacement))
        return z_out, a_out


RATES = [1e5, 1e6, 1e7]
#: natural frequencies as fractions of the sample rate: 5000 down to 2.5 samples per period
FREQ_FRACTIONS = np.array([2e-4, 2e-3, 2e-2, 0.1, 0.4])


@pytest.mark.parametrize("fs", RATES)
def test_spectra_are_exact_at_any_sample_rate(fs):
    """A 400-sample half sine and 1200 samples of residual (a shorter window than the default
    keeps the reference small); every spectrum within 1e-9 of the exact one. The filter's
    round-off is below 1e-12 here (measured 5e-14 at 5000 samples per period); the
    first-order-hold filter it replaces was off by 4e-6 to 8e-4 on these records."""
    pulse = np.sin(np.pi * np.arange(400) / 400.0)
    residual = 1200 / fs
    freq = FREQ_FRACTIONS * fs
    damping_ratio = 0.05
    spectra = shock_spectra(pulse, fs=fs, freq=freq, damping_ratio=damping_ratio, residual_duration=residual)
    padded = np.concatenate([pulse, np.zeros(1200)])
    for index, fn in enumerate(freq):
        displacement, acceleration = exact_response(padded, fs, fn, damping_ratio)
        peak_z = float(max(abs(value) for value in displacement))
        peak_a = float(max(abs(value) for value in acceleration))
        assert spectra.relative_displacement[index] == pytest.approx(peak_z, rel=1e-9, abs=0)
        assert spectra.pseudo_velocity[index] == pytest.approx(2 * np.pi * fn * peak_z, rel=1e-9, abs=0)
        assert spectra.absolute_acceleration[index] == pytest.approx(peak_a, rel=1e-9, abs=0)


@pytest.mark.parametrize("damping_ratio", [0.0, 0.05, 0.7])
@pytest.mark.parametrize("samples_per_period", [2.2, 5.0, 60.0, 1e4, 1e6])
def test_relative_displacement_coefficients_are_exact(samples_per_period, damping_ratio):
    """b from the exact response to one unit sample (the filter's impulse response h:
    b0 = h0, b1 = h1 + a1 h0, b2 = h2 + a1 h1 + a2 h0), a from the exact poles; each
    coefficient within 1e-12 relative (round-off of a few operations; the phi series and
    closed forms are both exercised: w_n T from 6e-6 to 2.9). The static gain
    sum(b) / sum(a) = -1 / w_n^2 follows from the same b and a."""
    fs = 1e6
    fn = fs / samples_per_period
    b, a = relative_displacement_coefficients([fn], fs=fs, damping_ratio=damping_ratio)
    with localcontext() as context:
        context.prec = PRECISION
        h = exact_response([1.0, 0.0, 0.0], fs, fn, damping_ratio)[0]
        theta = 2 * PI * Decimal(float(fn)) / Decimal(fs)
        zeta = Decimal(float(damping_ratio))
        decay = (-zeta * theta).exp()
        cosine = _sin_cos(theta * (1 - zeta * zeta).sqrt())[1]
        a_exact = [Decimal(1), -2 * decay * cosine, decay * decay]
        b_exact = [h[0], h[1] + a_exact[1] * h[0], h[2] + a_exact[1] * h[1] + a_exact[2] * h[0]]
    np.testing.assert_allclose(b[0], [float(value) for value in b_exact], rtol=1e-12, atol=0)
    np.testing.assert_allclose(a[0], [float(value) for value in a_exact], rtol=1e-12, atol=1e-300)
