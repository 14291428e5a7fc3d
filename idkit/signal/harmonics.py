"""Stepped-sine processing: harmonics, subharmonic, bias and HOSIDFs by least squares.

At each (frequency, amplitude) point of a stepped-sine test or simulation (SPEC sections 3
and 5, thesis sections 3.4 and 6.2) the base and top-mass velocities are reduced to

- the complex amplitudes of the harmonics ``k = 1..K`` of the excitation frequency,
- the complex amplitude of the 1/2 subharmonic (period doubling, thesis fig. 3.17-3.19),
- the bias (mean),

by linear least squares over an integer number of excitation periods, and the
higher-order sinusoidal input describing functions (HOSIDF) are formed as the k-th harmonic
of the response over the **first** harmonic of the input (the shaker input is not a pure sine,
SPEC section 3). The input distortion (2nd and 3rd harmonic over the first) and the
non-flat input amplitude over a sweep are reported too.

The peak of a response: :func:`resonance_peak` on sampled values (a stepped-sine sweep, a
harmonic map), :func:`search_resonance` on a magnitude that can be evaluated anywhere (a
model's small-amplitude transmissibility).

Complex amplitude convention: a signal is modelled as
``s(t) = bias + sum_k Re(C_k exp(i k omega t)) + Re(C_sub exp(i omega t / 2))`` with
``omega = 2 pi freq`` and ``t = n / fs`` the time of sample ``n`` counted from the **first
sample of the record** (not of the analysed window), so phases do not depend on how much
of the record was trimmed. ``|C_k|`` is the amplitude (peak, not RMS) and ``angle(C_k)`` the
phase of the cosine.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import optimize

from idkit.checks import Choice, Flag, Real, Reals, Samples, Whole, accepts, unchecked
from idkit.errors import DataError, ParameterError

__all__ = [
    "HarmonicFit",
    "HosidfResult",
    "InputFlatness",
    "fit_harmonics",
    "hosidf",
    "resonance_peak",
    "ResonanceSearch",
    "resonance_grid_maxima",
    "search_resonance",
    "input_flatness",
]

#: The contract of the analysis window and the fit's orders, shared by :func:`fit_harmonics` and
#: :func:`hosidf` (which analyses both its signals over one window).
_WINDOW_ARGUMENTS = dict(fs=Real(unit="Hz", gt=0), freq=Real(unit="Hz", gt=0), n_harmonics=Whole(ge=1),
                         n_periods=Whole(ge=1, optional=True), subharmonic=Flag(), align=Choice(("end", "start")),
                         error=DataError)


@dataclass(frozen=True)
class HarmonicFit:
    """Least-squares harmonic decomposition of one signal.

    Attributes
    ----------
    freq : float
        Excitation frequency, Hz.
    fs : float
        Sample rate, Hz.
    coefficients : ndarray of complex, shape (n_harmonics,)
        Complex amplitudes ``C_1..C_K`` (unit of the signal; peak amplitude and cosine phase).
    subharmonic : complex
        Complex amplitude of the 1/2 subharmonic, or ``nan`` when not fitted.
    bias : float
        Mean value (unit of the signal).
    n_periods : int
        Number of whole excitation periods analysed.
    n_samples : int
        Number of samples analysed (``floor(n_periods * fs / freq)``, see :func:`fit_harmonics`).
    first_sample : int
        Index in the record of the first analysed sample.
    residual_rms : float
        RMS of the least-squares residual (unit of the signal).
    standard_error : float
        Approximate standard error of the real and imaginary part of each coefficient,
        ``residual_rms * sqrt(2 / n_samples)`` (white residual, nearly orthogonal basis).
    """

    freq: float
    fs: float
    coefficients: NDArray[np.complex128]
    subharmonic: complex
    bias: float
    n_periods: int
    n_samples: int
    first_sample: int
    residual_rms: float
    standard_error: float

    @property
    def amplitude(self) -> NDArray[np.float64]:
        """Peak amplitudes ``|C_k|`` of harmonics 1..K (unit of the signal)."""
        return np.abs(self.coefficients)

    @property
    def phase(self) -> NDArray[np.float64]:
        """Phases ``angle(C_k)`` of harmonics 1..K, rad."""
        return np.angle(self.coefficients)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per component: order (0 = bias, 0.5 = subharmonic, 1..K), complex value,
        amplitude and phase (rad)."""
        orders = np.concatenate([[0.0, 0.5], np.arange(1, self.coefficients.size + 1)])
        values = np.concatenate([[self.bias, self.subharmonic], self.coefficients]).astype(complex)
        return pd.DataFrame(
            {
                "order": orders,
                "value": values,
                "amplitude": np.abs(values),
                "phase [rad]": np.angle(values),
            }
        )


