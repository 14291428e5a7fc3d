"""Shock records -> conditioned pulses, pulse characteristics, shock spectra, response ratios.

A shock record (:class:`idkit.io.AccelerationRecord`: one accelerometer channel, one column
per repeated test, m/s^2) is read as it comes from a drop tower or a shock machine. Every
function here takes that typed record and returns a typed result; none alters its input.

Choices (documented because a shock record is easy to misread):

- **Offset removal** (:func:`condition_shock`, ``offset="pre-trigger"``, the default): the
  median of the samples before the pulse starts is subtracted per test (the median, so
  the first rising samples of the pulse, which lie before the trigger, do not bias it). The pulse starts at
  the first sample whose deviation from the record's median exceeds ``trigger_fraction``
  (default 10 %) of the largest deviation. A record with fewer than
  :data:`MIN_PRE_TRIGGER_SAMPLES` samples before its pulse has no pre-trigger to read an
  offset from: idkit says so instead of guessing (``offset="none"`` keeps the record as is).
  The offset matters: an offset ``a0`` over a record of length ``T`` adds ``a0 T`` to the
  velocity change.
- **Filtering**: none by default. ``lowpass_hz`` applies a zero-phase Butterworth low-pass
  (order ``filter_order``, default 4, run forward and backward with
  :func:`scipy.signal.sosfiltfilt`, so the magnitude response is squared and the phase is
  zero); the cut-off must lie below the Nyquist frequency and at or above ``1 / T`` (a period
  longer than the record leaves only its mean and trend, as the SRS band starts at ``1 / T``).
- **Pulse characteristics** (:func:`shock_pulses`): the peak is the sample of largest
  magnitude (sign kept); the duration is the length of the contiguous span around it where
  ``|a| >= duration_fraction * |peak|`` (default 10 %, the usual pulse-width reading of
  shock-machine specifications); the velocity change is the trapezoidal integral of the
  acceleration over the whole record.
- **Spectra** (:func:`record_spectra`): the three ISO 18431-4 spectra of
  :func:`idkit.signal.srs.shock_spectra` for every test; the natural frequencies must have
  at least :data:`~idkit.signal.srs.MIN_SAMPLES_PER_PERIOD` samples per period. The default
  band runs from ``1 / T`` (the record length ``T``) to ``fs / 10``, 60 points per band,
  log-spaced.
- **Response over input** (:func:`response_ratio`): the absolute-acceleration SRS of a
  response channel divided by that of the input channel (fixture), test by test, on the
  same natural frequencies.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import signal as sps

from idkit.checks import Choice, Instance, Real, Whole, accepts
from idkit.errors import DataError, Message, Suggestion
from idkit.io import AccelerationRecord
from idkit.signal.srs import MIN_SAMPLES_PER_PERIOD, ShockSpectra, shock_spectra

__all__ = [
    "MIN_PRE_TRIGGER_SAMPLES",
    "ConditionedShock",
    "RecordSpectra",
    "ResponseRatio",
    "ShockPulses",
    "condition_shock",
    "default_srs_band",
    "record_spectra",
    "response_ratio",
    "shock_pulses",
]

#: Fewest samples before the pulse from which a pre-trigger offset is read.
MIN_PRE_TRIGGER_SAMPLES = 10


def _where(record: AccelerationRecord, test: int | None = None) -> str:
    column = "accel" if test is None else f"test {test + 1}"
    name = f" ({record.channel})" if record.channel else ""
    return record.source.where(column) + name


#: A shock record argument.
RECORD = Instance((AccelerationRecord,), what="an idkit.io.AccelerationRecord (time in s, one column of m/s^2 per test)")


def _pulse_start(values: NDArray[np.float64], trigger_fraction: float) -> int:
    deviation = np.abs(values - np.median(values))
    return int(np.flatnonzero(deviation >= trigger_fraction * deviation.max())[0])


@dataclass(frozen=True)
class ConditionedShock:
    """A shock record after offset removal and optional filtering.

    Attributes
    ----------
    record : AccelerationRecord
        The conditioned record (same time base, channel and source as the input).
    offset : ndarray, shape (n_tests,)
        Offset subtracted from each test, m/s^2 (0 with ``offset="none"``).
    pre_trigger_samples : ndarray of int, shape (n_tests,)
        Samples in each test's offset window (from the record's start).
    offset_rule : str
        "pre-trigger" or "none".
    lowpass_hz : float or None
        Cut-off of the zero-phase Butterworth low-pass, Hz (None: not filtered).
    filter_order : int
        Order of the Butterworth filter (applied twice: forward and backward).
    """

    record: AccelerationRecord
    offset: NDArray[np.float64]
    pre_trigger_samples: NDArray[np.int64]
    offset_rule: str
    lowpass_hz: float | None
    filter_order: int

    def report(self) -> str:
        """One line per test: offset and pre-trigger length."""
        lines = [f"conditioned {self.record.channel or 'record'}: offset {self.offset_rule}, "
                 + (f"low-pass {self.lowpass_hz:g} Hz (Butterworth order {self.filter_order}, zero phase)"
                    if self.lowpass_hz else "not filtered")]
        for j, (offset, samples) in enumerate(zip(self.offset, self.pre_trigger_samples)):
            lines.append(f"  test {j + 1}: offset {offset:.4g} m/s^2 from {samples} pre-trigger samples")
        return "\n".join(lines)


#: A fraction of a pulse's largest deviation (trigger, duration).
FRACTION = Real(gt=0, lt=1)


@accepts(record=RECORD, offset=Choice(("pre-trigger", "none")), trigger_fraction=FRACTION,
         lowpass_hz=Real(unit="Hz", gt=0, optional=True),
         filter_order=Whole(ge=1, le=10), error=DataError)
def condition_shock(record: AccelerationRecord, *, offset: str = "pre-trigger", trigger_fraction: float = 0.1,
                    pre_trigger_s: float | None = None, lowpass_hz: float | None = None,
                    filter_order: int = 4) -> ConditionedShock:
    """Remove each test's offset and optionally low-pass filter (module docstring for the rules).

    Parameters
    ----------
    record : AccelerationRecord
    offset : {"pre-trigger", "none"}, default "pre-trigger"
    trigger_fraction : float, default 0.1
        Start of the pulse: first deviation from the median above this fraction of the
        largest deviation, in (0, 1).
    pre_trigger_s : float, optional
        Length of the offset window from the record's start, s; it must end before the
        trigger. Default: half the time before the trigger.
    lowpass_hz : float, optional
        Cut-off of a zero-phase Butterworth low-pass, Hz, in (0, fs/2).
    filter_order : int, default 4

    Returns
    -------
    ConditionedShock

    Raises
    ------
    DataError
        An unknown option, a cut-off at or above Nyquist, a test without pre-trigger samples.

    Examples
    --------
    >>> from idkit.io import AccelerationRecord
    >>> t = np.arange(2000) * 1e-5
    >>> pulse = 5.0 + 100.0 * np.sin(np.pi * (t - 0.005) / 0.005) * ((t > 0.005) & (t < 0.01))
    >>> shock = condition_shock(AccelerationRecord(time=t, accel=pulse))
    >>> round(float(shock.offset[0]), 6)
    5.0
    """
    fs = record.sample_rate_hz
    accel = np.array(record.accel, dtype=float)
    offsets = np.zeros(record.n_tests)
    pre = np.zeros(record.n_tests, dtype=np.int64)
    for j in range(record.n_tests):
        start = _pulse_start(accel[:, j], trigger_fraction)
        pre[j] = start
        if offset == "pre-trigger":
            if pre_trigger_s is None:
                window = start // 2
            else:
                window = int(np.searchsorted(record.time - record.time[0], pre_trigger_s, side="right"))
                if window > start:
                    raise DataError(f"pre_trigger_s: found {pre_trigger_s:g} s, expected a window ending before the "
                                    f"pulse of {_where(record, j)}, which triggers at "
                                    f"{record.time[start] - record.time[0]:.6g} s")
            if window < MIN_PRE_TRIGGER_SAMPLES:
                raise DataError(Message(f"{_where(record, j)}: the pulse triggers at sample {start + 1}, leaving "
                                        f"{window} samples for the offset, expected at least "
                                        f"{MIN_PRE_TRIGGER_SAMPLES} (use ", Suggestion("offset", "none"),
                                        " to keep the record as recorded)"))
            pre[j] = window
            offsets[j] = float(np.median(accel[:window, j]))
    accel -= offsets
    if lowpass_hz is not None:
        if not lowpass_hz < fs / 2 * (1 - 1e-6):
            raise DataError(f"lowpass_hz: found {lowpass_hz!r}, expected a cut-off in (0, {fs / 2:g}) Hz "
                            f"(below the Nyquist frequency of {_where(record)})")
        span = float(record.time[-1] - record.time[0])
        if lowpass_hz * span < 1.0:  # a cut-off period longer than the record smooths the shock away
            raise DataError(f"lowpass_hz: found {lowpass_hz!r}, below 1 / record length = {1.0 / span:.6g} Hz "
                            f"({_where(record)}, {span:.6g} s): a cut-off whose period exceeds the record leaves only "
                            f"its mean and trend; expected a cut-off "
                            f"in [{1.0 / span:.6g}, {fs / 2:g}) Hz")
        sos = sps.butter(int(filter_order), lowpass_hz, fs=fs, output="sos")
        accel = sps.sosfiltfilt(sos, accel, axis=0)
    conditioned = AccelerationRecord(time=record.time, accel=accel, channel=record.channel, source=record.source)
    return ConditionedShock(record=conditioned, offset=offsets, pre_trigger_samples=pre, offset_rule=offset,
                            lowpass_hz=None if lowpass_hz is None else float(lowpass_hz),
                            filter_order=int(filter_order))


@dataclass(frozen=True)
class ShockPulses:
    """Pulse characteristics of every test of a record.

    Attributes
    ----------
    channel : str
    peak : ndarray, shape (n_tests,)
        Acceleration of largest magnitude, sign kept, m/s^2.
    time_of_peak : ndarray, shape (n_tests,)
        s.
    duration : ndarray, shape (n_tests,)
        Contiguous time around the peak with ``|a| >= duration_fraction |peak|``, s.
    velocity_change : ndarray, shape (n_tests,)
        Integral of the acceleration over the record, m/s.
    duration_fraction : float
    """

    channel: str
    peak: NDArray[np.float64]
    time_of_peak: NDArray[np.float64]
    duration: NDArray[np.float64]
    velocity_change: NDArray[np.float64]
    duration_fraction: float

    def to_dataframe(self) -> pd.DataFrame:
        """One row per test, units in the column names."""
        return pd.DataFrame({
            "channel": self.channel, "test": np.arange(1, self.peak.size + 1),
            "peak [m/s^2]": self.peak, "peak [g]": self.peak / 9.80665, "time_of_peak [s]": self.time_of_peak,
            "duration [s]": self.duration, "velocity_change [m/s]": self.velocity_change,
        })

    def report(self) -> str:
        """Text table of the pulses."""
        return self.to_dataframe().to_string(index=False, float_format=lambda v: f"{v:.4g}")


@accepts(record=RECORD, duration_fraction=FRACTION, error=DataError)
def shock_pulses(record: AccelerationRecord, *, duration_fraction: float = 0.1) -> ShockPulses:
    """Peak, time of peak, duration and velocity change of every test (module docstring).

    Condition the record first (:func:`condition_shock`) when it carries an offset.

    Examples
    --------
    A half sine of 100 m/s^2 over 5 ms: velocity change ``2 A tau / pi``; its span above
    10 % of the peak lasts ``tau (1 - 2 asin(0.1) / pi)``.

    >>> from idkit.io import AccelerationRecord
    >>> t = np.arange(10000) * 1e-6
    >>> pulse = 100.0 * np.sin(np.pi * t / 0.005) * (t <= 0.005)
    >>> pulses = shock_pulses(AccelerationRecord(time=t, accel=pulse))
    >>> round(float(pulses.velocity_change[0] / (2 * 100.0 * 0.005 / np.pi)), 4)
    1.0
    >>> round(float(pulses.duration[0] / (0.005 * (1 - 2 * np.arcsin(0.1) / np.pi))), 3)
    1.0
    """
    time = np.asarray(record.time)
    peak, at, duration, change = (np.empty(record.n_tests) for _ in range(4))
    for j in range(record.n_tests):
        values = np.asarray(record.accel[:, j])
        index = int(np.argmax(np.abs(values)))
        peak[j], at[j] = values[index], time[index]
        above = np.abs(values) >= duration_fraction * abs(values[index])
        below = np.flatnonzero(~above)
        first = below[below < index].max() + 1 if np.any(below < index) else 0
        last = below[below > index].min() - 1 if np.any(below > index) else values.size - 1
        duration[j] = time[last] - time[first]
        change[j] = float(np.trapezoid(values, time))
    return ShockPulses(channel=record.channel, peak=peak, time_of_peak=at, duration=duration,
                       velocity_change=change, duration_fraction=float(duration_fraction))


@accepts(record=RECORD, n_points=Whole(ge=2), error=DataError)
def default_srs_band(record: AccelerationRecord, n_points: int = 60) -> NDArray[np.float64]:
    """Log-spaced natural frequencies from ``1 / T`` to ``fs / 10``, Hz (module docstring)."""
    span = float(record.time[-1] - record.time[0])
    return np.logspace(np.log10(1.0 / span), np.log10(record.sample_rate_hz / MIN_SAMPLES_PER_PERIOD), n_points)


def _band(record: AccelerationRecord, freq: ArrayLike | None) -> NDArray[np.float64]:
    if freq is None:
        return default_srs_band(record)
    fn = np.atleast_1d(np.asarray(freq, dtype=float))
    fs = record.sample_rate_hz
    if fn.ndim != 1 or fn.size == 0 or not np.all(np.isfinite(fn) & (fn > 0)):
        raise DataError(f"freq: found {fn!r}, expected positive natural frequencies in Hz")
    if fn.max() * MIN_SAMPLES_PER_PERIOD > fs * (1 + 1e-12):
        raise DataError(f"{_where(record)}: sampled at {fs:.6g} Hz, too slowly for an SRS up to {fn.max():.6g} Hz: "
                        f"expected at least {MIN_SAMPLES_PER_PERIOD:g} samples per period (fs >= "
                        f"{MIN_SAMPLES_PER_PERIOD * fn.max():.6g} Hz, peaks then within 4.9 %); lower the band to "
                        f"<= {fs / MIN_SAMPLES_PER_PERIOD:.6g} Hz")
    return fn


@dataclass(frozen=True)
class RecordSpectra:
    """Shock spectra of every test of a record.

    Attributes
    ----------
    channel : str
    spectra : tuple of ShockSpectra
        One per test.
    """

    channel: str
    spectra: tuple[ShockSpectra, ...]

    @property
    def freq(self) -> NDArray[np.float64]:
        """Natural frequencies, Hz."""
        return self.spectra[0].freq

    def to_dataframe(self) -> pd.DataFrame:
        """Long table: one row per test and natural frequency."""
        frames = []
        for j, spectrum in enumerate(self.spectra):
            frame = spectrum.to_dataframe()
            frame.insert(0, "test", j + 1)
            frame.insert(0, "channel", self.channel)
            frames.append(frame)
        return pd.concat(frames, ignore_index=True)


@accepts(record=RECORD, error=DataError)
def record_spectra(record: AccelerationRecord, *, freq: ArrayLike | None = None,
                   damping_ratio: float = 0.05) -> RecordSpectra:
    """The three shock response spectra (ISO 18431-4) of every test of ``record``.

    Parameters
    ----------
    record : AccelerationRecord
    freq : array_like, optional
        Natural frequencies, Hz; default :func:`default_srs_band`. Each needs at least
        :data:`~idkit.signal.srs.MIN_SAMPLES_PER_PERIOD` samples per period.
    damping_ratio : float, default 0.05

    Returns
    -------
    RecordSpectra
    """
    fn = _band(record, freq)
    fs = record.sample_rate_hz
    spectra = tuple(shock_spectra(record.accel[:, j], fs=fs, freq=fn, damping_ratio=damping_ratio)
                    for j in range(record.n_tests))
    return RecordSpectra(channel=record.channel, spectra=spectra)


@dataclass(frozen=True)
class ResponseRatio:
    """Absolute-acceleration SRS of a response channel over that of the input, per test.

    Attributes
    ----------
    response_channel, input_channel : str
    freq : ndarray, shape (n_freq,)
        Hz.
    ratio : ndarray, shape (n_tests, n_freq)
        Response SRS / input SRS (dimensionless).
    """

    response_channel: str
    input_channel: str
    freq: NDArray[np.float64]
    ratio: NDArray[np.float64]

    def to_dataframe(self) -> pd.DataFrame:
        """One row per natural frequency, one column per test."""
        data = {"freq [Hz]": self.freq}
        for j, row in enumerate(self.ratio):
            data[f"test_{j + 1} [-]"] = row
        return pd.DataFrame(data)


@accepts(response=RECORD, input=RECORD, error=DataError)
def response_ratio(response: AccelerationRecord, input: AccelerationRecord, *, freq: ArrayLike | None = None,
                   damping_ratio: float = 0.05) -> ResponseRatio:
    """SRS of ``response`` over SRS of ``input`` (fixture), test by test.

    Both records must share the time base and the number of tests (the same shots).
    """
    if response.n_tests != input.n_tests:
        raise DataError(f"{_where(response)}: found {response.n_tests} tests, expected {input.n_tests} as in "
                        f"{_where(input)} (the same shots)")
    if response.time.shape != input.time.shape or not np.allclose(response.time, input.time, rtol=0,
                                                                   atol=1e-9 / input.sample_rate_hz):
        raise DataError(f"{_where(response)}: time column differs from {_where(input)}, expected one time base")
    fn = _band(input, freq)
    out = record_spectra(response, freq=fn, damping_ratio=damping_ratio)
    base = record_spectra(input, freq=fn, damping_ratio=damping_ratio)
    ratio = np.array([o.absolute_acceleration / b.absolute_acceleration for o, b in zip(out.spectra, base.spectra)])
    return ResponseRatio(response_channel=response.channel, input_channel=input.channel, freq=fn, ratio=ratio)
