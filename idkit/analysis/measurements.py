"""Measurement-level processing: :mod:`idkit.io` measurement objects -> typed results.

Thin glue over the array-level functions of this package, one function per kind of
measurement (SPEC section 3):

- :func:`process_quasi_static` - cycles, amplitudes, small/large classification and
  resampled loops (:mod:`~idkit.analysis.cycles`);
- :func:`frf_from_white_noise` - H1, H2 and coherence (:mod:`~idkit.analysis.frf`);
- :func:`hosidf_from_stepped_sine` / :func:`stepped_sine_sweep` - HOSIDFs of one point or a
  sweep, with the input-distortion and input-flatness report (:mod:`~idkit.analysis.harmonics`);
- :func:`process_drop_measurement` - impact, impact velocity, shock peaks
  (:mod:`~idkit.analysis.drop`);
- :func:`summarize_measurements` - overview and data-quality warnings of a set (clipped
  signals, non-flat or distorted sine input, low coherence), used by ``idkit inspect``.

Every function reads the signals and metadata of the measurement (sample rate from the time
column, drop height and masses from ``info``) and returns a frozen dataclass that keeps the
measurement id next to the array-level result.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.analysis.cycles import (
    CycleSplit,
    ResampledLoops,
    noise_level,
    resample_loops,
    reversal_threshold,
    split_cycles,
)
from idkit.analysis.drop import DropResult, process_drop
from idkit.analysis.frf import FrfEstimate, estimate_frf
from idkit.analysis.harmonics import HosidfResult, InputFlatness, hosidf, input_flatness
from idkit.errors import DataError
from idkit.io import (
    DropMeasurement,
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
)

__all__ = [
    "DropMeasurementResult",
    "InspectionWarning",
    "MeasurementSummary",
    "QuasiStaticResult",
    "SteppedSinePoint",
    "SteppedSineSweep",
    "WhiteNoiseFrf",
    "find_clipping",
    "frf_from_white_noise",
    "hosidf_from_stepped_sine",
    "noise_level",
    "process_drop_measurement",
    "process_quasi_static",
    "stepped_sine_sweep",
    "summarize_measurements",
]


def _require(measurement, cls, function: str):
    if not isinstance(measurement, cls):
        raise DataError(f"{function}: found {type(measurement).__name__}, expected {cls.__name__}")


def _sample_rate(time: np.ndarray) -> float:
    return 1.0 / float(np.median(np.diff(time)))


# ---------------------------------------------------------------------------------------------
# quasi-static


@dataclass(frozen=True)
class QuasiStaticResult:
    """Cycles and resampled loops of one quasi-static measurement.

    Attributes
    ----------
    measurement_id : str
        ``info.id`` of the measurement.
    cycles : CycleSplit
        Reversals, branches, cycles, amplitudes (m) and the small/large flags.
    loops : ResampledLoops
        Every complete branch resampled to ``points_per_branch`` points (deflection m, force N).
    min_excursion : float
        Reversal threshold used, m.
    deflection_noise : float
        Estimated deflection noise standard deviation, m (:func:`noise_level`).
    """

    measurement_id: str
    cycles: CycleSplit
    loops: ResampledLoops
    min_excursion: float
    deflection_noise: float

    @property
    def n_cycles(self) -> int:
        """Number of complete cycles."""
        return self.cycles.n_cycles

    @property
    def amplitude(self) -> np.ndarray:
        """Cycle amplitudes, m."""
        return self.cycles.amplitude

    @property
    def is_large(self) -> np.ndarray:
        """Large-cycle flags (all false without a threshold)."""
        return self.cycles.is_large

    def to_dataframe(self) -> pd.DataFrame:
        """One row per cycle (see :meth:`CycleSplit.to_dataframe`) with the measurement id."""
        table = self.cycles.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table

    def report(self) -> str:
        """Short text summary."""
        amp = self.amplitude * 1e3
        span = f"{amp.min():.3g}-{amp.max():.3g} mm" if amp.size else "none"
        return (f"{self.measurement_id}: {self.n_cycles} cycles, amplitudes {span}, "
                f"{int(self.is_large.sum())} large; min_excursion {self.min_excursion * 1e6:.3g} um, "
                f"deflection noise {self.deflection_noise * 1e6:.3g} um")


def process_quasi_static(measurement: QuasiStaticMeasurement, *,
                         min_excursion: float | None = None,
                         large_threshold: float | None = None,
                         points_per_branch: int = 100,
                         spacing: str = "deflection") -> QuasiStaticResult:
    """Split a quasi-static record into cycles and resample its loops (SPEC 4, eq. 7.1).

    Parameters
    ----------
    measurement : QuasiStaticMeasurement
        Force-deflection record.
    min_excursion : float, optional
        Reversal threshold in m (:func:`~idkit.analysis.cycles.find_reversals`). Default
        ``max(10 * noise, 1e-3 * range)``: ten times the estimated deflection noise
        (:func:`noise_level`), at least a thousandth of the deflection range; well below the
        smallest loop of SPEC 3 (0.05 mm amplitude) for a micrometre-level sensor.
    large_threshold : float, optional
        Amplitude in m above which a cycle is "large"; e.g. 4.5e-3 m for the wire-rope sets.
    points_per_branch : int, default 100
        Points per resampled branch, reversals included.
    spacing : {"deflection", "index"}
        Spacing of the resampled points along a branch.

    Returns
    -------
    QuasiStaticResult

    Raises
    ------
    DataError
        If ``measurement`` is not a :class:`~idkit.io.QuasiStaticMeasurement`.
    FitError
        If no reversal is found.

    Examples
    --------
    >>> from idkit.io import QuasiStaticMeasurement
    >>> t = np.linspace(0, 40, 4001)
    >>> x = 2e-3 * np.sin(2 * np.pi * t / 10)
    >>> result = process_quasi_static(QuasiStaticMeasurement(time=t, deflection=x, force=1e4 * x))
    >>> result.n_cycles, round(float(result.amplitude[0]) * 1e3, 3)
    (3, 2.0)
    """
    _require(measurement, QuasiStaticMeasurement, "process_quasi_static")
    x = measurement.deflection
    noise = noise_level(x)
    if min_excursion is None:
        min_excursion = reversal_threshold(x)
    cycles = split_cycles(x, min_excursion=min_excursion, large_threshold=large_threshold)
    loops = resample_loops(x, measurement.force, split=cycles, points_per_branch=points_per_branch,
                           spacing=spacing)
    return QuasiStaticResult(measurement_id=measurement.id, cycles=cycles, loops=loops,
                             min_excursion=float(min_excursion), deflection_noise=noise)


# ---------------------------------------------------------------------------------------------
# white noise


@dataclass(frozen=True)
class WhiteNoiseFrf:
    """Transmissibility estimate of one white-noise run.

    Attributes
    ----------
    measurement_id : str
        ``info.id``.
    top_mass_kg : float or None
        Top mass, kg.
    signals : str
        ``"velocity"`` (v_base -> v_top) or ``"acceleration"`` (a_base -> a_top).
    estimate : FrfEstimate
        Frequencies (Hz), H1, H2, coherence, Welch settings.
    band : tuple of float
        Band kept, Hz.
    """

    measurement_id: str
    top_mass_kg: float | None
    signals: str
    estimate: FrfEstimate
    band: tuple[float, float]

    @property
    def freq(self) -> np.ndarray:
        """Frequencies, Hz."""
        return self.estimate.freq

    @property
    def h1(self) -> np.ndarray:
        """H1 transmissibility (dimensionless)."""
        return self.estimate.h1

    @property
    def h2(self) -> np.ndarray:
        """H2 transmissibility (dimensionless)."""
        return self.estimate.h2

    @property
    def coherence(self) -> np.ndarray:
        """Ordinary coherence in [0, 1]."""
        return self.estimate.coherence

    @property
    def min_coherence(self) -> float:
        """Lowest coherence in the band."""
        return float(self.coherence.min())

    @property
    def mean_coherence(self) -> float:
        """Mean coherence in the band."""
        return float(self.coherence.mean())

    def to_dataframe(self) -> pd.DataFrame:
        """One row per frequency (see :meth:`FrfEstimate.to_dataframe`)."""
        table = self.estimate.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table

    def report(self) -> str:
        """Short text summary."""
        peak = int(np.argmax(np.abs(self.h1)))
        return (f"{self.measurement_id}: {self.band[0]:g}-{self.band[1]:g} Hz, peak |H1| "
                f"{abs(self.h1[peak]):.3g} at {self.freq[peak]:.3g} Hz, coherence mean "
                f"{self.mean_coherence:.3f} min {self.min_coherence:.3f}, "
                f"{self.estimate.n_segments} segments of {self.estimate.nperseg}")


def frf_from_white_noise(measurement: WhiteNoiseMeasurement, *,
                         band: tuple[float, float] | None = None,
                         nperseg: int | None = None, overlap: float = 0.5,
                         signals: str | None = None) -> WhiteNoiseFrf:
    """H1, H2 and coherence of a white-noise shaker run (Welch, Hann window).

    Parameters
    ----------
    measurement : WhiteNoiseMeasurement
        Base and top-mass velocities (or accelerations).
    band : (float, float), optional
        Band kept, Hz. Default: the declared excitation band (``info.excitation.band``)
        clipped to the Nyquist frequency, or 0 - Nyquist. SPEC 3 identifies on (1, 100).
    nperseg : int, optional
        Samples per segment. Default ``min(round(2 fs), n // 4)``: 0.5 Hz resolution when
        the record holds at least 4 segments (7 averages at 50 % overlap).
    overlap : float, default 0.5
        Segment overlap fraction.
    signals : {"velocity", "acceleration"}, optional
        Which pair to use; default velocity when present.

    Returns
    -------
    WhiteNoiseFrf

    Raises
    ------
    DataError
        Wrong measurement type, requested signals missing, or the errors of
        :func:`~idkit.analysis.frf.estimate_frf`.
    """
    _require(measurement, WhiteNoiseMeasurement, "frf_from_white_noise")
    if signals is None:
        signals = "velocity" if measurement.v_base is not None else "acceleration"
    if signals == "velocity":
        base, top = measurement.v_base, measurement.v_top
    elif signals == "acceleration":
        base, top = measurement.a_base, measurement.a_top
    else:
        raise DataError(f"signals: found {signals!r}, expected 'velocity' or 'acceleration'")
    if base is None:
        raise DataError(f"{measurement.id}: no {signals} signals in the measurement")
    fs = _sample_rate(measurement.time)
    if band is None:
        declared = measurement.band
        band = (0.0, fs / 2) if declared is None else (declared[0], min(declared[1], fs / 2))
    band = (float(band[0]), float(band[1]))
    if nperseg is None:
        nperseg = int(min(round(2 * fs), base.size // 4))
    estimate = estimate_frf(base, top, fs=fs, nperseg=nperseg, overlap=overlap,
                            f_lo=band[0], f_hi=band[1])
    return WhiteNoiseFrf(measurement_id=measurement.id, top_mass_kg=measurement.info.top_mass_kg,
                         signals=signals, estimate=estimate, band=band)


# ---------------------------------------------------------------------------------------------
# stepped sine


@dataclass(frozen=True)
class SteppedSinePoint:
    """HOSIDFs of one stepped-sine point (v_base -> v_top).

    Attributes
    ----------
    measurement_id : str
        ``info.id``.
    isolator : str or None
        Isolator name.
    top_mass_kg : float or None
        Top mass, kg.
    freq : float
        Excitation frequency, Hz.
    nominal_amplitude : float or None
        Declared amplitude (SI unit of ``info.excitation.amplitude_quantity``).
    result : HosidfResult
        Harmonic fits of input and output and the HOSIDFs.
    """

    measurement_id: str
    isolator: str | None
    top_mass_kg: float | None
    freq: float
    nominal_amplitude: float | None
    result: HosidfResult

    @property
    def hosidf(self) -> np.ndarray:
        """Complex HOSIDFs of orders 1..K."""
        return self.result.hosidf

    @property
    def input_amplitude(self) -> float:
        """First-harmonic amplitude of v_base, m/s."""
        return self.result.input_amplitude

    @property
    def input_distortion(self) -> np.ndarray:
        """``|C2| / |C1|`` and ``|C3| / |C1|`` of v_base."""
        return self.result.input_distortion

    def to_dataframe(self) -> pd.DataFrame:
        """One row per order (see :meth:`HosidfResult.to_dataframe`) with the id."""
        table = self.result.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table


def hosidf_from_stepped_sine(measurement: SteppedSineMeasurement, *, n_harmonics: int = 5,
                             subharmonic: bool = True) -> SteppedSinePoint:
    """HOSIDFs of one stepped-sine point: harmonics of v_top over the first harmonic of v_base.

    The whole record is analysed over the largest even number of excitation periods that fits,
    aligned with its end (:func:`~idkit.analysis.harmonics.fit_harmonics`). The number of
    harmonics is reduced so that the highest one stays below the Nyquist frequency.

    Parameters
    ----------
    measurement : SteppedSineMeasurement
        One (frequency, amplitude) point.
    n_harmonics : int, default 5
        Output harmonics 1..K (fewer if K f reaches fs/2).
    subharmonic : bool, default True
        Fit the 1/2 subharmonic.

    Returns
    -------
    SteppedSinePoint
    """
    _require(measurement, SteppedSineMeasurement, "hosidf_from_stepped_sine")
    fs = _sample_rate(measurement.time)
    freq = measurement.freq
    usable = int(np.ceil(fs / 2 / freq)) - 1
    if usable < 1:
        raise DataError(f"{measurement.id}: frequency {freq:g} Hz is at or above the Nyquist "
                        f"frequency {fs / 2:g} Hz")
    result = hosidf(measurement.v_base, measurement.v_top, fs=fs, freq=freq,
                    n_harmonics=min(int(n_harmonics), usable), subharmonic=subharmonic)
    return SteppedSinePoint(measurement_id=measurement.id, isolator=measurement.info.isolator,
                            top_mass_kg=measurement.info.top_mass_kg, freq=freq, nominal_amplitude=measurement.nominal_amplitude,
                            result=result)


@dataclass(frozen=True)
class SteppedSineSweep:
    """HOSIDFs of a set of stepped-sine points with the input-quality report.

    Attributes
    ----------
    points : tuple of SteppedSinePoint
        Every point, in the order given.
    flatness : dict
        ``{(isolator, top_mass_kg, nominal_amplitude): InputFlatness}``: first-harmonic base
        amplitude versus frequency of each sweep (one nominal level of one setup).
    """

    points: tuple[SteppedSinePoint, ...]
    flatness: dict

    @property
    def max_input_distortion(self) -> float:
        """Largest ``|C2|/|C1|`` or ``|C3|/|C1|`` of the input over all points."""
        values = np.array([p.input_distortion for p in self.points], dtype=float)
        return float(np.nanmax(values)) if values.size else float("nan")

    def to_dataframe(self) -> pd.DataFrame:
        """One row per point: id, isolator, freq, nominal and measured input amplitude,
        input distortion (2nd, 3rd), |HOSIDF| and phase of orders 1..3, |subharmonic|."""
        rows = []
        for p in self.points:
            row = {"measurement_id": p.measurement_id, "isolator": p.isolator, "freq_Hz": p.freq,
                   "nominal_amplitude": p.nominal_amplitude, "input_amplitude": p.input_amplitude,
                   "input_distortion_2": p.input_distortion[0],
                   "input_distortion_3": p.input_distortion[1]}
            for order in range(1, 4):
                value = p.hosidf[order - 1] if order <= p.hosidf.size else np.nan
                row[f"abs_H{order}"] = abs(value)
                row[f"phase_H{order}_rad"] = float(np.angle(value))
            row["abs_H0.5"] = abs(p.result.subharmonic)
            rows.append(row)
        return pd.DataFrame(rows)

    def report(self) -> str:
        """Input distortion and flatness per sweep."""
        lines = [f"{len(self.points)} stepped-sine points; input distortion up to "
                 f"{self.max_input_distortion:.2%} of the first harmonic"]
        for (isolator, mass, nominal), flat in self.flatness.items():
            lines.append(f"  {isolator} {mass} kg, nominal {nominal:g}: base amplitude max/min "
                         f"{flat.ratio:.2f} ({flat.ratio_db:.1f} dB), min at {flat.freq_of_min:g} Hz, "
                         f"max at {flat.freq_of_max:g} Hz")
        return "\n".join(lines)


def stepped_sine_sweep(measurements: Iterable[SteppedSineMeasurement], *, n_harmonics: int = 5,
                       subharmonic: bool = True) -> SteppedSineSweep:
    """HOSIDFs of every point and the input flatness of every sweep.

    Points are grouped into sweeps by (isolator, top mass, nominal amplitude); the flatness of
    each sweep is :func:`~idkit.analysis.harmonics.input_flatness` of the measured first
    harmonic of v_base over frequency (SPEC 3: the shaker does not keep it flat).

    Parameters
    ----------
    measurements : iterable of SteppedSineMeasurement
    n_harmonics, subharmonic : see :func:`hosidf_from_stepped_sine`.

    Returns
    -------
    SteppedSineSweep
    """
    points = tuple(hosidf_from_stepped_sine(m, n_harmonics=n_harmonics, subharmonic=subharmonic)
                   for m in measurements)
    groups: dict = {}
    for p in points:
        groups.setdefault((p.isolator, p.top_mass_kg, p.nominal_amplitude), []).append(p)
    flatness: dict[tuple, InputFlatness] = {}
    for key, members in groups.items():
        members = sorted(members, key=lambda q: q.freq)
        flatness[key] = input_flatness([q.freq for q in members],
                                       [q.input_amplitude for q in members])
    return SteppedSineSweep(points=points, flatness=flatness)


# ---------------------------------------------------------------------------------------------
# drops


@dataclass(frozen=True)
class DropMeasurementResult:
    """Characteristic values of one drop test.

    Attributes
    ----------
    measurement_id : str
        ``info.id``.
    isolator : str or None
        Isolator name.
    top_mass_kg : float or None
        Top mass, kg.
    drop_height_m : float or None
        Declared drop height, m.
    result : DropResult
        Impact, impact velocities (measured and from the height), phase peaks, peak
        deflections and the processed records.
    """

    measurement_id: str
    isolator: str | None
    top_mass_kg: float | None
    drop_height_m: float | None
    result: DropResult

    @property
    def impact_velocity(self) -> float:
        """Measured impact velocity, m/s (negative)."""
        return self.result.impact_velocity

    @property
    def impact_velocity_from_height(self) -> float:
        """``-sqrt(2 g h)`` from the declared height, m/s."""
        return self.result.impact_velocity_from_height

    @property
    def peak_acceleration(self) -> float:
        """Rest shock level: largest acceleration magnitude after the impact, m/s^2."""
        return self.result.peak_acceleration

    def to_dataframe(self) -> pd.DataFrame:
        """One-row table (see :meth:`DropResult.to_dataframe`) with id, masses and height."""
        table = self.result.to_dataframe()
        table.insert(0, "drop_height_m", self.drop_height_m)
        table.insert(0, "top_mass_kg", self.top_mass_kg)
        table.insert(0, "isolator", self.isolator)
        table.insert(0, "measurement_id", self.measurement_id)
        return table


def process_drop_measurement(measurement: DropMeasurement, *, window: int = 5,
                             impact_fraction: float = 0.5) -> DropMeasurementResult:
    """Process one drop test (SPEC 3): mean of the two accelerometers, zero-phase 5-sample
    moving average, impact from the step in relative velocity, shock peaks.

    The relative velocity is the recorded ``v_rel`` (laser vibrometer) when present,
    otherwise the derivative of the deflection. Accelerations are used as recorded
    (kinematic, 1 g offset removed at rest), see :func:`~idkit.analysis.drop.process_drop`.

    Parameters
    ----------
    measurement : DropMeasurement
        The drop record; ``info.drop_height_m`` gives the height-based impact velocity.
    window : int, default 5
        Moving-average length, samples.
    impact_fraction : float, default 0.5
        Fraction of the most negative relative velocity that marks the impact.

    Returns
    -------
    DropMeasurementResult
    """
    _require(measurement, DropMeasurement, "process_drop_measurement")
    result = process_drop(measurement.time, measurement.deflection,
                          np.vstack([measurement.a_top_1, measurement.a_top_2]),
                          relative_velocity=measurement.v_rel,
                          drop_height=measurement.info.drop_height_m, window=window,
                          impact_fraction=impact_fraction)
    info = measurement.info
    return DropMeasurementResult(measurement_id=measurement.id, isolator=info.isolator,
                                 top_mass_kg=info.top_mass_kg, drop_height_m=info.drop_height_m,
                                 result=result)


# ---------------------------------------------------------------------------------------------
# overview and data-quality warnings


def find_clipping(signal, *, min_run: int = 5) -> tuple[int, float]:
    """Longest run of samples stuck at the record's maximum or minimum (a clipped sensor).

    Parameters
    ----------
    signal : array_like
        Record (any unit).
    min_run : int, default 5
        Runs shorter than this are ignored (a smooth peak may repeat a rounded value a few
        times).

    Returns
    -------
    (int, float)
        Length of the longest run at an extreme (0 if none reaches ``min_run``) and the
        value it sits at.

    Examples
    --------
    >>> find_clipping([0.0, 1.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 1.0])
    (6, 2.0)
    """
    values = np.asarray(signal, dtype=float)
    best, level = 0, float("nan")
    for extreme in (values.max(), values.min()):
        at = np.concatenate([[False], values == extreme, [False]])
        edges = np.flatnonzero(np.diff(at.astype(np.int8)))
        runs = edges[1::2] - edges[::2]
        if runs.size and runs.max() > best:
            best, level = int(runs.max()), float(extreme)
    return (best, level) if best >= min_run else (0, float("nan"))


@dataclass(frozen=True)
class InspectionWarning:
    """A data-quality finding.

    Attributes
    ----------
    measurement_id : str
        Measurement (or sweep) concerned.
    kind : str
        ``clipped``, ``non_flat_input``, ``input_distortion`` or ``low_coherence``.
    message : str
        What was found and what was expected.
    """

    measurement_id: str
    kind: str
    message: str


@dataclass(frozen=True)
class MeasurementSummary:
    """Overview of a collection of measurements and their data-quality warnings.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per measurement: id, kind, isolator, split, sample rate (Hz), duration (s),
        samples, masses (kg), drop height (m), frequency (Hz), nominal amplitude.
    warnings : tuple of InspectionWarning
        Findings, in measurement order.
    """

    table: pd.DataFrame
    warnings: tuple[InspectionWarning, ...]

    def to_dataframe(self) -> pd.DataFrame:
        """The per-measurement table (a copy)."""
        return self.table.copy()

    def report(self) -> str:
        """Human-readable summary: counts, ranges per kind, then the warnings."""
        t = self.table
        lines = [f"{len(t)} measurements: " + ", ".join(
            f"{n} {kind}" for kind, n in t["kind"].value_counts(sort=False).items())]
        if t["split"].notna().any():
            lines.append("split: " + ", ".join(
                f"{n} {split}" for split, n in t["split"].value_counts(sort=False).items()))

        def span(column, scale=1.0, unit=""):
            values = t_kind[column].dropna().to_numpy(dtype=float) * scale
            if values.size == 0:
                return None
            low, high = values.min(), values.max()
            return f"{low:.4g} {unit}".strip() if low == high else f"{low:.4g}-{high:.4g} {unit}".strip()

        for kind, t_kind in t.groupby("kind", sort=False):
            isolators = ", ".join(sorted(str(v) for v in t_kind["isolator"].dropna().unique()))
            parts = [f"{kind}: {len(t_kind)}", f"isolators {isolators or '-'}",
                     f"fs {span('sample_rate_Hz', unit='Hz')}",
                     f"duration {span('duration_s', unit='s')}"]
            for column, label, scale, unit in (("top_mass_kg", "top mass", 1, "kg"),
                                               ("drop_height_m", "height", 100, "cm"),
                                               ("freq_Hz", "freq", 1, "Hz"),
                                               ("nominal_amplitude", "nominal amplitude", 1, ""),
                                               ("deflection_range_mm", "deflection", 1, "mm")):
                text = span(column, scale, unit)
                if text is not None:
                    parts.append(f"{label} {text}")
            lines.append("  " + "; ".join(parts))
        if self.warnings:
            lines.append(f"{len(self.warnings)} warning(s):")
            lines.extend(f"  [{w.kind}] {w.measurement_id}: {w.message}" for w in self.warnings)
        else:
            lines.append("no warnings")
        return "\n".join(lines)


def summarize_measurements(measurements: Sequence, *, clip_run: int = 5,
                           flatness_limit: float = 1.25, distortion_limit: float = 0.03,
                           coherence_band: tuple[float, float] = (1.0, 100.0),
                           coherence_limit: float = 0.9) -> MeasurementSummary:
    """Overview table and data-quality warnings of a set of measurements (``idkit inspect``).

    Warnings:

    - ``clipped``: a signal sits at its maximum or minimum for ``clip_run`` or more
      consecutive samples (:func:`find_clipping`);
    - ``non_flat_input``: a stepped-sine sweep whose first-harmonic base amplitude varies by
      more than ``flatness_limit`` (max/min) over frequency;
    - ``input_distortion``: a stepped-sine point whose base 2nd or 3rd harmonic exceeds
      ``distortion_limit`` of the first;
    - ``low_coherence``: a white-noise run whose mean coherence in ``coherence_band`` is
      below ``coherence_limit``.

    Parameters
    ----------
    measurements : sequence of measurements
        E.g. ``load_measurement_set(folder).measurements``.
    clip_run, flatness_limit, distortion_limit, coherence_band, coherence_limit
        Thresholds above.

    Returns
    -------
    MeasurementSummary
    """
    rows, warnings = [], []
    sine = []
    for m in measurements:
        info = m.info
        exc = info.excitation
        fs = _sample_rate(m.time)
        row = {"id": m.id, "kind": m.kind, "isolator": info.isolator, "split": info.split,
               "sample_rate_Hz": fs, "duration_s": float(m.time[-1] - m.time[0]),
               "n_samples": m.n_samples, "top_mass_kg": info.top_mass_kg,
               "drop_height_m": info.drop_height_m,
               "freq_Hz": None if exc is None else exc.freq,
               "nominal_amplitude": None if exc is None else exc.amplitude,
               "deflection_range_mm": None}
        if getattr(m, "deflection", None) is not None:
            row["deflection_range_mm"] = float(np.ptp(m.deflection)) * 1e3
        rows.append(row)
        for name, values in m.signals().items():
            if name == "time":
                continue
            run, level = find_clipping(values, min_run=clip_run)
            if run:
                warnings.append(InspectionWarning(
                    m.id, "clipped", f"{name} stays at its extreme {level:.6g} (SI) for {run} "
                    f"consecutive samples; expected a signal that does not saturate"))
        if isinstance(m, SteppedSineMeasurement):
            sine.append(m)
        if isinstance(m, WhiteNoiseMeasurement):
            low, high = coherence_band
            frf = frf_from_white_noise(m, band=(low, min(high, fs / 2)))
            if frf.mean_coherence < coherence_limit:
                warnings.append(InspectionWarning(
                    m.id, "low_coherence", f"mean coherence {frf.mean_coherence:.3f} in "
                    f"{low:g}-{high:g} Hz (min {frf.min_coherence:.3f}); expected >= "
                    f"{coherence_limit:g}"))
    if sine:
        sweep = stepped_sine_sweep(sine, n_harmonics=3)
        for p in sweep.points:
            worst = float(np.nanmax(p.input_distortion))
            if worst > distortion_limit:
                warnings.append(InspectionWarning(
                    p.measurement_id, "input_distortion", f"base harmonic 2/3 at {worst:.2%} of "
                    f"the first; expected <= {distortion_limit:.0%}"))
        for (isolator, mass, nominal), flat in sweep.flatness.items():
            if flat.ratio > flatness_limit:
                warnings.append(InspectionWarning(
                    f"sweep {isolator} {mass} kg nominal {nominal:g}", "non_flat_input",
                    f"first-harmonic base amplitude varies {flat.ratio:.2f}:1 over frequency "
                    f"(min at {flat.freq_of_min:g} Hz, max at {flat.freq_of_max:g} Hz); "
                    f"expected <= {flatness_limit:g}:1; report results against the measured "
                    "first harmonic"))
    return MeasurementSummary(table=pd.DataFrame(rows), warnings=tuple(warnings))
