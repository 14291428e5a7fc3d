"""Shock response spectrum (SRS) of an acceleration record.

The SRS is the peak response of a bank of base-excited, linear, viscously damped SDOF
oscillators, one per natural frequency, driven by the record (ISO 18431-4:2007; Smallwood,
"An improved recursive formula for calculating shock response spectra", Shock and Vibration
Bulletin 51, 1981). It complements the rest shock level of :mod:`idkit.signal.drop` when
comparing isolators on a measured shock (SPEC sections 3, 6). The three spectra of
ISO 18431-4 are the **absolute acceleration** ``max |x''|``, the **relative displacement**
``max |z|`` of ``z = x - x_base`` (``z'' + 2 zeta w_n z' + w_n^2 z = -a_base``) and the
**pseudo-velocity** ``w_n max |z|`` (:func:`shock_spectra`).

Ramp invariance: every oscillator is evaluated exactly at the sample instants for a base
acceleration linear between samples (what Smallwood's filter does). The oscillator is one
complex mode, ``w' = lambda w + a_base`` with ``lambda = -zeta w_n + i w_d``,
``w_d = w_n sqrt(1 - zeta^2)``, whose exact step over ``T = 1/fs`` for a linear input is::

    w[k+1] = exp(x) w[k] + T (phi1(x) - phi2(x)) a[k] + T phi2(x) a[k+1],   x = lambda T,

    phi1(x) = (exp(x) - 1) / x,   phi2(x) = (exp(x) - 1 - x) / x^2,

and ``z = -Im(w) / w_d``, ``x'' = Im(kappa w) / w_d`` with
``kappa = w_n^2 (1 - 2 zeta^2) + 2 i zeta w_n w_d`` (:func:`_oscillator_peaks`). The phi
functions come from their power series where ``|x| < 1`` (no subtraction of nearly equal
numbers) and from the closed forms above elsewhere (``|x| = w_n T`` is below pi at any
natural frequency under the Nyquist frequency), so each coefficient carries round-off
only. The recursion is a one-pole filter, whose pole ``exp(x)`` keeps ``x`` to round-off,
i.e. ``w_n`` and ``zeta`` to ``eps / (w_n T)``, and whose round-off grows like that of a
well-damped first-order filter: the spectra are exact to about 1e-12 at any sample rate
(tested against a 40-digit reference at 100 kHz, 1 MHz and 10 MHz).

The same filter written as the usual real second-order recursion (:func:`smallwood_coefficients`,
:func:`relative_displacement_coefficients`, coefficients ``b``, ``a`` for
:func:`scipy.signal.lfilter`) has ``a ~ [1, -2, 1]`` at high rates: its DC gain
``sum(b) / sum(a)`` divides by ``sum(a) ~ (w_n T)^2``, so its round-off is amplified by
``(fs / (2 pi f_n))^2`` (1e-9 at ``fs = 1e4 f_n``, 1e-8 at ``1e5 f_n``). The coefficients are
given for use elsewhere; the spectra use the complex mode.

The filter gives the response at the samples only, so a peak between samples is missed by
at most about ``(w_n T)^2 / 8`` relative: 4.9 % at ``fs = 10 f_n`` (the usual minimum
rate), 1.2 % at ``20 f_n``, 0.2 % at ``50 f_n``. Sample the record accordingly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar
from math import factorial

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import signal as sps

from idkit.checks import Real, Reals, Samples, accepts
from idkit.errors import DataError
from idkit.limits import MAX_SAMPLES

__all__ = [
    "MIN_SAMPLES_PER_PERIOD",
    "ShockResponseSpectrum",
    "ShockSpectra",
    "relative_displacement_coefficients",
    "shock_response_spectrum",
    "shock_spectra",
    "smallwood_coefficients",
]

#: Fewest samples per period of the highest natural frequency an SRS is computed for:
#: a peak between samples is then missed by at most ``(2 pi / 10)^2 / 8 = 4.9 %``.
MIN_SAMPLES_PER_PERIOD = 10.0
#: Most samples of the residual window (one period of the lowest natural frequency, zeros after
#: the record): one signal array's limit.
MAX_RESIDUAL_SAMPLES = MAX_SAMPLES

#: The contract of both spectra's arguments.
_SPECTRUM_ARGUMENTS = dict(acceleration=Samples(min_size=2), fs=Real(unit="Hz", gt=0),
                           freq=Reals(unit="Hz", gt=0, meaning="natural frequencies below fs / 2"),
                           damping_ratio=Real(ge=0, lt=1), residual_duration=Real(unit="s", ge=0, optional=True),
                           error=DataError)


@accepts(freq=Reals(unit="Hz", gt=0), fs=Real(unit="Hz", gt=0), damping_ratio=Real(ge=0, lt=1), error=DataError)
def smallwood_coefficients(
    freq: ArrayLike, *, fs: float, damping_ratio: float = 0.05
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Smallwood ramp-invariant filter coefficients for absolute acceleration response.

    For :func:`scipy.signal.lfilter`; as a real second-order recursion it loses about
    ``eps (fs / 2 pi f_n)^2`` (module docstring), so the spectra run the same filter as a
    complex mode instead.

    Parameters
    ----------
    freq : array_like, shape (n_freq,)
        Natural frequencies, Hz, in (0, fs/2).
    fs : float
        Sample rate, Hz.
    damping_ratio : float, default 0.05
        Viscous damping ratio zeta in [0, 1) (0.05 is Q = 10).

    Returns
    -------
    b, a : ndarray, shape (n_freq, 3)
        Numerator and denominator coefficients per natural frequency (``a[:, 0] = 1``).
    """
    fn = np.atleast_1d(np.asarray(freq, dtype=float))
    omega_n = 2 * np.pi * fn
    period = 1.0 / fs
    decay = np.exp(-damping_ratio * omega_n * period)
    phase = omega_n * np.sqrt(1.0 - damping_ratio**2) * period
    sine = decay * np.sin(phase) / phase
    cosine = decay * np.cos(phase)
    b = np.column_stack([1.0 - sine, 2.0 * (sine - cosine), decay**2 - sine])
    a = np.column_stack([np.ones_like(fn), -2.0 * cosine, decay**2])
    return b, a


