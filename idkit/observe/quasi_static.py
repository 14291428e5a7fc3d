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
  peak-to-peak deflection). Default threshold :func:`split_threshold`, from the data's own
  amplitude range: the geometric mean of the smallest and the largest record amplitude (the
  study's small-loop sets reach 4.5 mm and its large-loop sets 15 mm (SPEC 3): 8.2 mm, about
  the former fixed :data:`SMALL_THRESHOLD` of 8 mm; loops of 13-38 mm: 22 mm).
* :func:`cycle_statistics` / :class:`CycleStatistics` and :func:`remove_loop_offsets` /
  :class:`OffsetCorrection` - the loops as they come from a rig: per-cycle amplitude and
  centre, centre drift and force offset, and their removal.

The elastomer's static stiffness read off the same records is :mod:`idkit.observe.k0`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.checks import Instance, Real, Reals, Whole, accepts
from idkit.errors import DataError, FitError, Message, Suggestion
from idkit.io import QuasiStaticMeasurement
from idkit.io.selection import DataProvenance, select_measurements
from idkit.signal.cycles import (
    CycleSplit,
    ResampledLoops,
    noise_level,
    resample_loops,
    reversal_threshold,
    split_cycles,
)

__all__ = [
    "QuasiStaticResult", "process_quasi_static", "require_moving_loops",
    "MIN_POINTS", "UNLOADED_FRACTION", "LoopSet", "prepare_loops", "as_loop_sets",
    "SMALL_THRESHOLD", "split_threshold", "LOOP_POINTS_PER_SET", "LoopData", "loop_sets",
    "record_cycles", "CycleStatistics", "cycle_statistics", "OffsetCorrection", "remove_loop_offsets",
]

MIN_POINTS = 20  # per set, after resampling: fewer cannot resolve slip onset and loop height
#: A record "starts unloaded" when its first deflection and force are within this share
#: of their largest magnitudes in the record (an isolator at rest, sensors zeroed).
UNLOADED_FRACTION = 0.02
#: The study's amplitude (m) separating small-loop from large-loop quasi-static records (SPEC 3):
#: about :func:`split_threshold` of its records; no longer a default (it assumed the thesis's rope).
SMALL_THRESHOLD = 8e-3
#: Default resampled points per quasi-static record: about 20 per branch for the
#: study's 15-loop records (30 branches); 200 would leave 7 points on a 4.5 mm branch.
LOOP_POINTS_PER_SET = 600
#: Records whose amplitudes all lie within this fraction of their median form a one-amplitude
#: test: there is no small/large split to make, and every fit stage uses all of its loops.
SINGLE_AMPLITUDE_SPREAD = 0.25


@accepts(amplitudes=Reals(unit="m", gt=0, meaning="record amplitudes"), error=FitError)
def split_threshold(amplitudes) -> float:
    """The default small/large split of loop records, m: the geometric mean of the smallest and the
    largest record amplitude (half the peak-to-peak deflection), so the split follows the data's own
    range on a log scale whatever the device's size. Records of one amplitude give that amplitude
    (all "small"; :func:`loop_sets` then fits every stage on all of them).

    Examples
    --------
    >>> round(split_threshold([4.5e-3, 4.4e-3, 15e-3]) * 1e3, 2)     # the study's loops
    8.12
    >>> round(split_threshold([13e-3, 25e-3, 38e-3]) * 1e3, 1)       # a friction damper's 13-38 mm
    22.2
    """
    return float(math.sqrt(amplitudes.min() * amplitudes.max()))


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


