"""Shock response spectrum (SRS) of an acceleration record.

The SRS is the peak absolute acceleration of a bank of base-excited, linear, viscously
damped SDOF oscillators, one per natural frequency, driven by the record
(ISO 18431-4:2007; Smallwood, "An improved recursive formula for calculating shock response
spectra", Shock and Vibration Bulletin 51, 1981). It complements the rest shock level of
:mod:`idkit.signal.drop` when comparing isolators on a measured shock (SPEC sections 3, 6).

Each oscillator is evaluated with Smallwood's ramp-invariant digital filter: exact at the
sample instants when the base acceleration is linear between samples. For natural
frequency ``f_n``, damping ratio ``zeta`` and sample interval ``T`` with
``A = zeta w_n T``, ``B = w_d T``, ``w_d = w_n sqrt(1 - zeta^2)``, ``E = exp(-A)``,
``S = E sin(B) / B``, ``C = E cos(B)``::

    b = [1 - S, 2 (S - C), E^2 - S],   a = [1, -2 C, E^2]

The relative displacement ``z = x - x_base`` of the same oscillators,
``Z(s) / A(s) = -1 / (s^2 + 2 zeta w_n s + w_n^2)``, is discretised the same way (first-order
hold, i.e. ramp invariance, :func:`relative_displacement_coefficients`), and gives the two
other spectra of ISO 18431-4: the **relative displacement SRS** ``max |z|`` and the
**pseudo-velocity SRS** ``w_n max |z|`` (:func:`shock_spectra`). Without damping the
absolute acceleration is ``-w_n^2 z`` exactly, so the three spectra are then one curve
scaled by ``w_n``.

The filter gives the response at the samples only, so a peak between samples is missed by
at most about ``(w_n T)^2 / 8`` relative: 4.9 % at ``fs = 10 f_n`` (the usual minimum
rate), 1.2 % at ``20 f_n``, 0.2 % at ``50 f_n``. Sample the record accordingly.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import signal as sps

from idkit.errors import DataError

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
#: the record): the simulator's own step limit (idkit.cli.options.MAX_STEPS). A natural frequency
#: of 1e-300 Hz asked for 1e305 samples and ended in numpy's "Maximum allowed dimension exceeded".
MAX_RESIDUAL_SAMPLES = 10**8


def smallwood_coefficients(
    freq: ArrayLike, *, fs: float, damping_ratio: float = 0.05
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Smallwood ramp-invariant filter coefficients for absolute acceleration response.

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


def relative_displacement_coefficients(
    freq: ArrayLike, *, fs: float, damping_ratio: float = 0.05
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Ramp-invariant filters from base acceleration to the oscillators' relative displacement.

    First-order-hold discretisation (:func:`scipy.signal.cont2discrete`, ``method="foh"``) of
    ``Z(s) / A(s) = -1 / (s^2 + 2 zeta w_n s + w_n^2)``: exact at the samples when the base
    acceleration is linear between them, like :func:`smallwood_coefficients` (which is the
    same discretisation of the absolute-acceleration transfer function).

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
    """
    fn = np.atleast_1d(np.asarray(freq, dtype=float))
    b = np.empty((fn.size, 3))
    a = np.empty((fn.size, 3))
    for index, f in enumerate(fn):
        b[index], a[index] = _foh_coefficients(float(f), float(fs), float(damping_ratio))
    return b, a


@lru_cache(maxsize=4096)
def _foh_coefficients(freq: float, fs: float, damping_ratio: float) -> tuple[tuple, tuple]:
    """One oscillator's first-order-hold filter (a matrix exponential each: cached, since the
    same natural frequencies and sample rate recur record after record)."""
    omega = 2.0 * np.pi * freq
    num, den, _ = sps.cont2discrete(([-1.0], [1.0, 2.0 * damping_ratio * omega, omega**2]), 1.0 / fs,
                                    method="foh")
    return tuple(np.ravel(num)[-3:]), tuple(den)


@dataclass(frozen=True)
class ShockSpectra:
    """The three shock response spectra of ISO 18431-4 of one acceleration record.

    Attributes
    ----------
    freq : ndarray, shape (n_freq,)
        Natural frequencies, Hz.
    absolute_acceleration : ndarray, shape (n_freq,)
        Maximax absolute acceleration of the oscillators, m/s^2 (unit of the input).
    relative_displacement : ndarray, shape (n_freq,)
        Maximax relative displacement ``max |z|``, m (input unit times s^2).
    pseudo_velocity : ndarray, shape (n_freq,)
        ``2 pi freq * relative_displacement``, m/s.
    damping_ratio : float
        Damping ratio of the oscillators.
    """

    freq: NDArray[np.float64]
    absolute_acceleration: NDArray[np.float64]
    relative_displacement: NDArray[np.float64]
    pseudo_velocity: NDArray[np.float64]
    damping_ratio: float

    def to_dataframe(self) -> pd.DataFrame:
        """One row per natural frequency, units in the column names."""
        return pd.DataFrame({
            "freq [Hz]": self.freq,
            "absolute_acceleration [m/s^2]": self.absolute_acceleration,
            "pseudo_velocity [m/s]": self.pseudo_velocity,
            "relative_displacement [m]": self.relative_displacement,
        })