def _analysis_window(
    n_total: int,
    *,
    fs: float,
    freq: float,
    n_periods: int | None,
    even_periods: bool,
    align: str,
) -> tuple[int, int, int]:
    """Return (first_sample, n_samples, n_periods) of the analysed window."""
    samples_per_period = fs / freq
    available = int(np.floor(n_total / samples_per_period * (1 + 1e-12)))
    if n_periods is None:
        periods = available - (available % 2 if even_periods else 0)
    else:
        periods = n_periods
        if even_periods and periods % 2:
            raise DataError(
                f"n_periods={periods} is odd; the 1/2 subharmonic needs an even number of "
                "periods (or pass subharmonic=False)"
            )
        if periods > available:
            raise DataError(
                f"n_periods={periods} does not fit: the record of {n_total} samples at "
                f"fs={fs:g} Hz holds {available} periods of {freq:g} Hz"
            )
    minimum = 2 if even_periods else 1
    if periods < minimum:
        raise DataError(
            f"the record of {n_total} samples at fs={fs:g} Hz holds {available} whole periods "
            f"of {freq:g} Hz; at least {minimum} are needed"
        )
    n_samples = int(np.floor(periods * samples_per_period * (1 + 1e-12)))
    first = n_total - n_samples if align == "end" else 0
    return first, n_samples, periods


@accepts(signal=Samples(), **_WINDOW_ARGUMENTS)
def fit_harmonics(
    signal: ArrayLike,
    *,
    fs: float,
    freq: float,
    n_harmonics: int = 5,
    n_periods: int | None = None,
    subharmonic: bool = True,
    align: Literal["end", "start"] = "end",
) -> HarmonicFit:
    """Fit bias, harmonics 1..K and the 1/2 subharmonic of a periodic signal by least squares.

    Window: an integer number of excitation periods is analysed, by default the largest that
    fits (the largest **even** number when ``subharmonic`` is true, so that the subharmonic
    completes whole periods too). When the record is not an integer number of periods it is
    trimmed to ``n_samples = floor(n_periods * fs / freq)`` samples, taken from the **end** of
    the record by default (the most settled part of a stepped-sine step or a simulation run to
    steady state) or from its start; ``n_samples``, ``first_sample`` and ``n_periods`` are
    reported. If ``fs / freq`` is not an integer the window misses a fraction of a sample of
    being whole periods; the least-squares fit stays exact for a noiseless periodic signal,
    only the basis is then marginally non-orthogonal.

    Parameters
    ----------
    signal : array_like, shape (n,)
        Uniformly sampled signal (any unit, e.g. m/s).
    fs : float
        Sample rate, Hz.
    freq : float
        Excitation frequency, Hz; ``n_harmonics * freq`` must stay below ``fs / 2``.
    n_harmonics : int, default 5
        Number K of harmonics fitted (orders 1..K).
    n_periods : int, optional
        Number of whole periods to analyse; default the largest that fits.
    subharmonic : bool, default True
        Fit the 1/2 subharmonic as well (needs an even number of periods).
    align : {"end", "start"}, default "end"
        Take the analysed window from the end or the start of the record.

    Returns
    -------
    HarmonicFit
        Complex amplitudes, bias, window and residual statistics.

    Raises
    ------
    DataError
        Bad sizes or options, too short a record, harmonics above the Nyquist frequency.

    Examples
    --------
    >>> import numpy as np
    >>> fs, f = 1000.0, 10.0
    >>> t = np.arange(1000) / fs
    >>> fit = fit_harmonics(0.1 + 2 * np.cos(2 * np.pi * f * t - 0.3), fs=fs, freq=f)
    >>> round(float(fit.amplitude[0]), 9), round(float(fit.phase[0]), 9), round(fit.bias, 9)
    (2.0, -0.3, 0.1)
    """
    values = signal
    if n_harmonics * freq >= fs / 2:
        raise DataError(f"n_harmonics, freq: found harmonic {n_harmonics} of {freq:g} Hz, expected one below the "
                        f"Nyquist frequency {fs / 2:g} Hz (lower n_harmonics or raise fs)")
    first, n_samples, periods = _analysis_window(
        values.size, fs=fs, freq=freq, n_periods=n_periods, even_periods=subharmonic, align=align
    )
    window = values[first : first + n_samples]
    # Phase argument omega*t reduced modulo one subharmonic period (4 pi) to keep cos/sin
    # accurate for late windows; exact because every column is periodic in it.
    sample = np.arange(first, first + n_samples)
    half_phase = np.mod(np.pi * freq * sample / fs, 2 * np.pi)  # (omega/2) t, wrapped
    columns = [np.ones(n_samples)]
    orders = np.arange(1, n_harmonics + 1)
    angles = 2.0 * orders[:, None] * half_phase[None, :]
    columns.extend(np.cos(angles))
    columns.extend(np.sin(angles))
    if subharmonic:
        columns.append(np.cos(half_phase))
        columns.append(np.sin(half_phase))
    design = np.column_stack(columns)
    solution, *_ = np.linalg.lstsq(design, window, rcond=None)
    residual = window - design @ solution
    cosine = solution[1 : 1 + n_harmonics]
    sine = solution[1 + n_harmonics : 1 + 2 * n_harmonics]
    # a cos + b sin = Re((a - i b) exp(i angle))
    coefficients = cosine - 1j * sine
    sub = complex(solution[-2] - 1j * solution[-1]) if subharmonic else complex(np.nan, np.nan)
    n_parameters = design.shape[1]
    dof = max(n_samples - n_parameters, 1)
    residual_rms = float(np.sqrt(residual @ residual / dof))
    return HarmonicFit(
        freq=float(freq),
        fs=float(fs),
        coefficients=coefficients,
        subharmonic=sub,
        bias=float(solution[0]),
        n_periods=periods,
        n_samples=n_samples,
        first_sample=first,
        residual_rms=residual_rms,
        standard_error=residual_rms * float(np.sqrt(2.0 / n_samples)),
    )