#: Below this ``|x| = w_n T`` the phi functions come from their power series (the first term
#: left out, ``|x|^20 / 22!``, is below 1e-21); above it their closed forms subtract numbers
#: at most a few times larger than the result.
_SERIES_RADIUS = 1.0
_SERIES_TERMS = 20


def _phi_functions(x: NDArray[np.complex128]) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """``phi1(x) = (e^x - 1) / x`` and ``phi2(x) = (e^x - 1 - x) / x^2`` to round-off, for complex ``x``."""
    x = np.asarray(x, dtype=complex)
    small = np.abs(x) < _SERIES_RADIUS
    phi2 = np.empty_like(x)
    inner = x[small]
    series = np.zeros_like(inner)
    for n in range(_SERIES_TERMS - 1, -1, -1):  # Horner: sum x^n / (n + 2)!
        series = series * inner + 1.0 / factorial(n + 2)
    phi2[small] = series
    large = x[~small]
    phi1_large = np.expm1(large) / large
    phi2[~small] = (phi1_large - 1.0) / large
    phi1 = 1.0 + x * phi2  # |x phi2| < 0.6 where small: no cancellation
    phi1[~small] = phi1_large
    return phi1, phi2


def _ramp_invariant_modes(fn: NDArray[np.float64], fs: float, damping_ratio: float):
    """Each oscillator's complex mode (module docstring): the pole ``exp(lambda T)``, the weights
    of the current and the previous input sample, and ``w_d`` (rad/s)."""
    omega = 2.0 * np.pi * fn
    period = 1.0 / fs
    root = np.sqrt(1.0 - damping_ratio**2)
    x = omega * period * (-damping_ratio + 1j * root)
    phi1, phi2 = _phi_functions(x)
    pole = np.exp(-damping_ratio * omega * period) * np.exp(1j * omega * root * period)
    return pole, period * phi2, period * (phi1 - phi2), omega * root