@dataclass(frozen=True)
class ShockResponseSpectrum:
    """Shock response spectrum (absolute acceleration).

    Attributes
    ----------
    freq : ndarray, shape (n_freq,)
        Natural frequencies, Hz.
    positive : ndarray, shape (n_freq,)
        Largest response acceleration (signed maximum), m/s^2 (unit of the input).
    negative : ndarray, shape (n_freq,)
        Largest response acceleration in the negative direction as a magnitude,
        ``-min(response)``, m/s^2.
    maximax : ndarray, shape (n_freq,)
        ``max(|response|) = max(positive, negative)``, m/s^2.
    damping_ratio : float
        Damping ratio of the oscillators.
    """

    freq: NDArray[np.float64]
    positive: NDArray[np.float64]
    negative: NDArray[np.float64]
    maximax: NDArray[np.float64]
    damping_ratio: float

    def to_dataframe(self) -> pd.DataFrame:
        """One row per natural frequency: freq_Hz, positive, negative, maximax."""
        return pd.DataFrame(
            {
                "freq [Hz]": self.freq,
                "positive": self.positive,
                "negative": self.negative,
                "maximax": self.maximax,
            }
        )


def _checked(acceleration, fs, freq, damping_ratio, residual_duration):
    """Checked natural frequencies and the record padded with its residual window."""
    values = np.asarray(acceleration, dtype=float)
    if values.ndim != 1 or values.size < 2:
        raise DataError(f"acceleration must be 1-D with >= 2 samples; found shape {values.shape}")
    if not np.all(np.isfinite(values)):
        raise DataError("acceleration must be finite; found NaN or inf")
    if not (np.isfinite(fs) and fs > 0):
        raise DataError(f"fs must be a positive sample rate in Hz; found {fs!r}")
    fn = np.atleast_1d(np.asarray(freq, dtype=float))
    if fn.ndim != 1 or fn.size == 0 or not np.all(np.isfinite(fn) & (fn > 0) & (fn < fs / 2)):
        raise DataError(
            f"freq must be natural frequencies in (0, fs/2) = (0, {fs / 2:g}) Hz; found {fn!r}"
        )
    if not (0 <= damping_ratio < 1):
        raise DataError(f"damping_ratio must be in [0, 1); found {damping_ratio!r}")
    if residual_duration is None:
        residual_duration = 1.0 / fn.min()
    if not (np.isfinite(residual_duration) and residual_duration >= 0):
        raise DataError(f"residual_duration must be >= 0 s; found {residual_duration!r}")
    if residual_duration * fs * (1 - 1e-12) > MAX_RESIDUAL_SAMPLES:
        raise DataError(
            f"freq: the lowest natural frequency {fn.min():g} Hz needs a residual window of {residual_duration:.4g} s, "
            f"{residual_duration * fs:.4g} samples at {fs:g} Hz; expected at most {MAX_RESIDUAL_SAMPLES:.0e} "
            f"(natural frequencies >= {fs / MAX_RESIDUAL_SAMPLES:.4g} Hz, or a shorter residual_duration)"
        )
    # a window of whole samples; the small margin keeps a product like 0.1 s x 200 kHz at 20000
    padded = np.concatenate([values, np.zeros(int(np.ceil(residual_duration * fs * (1 - 1e-12))))])
    return fn, padded


def shock_response_spectrum(
    acceleration: ArrayLike,
    *,
    fs: float,
    freq: ArrayLike,
    damping_ratio: float = 0.05,
    residual_duration: float | None = None,
) -> ShockResponseSpectrum:
    """Shock response spectrum of a base acceleration record (Smallwood filter).

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
    Each oscillator is one call of :func:`scipy.signal.lfilter` (C speed); lfilter does not
    take per-row coefficients, so the bank is a loop over natural frequencies, each of cost
    O(n). The computation is ``O(n_freq * n)``.

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
    b, a = smallwood_coefficients(fn, fs=fs, damping_ratio=damping_ratio)
    positive = np.empty(fn.size)
    negative = np.empty(fn.size)
    for index in range(fn.size):
        response = sps.lfilter(b[index], a[index], padded)
        positive[index] = response.max()
        negative[index] = -response.min()
    return ShockResponseSpectrum(
        freq=fn,
        positive=positive,
        negative=negative,
        maximax=np.maximum(positive, negative),
        damping_ratio=float(damping_ratio),
    )


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
    window). The absolute acceleration is the Smallwood filter's maximax; the relative
    displacement comes from :func:`relative_displacement_coefficients`; the pseudo-velocity
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
    b_abs, a_abs = smallwood_coefficients(fn, fs=fs, damping_ratio=damping_ratio)
    b_rel, a_rel = relative_displacement_coefficients(fn, fs=fs, damping_ratio=damping_ratio)
    absolute = np.empty(fn.size)
    relative = np.empty(fn.size)
    for index in range(fn.size):
        absolute[index] = np.abs(sps.lfilter(b_abs[index], a_abs[index], padded)).max()
        relative[index] = np.abs(sps.lfilter(b_rel[index], a_rel[index], padded)).max()
    return ShockSpectra(freq=fn, absolute_acceleration=absolute, relative_displacement=relative,
                        pseudo_velocity=2.0 * np.pi * fn * relative, damping_ratio=float(damping_ratio))