@dataclass(frozen=True)
class HosidfResult:
    """HOSIDFs of one stepped-sine point: response harmonics over the input's first harmonic.

    Attributes
    ----------
    freq : float
        Excitation frequency, Hz.
    input : HarmonicFit
        Decomposition of the input (base) signal.
    output : HarmonicFit
        Decomposition of the output (top-mass) signal.
    hosidf : ndarray of complex, shape (n_harmonics,)
        ``C_k(output) / C_1(input)``, k = 1..K (dimensionless for like signals).
    subharmonic : complex
        ``C_1/2(output) / C_1(input)`` (``nan`` when not fitted).
    bias : float
        ``bias(output) / |C_1(input)|``.
    input_distortion : ndarray, shape (2,)
        ``|C_2(input)| / |C_1(input)|`` and ``|C_3(input)| / |C_1(input)|``.
    output_half_range : float
        Half the peak-to-peak output over the analysed window (unit of the output).
    """

    freq: float
    input: HarmonicFit
    output: HarmonicFit
    hosidf: NDArray[np.complex128]
    subharmonic: complex
    bias: float
    input_distortion: NDArray[np.float64]
    output_half_range: float

    @property
    def input_amplitude(self) -> float:
        """First-harmonic amplitude ``|C_1|`` of the input (unit of the input)."""
        return float(np.abs(self.input.coefficients[0]))

    def to_dataframe(self) -> pd.DataFrame:
        """One row per order (0 = bias, 0.5 = subharmonic, 1..K): complex ratio,
        magnitude, phase (rad)."""
        orders = np.concatenate([[0.0, 0.5], np.arange(1, self.hosidf.size + 1)])
        values = np.concatenate([[self.bias, self.subharmonic], self.hosidf]).astype(complex)
        return pd.DataFrame(
            {
                "freq [Hz]": self.freq,
                "order": orders,
                "value": values,
                "magnitude": np.abs(values),
                "phase [rad]": np.angle(values),
            }
        )