@accepts(freq=Reals(unit="Hz", gt=0), fs=Real(unit="Hz", gt=0), damping_ratio=Real(ge=0, lt=1), error=DataError)
def relative_displacement_coefficients(
    freq: ArrayLike, *, fs: float, damping_ratio: float = 0.05
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Ramp-invariant filters from base acceleration to the oscillators' relative displacement.

    The ISO 18431-4 relative-displacement filter of
    ``Z(s) / A(s) = -1 / (s^2 + 2 zeta w_n s + w_n^2)``: exact at the samples when the base
    acceleration is linear between them, like :func:`smallwood_coefficients`. The textbook
    closed form subtracts terms of order ``1 / (w_n^3 T)`` to get coefficients of order
    ``T^2``; here they come from the complex mode of the module docstring,
    ``H = -Im[(c0 + c1 q)(1 - conj(p) q)] / (w_d |1 - p q|^2)`` (``q = z^-1``, pole ``p``,
    weights ``c0 = T phi2``, ``c1 = T (phi1 - phi2)``), each to round-off at any sample rate.
    Run as a real second-order recursion they still lose ``eps (fs / 2 pi f_n)^2`` (module
    docstring); :func:`shock_spectra` does not use them.

    Parameters
    ----------
    freq : array_like, shape (n_freq,)
        Natural frequencies, Hz, in (0, fs/2).
    fs : float
        Sample rate, Hz.
    damping_ratio : float, default 0.05
        Viscous damping ratio in [0, 1).

    Returns
    -------
    b, a : ndarray, shape (n_freq, 3)
        Numerator (s^2 per input unit: m per m/s^2) and denominator (``a[:, 0] = 1``).

    Examples
    --------
    The static gain is ``-1 / w_n^2``:

    >>> b, a = relative_displacement_coefficients([10.0], fs=1e6)
    >>> round(float(b.sum() / a.sum() * (2 * np.pi * 10.0) ** 2), 6)
    -1.0
    """
    fn = np.atleast_1d(np.asarray(freq, dtype=float))
    pole, current, previous, omega_d = _ramp_invariant_modes(fn, float(fs), float(damping_ratio))
    numerator = np.column_stack([current, previous - current * np.conj(pole), -previous * np.conj(pole)])
    b = -numerator.imag / omega_d[:, None]
    decay = np.exp(-damping_ratio * 2.0 * np.pi * fn / fs)
    a = np.column_stack([np.ones_like(fn), -2.0 * pole.real, decay**2])
    return b, a


def _oscillator_peaks(padded: NDArray[np.float64], fn: NDArray[np.float64], fs: float, damping_ratio: float):
    """Per natural frequency: the largest and the smallest absolute acceleration and the largest
    ``|z|`` over the padded record (one complex one-pole filter each, module docstring)."""
    pole, current, previous, omega_d = _ramp_invariant_modes(fn, fs, damping_ratio)
    omega = 2.0 * np.pi * fn
    gain = omega**2 * (1.0 - 2.0 * damping_ratio**2) + 2j * damping_ratio * omega * omega_d
    largest, smallest, displacement = (np.empty(fn.size) for _ in range(3))
    drive = padded.astype(complex)
    for index in range(fn.size):
        mode = sps.lfilter([current[index], previous[index]], [1.0, -pole[index]], drive)
        part = mode.imag
        acceleration = part * (gain[index].real / omega_d[index])
        acceleration += mode.real * (gain[index].imag / omega_d[index])
        largest[index] = acceleration.max()
        smallest[index] = acceleration.min()
        displacement[index] = max(part.max(), -part.min()) / omega_d[index]
    return largest, smallest, displacement


@dataclass(frozen=True, kw_only=True)
class _OscillatorBankSpectrum:
    """Peaks per natural frequency of a bank of oscillators with one damping ratio: the natural
    frequencies, the damping ratio and the table every spectrum of this module gives.

    ``_COLUMNS``: (attribute, column label with its unit) of each spectrum, in table order.
    """

    freq: NDArray[np.float64]
    damping_ratio: float
    _COLUMNS: ClassVar[tuple[tuple[str, str], ...]] = ()

    def to_dataframe(self) -> pd.DataFrame:
        """One row per natural frequency: ``freq [Hz]``, then each spectrum."""
        return pd.DataFrame({"freq [Hz]": self.freq, **{label: getattr(self, name) for name, label in self._COLUMNS}})


@dataclass(frozen=True, kw_only=True)
class ShockSpectra(_OscillatorBankSpectrum):
    """The three shock response spectra of ISO 18431-4 of one acceleration record.

    Attributes
    ----------
    absolute_acceleration : ndarray, shape (n_freq,)
        Maximax absolute acceleration of the oscillators, m/s^2 (unit of the input).
    relative_displacement : ndarray, shape (n_freq,)
        Maximax relative displacement ``max |z|``, m (input unit times s^2).
    pseudo_velocity : ndarray, shape (n_freq,)
        ``2 pi freq * relative_displacement``, m/s.
    freq, damping_ratio : ndarray, shape (n_freq,); float
        Natural frequencies (Hz) and the oscillators' damping ratio, as every spectrum here.

    ``to_dataframe()``: columns ``freq [Hz]``, ``absolute_acceleration [m/s^2]``,
    ``pseudo_velocity [m/s]``, ``relative_displacement [m]``.
    """

    absolute_acceleration: NDArray[np.float64]
    relative_displacement: NDArray[np.float64]
    pseudo_velocity: NDArray[np.float64]
    _COLUMNS = (("absolute_acceleration", "absolute_acceleration [m/s^2]"), ("pseudo_velocity", "pseudo_velocity [m/s]"),
                ("relative_displacement", "relative_displacement [m]"))


@dataclass(frozen=True, kw_only=True)
class ShockResponseSpectrum(_OscillatorBankSpectrum):
    """Shock response spectrum (absolute acceleration).

    Attributes
    ----------
    positive : ndarray, shape (n_freq,)
        Largest response acceleration (signed maximum), m/s^2 (unit of the input).
    negative : ndarray, shape (n_freq,)
        Largest response acceleration in the negative direction as a magnitude,
        ``-min(response)``, m/s^2.
    maximax : ndarray, shape (n_freq,)
        ``max(|response|) = max(positive, negative)``, m/s^2.
    freq, damping_ratio : ndarray, shape (n_freq,); float
        Natural frequencies (Hz) and the oscillators' damping ratio, as every spectrum here.

    ``to_dataframe()``: columns ``freq [Hz]``, ``positive``, ``negative``, ``maximax``
    (unit of the input).
    """

    positive: NDArray[np.float64]
    negative: NDArray[np.float64]
    maximax: NDArray[np.float64]
    _COLUMNS = (("positive", "positive"), ("negative", "negative"), ("maximax", "maximax"))


def _checked(acceleration, fs, freq, damping_ratio, residual_duration):
    """Natural frequencies (checked against ``fs``) and the record padded with its residual window."""
    values, fn = acceleration, np.atleast_1d(freq)
    if fn.ndim != 1 or not np.all(fn < fs / 2):
        raise DataError(f"freq: found {fn!r}, expected a 1-D array of natural frequencies below fs / 2 = "
                        f"{fs / 2:g} Hz")
    if residual_duration is None:
        residual_duration = 1.0 / fn.min()
    if residual_duration * fs * (1 - 1e-12) > MAX_RESIDUAL_SAMPLES:
        raise DataError(
            f"freq: the lowest natural frequency {fn.min():g} Hz needs a residual window of {residual_duration:.4g} s, "
            f"{residual_duration * fs:.4g} samples at {fs:g} Hz; expected at most {MAX_RESIDUAL_SAMPLES:.0e} "
            f"(natural frequencies >= {fs / MAX_RESIDUAL_SAMPLES:.4g} Hz, or a shorter residual_duration)"
        )
    # a window of whole samples; the small margin keeps a product like 0.1 s x 200 kHz at 20000
    padded = np.concatenate([values, np.zeros(int(np.ceil(residual_duration * fs * (1 - 1e-12))))])
    return fn, padded


@accepts(**_SPECTRUM_ARGUMENTS)
def shock_response_spectrum(
    acceleration: ArrayLike,
    *,
    fs: float,
    freq: ArrayLike,
    damping_ratio: float = 0.05,
    residual_duration: float | None = None,
) -> ShockResponseSpectrum:
    """Shock response spectrum (absolute acceleration) of a base acceleration record.

    Parameters
    ----------
    acceleration : array_like, shape (n,)
        Base acceleration, m/s^2 (any unit: the SRS has the same one), sampled at ``fs``.
    fs : float
        Sample rate, Hz.
    freq : array_like, shape (n_freq,)
        Natural frequencies, Hz, each in (0, fs/2); ``fs >= 20 freq`` for peaks within 1.2 %.
    damping_ratio : float, default 0.05
        Damping ratio of every oscillator (0.05 is Q = 10), in [0, 1).
    residual_duration : float, optional
        Seconds of zero input appended after the record so that the residual (free-vibration)
        peak is captured. Default: one period of the lowest natural frequency, ``1 /
        min(freq)``, which contains the first residual peak of every oscillator. 0 disables.

    Returns
    -------
    ShockResponseSpectrum

    Raises
    ------
    DataError
        Bad shapes or values, a natural frequency at or above the Nyquist frequency.

    Notes
    -----
    Each oscillator is the ramp-invariant (Smallwood) filter run as one complex mode (module
    docstring), one call of :func:`scipy.signal.lfilter` (C speed); lfilter does not take
    per-row coefficients, so the bank is a loop over natural frequencies, each of cost O(n).
    The computation is ``O(n_freq * n)``.

    Examples
    --------
    >>> import numpy as np
    >>> fs = 20000.0
    >>> t = np.arange(0, 0.011, 1 / fs)
    >>> pulse = np.where(t < 0.011, np.sin(np.pi * t / 0.011), 0.0)  # 1 m/s^2, 11 ms
    >>> srs = shock_response_spectrum(pulse, fs=fs, freq=[2000.0])
    >>> round(float(srs.maximax[0]), 2)  # far above the pulse: the static response
    1.0
    """
    fn, padded = _checked(acceleration, fs, freq, damping_ratio, residual_duration)
    positive, smallest, _ = _oscillator_peaks(padded, fn, float(fs), float(damping_ratio))
    negative = -smallest
    return ShockResponseSpectrum(
        freq=fn,
        positive=positive,
        negative=negative,
        maximax=np.maximum(positive, negative),
        damping_ratio=float(damping_ratio),
    )


@accepts(**_SPECTRUM_ARGUMENTS)
def shock_spectra(
    acceleration: ArrayLike,
    *,
    fs: float,
    freq: ArrayLike,
    damping_ratio: float = 0.05,
    residual_duration: float | None = None,
) -> ShockSpectra:
    """Absolute-acceleration, pseudo-velocity and relative-displacement SRS of one record.

    Parameters are those of :func:`shock_response_spectrum` (same checks, same residual
    window). The absolute acceleration and the relative displacement are read from the same
    ramp-invariant complex mode of each oscillator (module docstring: exact at the samples
    for an input linear between them, to round-off at any sample rate); the pseudo-velocity
    is ``2 pi freq`` times the relative displacement.

    Returns
    -------
    ShockSpectra

    Examples
    --------
    A short pulse seen by a slow oscillator: its pseudo-velocity is the pulse's velocity
    change (here a half sine of 1 m/s^2 over 10 ms: ``dv = 2 A tau / pi``).

    >>> fs = 100000.0
    >>> t = np.arange(0, 0.01, 1 / fs)
    >>> pulse = np.sin(np.pi * t / 0.01)
    >>> spectra = shock_spectra(pulse, fs=fs, freq=[1.0], damping_ratio=0.0)
    >>> round(float(spectra.pseudo_velocity[0] / (2 * 0.01 / np.pi)), 3)
    1.0
    """
    fn, padded = _checked(acceleration, fs, freq, damping_ratio, residual_duration)
    largest, smallest, relative = _oscillator_peaks(padded, fn, float(fs), float(damping_ratio))
    absolute = np.maximum(largest, -smallest)
    return ShockSpectra(freq=fn, absolute_acceleration=absolute, relative_displacement=relative,
                        pseudo_velocity=2.0 * np.pi * fn * relative, damping_ratio=float(damping_ratio))
