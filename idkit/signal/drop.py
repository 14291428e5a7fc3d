"""Drop-test processing: smoothing, impact detection, impact velocity and shock peaks.

The drop tests of SPEC section 3 (thesis section 6.3 and appendix F) record the deflection
and relative velocity over the isolator (laser vibrometer) and the vertical acceleration of
the top mass with two accelerometers. As in the thesis, the accelerations are averaged, and
velocity and acceleration are smoothed by a 5-sample moving average run forward and
backward (zero phase). From the smoothed records this module finds the impact, the impact
velocity, the peak acceleration magnitude in the compression and in the tension phase (the
"rest shock level", thesis section 8.3) and the peak compression and tension.

Sign conventions (SPEC): deflection ``x = x_top - x_base`` in m, positive = tension; velocity
and acceleration positive upward (towards tension). A drop moves the top mass down onto the
isolator, so the impact velocity is negative, ``v0 = -sqrt(2 g h)`` (thesis eq. (3.18)).
During compression the isolator pushes the top mass up: the acceleration is positive.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import signal as sps

from idkit.checks import Real, Samples, Whole, accepts, unchecked
from idkit.errors import DataError
from idkit.gravity import STANDARD_GRAVITY, impact_velocity_from_height

__all__ = [
    "STANDARD_GRAVITY",
    "DropResult",
    "PhasePeaks",
    "drop_phase_peaks",
    "impact_velocity_from_height",
    "process_drop",
    "zero_phase_moving_average",
]


@accepts(signal=Samples(finite=False), window=Whole(ge=1, meaning="samples"), error=DataError)
def zero_phase_moving_average(signal: ArrayLike, *, window: int = 5) -> NDArray[np.float64]:
    """Moving average of ``window`` samples run forward and backward (zero phase).

    Implemented with :func:`scipy.signal.filtfilt` and a boxcar of ``window`` equal taps. The
    net filter is the triangle of ``2 window - 1`` samples (boxcar convolved with itself),
    magnitude response ``(sin(window w T / 2) / (window sin(w T / 2)))**2``: a sine of angular
    frequency ``w`` sampled at interval ``T`` loses about ``(window**2 - 1) (w T)**2 / 12`` of its
    amplitude (2 (w T)^2 for window 5), with no phase shift.

    Edge handling: filtfilt's default odd extension by ``3 window`` samples at each end (the
    record is extended by its point reflection about the end sample), which keeps a linear
    trend, and a step that starts at the first sample, unbiased at the ends.

    Parameters
    ----------
    signal : array_like, shape (n,)
        Uniformly sampled record (any unit); ``n > 3 window``.
    window : int, default 5
        Moving-average length in samples; 1 returns a copy of the input.

    Returns
    -------
    ndarray, shape (n,)
        Smoothed record, same unit.

    Examples
    --------
    >>> import numpy as np
    >>> ramp = np.arange(20.0)
    >>> bool(np.allclose(zero_phase_moving_average(ramp), ramp))  # a ramp is kept, ends too
    True
    """
    values = signal
    if window == 1:
        return values.copy()
    if values.size <= 3 * window:
        raise DataError(
            f"signal has {values.size} samples; more than {3 * window} are needed for a "
            f"{window}-sample forward-backward moving average"
        )
    return sps.filtfilt(np.full(window, 1.0 / window), [1.0], values)


@dataclass(frozen=True)
class PhasePeaks:
    """Shock peaks of drop records, per phase (the one reduction idkit uses for drops).

    Every array has the leading shape of the records given to :func:`drop_phase_peaks`.

    Attributes
    ----------
    acceleration_compression, acceleration_tension : ndarray
        Largest acceleration magnitude of the top mass while the deflection is below / above
        its reference, m/s^2 (``nan`` when the phase never occurs).
    index_compression, index_tension : ndarray of int
        Sample of each peak (-1 when the phase never occurs).
    compression, tension : ndarray
        Largest travel below / above the reference, ``reference - min`` and
        ``max - reference``, m, >= 0.
    """

    acceleration_compression: NDArray[np.float64]
    acceleration_tension: NDArray[np.float64]
    index_compression: NDArray[np.int64]
    index_tension: NDArray[np.int64]
    compression: NDArray[np.float64]
    tension: NDArray[np.float64]

    @property
    def rest_shock_level(self) -> NDArray[np.float64]:
        """The larger of the two phase peaks, m/s^2 (thesis 8.3)."""
        with np.errstate(invalid="ignore"):
            return np.fmax(self.acceleration_compression, self.acceleration_tension)


@accepts(start=Whole(ge=0, meaning="sample index"), error=DataError)
def drop_phase_peaks(deflection: ArrayLike, acceleration: ArrayLike, *, reference: ArrayLike | None = None,
                     start: int = 0) -> PhasePeaks:
    """Peak accelerations and travels of drop records in compression and in tension.

    The one definition of a drop's phases, shared by the measured records
    (:func:`process_drop`), the simulated ones (:func:`idkit.responses.shock.shock_sweep`),
    the drop validation and the CLI: from sample ``start`` on, the record is in
    **compression** where ``deflection < reference`` and in **tension** where it is above;
    ``deflection`` is the travel of the top mass relative to the base (``x_top - x_base``,
    the quantity a drop rig measures; for a hybrid the sum over both isolators). The peaks
    are magnitudes, so the compression peak (acceleration upward) and the tension peak
    (downward) compare directly. Non-finite samples (a simulation stopped by a validity
    flag) are ignored.

    Parameters
    ----------
    deflection : array_like, shape (..., n)
        Deflection records, m, positive = tension.
    acceleration : array_like, shape (..., n)
        Top-mass acceleration records, m/s^2.
    reference : array_like, shape (...), optional
        Deflection taken as the start of the phases, m; default the deflection at ``start``.
    start : int, default 0
        First sample considered (the impact).

    Returns
    -------
    PhasePeaks

    Examples
    --------
    >>> t = np.linspace(0.0, 0.2, 2001)
    >>> x = -0.01 * np.sin(2 * np.pi * 10 * t)  # one compression, then one tension
    >>> peaks = drop_phase_peaks(x, -(2 * np.pi * 10) ** 2 * x)
    >>> round(float(peaks.compression), 6), round(float(peaks.acceleration_tension), 3)
    (0.01, 39.478)
    """
    x = np.asarray(deflection, dtype=float)
    a = np.asarray(acceleration, dtype=float)
    if x.shape != a.shape or x.ndim < 1:
        raise DataError(f"deflection and acceleration: found shapes {x.shape} and {a.shape}, expected equal (..., n)")
    if start >= x.shape[-1]:
        raise DataError(f"start: found {start!r}, expected a sample index in [0, {x.shape[-1]})")
    x, a = x[..., start:], a[..., start:]
    ref = x[..., 0] if reference is None else np.broadcast_to(np.asarray(reference, dtype=float), x.shape[:-1])
    relative = x - ref[..., None]
    finite = np.isfinite(relative) & np.isfinite(a)
    magnitude = np.where(finite, np.abs(a), -np.inf)

    def phase(mask):
        values = np.where(mask & finite, magnitude, -np.inf)
        index = np.argmax(values, axis=-1)
        peak = np.take_along_axis(values, index[..., None], axis=-1)[..., 0]
        present = np.isfinite(peak)
        return np.where(present, peak, np.nan), np.where(present, index + int(start), -1).astype(np.int64)

    acc_c, idx_c = phase(relative < 0)
    acc_t, idx_t = phase(relative > 0)
    safe = np.where(finite, relative, 0.0)
    return PhasePeaks(acceleration_compression=acc_c, acceleration_tension=acc_t, index_compression=idx_c,
                      index_tension=idx_t, compression=np.maximum(-safe.min(axis=-1), 0.0),
                      tension=np.maximum(safe.max(axis=-1), 0.0))


@dataclass(frozen=True)
class DropResult:
    """Characteristic values of one drop.

    Attributes
    ----------
    impact_index : int
        Sample of the impact (see :func:`process_drop` for the rule).
    impact_time : float
        Time of the impact sample, s.
    impact_velocity : float
        Measured impact velocity, m/s (negative): the most negative smoothed relative velocity
        between the impact and the end of the first compression stroke.
    impact_velocity_from_height : float
        ``-sqrt(2 g h)`` from the drop height, m/s (``nan`` when no height was given).
    peak_acceleration_compression : float
        Largest acceleration **magnitude** of the top mass while the isolator is compressed
        (deflection below the reference) after the impact, m/s^2 (>= 0).
    time_peak_acceleration_compression : float
        Its time, s.
    peak_acceleration_tension : float
        Largest acceleration magnitude while the isolator is in tension after the impact,
        m/s^2 (``nan`` when it never is).
    time_peak_acceleration_tension : float
        Its time, s (``nan`` when there is no tension phase).
    max_compression : float
        Peak compression as a **positive magnitude**: ``reference - min(deflection)`` after
        the impact, m.
    max_tension : float
        Peak tension ``max(deflection) - reference`` after the impact, m (0 if never positive).
    deflection_reference : float
        Deflection taken as zero (isolator unloaded at impact), m.
    time : ndarray
        Time, s.
    acceleration : ndarray
        Mean of the accelerometers, smoothed, m/s^2.
    relative_velocity : ndarray
        Relative velocity over the isolator, smoothed, m/s.
    deflection : ndarray
        Deflection relative to ``deflection_reference``, m (not smoothed).
    """

    impact_index: int
    impact_time: float
    impact_velocity: float
    impact_velocity_from_height: float
    peak_acceleration_compression: float
    time_peak_acceleration_compression: float
    peak_acceleration_tension: float
    time_peak_acceleration_tension: float
    max_compression: float
    max_tension: float
    deflection_reference: float
    time: NDArray[np.float64]
    acceleration: NDArray[np.float64]
    relative_velocity: NDArray[np.float64]
    deflection: NDArray[np.float64]

    @property
    def peak_acceleration(self) -> float:
        """Rest shock level: the larger of the two phase peaks, m/s^2."""
        peaks = [self.peak_acceleration_compression, self.peak_acceleration_tension]
        return float(np.nanmax(peaks))

    def to_dataframe(self) -> pd.DataFrame:
        """One-row table of the scalar results (SI units in the column names)."""
        return pd.DataFrame(
            {
                "impact_time [s]": [self.impact_time],
                "impact_velocity [m/s]": [self.impact_velocity],
                "impact_velocity_from_height [m/s]": [self.impact_velocity_from_height],
                "peak_acceleration_compression [m/s^2]": [self.peak_acceleration_compression],
                "peak_acceleration_tension [m/s^2]": [self.peak_acceleration_tension],
                "max_compression [m]": [self.max_compression],
                "max_tension [m]": [self.max_tension],
            }
        )

    def time_series(self) -> pd.DataFrame:
        """The processed records as a table: time, deflection, relative velocity, acceleration."""
        return pd.DataFrame(
            {
                "time [s]": self.time,
                "deflection [m]": self.deflection,
                "relative_velocity [m/s]": self.relative_velocity,
                "acceleration [m/s^2]": self.acceleration,
            }
        )


@accepts(time=Samples(unit="s", min_size=2), deflection=Samples(unit="m"),
         acceleration=Samples(unit="m/s^2", ndim=(1, 2)), relative_velocity=Samples(unit="m/s", optional=True),
         drop_height=Real(unit="m", ge=0, optional=True), window=Whole(ge=1, meaning="samples"),
         impact_fraction=Real(gt=0, lt=1), deflection_reference=Real(unit="m", optional=True),
         g=Real(unit="m/s^2", ge=0), error=DataError)
def process_drop(
    time: ArrayLike,
    deflection: ArrayLike,
    acceleration: ArrayLike,
    *,
    relative_velocity: ArrayLike | None = None,
    drop_height: float | None = None,
    window: int = 5,
    impact_fraction: float = 0.5,
    deflection_reference: float | None = None,
    g: float = STANDARD_GRAVITY,
) -> DropResult:
    """Process one drop record into impact velocity, shock peaks and peak deflections.

    Steps:

    1. ``acceleration`` of shape (n_sensors, n) is averaged over the sensors.
    2. Acceleration and relative velocity are smoothed with
       :func:`zero_phase_moving_average` (``window`` samples, default 5 as in the thesis);
       the deflection is used as measured. Without ``relative_velocity`` it is computed as
       :func:`numpy.gradient` of the deflection, then smoothed.
    3. Impact: at impact the base stops and the relative velocity steps from about zero to
       ``v0 < 0``. The impact sample is the first at which the smoothed relative velocity
       falls to ``impact_fraction`` (default one half) of its most negative value, i.e. the
       middle of the smoothed step; the zero-phase filter keeps the step centred on the
       raw one. A record that starts at impact (a simulation from ``v0``) gives sample 0.
    4. Reference deflection (unloaded isolator): unless given, the mean deflection over the
       ``window`` samples ending ``window`` samples before the impact (before the smoothed
       step), or the first sample when the impact is at the start.
    5. Phases after the impact: compression where ``deflection < reference``, tension where
       it is above. The peaks are acceleration magnitudes within each phase, so the
       compression peak (acceleration upward, positive) and the tension peak (downward,
       negative) are directly comparable.
    6. Measured impact velocity: the most negative smoothed relative velocity between the
       impact and the end of the first stroke (where the relative velocity turns upward);
       for an isolator whose force starts from zero it is the velocity just after the step.
       Smoothing makes it slightly too small in magnitude: the smoothed step reaches full
       height ``window - 1`` samples after the raw one, so for an oscillator of angular
       frequency ``w0`` sampled at interval ``T`` and the default window the magnitude is
       low by about ``10 (w0 T)**2`` relative (``8`` from the 4-sample delay, ``2`` from
       the filter gain).

    Accelerations are used as given (no gravity correction): pass kinematic acceleration,
    or accept that accelerometer readings include the 1 g offset after impact.

    Parameters
    ----------
    time : array_like, shape (n,)
        Uniformly sampled time, s.
    deflection : array_like, shape (n,)
        Deflection over the isolator, m (positive = tension).
    acceleration : array_like, shape (n,) or (n_sensors, n)
        Top-mass acceleration(s), m/s^2, positive upward.
    relative_velocity : array_like, shape (n,), optional
        Relative velocity over the isolator, m/s (``d deflection / dt``).
    drop_height : float, optional
        Drop height, m, for ``impact_velocity_from_height``.
    window : int, default 5
        Moving-average length in samples (1 disables smoothing).
    impact_fraction : float, default 0.5
        Fraction of the most negative relative velocity that marks the impact, in (0, 1).
    deflection_reference : float, optional
        Deflection of the unloaded isolator, m; overrides step 4.
    g : float, default 9.80665
        Gravitational acceleration, m/s^2.

    Returns
    -------
    DropResult

    Raises
    ------
    DataError
        Mismatched shapes, non-uniform or non-increasing time, no compression (no negative
        relative velocity).

    Examples
    --------
    >>> import numpy as np
    >>> w0, v0 = 2 * np.pi * 20.0, -1.0
    >>> t = np.arange(0.0, 0.1, 1e-4)
    >>> x = v0 / w0 * np.sin(w0 * t)
    >>> result = process_drop(t, x, -w0**2 * x, relative_velocity=v0 * np.cos(w0 * t))
    >>> round(result.peak_acceleration_compression / (w0 * abs(v0)), 3)
    1.0
    """
    t, x, acc = time, deflection, acceleration
    if x.shape != t.shape:
        raise DataError(
            f"time and deflection must be 1-D of equal length; found {t.shape} and {x.shape}"
        )
    if acc.ndim == 2:
        acc = acc.mean(axis=0)
    if acc.shape != t.shape:
        raise DataError(
            f"acceleration has shape {np.shape(acceleration)}; expected ({t.size},) or "
            f"(n_sensors, {t.size})"
        )
    steps = np.diff(t)
    if np.any(steps <= 0) or np.ptp(steps) > 1e-6 * steps.mean():
        raise DataError(
            "time must increase uniformly (the moving average assumes a constant sample "
            f"interval); found steps from {steps.min():g} to {steps.max():g} s"
        )
    if relative_velocity is None:
        velocity_raw = np.gradient(x, t)
    else:
        velocity_raw = relative_velocity
        if velocity_raw.shape != t.shape:
            raise DataError(f"relative_velocity: found shape {velocity_raw.shape}, expected {t.shape} like time")
    smooth = unchecked(zero_phase_moving_average)
    velocity = smooth(velocity_raw, window=window)
    acc = smooth(acc, window=window)

    most_negative = velocity.min()
    if not most_negative < 0:
        raise DataError(
            "relative_velocity never becomes negative: no compression, no impact found "
            f"(minimum {most_negative:g} m/s)"
        )
    impact = int(np.flatnonzero(velocity <= impact_fraction * most_negative)[0])
    if deflection_reference is None:
        stop = max(impact - window, 0)
        start = max(stop - window + 1, 0)
        reference = float(x[start : stop + 1].mean())
    else:
        reference = float(deflection_reference)
    relative = x - reference
    peaks = drop_phase_peaks(x, acc, reference=reference, start=impact)
    if peaks.index_compression < 0:
        raise DataError("the deflection never goes below its reference after the impact")

    def at(index) -> float:
        return float(t[index]) if index >= 0 else float("nan")

    # First compression phase: from the impact until the relative velocity turns upward
    # (the peak compression of the first stroke); velocity[impact] < 0 so it is not empty.
    turning = np.flatnonzero(velocity[impact:] >= 0)
    end = impact + int(turning[0]) if turning.size else t.size
    first_phase = velocity[impact:end]
    return DropResult(
        impact_index=impact,
        impact_time=float(t[impact]),
        impact_velocity=float(first_phase.min()),
        impact_velocity_from_height=(
            float("nan") if drop_height is None else impact_velocity_from_height(drop_height, g=g)
        ),
        peak_acceleration_compression=float(peaks.acceleration_compression),
        time_peak_acceleration_compression=at(int(peaks.index_compression)),
        peak_acceleration_tension=float(peaks.acceleration_tension),
        time_peak_acceleration_tension=at(int(peaks.index_tension)),
        max_compression=float(peaks.compression),
        max_tension=float(peaks.tension),
        deflection_reference=reference,
        time=t,
        acceleration=acc,
        relative_velocity=velocity,
        deflection=relative,
    )