@accepts(base=Samples(), top=Samples(), **_WINDOW_ARGUMENTS)
def hosidf(
    base: ArrayLike,
    top: ArrayLike,
    *,
    fs: float,
    freq: float,
    n_harmonics: int = 5,
    n_periods: int | None = None,
    subharmonic: bool = True,
    align: Literal["end", "start"] = "end",
) -> HosidfResult:
    """Higher-order sinusoidal input describing functions of one stepped-sine point.

    Both signals are decomposed over the same window by :func:`fit_harmonics`; the k-th
    HOSIDF is the k-th harmonic of the output over the **first** harmonic of the input
    (SPEC section 5, thesis section 6.2), so a distorted input (SPEC section 3: 2nd/3rd
    harmonics about two decades below the first) is reported, not corrected. The input is
    fitted with at least 3 harmonics so that its distortion is always available.

    Parameters
    ----------
    base : array_like, shape (n,)
        Input signal, e.g. base velocity v_b in m/s.
    top : array_like, shape (n,)
        Output signal, e.g. top-mass velocity v_m in m/s (same sampling as ``base``).
    fs : float
        Sample rate, Hz.
    freq : float
        Excitation frequency, Hz.
    n_harmonics : int, default 5
        Number K of output harmonics.
    n_periods : int, optional
        Whole periods analysed (default: largest that fits, even with ``subharmonic``).
    subharmonic : bool, default True
        Fit the 1/2 subharmonic.
    align : {"end", "start"}, default "end"
        Window at the end (steady state) or the start of the records.

    Returns
    -------
    HosidfResult

    Raises
    ------
    DataError
        Mismatched lengths, zero input first harmonic, and the errors of :func:`fit_harmonics`.

    Examples
    --------
    >>> import numpy as np
    >>> fs, f = 1000.0, 10.0
    >>> t = np.arange(2000) / fs
    >>> vb = np.cos(2 * np.pi * f * t)
    >>> vm = 0.5 * np.cos(2 * np.pi * f * t - 1.0) + 0.1 * np.cos(4 * np.pi * f * t)
    >>> result = hosidf(vb, vm, fs=fs, freq=f, n_harmonics=2)
    >>> np.round(np.abs(result.hosidf), 9).tolist()
    [0.5, 0.1]
    """
    base_values, top_values = base, top
    if base_values.shape != top_values.shape:
        raise DataError(
            f"top has shape {top_values.shape}; expected the shape of base {base_values.shape}"
        )
    options = dict(fs=fs, freq=freq, n_periods=n_periods, subharmonic=subharmonic, align=align)
    input_harmonics = max(n_harmonics, 3)
    if input_harmonics * freq >= fs / 2:
        input_harmonics = n_harmonics  # distortion orders above Nyquist: not available
    fit = unchecked(fit_harmonics)
    input_fit = fit(base_values, n_harmonics=input_harmonics, **options)
    output_fit = fit(top_values, n_harmonics=n_harmonics, **options)
    first = input_fit.coefficients[0]
    if abs(first) == 0:
        raise DataError("base has a zero first harmonic; the HOSIDF is undefined")
    distortion = np.full(2, np.nan)
    available = input_fit.amplitude[1:3] / abs(first)
    distortion[: available.size] = available
    window = top_values[output_fit.first_sample : output_fit.first_sample + output_fit.n_samples]
    return HosidfResult(
        freq=float(freq),
        input=input_fit,
        output=output_fit,
        hosidf=output_fit.coefficients / first,
        subharmonic=output_fit.subharmonic / first,
        bias=output_fit.bias / abs(first),
        input_distortion=distortion,
        output_half_range=float(0.5 * (window.max() - window.min())),
    )


@dataclass(frozen=True)
class InputFlatness:
    """First-harmonic input amplitude across a frequency sweep.

    Attributes
    ----------
    freq : ndarray, shape (n,)
        Excitation frequencies, Hz (in the order given).
    amplitude : ndarray, shape (n,)
        First-harmonic input amplitudes (unit of the input, e.g. m/s).
    ratio : float
        ``max(amplitude) / min(amplitude)`` (1 for a flat sweep).
    ratio_db : float
        ``20 log10(ratio)``, dB.
    freq_of_max, freq_of_min : float
        Frequencies of the largest and smallest amplitude, Hz.
    """

    freq: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    ratio: float
    ratio_db: float
    freq_of_max: float
    freq_of_min: float

    def to_dataframe(self) -> pd.DataFrame:
        """One row per sweep point: ``freq [Hz]``, ``amplitude``, ``relative_to_max`` (amplitude over the largest)."""
        return pd.DataFrame(
            {
                "freq [Hz]": self.freq,
                "amplitude": self.amplitude,
                "relative_to_max": self.amplitude / self.amplitude.max(),
            }
        )


