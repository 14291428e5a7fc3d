"""Quasi-static records -> cycles, amplitudes and resampled loops (SPEC 4).

The one place a force-deflection record becomes loops, for ``idkit inspect``
(:func:`process_quasi_static`) and the loop fits (:func:`prepare_loops`,
:func:`loop_sets`) alike: both cut the record at the reversals that
:func:`~idkit.signal.cycles.split_cycles` finds with the noise-based threshold
:func:`~idkit.signal.cycles.reversal_threshold`, so they see the same cycles.

* :func:`prepare_loops` / :class:`LoopSet` - one record cut at its first and last
  reversal and resampled, as the fitters take it; :func:`as_loop_sets` coerces loose
  inputs (pairs of arrays, objects with ``.deflection``/``.force``).
* :func:`loop_sets` / :class:`LoopData` - the quasi-static records of a measurement set
  split **per measurement** into small and large sets by their amplitude (half the
  peak-to-peak deflection). Default threshold :data:`SMALL_THRESHOLD` = 8 mm: the study's
  small-loop sets reach 4.5 mm and its large-loop sets 15 mm (SPEC 3); 8 mm is about their
  geometric mean, so either kind of set may over- or undershoot its nominal amplitude by
  40 % and still be classified right.
* :func:`estimate_k0` / :class:`K0Estimate` and :func:`k0_from_measurements` /
  :class:`K0FromLoops` - the elastomer's static stiffness, the slope around the origin.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.errors import FitError
from idkit.io import QuasiStaticMeasurement
from idkit.io.provenance import DataProvenance, select_measurements
from idkit.observe._common import _require
from idkit.signal.cycles import (
    CycleSplit,
    ResampledLoops,
    noise_level,
    resample_loops,
    reversal_threshold,
    split_cycles,
)

__all__ = [
    "QuasiStaticResult", "process_quasi_static",
    "MIN_POINTS", "UNLOADED_FRACTION", "LoopSet", "prepare_loops", "as_loop_sets",
    "SMALL_THRESHOLD", "LOOP_POINTS_PER_SET", "LoopData", "loop_sets",
    "K0Estimate", "estimate_k0", "K0FromLoops", "k0_from_measurements", "k0_from_records", "record_cycles",
]

MIN_POINTS = 20  # per set, after resampling: fewer cannot resolve slip onset and loop height
#: A record "starts unloaded" when its first deflection and force are within this share
#: of their largest magnitudes in the record (an isolator at rest, sensors zeroed).
UNLOADED_FRACTION = 0.02
#: Default amplitude (m) separating small-loop from large-loop quasi-static records.
SMALL_THRESHOLD = 8e-3
#: Default resampled points per quasi-static record: about 20 per branch for the
#: study's 15-loop records (30 branches); 200 would leave 7 points on a 4.5 mm branch.
LOOP_POINTS_PER_SET = 600


def record_cycles(deflection, *, min_excursion: float | None = None,
                  large_threshold: float | None = None) -> CycleSplit:
    """Reversals, branches and cycles of a deflection record with the one default threshold.

    Parameters
    ----------
    deflection : array_like, shape (n,)
        Deflection record in m.
    min_excursion : float, optional
        Reversal threshold in m; default :func:`~idkit.signal.cycles.reversal_threshold`
        (ten times the deflection noise, at least 0.1 % of the range).
    large_threshold : float, optional
        Amplitude in m above which a cycle is "large".

    Returns
    -------
    CycleSplit
        As :func:`~idkit.signal.cycles.split_cycles`; :func:`process_quasi_static` and
        :func:`prepare_loops` both call this, so ``inspect`` and the fits see the same cycles.

    Raises
    ------
    FitError
        No reversal found (:func:`~idkit.signal.cycles.split_cycles`).
    """
    x = np.asarray(deflection, dtype=float)
    threshold = reversal_threshold(x) if min_excursion is None else float(min_excursion)
    return split_cycles(x, min_excursion=threshold, large_threshold=large_threshold)


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
        Reversal threshold in m (:func:`~idkit.signal.cycles.find_reversals`). Default
        :func:`~idkit.signal.cycles.reversal_threshold`, ``max(10 * noise, 1e-3 * range)``:
        ten times the estimated deflection noise (:func:`noise_level`), at least a thousandth
        of the deflection range; well below the smallest loop of SPEC 3 (0.05 mm amplitude)
        for a micrometre-level sensor. The fits use the same (:func:`prepare_loops`).
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
    cycles = record_cycles(x, min_excursion=min_excursion, large_threshold=large_threshold)
    loops = resample_loops(x, measurement.force, split=cycles, points_per_branch=points_per_branch,
                           spacing=spacing)
    return QuasiStaticResult(measurement_id=measurement.id, cycles=cycles, loops=loops,
                             min_excursion=float(min_excursion), deflection_noise=noise)


# ---------------------------------------------------------------------------------------------
# loop sets for the fits


@dataclass(frozen=True)
class LoopSet:
    """One quasi-static data set ready for fitting (a path starting at a reversal).

    Attributes
    ----------
    deflection : ndarray, shape (n,)
        Deflection path in m (positive = tension).
    force : ndarray, shape (n,)
        Measured force in N.
    reversals : ndarray of int
        Indices of the first point, every reversal and the last point.
    name : str
    starts_unloaded : bool
        The raw record began unloaded (deflection and force within
        :data:`UNLOADED_FRACTION` of their peaks) and reached the first point of the
        set without a reversal: the "virgin" start state is then exact.
    """

    deflection: np.ndarray
    force: np.ndarray
    reversals: np.ndarray
    name: str = ""
    starts_unloaded: bool = False

    @property
    def amplitude(self) -> float:
        """Half the peak-to-peak deflection, m."""
        return 0.5 * float(np.ptp(self.deflection))


def _as_pair(item, index: int, group: str):
    if isinstance(item, LoopSet):
        return item.deflection, item.force, item.name or f"{group}{index}"
    if hasattr(item, "deflection") and hasattr(item, "force"):
        return item.deflection, item.force, getattr(item, "name", "") or f"{group}{index}"
    try:
        deflection, force = item
    except (TypeError, ValueError):
        raise FitError(
            f"{group} set {index}: found {type(item).__name__}, expected a (deflection, force) pair "
            "of arrays or an object with .deflection and .force"
        ) from None
    return deflection, force, f"{group}{index}"


def _check_record(values, what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.ndim != 1:
        raise FitError(f"{what}: found shape {array.shape}, expected a 1-D array")
    if array.size < MIN_POINTS:
        raise FitError(f"{what}: found {array.size} points, expected at least {MIN_POINTS}")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise FitError(f"{what}: found {array[bad[0]]} at index {bad[0]}, expected finite values")
    return array


def prepare_loops(
    deflection,
    force,
    *,
    points_per_set: int | None = 200,
    min_excursion: float | None = None,
    name: str = "",
) -> LoopSet:
    """Cut a loop record to its complete branches and resample it to a fixed size.

    Parameters
    ----------
    deflection, force : array_like, shape (n,)
        Record in m and N, at least 20 finite points, with at least two reversals.
    points_per_set : int or None, default 200
        Total points of the resampled set (every branch gets the same count, the
        reversals are kept exactly, :func:`idkit.signal.cycles.resample_loops` with
        equal deflection spacing). ``None`` keeps the record as given after
        cutting it at the first and last reversal.
    min_excursion : float, optional
        Reversal threshold in m; default :func:`idkit.signal.cycles.reversal_threshold`
        (ten times the record's deflection noise, at least 0.1 % of its range), so every
        loop the record holds enters the fit; the threshold of :func:`process_quasi_static`.
    name : str

    Returns
    -------
    LoopSet

    Raises
    ------
    FitError
        Too few or non-finite points, mismatched lengths, fewer than two reversals.
    """
    what = f"set {name!r}" if name else "set"
    x = _check_record(deflection, f"{what} deflection")
    f = _check_record(force, f"{what} force")
    if f.size != x.size:
        raise FitError(f"{what}: found {f.size} force and {x.size} deflection samples, expected equal counts")
    span = float(np.ptp(x))
    if span <= 0:
        raise FitError(f"{what} deflection: found a constant record, expected loops with reversals")
    try:
        split = record_cycles(x, min_excursion=min_excursion)
    except FitError as error:
        raise FitError(f"{what}: {error}") from None
    if split.branch_start.size == 0:
        raise FitError(
            f"{what} deflection: found {split.reversals.size} reversal, expected at least 2 "
            "(one complete branch between reversals)"
        )
    n_branches = split.branch_start.size
    if points_per_set is None:
        first, last = int(split.reversals[0]), int(split.reversals[-1])
        path_x, path_f = x[first : last + 1], f[first : last + 1]
        reversals = np.concatenate([split.reversals - first])
    else:
        if int(points_per_set) != points_per_set or points_per_set < MIN_POINTS:
            raise FitError(f"points_per_set: found {points_per_set!r}, expected an integer >= {MIN_POINTS}")
        per_branch = max(2, int(math.ceil((points_per_set - 1) / n_branches)) + 1)
        loops = resample_loops(x, f, split=split, points_per_branch=per_branch)
        path_x, path_f = loops.deflection, loops.force
        reversals = np.arange(n_branches + 1) * (per_branch - 1)
    if path_x.size < MIN_POINTS:
        raise FitError(f"{what}: found {path_x.size} points between the first and last reversal, "
                       f"expected at least {MIN_POINTS}")
    if not np.any(path_f):
        raise FitError(f"{what} force: found all zeros, expected a measured force (the error (7.1) divides by it)")
    unloaded = (abs(x[0]) <= UNLOADED_FRACTION * np.max(np.abs(x))
                and abs(f[0]) <= UNLOADED_FRACTION * np.max(np.abs(f)))
    return LoopSet(deflection=np.ascontiguousarray(path_x), force=np.ascontiguousarray(path_f),
                   reversals=reversals.astype(np.intp), name=name, starts_unloaded=bool(unloaded))


def as_loop_sets(sets, group: str, points_per_set: int | None = 200) -> list[LoopSet]:
    """The one coercion of loose loop inputs into named :class:`LoopSet` items.

    Parameters
    ----------
    sets : sequence
        Items that are :class:`LoopSet` (kept, named ``{group}{index}`` when unnamed),
        ``(deflection, force)`` pairs of arrays in m and N, or objects with ``.deflection``
        and ``.force`` (e.g. :class:`~idkit.signal.cycles.ResampledLoops`); the latter two
        are prepared by :func:`prepare_loops`.
    group : str
        Name of the group in messages and default set names, e.g. ``"small"``.
    points_per_set : int or None, default 200
        See :func:`prepare_loops`.

    Returns
    -------
    list of LoopSet

    Raises
    ------
    FitError
        No set, an item of another type, or the errors of :func:`prepare_loops`.
    """
    if sets is None or len(sets) == 0:
        raise FitError(f"{group}: found no data set, expected at least one loop set")
    prepared = []
    for index, item in enumerate(sets):
        if isinstance(item, LoopSet):
            prepared.append(item if item.name else dataclasses.replace(item, name=f"{group}{index}"))
            continue
        deflection, force, name = _as_pair(item, index, group)
        prepared.append(prepare_loops(deflection, force, points_per_set=points_per_set, name=name))
    return prepared


@dataclass(frozen=True)
class LoopData:
    """Quasi-static records split into small and large loop sets.

    ``small_repetitions`` / ``large_repetitions`` hold each set's repetition number
    (``info.repetition``, or its position when absent) for the bootstrap.
    ``amplitudes`` maps measurement id -> amplitude in m.
    """

    small: tuple[LoopSet, ...]
    large: tuple[LoopSet, ...]
    small_repetitions: tuple[int, ...]
    large_repetitions: tuple[int, ...]
    amplitudes: dict
    threshold: float
    provenance: DataProvenance


def loop_sets(
    measurements,
    *,
    small_threshold: float = SMALL_THRESHOLD,
    isolator: str | None = "wire_rope",
    split: str | None = "fit",
    points_per_set: int | None = LOOP_POINTS_PER_SET,
    min_excursion: float | None = None,
) -> LoopData:
    """Quasi-static records -> small and large loop sets (one set per record).

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
        Selected by :func:`idkit.io.provenance.select_measurements`.
    small_threshold : float, default :data:`SMALL_THRESHOLD` (8e-3 m)
        A record whose amplitude (half its peak-to-peak deflection) is at most this
        is a small-loop set, otherwise a large-loop set.
    isolator : str or None, default "wire_rope"
        Only records of this isolator (None: any).
    split : {"fit", "validation", None}, default "fit"
    points_per_set : int or None, default :data:`LOOP_POINTS_PER_SET`
        See :func:`prepare_loops`.
    min_excursion : float, optional
        Reversal threshold in m; default :func:`idkit.signal.cycles.reversal_threshold` of
        each record, the threshold :func:`process_quasi_static` (``idkit inspect``) uses.

    Returns
    -------
    LoopData

    Raises
    ------
    FitError
        No matching record, a record without reversals, or only small or only
        large sets (the message lists the amplitudes and the threshold).
    """
    if not (math.isfinite(small_threshold) and small_threshold > 0):
        raise FitError(f"small_threshold: found {small_threshold!r}, expected a positive amplitude in m")
    records, provenance = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    small, large, small_rep, large_rep, amplitudes = [], [], [], [], {}
    for position, record in enumerate(records, start=1):
        name = record.id or f"record{position}"
        amplitude = 0.5 * float(np.ptp(record.deflection))
        amplitudes[name] = amplitude
        try:
            prepared = prepare_loops(record.deflection, record.force, points_per_set=points_per_set,
                                     min_excursion=min_excursion, name=name)
        except FitError as problem:
            raise FitError(f"{record.source.where()}: {problem}") from None
        repetition = record.info.repetition if record.info.repetition is not None else position
        if amplitude <= small_threshold:
            small.append(prepared)
            small_rep.append(repetition)
        else:
            large.append(prepared)
            large_rep.append(repetition)
    if not small or not large:
        listed = ", ".join(f"{name}: {1e3 * a:.3g} mm" for name, a in amplitudes.items())
        missing = "small" if not small else "large"
        raise FitError(f"loops: found no {missing}-loop record with small_threshold={1e3 * small_threshold:g} mm "
                       f"(amplitudes {listed}); expected both small and large loop sets")
    return LoopData(small=tuple(small), large=tuple(large), small_repetitions=tuple(small_rep),
                    large_repetitions=tuple(large_rep), amplitudes=amplitudes, threshold=float(small_threshold),
                    provenance=provenance)


# ---------------------------------------------------------------------------------------------
# static stiffness


@dataclass(frozen=True)
class K0Estimate:
    """Static stiffness from the quasi-static slope around the origin.

    ``k0`` (N/m) is the least-squares slope of ``force = a + k0 * deflection`` over
    the points with ``|deflection| <= window``; ``stderr`` its standard error from
    the residual variance (N/m); ``intercept`` ``a`` in N; ``n_points`` used.
    """

    k0: float
    stderr: float
    intercept: float
    n_points: int
    window: float


def estimate_k0(deflection, force, window: float) -> K0Estimate:
    """Least-squares slope of force over deflection around the origin, with its standard error.

    Parameters
    ----------
    deflection, force : array_like
        Quasi-static record in m and N.
    window : float
        Half-width in m of the deflection window around 0 (e.g. 1e-3).

    Returns
    -------
    K0Estimate

    Raises
    ------
    FitError
        Fewer than 3 points in the window, non-finite values, a non-positive slope.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-2e-3, 2e-3, 101)
    >>> round(estimate_k0(x, 1.4e4 * x + 0.1, window=1e-3).k0)
    14000
    """
    x = np.asarray(deflection, dtype=float)
    f = np.asarray(force, dtype=float)
    if x.shape != f.shape or x.ndim != 1:
        raise FitError(f"estimate_k0: found deflection shape {x.shape} and force shape {f.shape}, "
                       "expected equal 1-D shapes")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(f))):
        raise FitError("estimate_k0: found non-finite deflection or force, expected finite values")
    if not (math.isfinite(window) and window > 0):
        raise FitError(f"estimate_k0: found window={window!r}, expected a positive half-width in m")
    inside = np.abs(x) <= window
    n = int(inside.sum())
    if n < 3 or np.ptp(x[inside]) <= 0:
        raise FitError(f"estimate_k0: found {n} points with |deflection| <= {window:g} m, "
                       "expected at least 3 distinct deflections (widen the window)")
    design = np.column_stack([np.ones(n), x[inside]])
    coefficients, _, _, _ = np.linalg.lstsq(design, f[inside], rcond=None)
    residual = f[inside] - design @ coefficients
    variance = float(residual @ residual) / max(n - 2, 1)
    covariance = variance * np.linalg.inv(design.T @ design)
    slope = float(coefficients[1])
    if not slope > 0:
        raise FitError(f"estimate_k0: found slope {slope:g} N/m, expected a positive stiffness "
                       "(is tension positive in both deflection and force?)")
    return K0Estimate(k0=slope, stderr=float(math.sqrt(covariance[1, 1])), intercept=float(coefficients[0]),
                      n_points=n, window=float(window))


@dataclass(frozen=True)
class K0FromLoops:
    """Static stiffness of the elastomer from its quasi-static loops.

    Attributes
    ----------
    k0 : float
        Pooled least-squares slope around the origin, N/m.
    stderr : float
        Its uncertainty (N/m): the larger of the regression standard error of the
        pooled fit and the standard error of the mean of the per-record slopes
        (records differ by more than the regression within one record admits).
    pooled : K0Estimate
    per_record : dict
        Measurement id -> slope (N/m).
    window : float
        Half-width of the deflection window, m.
    """

    k0: float
    stderr: float
    pooled: K0Estimate
    per_record: dict
    window: float


def k0_from_measurements(
    measurements,
    *,
    window: float = 1e-3,
    isolator: str | None = "elastomer",
    split: str | None = "fit",
) -> K0FromLoops:
    """Static stiffness from the quasi-static loops: slope around the origin with its uncertainty.

    Parameters
    ----------
    measurements : MeasurementSet or sequence of QuasiStaticMeasurement
    window : float, default 1e-3
        Half-width (m) of the deflection window around 0.
    isolator, split : as :func:`loop_sets`

    Returns
    -------
    K0FromLoops
        The pooled slope (:func:`estimate_k0` on all records' points), its uncertainty and
        each record's own slope.

    Raises
    ------
    FitError
        Fewer than 3 points in the window, a non-positive slope (:func:`estimate_k0`).
    DataError
        No quasi-static record matches the selection.
    """
    records, _ = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    return k0_from_records(records, window=window)


def k0_from_records(records, *, window: float = 1e-3) -> K0FromLoops:
    """Static stiffness from quasi-static records already selected (:func:`k0_from_measurements`).

    Parameters
    ----------
    records : sequence of QuasiStaticMeasurement
        At least one record.
    window : float, default 1e-3
        Half-width (m) of the deflection window around 0.

    Returns
    -------
    K0FromLoops

    Raises
    ------
    FitError
        No record, fewer than 3 points in the window, a non-positive slope.
    DataError
        An item that is not a :class:`~idkit.io.QuasiStaticMeasurement`.
    """
    records = list(records)
    if not records:
        raise FitError("records: found none, expected at least one quasi-static record")
    for record in records:
        _require(record, QuasiStaticMeasurement, "k0_from_records")
    x = np.concatenate([r.deflection for r in records])
    f = np.concatenate([r.force for r in records])
    pooled = estimate_k0(x, f, window)
    per_record = {r.id or f"record{i}": estimate_k0(r.deflection, r.force, window).k0
                  for i, r in enumerate(records, start=1)}
    values = np.array(list(per_record.values()))
    spread = float(np.std(values, ddof=1) / math.sqrt(values.size)) if values.size > 1 else 0.0
    return K0FromLoops(k0=pooled.k0, stderr=max(pooled.stderr, spread), pooled=pooled, per_record=per_record,
                       window=float(window))