def require_moving_loops(measurement: QuasiStaticMeasurement) -> None:
    """Refuse a loop record whose deflection or force never changes, naming its file and column.

    Such a record has no loops (a constant deflection has no reversal, a constant force no
    stiffness): a disconnected sensor or a wrong column. Every loop analysis starts here, so
    the message names the record rather than an internal threshold or a zero slope.

    Raises
    ------
    FitError
        ``file 'a.csv', column 'force [kN]' (record qs_1): found a constant force ...``.
    """
    for column, unit in (("deflection", "m"), ("force", "N")):
        values = getattr(measurement, column)
        if float(np.ptp(values)) == 0.0:
            record = f" (record {measurement.id})" if measurement.id else ""
            raise FitError(f"{measurement.source.where(column)}{record}: found a constant {column}, "
                           f"{float(values[0]):g} {unit} in all {values.size} samples; expected loops, a "
                           f"{column} that varies (a disconnected sensor or another column?)")


@accepts(measurement=Instance((QuasiStaticMeasurement,)), error=DataError)
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
    require_moving_loops(measurement)
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
    source_index : ndarray, shape (n,), or None
        Fractional sample index in the raw record of each point of a resampled set (the point
        at ``i + a`` interpolates samples ``i`` and ``i + 1``); None when every point is a
        measured sample of its own. The fits' standard errors count the measured samples
        through it (:func:`idkit.fit._params.jacobian_statistics`, ``point_sources``): a
        0.05 mm branch of 20 samples resampled to 41 points holds 20 measurements, not 41.
    """

    deflection: np.ndarray
    force: np.ndarray
    reversals: np.ndarray
    name: str = ""
    starts_unloaded: bool = False
    source_index: np.ndarray | None = None

    @property
    def amplitude(self) -> float:
        """Half the peak-to-peak deflection, m."""
        return 0.5 * float(np.ptp(self.deflection))

    @property
    def branch_amplitudes(self) -> np.ndarray:
        """Half the deflection travelled by each branch between two reversals, m (a set made by
        :func:`loop_set` is cut at its first and last reversal: every branch is complete)."""
        at_reversals = self.deflection[np.asarray(self.reversals, dtype=int)]
        return 0.5 * np.abs(np.diff(at_reversals))


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


@accepts(points_per_set=Whole(ge=MIN_POINTS, optional=True, meaning="None: the record as measured"),
         min_excursion=Real(unit="m", gt=0, optional=True), error=FitError)
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
    source_index = None
    if points_per_set is None:
        first, last = int(split.reversals[0]), int(split.reversals[-1])
        path_x, path_f = x[first : last + 1], f[first : last + 1]
        reversals = np.concatenate([split.reversals - first])
    else:
        per_branch = max(2, int(math.ceil((points_per_set - 1) / n_branches)) + 1)
        loops = resample_loops(x, f, split=split, points_per_branch=per_branch)
        path_x, path_f = loops.deflection, loops.force
        reversals = np.arange(n_branches + 1) * (per_branch - 1)
        source_index = np.ascontiguousarray(loops.source_index)
    if path_x.size < MIN_POINTS:
        raise FitError(f"{what}: found {path_x.size} points between the first and last reversal, "
                       f"expected at least {MIN_POINTS}")
    if not np.any(path_f):
        raise FitError(f"{what} force: found all zeros, expected a measured force (the error (7.1) divides by it)")
    unloaded = (abs(x[0]) <= UNLOADED_FRACTION * np.max(np.abs(x))
                and abs(f[0]) <= UNLOADED_FRACTION * np.max(np.abs(f)))
    return LoopSet(deflection=np.ascontiguousarray(path_x), force=np.ascontiguousarray(path_f),
                   reversals=reversals.astype(np.intp), name=name, starts_unloaded=bool(unloaded),
                   source_index=source_index)


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
    offset_corrections: tuple = ()
    single_amplitude: bool = False

    def amplitude_range(self) -> tuple[float, float]:
        """Smallest and largest loop amplitude (m) over every set: half the deflection travelled
        between two reversals. A model identified on these loops is extrapolated at
        deflection amplitudes outside this range."""
        amplitudes = np.concatenate([loop.branch_amplitudes for loop in self.small + self.large] + [np.zeros(0)])
        amplitudes = amplitudes[amplitudes > 0.0]
        if amplitudes.size == 0:
            return float("nan"), float("nan")
        return float(amplitudes.min()), float(amplitudes.max())


@accepts(small_threshold=Real(unit="m", gt=0, optional=True), error=FitError)
def loop_sets(
    measurements,
    *,
    small_threshold: float | None = None,
    isolator: str | None = "wire_rope",
    split: str | None = "fit",
    points_per_set: int | None = LOOP_POINTS_PER_SET,
    min_excursion: float | None = None,
    remove_offsets: bool = False,
) -> LoopData:
    """Quasi-static records -> small and large loop sets (one set per record).

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
        Selected by :func:`idkit.io.selection.select_measurements`.
    small_threshold : float or None
        A record whose amplitude (half its peak-to-peak deflection) is at most this (m)
        is a small-loop set, otherwise a large-loop set. Default (None):
        :func:`split_threshold` of the selected records' amplitudes.
    isolator : str or None, default "wire_rope"
        Only records of this isolator (None: any).
    split : {"fit", "validation", None}, default "fit"
    points_per_set : int or None, default :data:`LOOP_POINTS_PER_SET`
        See :func:`prepare_loops`.
    min_excursion : float, optional
        Reversal threshold in m; default :func:`idkit.signal.cycles.reversal_threshold` of
        each record, the threshold :func:`process_quasi_static` (``idkit inspect``) uses.
    remove_offsets : bool, default False
        Remove each record's loop-centre drift and force offset first
        (:func:`remove_loop_offsets`); what was subtracted is kept in
        ``LoopData.offset_corrections`` for the provenance. Off by default: idkit never
        alters data unless asked.

    Returns
    -------
    LoopData
        With ``single_amplitude=True`` when every record's amplitude lies within
        :data:`SINGLE_AMPLITUDE_SPREAD` of the median (a one-amplitude test): ``small`` and
        ``large`` then hold the same sets, whatever ``small_threshold`` says.

    Raises
    ------
    FitError
        No matching record, a record without reversals, or records of different amplitudes
        that ``small_threshold`` puts all on one side (the message lists the amplitudes and
        the threshold).
    """
    records, provenance = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    small, large, small_rep, large_rep, amplitudes, corrections, prepared_sets = [], [], [], [], {}, [], []
    for position, record in enumerate(records, start=1):
        name = record.id or f"record{position}"
        require_moving_loops(record)
        if remove_offsets:
            record, correction = remove_loop_offsets(record)
            corrections.append(correction)
        amplitudes[name] = 0.5 * float(np.ptp(record.deflection))
        try:
            prepared = prepare_loops(record.deflection, record.force, points_per_set=points_per_set,
                                     min_excursion=min_excursion, name=name)
        except FitError as problem:
            raise FitError(f"{record.source.where()}: {problem}") from None
        repetition = record.info.repetition if record.info.repetition is not None else position
        prepared_sets.append((prepared, amplitudes[name], repetition))
    if small_threshold is None:  # every record has reversals, so a positive amplitude
        small_threshold = split_threshold(list(amplitudes.values()))
    for prepared, amplitude, repetition in prepared_sets:
        if amplitude <= small_threshold:
            small.append(prepared)
            small_rep.append(repetition)
        else:
            large.append(prepared)
            large_rep.append(repetition)
    single = False
    if not small or not large:
        values = np.array(list(amplitudes.values()))
        if np.all(np.abs(values / np.median(values) - 1.0) <= SINGLE_AMPLITUDE_SPREAD):
            # a one-amplitude test: every stage fits the same loops (said in the fit's report)
            single = True
            group, reps = (small, small_rep) if small else (large, large_rep)
            small, large, small_rep, large_rep = group, group, reps, reps
    if not small or not large:
        listed = ", ".join(f"{name}: {1e3 * a:.3g} mm" for name, a in amplitudes.items())
        missing = "small" if not small else "large"
        raise FitError(f"loops: found no {missing}-loop record with small_threshold={1e3 * small_threshold:g} mm "
                       f"(amplitudes {listed}); expected both small and large loop sets")
    return LoopData(small=tuple(small), large=tuple(large), small_repetitions=tuple(small_rep),
                    large_repetitions=tuple(large_rep), amplitudes=amplitudes, threshold=float(small_threshold),
                    provenance=provenance, offset_corrections=tuple(corrections), single_amplitude=single)


# ---------------------------------------------------------------------------------------------
# loops as they come from a rig: centre drift, force offset, per-cycle statistics

#: A record whose loop centres wander (over its steady cycles) by more than this fraction of the
#: median amplitude is flagged (``loop_drift``): a drifting actuator or a slipping clamp.
DRIFT_WARNING_FRACTION = 0.1
#: Cycles whose amplitude is within this fraction of both neighbours' count as steady cycling
#: (the drift is read on them only).
STEADY_AMPLITUDE_FRACTION = 0.1
#: A record whose loop midline at the loop centre sits further from zero than this fraction of
#: the median force amplitude is flagged (``force_offset``): an unzeroed load cell or preload.
FORCE_OFFSET_WARNING_FRACTION = 0.05


@dataclass(frozen=True)
class CycleStatistics:
    """Per-cycle statistics of one quasi-static record.

    Attributes
    ----------
    measurement_id : str
    time : ndarray, shape (n_cycles,)
        Mid time of each cycle, s.
    amplitude, center : ndarray
        Deflection half-range and centre of each cycle, m.
    force_offset : ndarray
        Midline of the loop at its centre: the mean of the loading and unloading force at the
        cycle's centre deflection, N. Zero for a loop symmetric about the origin (any
        hysteresis, any odd spring); a load-cell offset or a preload shows here.
    force_amplitude : ndarray
        Half the force range, N.
    secant_stiffness : ndarray
        Force range over deflection range, N/m.
    dissipated_energy : ndarray
        Loop area ``|closed integral of F dx|``, J.
    """

    measurement_id: str
    time: np.ndarray
    amplitude: np.ndarray
    center: np.ndarray
    force_offset: np.ndarray
    force_amplitude: np.ndarray
    secant_stiffness: np.ndarray
    dissipated_energy: np.ndarray

    @property
    def steady(self) -> np.ndarray:
        """Cycles of steady cycling: amplitude within :data:`STEADY_AMPLITUDE_FRACTION` of both
        neighbours (a cycle that spans a change of amplitude has its centre moved by half the
        change, which is the protocol, not drift)."""
        amplitude = self.amplitude
        if amplitude.size < 2:
            return np.zeros(amplitude.size, dtype=bool)
        close = np.abs(np.diff(amplitude)) <= STEADY_AMPLITUDE_FRACTION * np.maximum(amplitude[1:], amplitude[:-1])
        before = np.r_[True, close]
        after = np.r_[close, True]
        return before & after & (np.r_[close, False] | np.r_[False, close])

    @property
    def center_drift(self) -> float:
        """Range of the loop centres over the steady cycles, m (0 with fewer than two)."""
        centres = self.center[self.steady]
        return float(np.ptp(centres)) if centres.size >= 2 else 0.0

    @property
    def median_force_offset(self) -> float:
        """Median loop midline at the centre over the cycles where it is measured, N (0 without
        cycles; NaN when no cycle has both branches crossing its centre). A cycle whose loading
        or unloading branch does not reach its centre (the record's first or last turn) has no
        midline there (NaN) and is left out: with it the median was NaN, and subtracting it made
        every force sample NaN."""
        measured = self.force_offset[np.isfinite(self.force_offset)]
        if self.force_offset.size == 0:
            return 0.0
        return float(np.median(measured)) if measured.size else float("nan")

    def findings(self) -> list[str]:
        """Drift and offset beyond :data:`DRIFT_WARNING_FRACTION` / :data:`FORCE_OFFSET_WARNING_FRACTION`."""
        found = []
        if self.amplitude.size == 0:
            return found
        amplitude, force = float(np.median(self.amplitude)), float(np.median(self.force_amplitude))
        if self.center_drift > DRIFT_WARNING_FRACTION * amplitude:
            centres = self.center[self.steady]
            found.append(f"loop centre drifts from {centres[0] * 1e3:.3g} to {centres[-1] * 1e3:.3g} mm "
                         f"(range {self.center_drift * 1e3:.3g} mm over {centres.size} steady cycles, "
                         f"{self.center_drift / amplitude:.0%} of the median amplitude {amplitude * 1e3:.3g} mm)")
        if abs(self.median_force_offset) > FORCE_OFFSET_WARNING_FRACTION * force:
            share = f"{abs(self.median_force_offset) / force:.0%} of" if force > 0 else "with"
            found.append(f"force offset {self.median_force_offset:+.4g} N at the loop centres "
                         f"({share} the median force amplitude {force:.4g} N)")
        return found

    def to_dataframe(self) -> pd.DataFrame:
        """One row per cycle, units in the column names."""
        return pd.DataFrame({
            "measurement_id": self.measurement_id, "cycle": np.arange(1, self.amplitude.size + 1),
            "time [s]": self.time, "amplitude [m]": self.amplitude, "center [m]": self.center,
            "force_offset [N]": self.force_offset, "force_amplitude [N]": self.force_amplitude,
            "secant_stiffness [N/m]": self.secant_stiffness, "dissipated_energy [J]": self.dissipated_energy,
        })


def _midline(x: np.ndarray, force: np.ndarray, at: float) -> float:
    """Mean of the loading and the unloading force at deflection ``at`` within one cycle."""
    velocity = np.gradient(x)
    values = []
    for branch in (velocity > 0, velocity < 0):
        xb, fb = x[branch], force[branch]
        if xb.size < 2 or not (xb.min() <= at <= xb.max()):
            return float("nan")
        order = np.argsort(xb, kind="stable")
        values.append(float(np.interp(at, xb[order], fb[order])))
    return 0.5 * (values[0] + values[1])


@accepts(measurement=Instance((QuasiStaticMeasurement,)), error=DataError)
def cycle_statistics(measurement: QuasiStaticMeasurement, *, result: QuasiStaticResult | None = None
                     ) -> CycleStatistics:
    """Amplitude, centre, force offset, secant stiffness and loop energy of every cycle.

    Parameters
    ----------
    measurement : QuasiStaticMeasurement
    result : QuasiStaticResult, optional
        The record's cycles (default :func:`process_quasi_static` with its defaults).

    Returns
    -------
    CycleStatistics

    Examples
    --------
    A linear spring with viscous loops, offset by 3 mm and 50 N:

    >>> from idkit.io import QuasiStaticMeasurement
    >>> t = np.linspace(0, 40, 8001)
    >>> x = 3e-3 + 2e-3 * np.sin(2 * np.pi * t / 10)
    >>> f = 50.0 + 1e4 * (x - 3e-3) + 2e3 * np.gradient(x, t)
    >>> stats = cycle_statistics(QuasiStaticMeasurement(time=t, deflection=x, force=f))
    >>> round(float(stats.center[0]) * 1e3, 3), round(stats.median_force_offset, 2)
    (3.0, 50.0)
    """
    result = process_quasi_static(measurement) if result is None else result
    cycles = result.cycles
    x, force, time = measurement.deflection, measurement.force, measurement.time
    n = cycles.n_cycles
    mid_time, offset, force_amp, secant, energy = (np.empty(n) for _ in range(5))
    for i in range(n):
        start, stop = int(cycles.cycle_start[i]), int(cycles.cycle_stop[i]) + 1
        xs, fs = x[start:stop], force[start:stop]
        mid_time[i] = 0.5 * (time[start] + time[stop - 1])
        offset[i] = _midline(xs, fs, float(cycles.center[i]))
        force_amp[i] = 0.5 * float(np.ptp(fs))
        secant[i] = float(np.ptp(fs) / np.ptp(xs)) if np.ptp(xs) > 0 else float("nan")
        energy[i] = abs(float(np.trapezoid(fs, xs)))
    return CycleStatistics(measurement_id=measurement.id, time=mid_time, amplitude=np.array(cycles.amplitude),
                           center=np.array(cycles.center), force_offset=offset, force_amplitude=force_amp,
                           secant_stiffness=secant, dissipated_energy=energy)


@dataclass(frozen=True)
class OffsetCorrection:
    """What :func:`remove_loop_offsets` subtracted from a record (for provenance).

    Attributes
    ----------
    measurement_id : str
    center_knots_time, center_knots : ndarray
        The loop centres (m) at the cycle mid times (s) whose piecewise-linear interpolation
        (held constant beyond the first and last cycle) was subtracted from the deflection;
        empty when the drift was kept.
    force_offset : float
        Constant subtracted from the force, N (0 when kept).
    """

    measurement_id: str
    center_knots_time: np.ndarray
    center_knots: np.ndarray
    force_offset: float

    def to_dict(self) -> dict:
        """JSON-ready record."""
        return {"measurement_id": self.measurement_id, "force_offset_N": self.force_offset,
                "center_knots_time_s": [float(v) for v in self.center_knots_time],
                "center_knots_m": [float(v) for v in self.center_knots]}


def remove_loop_offsets(measurement: QuasiStaticMeasurement, *, drift: bool = True, force_offset: bool = True
                        ) -> tuple[QuasiStaticMeasurement, OffsetCorrection]:
    """A copy of the record with the loop-centre drift and the force offset removed.

    The deflection loses the piecewise-linear curve through the cycle centres (at the cycle
    mid times; constant before the first and after the last cycle), so every loop is centred
    on zero; the force loses the median loop midline at the centres
    (:class:`CycleStatistics`). The input is not altered; the returned correction records
    exactly what was subtracted, and the new measurement's ``info.notes`` says so.

    Examples
    --------
    >>> from idkit.io import QuasiStaticMeasurement
    >>> t = np.linspace(0, 40, 8001)
    >>> x = 3e-3 + 2e-3 * np.sin(2 * np.pi * t / 10)
    >>> record = QuasiStaticMeasurement(time=t, deflection=x, force=50.0 + 1e4 * (x - 3e-3))
    >>> clean, correction = remove_loop_offsets(record)
    >>> round(float(np.median(clean.deflection)) * 1e3, 6), round(correction.force_offset, 3)
    (0.0, 50.0)
    """
    import dataclasses

    stats = cycle_statistics(measurement)
    deflection = np.array(measurement.deflection, dtype=float)
    force = np.array(measurement.force, dtype=float)
    knots_t, knots_c = np.array([]), np.array([])
    if drift and stats.center.size:
        knots_t, knots_c = stats.time, stats.center
        deflection = deflection - np.interp(measurement.time, knots_t, knots_c)
    offset = stats.median_force_offset if force_offset else 0.0
    if not np.isfinite(offset):
        raise DataError(Message(f"{measurement.id}: no cycle has both its loading and unloading branch crossing "
                                f"its centre ({stats.force_offset.size} cycles), so the force offset cannot be "
                                "measured; expected at least one full loop (or keep the offset: ",
                                Suggestion("force_offset", False), ")"))
    force = force - offset
    correction = OffsetCorrection(measurement_id=measurement.id, center_knots_time=knots_t, center_knots=knots_c,
                                  force_offset=float(offset))
    note = (f"loop offsets removed by idkit: centre drift {'removed' if drift else 'kept'}, "
            f"force offset {offset:+.6g} N subtracted")
    info = dataclasses.replace(measurement.info, notes=(measurement.info.notes + "; " if measurement.info.notes
                                                        else "") + note)
    clean = dataclasses.replace(measurement, deflection=deflection, force=force, info=info)
    return clean, correction