def input_flatness(
    freq: ArrayLike | Sequence[float], amplitude: ArrayLike | Sequence[HosidfResult]
) -> InputFlatness:
    """Quantify how far the input amplitude of a sweep is from flat.

    The shaker of SPEC section 3 does not keep the base amplitude constant over frequency;
    this reports the first-harmonic amplitude versus frequency and its max/min ratio.

    Parameters
    ----------
    freq : array_like, shape (n,)
        Excitation frequencies, Hz.
    amplitude : array_like, shape (n,), or sequence of HosidfResult
        First-harmonic input amplitudes (complex values are reduced to their modulus), or
        the :class:`HosidfResult` of each sweep point (their ``input_amplitude`` is used).

    Returns
    -------
    InputFlatness

    Raises
    ------
    DataError
        Mismatched lengths, empty sweep, non-positive amplitudes.

    Examples
    --------
    >>> flat = input_flatness([10.0, 20.0, 40.0], [0.010, 0.012, 0.008])
    >>> round(flat.ratio, 6), flat.freq_of_min
    (1.5, 40.0)
    """
    if isinstance(amplitude, Sequence) and amplitude and isinstance(amplitude[0], HosidfResult):
        values = np.array([point.input_amplitude for point in amplitude])
    else:
        values = np.abs(np.asarray(amplitude))
    freq_values = np.asarray(freq, dtype=float)
    if values.ndim != 1 or values.shape != freq_values.shape or values.size == 0:
        raise DataError(
            f"amplitude has shape {values.shape}; expected a non-empty 1-D array like freq "
            f"{freq_values.shape}"
        )
    if not np.all(np.isfinite(values) & (values > 0)):
        raise DataError("amplitude must be finite and positive at every sweep point")
    ratio = float(values.max() / values.min())
    return InputFlatness(
        freq=freq_values,
        amplitude=values.astype(float),
        ratio=ratio,
        ratio_db=float(20 * np.log10(ratio)),
        freq_of_max=float(freq_values[np.argmax(values)]),
        freq_of_min=float(freq_values[np.argmin(values)]),
    )


@accepts(freq=Reals(unit="Hz", gt=0), magnitude=Samples(finite=False), error=DataError)
def resonance_peak(freq, magnitude) -> tuple[float, float]:
    """Frequency and height of the largest ``magnitude`` over ``freq``.

    A parabola in (log f, log |H|) through the highest point and its two neighbours
    refines both when the peak lies inside the range (the grid maximum otherwise). NaN
    values (e.g. points a simulation could not settle) are skipped, never taken for the
    peak; ``(nan, nan)`` when every value is NaN. A parabola through a NaN or non-positive
    neighbour is not drawn.
    """
    if freq.shape != magnitude.shape:
        raise DataError(f"freq, magnitude: found shapes {freq.shape} and {magnitude.shape}, expected two "
                        "1-D arrays of one length")
    if np.all(np.isnan(magnitude)):
        return float("nan"), float("nan")
    order = np.argsort(freq)
    freq, magnitude = freq[order], magnitude[order]
    index = int(np.nanargmax(magnitude))  # argmax takes a NaN for the largest value
    neighbours = magnitude[max(index - 1, 0):index + 2]
    if 0 < index < freq.size - 1 and np.all(np.isfinite(neighbours) & (neighbours > 0)):
        x = np.log(freq[index - 1 : index + 2])
        y = np.log(magnitude[index - 1 : index + 2])
        coefficients = np.polyfit(x, y, 2)
        if coefficients[0] < 0:
            vertex = -coefficients[1] / (2 * coefficients[0])
            if x[0] <= vertex <= x[2]:
                return float(np.exp(vertex)), float(np.exp(np.polyval(coefficients, vertex)))
    return float(freq[index]), float(magnitude[index])


