"""Random vibration: PSD profiles, random-phase synthesis, Welch estimates, RMS.

SPEC section 5 (thesis sections 2.3, 3.5 and 8.4): a floor-acceleration PSD, a flat level over
a band or a breakpoint table as test standards state them (e.g. MIL-STD-810, IEC 60068-2-64),
is turned into time signals by random phase spectra; the responses are reduced to PSDs by
Welch averaging and to RMS values; for linear systems the output PSD is ``|H|^2 S_xx``.

Units: frequency in Hz, acceleration PSD in (m/s^2)^2/Hz (one-sided), RMS in m/s^2.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import integrate
from scipy import signal as sps

from idkit.checks import Flag, Real, Reals, Samples, Seed, Whole, accepts
from idkit.errors import DataError

__all__ = [
    "PsdEstimate",
    "PsdProfile",
    "cumulative_rms",
    "output_psd",
    "rms_from_psd",
    "synthesize_random",
    "welch_psd",
    "welch_rms",
]

_DB_PER_OCTAVE_PER_EXPONENT = 10.0 * np.log10(2.0)  # 3.0103 dB/octave for S ~ f^1


#: Breakpoints and levels of a :class:`PsdProfile`.
_BREAKPOINTS = Reals(unit="Hz", gt=0, min_size=2, increasing=True)
_LEVELS = Reals(unit="(m/s^2)^2/Hz", gt=0, min_size=2, meaning="positive: log-log interpolation")


@dataclass(frozen=True)
class PsdProfile:
    """A one-sided PSD given by breakpoints, log-log interpolated between them.

    Between breakpoints ``(f_i, S_i)`` and ``(f_{i+1}, S_{i+1})`` the level is the power law
    ``S_i (f / f_i)^alpha_i`` with ``alpha_i = log(S_{i+1}/S_i) / log(f_{i+1}/f_i)``: a straight
    line on log-log axes, as test standards draw and tabulate PSD profiles. The slope in
    dB/octave is ``10 log10(2) alpha_i = 3.01 alpha_i``. Outside ``[f_0, f_last]`` the level
    is zero.

    Attributes
    ----------
    freq : ndarray, shape (n,)
        Breakpoint frequencies, Hz, strictly increasing, > 0.
    level : ndarray, shape (n,)
        PSD at the breakpoints, (m/s^2)^2/Hz, > 0.

    Examples
    --------
    >>> profile = PsdProfile([10.0, 100.0], [1e-3, 1e-2])
    >>> round(float(profile(31.6227766)), 12)
    0.00316227766
    """

    freq: NDArray[np.float64]
    level: NDArray[np.float64]

    def __post_init__(self) -> None:
        freq = _BREAKPOINTS.check(self.freq, "freq", DataError)
        level = _LEVELS.check(self.level, "level", DataError)
        if freq.shape != level.shape:
            raise DataError(f"freq, level: found shapes {freq.shape} and {level.shape}, expected one length")
        object.__setattr__(self, "freq", np.array(freq))
        object.__setattr__(self, "level", np.array(level))

    @classmethod
    def flat(cls, level: float, *, f_lo: float, f_hi: float) -> PsdProfile:
        """A flat level over ``[f_lo, f_hi]`` Hz, (m/s^2)^2/Hz (SPEC 5: 1e-8 ... 1e-2 over
        0.1-100 Hz)."""
        return cls(np.array([f_lo, f_hi], dtype=float), np.array([level, level], dtype=float))

    @classmethod
    @accepts(freq=Reals(unit="Hz", gt=0), start_level=Real(unit="(m/s^2)^2/Hz", gt=0),
             slopes_db_per_octave=Reals(unit="dB/octave", min_size=0), error=DataError)
    def from_slopes(
        cls, freq: ArrayLike, *, start_level: float, slopes_db_per_octave: ArrayLike
    ) -> PsdProfile:
        """Breakpoints from a start level and the slope of each segment in dB/octave.

        Parameters
        ----------
        freq : array_like, shape (n,)
            Breakpoint frequencies, Hz.
        start_level : float
            Level at ``freq[0]``, (m/s^2)^2/Hz.
        slopes_db_per_octave : array_like, shape (n - 1,)
            Slope of each segment, dB/octave (0 = flat; +3 dB/octave ~ S proportional to f).

        Examples
        --------
        >>> profile = PsdProfile.from_slopes([20.0, 40.0], start_level=1e-3,
        ...                                  slopes_db_per_octave=[3.0103])
        >>> round(float(profile.level[1]), 6)
        0.002
        """
        slopes = slopes_db_per_octave
        if slopes.shape != (freq.size - 1,):
            raise DataError(
                f"slopes_db_per_octave has shape {slopes.shape}; expected ({freq.size - 1},), "
                "one per segment"
            )
        octaves = np.log2(freq[1:] / freq[:-1])
        gains_db = np.concatenate([[0.0], np.cumsum(slopes * octaves)])
        return cls(freq, start_level * 10.0 ** (gains_db / 10.0))

    @property
    def exponents(self) -> NDArray[np.float64]:
        """Power-law exponent ``alpha_i`` of each segment (``S ~ f^alpha``)."""
        return np.log(self.level[1:] / self.level[:-1]) / np.log(self.freq[1:] / self.freq[:-1])

    @property
    def slopes_db_per_octave(self) -> NDArray[np.float64]:
        """Slope of each segment, dB/octave."""
        return _DB_PER_OCTAVE_PER_EXPONENT * self.exponents

    def __call__(self, freq: ArrayLike) -> NDArray[np.float64]:
        """PSD level at ``freq`` (Hz), (m/s^2)^2/Hz; zero outside the breakpoint range."""
        f = np.asarray(freq, dtype=float)
        inside = (f >= self.freq[0]) & (f <= self.freq[-1])
        log_f = np.log(np.where(inside, f, self.freq[0]))
        value = np.exp(np.interp(log_f, np.log(self.freq), np.log(self.level)))
        return np.where(inside, value, 0.0)

    def mean_square(self) -> float:
        """Exact integral of the profile over its band, (m/s^2)^2 (power law per segment)."""
        f1, f2 = self.freq[:-1], self.freq[1:]
        s1 = self.level[:-1]
        alpha = self.exponents
        ratio = f2 / f1
        with np.errstate(divide="ignore", invalid="ignore"):
            general = s1 * f1 / (alpha + 1.0) * (ratio ** (alpha + 1.0) - 1.0)
        logarithmic = s1 * f1 * np.log(ratio)  # alpha = -1
        return float(np.sum(np.where(np.isclose(alpha, -1.0), logarithmic, general)))

    def rms(self) -> float:
        """RMS over the band, m/s^2 (square root of :meth:`mean_square`)."""
        return float(np.sqrt(self.mean_square()))

    def to_dataframe(self) -> pd.DataFrame:
        """Breakpoint table: ``freq [Hz]``, ``level``, ``slope [dB/octave]`` of the segment starting there."""
        slopes = np.append(self.slopes_db_per_octave, np.nan)
        return pd.DataFrame(
            {"freq [Hz]": self.freq, "level": self.level, "slope [dB/octave]": slopes}
        )


@accepts(seed=Seed(), fs=Real(unit="Hz", gt=0), freq_step=Real(unit="Hz", gt=0),
         n_realizations=Whole(ge=1), error=DataError)
def synthesize_random(
    psd: Callable[[NDArray[np.float64]], ArrayLike],
    *,
    seed: int | np.random.SeedSequence | np.random.Generator,
    fs: float = 800.0,
    freq_step: float = 0.05,
    n_realizations: int = 30,
) -> NDArray[np.float64]:
    """Real time signals with a prescribed one-sided PSD, by random phases.

    On the grid ``f_k = k freq_step``, ``k = 0 .. n/2`` with ``n = fs / freq_step`` samples
    (duration ``1 / freq_step``: 20 s with the defaults of SPEC section 5), each line gets
    the deterministic amplitude ``A_k = sqrt(2 S(f_k) freq_step)`` and a phase drawn
    uniformly in [0, 2 pi) from ``numpy.random.default_rng(seed)``. The half spectrum
    ``(n / 2) A_k exp(i phi_k)`` is completed conjugate-symmetrically by
    :func:`numpy.fft.irfft`, giving ``x(t) = sum_k A_k cos(2 pi f_k t + phi_k)``, periodic over
    the record. The DC and Nyquist lines are set to zero. By Parseval the mean square of
    every realization is exactly ``sum_k S(f_k) freq_step`` (the rectangle rule of the PSD
    integral on the grid, which differs from the exact integral only by the band-edge
    lines).

    Parameters
    ----------
    psd : callable
        One-sided PSD, ``psd(freq_Hz) -> level`` in (m/s^2)^2/Hz, vectorized (e.g. a
        :class:`PsdProfile`), sampled on the grid up to ``fs / 2``. A :class:`PsdProfile`
        reaching above ``fs / 2`` is refused (its band would be cut off); a general
        callable is read up to ``fs / 2`` only.
    seed : int, SeedSequence or Generator
        Seed of the phase generator (required: results must be reproducible).
    fs : float, default 800.0
        Sample rate, Hz.
    freq_step : float, default 0.05
        Frequency step, Hz; ``fs / freq_step`` must be an integer.
    n_realizations : int, default 30
        Number of independent realizations.

    Returns
    -------
    ndarray, shape (n_realizations, n_samples)
        Realizations (unit: square root of the PSD unit times Hz, m/s^2); sample ``j`` is at
        time ``j / fs``.

    Examples
    --------
    >>> signals = synthesize_random(PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0), seed=1)
    >>> signals.shape
    (30, 16000)
    """
    ratio = fs / freq_step
    n_samples = int(round(ratio))
    if abs(ratio - n_samples) > 1e-9 * ratio or n_samples < 4:
        raise DataError(
            f"fs / freq_step must be an integer number of samples >= 4; found {fs:g} / "
            f"{freq_step:g} = {ratio:.6g}"
        )
    if not callable(psd):
        raise DataError(f"psd: found {type(psd).__name__}, expected a callable psd(freq_Hz) such as a PsdProfile")
    if isinstance(psd, PsdProfile) and psd.freq[-1] > fs / 2:
        raise DataError(
            f"psd: found a profile reaching {psd.freq[-1]:g} Hz, expected none above the Nyquist "
            f"frequency fs / 2 = {fs / 2:g} Hz of the synthesized signals (its band above would be "
            "cut off); raise fs or end the profile lower")
    grid = np.arange(n_samples // 2 + 1) * freq_step
    level = np.asarray(psd(grid), dtype=float)
    if level.shape != grid.shape or not np.all(np.isfinite(level) & (level >= 0)):
        raise DataError(
            "psd(freq) must return finite levels >= 0 of the same shape as freq; found "
            f"shape {level.shape}"
        )
    amplitude = np.sqrt(2.0 * level * freq_step)
    amplitude[0] = 0.0
    if n_samples % 2 == 0:
        amplitude[-1] = 0.0
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0.0, 2.0 * np.pi, size=(int(n_realizations), grid.size))
    spectrum = (n_samples / 2.0) * amplitude * np.exp(1j * phase)
    return np.fft.irfft(spectrum, n=n_samples, axis=-1)


@dataclass(frozen=True)
class PsdEstimate:
    """Welch PSD averaged over segments and realizations.

    Attributes
    ----------
    freq : ndarray, shape (n_freq,)
        Frequencies, Hz.
    psd : ndarray, shape (n_freq,)
        One-sided PSD, (unit)^2/Hz; ``(n_realizations, n_freq)`` from ``welch_psd(average=False)``.
    n_segments : int
        Segments per realization.
    n_realizations : int
        Realizations averaged.
    nperseg, noverlap : int
        Segment length and overlap, samples.
    """

    freq: NDArray[np.float64]
    psd: NDArray[np.float64]
    n_segments: int
    n_realizations: int
    nperseg: int
    noverlap: int

    def to_dataframe(self) -> pd.DataFrame:
        """One row per frequency: ``freq [Hz]``, ``psd``."""
        return pd.DataFrame({"freq [Hz]": self.freq, "psd": self.psd})


@accepts(signals=Samples(ndim=(1, 2), min_size=8), fs=Real(unit="Hz", gt=0),
         nperseg=Whole(ge=2, optional=True), overlap=Real(ge=0, lt=1), average=Flag(), error=DataError)
def welch_psd(
    signals: ArrayLike,
    *,
    fs: float,
    nperseg: int | None = None,
    overlap: float = 2.0 / 3.0,
    average: bool = True,
) -> PsdEstimate:
    """Welch PSD of one or several realizations, averaged over all of them (or each its own).

    Hann window, ``noverlap = round(overlap * nperseg)`` (2/3 by default, SPEC section 5),
    segment means removed (``detrend="constant"``), one-sided density.

    Parameters
    ----------
    signals : array_like, shape (n_samples,) or (n_realizations, n_samples)
        Time signals sampled at ``fs``.
    fs : float
        Sample rate, Hz.
    nperseg : int, optional
        Segment length in samples. Default: the largest multiple of 3 not above
        ``n_samples / 8`` (so that 2/3 overlap is exact): about 22 segments per realization,
        resolution ``fs / nperseg`` (0.40 Hz for 20 s at 800 Hz).
    overlap : float, default 2/3
        Overlap fraction in [0, 1).
    average : bool, default True
        False: ``psd`` has one row per realization, ``(n_realizations, n_freq)`` (many
        independent signals estimated in one call).

    Returns
    -------
    PsdEstimate

    Examples
    --------
    >>> signals = synthesize_random(PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0), seed=1)
    >>> estimate = welch_psd(signals, fs=800.0)
    >>> estimate.nperseg, estimate.n_segments
    (1998, 22)
    """
    values = signals if signals.ndim == 2 else signals[None, :]
    n_samples = values.shape[1]
    if nperseg is None:
        nperseg = max(3 * (n_samples // 24), 3)
    if nperseg > n_samples:
        raise DataError(f"nperseg: found {nperseg}, expected at most the record length {n_samples}")
    noverlap = int(round(overlap * nperseg))
    freq, density = sps.welch(
        values, fs=fs, window="hann", nperseg=nperseg, noverlap=noverlap, detrend="constant",
        axis=-1,
    )
    return PsdEstimate(
        freq=freq,
        psd=density.mean(axis=0) if average else density,
        n_segments=int((n_samples - noverlap) // (nperseg - noverlap)),
        n_realizations=int(values.shape[0]),
        nperseg=nperseg,
        noverlap=noverlap,
    )


@accepts(signals=Samples(ndim=(1, 2), min_size=8), fs=Real(unit="Hz", gt=0), nperseg=Whole(ge=2),
         overlap=Real(ge=0, lt=1), error=DataError)
def welch_rms(signals: ArrayLike, *, fs: float, nperseg: int, overlap: float = 2.0 / 3.0) -> NDArray[np.float64]:
    """RMS of each realization's Welch PSD, without forming the spectrum.

    What :func:`rms_from_psd` gives of each row of ``welch_psd(signals, fs=fs, nperseg=nperseg,
    overlap=overlap, average=False).psd`` (the trapezoidal rule over every bin, DC to the last
    one), to round-off, from Parseval's theorem: a segment's one-sided density sums to
    ``sum v^2 / (fs sum w^2)`` per bin width ``fs / nperseg`` (``v`` the windowed segment less its
    mean, ``w`` the Hann window), and the trapezoidal rule takes away half of the first and last
    bins' values, which are single DFT terms: ``|V_0|^2`` and ``|V_H|^2`` (``H = nperseg // 2``; the
    last bin counts twice for an odd ``nperseg``, whose one-sided spectrum doubles it). The
    segments' values are averaged as :func:`welch_psd` averages their densities.

    Returns
    -------
    ndarray, shape (n_realizations,)
        RMS in the unit of the signals (a 1-D signal is one realization).
    """
    values = signals if signals.ndim == 2 else signals[None, :]
    n_samples = values.shape[1]
    if nperseg > n_samples:
        raise DataError(f"nperseg: found {nperseg}, expected at most the record length {n_samples}")
    noverlap = int(round(overlap * nperseg))
    n_segments = (n_samples - noverlap) // (nperseg - noverlap)
    window = sps.get_window("hann", nperseg)  # what welch_psd's window="hann" takes
    half = nperseg // 2
    # the DFT terms of the first and last bins: sums against these rows (DC; Nyquist, or the last bin)
    if nperseg % 2 == 0:
        ends = np.vstack([np.ones(nperseg), np.where(np.arange(nperseg) % 2 == 0, 1.0, -1.0)])
    else:
        ends = np.vstack([np.ones(nperseg), np.exp(-2j * np.pi * half * np.arange(nperseg) / nperseg)])
    # the end bins' shares: half of each, and the last bin twice for an odd nperseg
    shares = np.array([0.5, 0.5 if nperseg % 2 == 0 else 1.0])
    power = np.zeros(values.shape[0])
    for start in range(0, n_segments * (nperseg - noverlap), nperseg - noverlap):
        segment = values[:, start:start + nperseg]
        windowed = (segment - segment.mean(axis=1, keepdims=True)) * window
        terms = np.abs(windowed @ ends.T) ** 2
        power += np.einsum("rn,rn->r", windowed, windowed) - terms @ shares / nperseg
    power /= n_segments * np.sum(window**2)
    return np.sqrt(power)


#: The contract of a one-sided spectrum: frequencies (Hz) and levels (unit^2/Hz) of one length.
_SPECTRUM = dict(freq=Reals(unit="Hz", min_size=2, increasing=True),
                 psd=Reals(unit="unit^2/Hz", ge=0, meaning="a power spectral density"), error=DataError)


def _paired(f: NDArray, s: NDArray) -> tuple[NDArray, NDArray]:
    if s.shape != f.shape:
        raise DataError(f"freq, psd: found shapes {f.shape} and {s.shape}, expected one length")
    return f, s


@accepts(**_SPECTRUM)
def rms_from_psd(freq: ArrayLike, psd: ArrayLike) -> float:
    """RMS from a one-sided PSD by the trapezoidal rule, ``sqrt(int S df)``.

    Parameters
    ----------
    freq : array_like, shape (n,)
        Frequencies, Hz, increasing.
    psd : array_like, shape (n,)
        One-sided PSD, (unit)^2/Hz, e.g. (m/s^2)^2/Hz.

    Returns
    -------
    float
        RMS in the unit of the signal, e.g. m/s^2.

    Examples
    --------
    >>> round(rms_from_psd([0.0, 100.0], [1e-2, 1e-2]), 6)
    1.0
    """
    f, s = _paired(freq, psd)
    return float(np.sqrt(integrate.trapezoid(s, f)))


@accepts(**_SPECTRUM)
def cumulative_rms(freq: ArrayLike, psd: ArrayLike) -> NDArray[np.float64]:
    """Cumulative RMS ``sqrt(int_{f_0}^{f} S df)`` at every frequency (trapezoidal rule).

    Parameters
    ----------
    freq : array_like, shape (n,)
        Frequencies, Hz, increasing.
    psd : array_like, shape (n,)
        One-sided PSD, (unit)^2/Hz.

    Returns
    -------
    ndarray, shape (n,)
        Cumulative RMS (unit of the signal), 0 at ``freq[0]``, :func:`rms_from_psd` at the end.
    """
    f, s = _paired(freq, psd)
    return np.sqrt(integrate.cumulative_trapezoid(s, f, initial=0.0))


def output_psd(frequency_response: ArrayLike, input_psd: ArrayLike) -> NDArray[np.float64]:
    """Output PSD of a linear system, ``S_yy = |H|^2 S_xx`` (SPEC section 5).

    Parameters
    ----------
    frequency_response : array_like, complex
        ``H`` at the PSD frequencies (e.g. the transmissibility, dimensionless).
    input_psd : array_like
        Input PSD ``S_xx`` at the same frequencies, e.g. (m/s^2)^2/Hz.

    Returns
    -------
    ndarray
        ``S_yy`` in the output unit squared per Hz.
    """
    h = np.asarray(frequency_response)
    s = np.asarray(input_psd, dtype=float)
    if h.shape != s.shape:
        raise DataError(
            f"frequency_response has shape {h.shape}; expected the shape of input_psd {s.shape}"
        )
    return np.abs(h) ** 2 * s