@dataclass(frozen=True)
class ResonanceSearch:
    """The peak of a magnitude found by :func:`search_resonance`.

    Attributes
    ----------
    freq : float
        Peak frequency, Hz: refined, or the grid maximum (not refined, or at an end of the grid).
    peak : float
        The magnitude at ``freq``.
    grid : ndarray
        The log-spaced search grid, Hz (its ends exactly ``f_min`` and ``f_max``).
    values : ndarray
        The magnitude on ``grid``.
    index : int
        Index of the grid maximum.
    """

    freq: float
    peak: float
    grid: NDArray[np.float64]
    values: NDArray[np.float64]
    index: int

    @property
    def inside(self) -> bool:
        """The grid maximum lies inside the grid: a peak was located (at an end, the magnitude
        may rise beyond the searched band or have no peak)."""
        return 0 < self.index < self.grid.size - 1


@accepts(f_min=Real(unit="Hz", gt=0), f_max=Real(unit="Hz", gt=0),
         n_grid=Whole(ge=3, meaning="a peak needs a sample on each side"))
def resonance_grid_maxima(magnitude: Callable[[NDArray[np.float64]], NDArray[np.float64]], *, f_min: float,
                          f_max: float, n_grid: int) -> tuple[NDArray[np.float64], NDArray[np.float64], np.ndarray]:
    """The grid part of the resonance search, for one magnitude or several evaluated at once.

    ``magnitude(grid)`` is evaluated on ``n_grid`` log-spaced frequencies from ``f_min`` to
    ``f_max`` Hz (:func:`numpy.geomspace`) and may return shape ``(n_grid,)`` or ``(..., n_grid)``
    (one row per system, e.g.); the maximum of each row is its first largest value.

    Returns
    -------
    (ndarray, ndarray, ndarray)
        The grid (Hz), the magnitudes on it and the index of each row's maximum (shape
        ``values.shape[:-1]``: a 0-d integer array for one magnitude).
    """
    if not f_min < f_max:
        raise ParameterError(f"f_min, f_max: found {f_min!r}, {f_max!r}, expected f_min < f_max in Hz")
    grid = np.geomspace(f_min, f_max, n_grid)
    values = magnitude(grid)
    return grid, values, np.argmax(values, axis=-1)


@accepts(f_min=Real(unit="Hz", gt=0), f_max=Real(unit="Hz", gt=0),
         n_grid=Whole(ge=3, meaning="a peak needs a sample on each side"), refine=Flag())
def search_resonance(magnitude: Callable[[NDArray[np.float64]], NDArray[np.float64]], *, f_min: float,
                     f_max: float, n_grid: int, refine: bool = True) -> ResonanceSearch:
    """The largest value of ``magnitude(freq)`` over ``[f_min, f_max]`` Hz.

    ``magnitude`` is evaluated on ``n_grid`` log-spaced frequencies (:func:`numpy.geomspace`,
    :func:`resonance_grid_maxima`, which also serves many systems at once); with ``refine``, a maximum inside the grid is refined by bounded Brent minimisation of
    ``-log magnitude`` in ``log f`` between the grid neighbours, to ``1e-12`` in ``log f``. A
    maximum at an end of the grid is returned as it is (:attr:`ResonanceSearch.inside` false).

    Examples
    --------
    >>> zeta, f_n = 0.05, 5.0
    >>> def magnitude(f):
    ...     r = np.asarray(f) / f_n
    ...     return np.abs((1 + 2j * zeta * r) / (1 - r**2 + 2j * zeta * r))
    >>> found = search_resonance(magnitude, f_min=0.1, f_max=100.0, n_grid=400)
    >>> round(found.freq, 6), round(float(f_n * np.sqrt(np.sqrt(1 + 8 * zeta**2) - 1) / (2 * zeta)), 6)
    (4.987608, 4.987608)
    """
    grid, values, index = unchecked(resonance_grid_maxima)(magnitude, f_min=f_min, f_max=f_max, n_grid=n_grid)
    index = int(index)
    if not refine or index in (0, grid.size - 1):
        return ResonanceSearch(float(grid[index]), float(values[index]), grid, values, index)
    refined = optimize.minimize_scalar(lambda log_f: -np.log(magnitude(np.exp(log_f))),
                                       bounds=(np.log(grid[index - 1]), np.log(grid[index + 1])),
                                       method="bounded", options={"xatol": 1e-12})
    freq = float(np.exp(refined.x))
    return ResonanceSearch(freq, float(magnitude(freq)), grid, values, index)
