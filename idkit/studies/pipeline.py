"""The compute half of ``idkit report``: discover, fit, validate and study a data set.

:func:`compute_report_data` runs the stages below and returns a typed :class:`ReportData`;
:mod:`idkit.report.main_report` renders it (HTML, model files, tables, provenance) and
computes nothing. Stages (each timed):

1. load and inspect every measurement set under the data folder
   (:func:`idkit.io.discover.find_measurement_sets`: one folder with a ``manifest.json``
   per isolator: ``wire_rope``, ``elastomer``, ``hybrid``), refusing two records with the same
   samples (:func:`refuse_repeated_records`) and one with no record for a validation
   (:func:`refuse_missing_held_out`), before any fit;
2. fit the elastomer (bounded SQP with a global cross-check; order table n = 1..4 and
   Voigt) and then the wire rope (three-stage Iwan, its parameters' spread over one refit per
   repetition (:meth:`~idkit.fit.MeasurementFit.with_repetition_spread`)) on the ``fit``
   split; the Bouc-Wen comparison fit runs in a forked child process beside both
   (:func:`idkit.forked.fork_call`), so its time is shared by the two stages' timings;
3. validate both on the ``validation`` split, and the hybrid built from them on all hybrid
   sweeps and drops (nothing was fitted to the hybrid), with the wrong components each
   hybrid check cannot see (:func:`idkit.validate.blind_spots`); the elastomer's checks need
   no wire rope and run in a forked child beside the wire-rope fit (:func:`_elastomer_checks`),
   which also compiles the kernels they share with the later stages on an empty kernel cache;
4. run the transport-tool study with the identified parts (:mod:`idkit.studies.transport`),
   in a forked child process while stage 3 runs and the report is written
   (:func:`idkit.forked.fork_call`): :func:`compute_report_data` returns without waiting for
   it, the writer draws everything that does not need it first and the first use of
   :attr:`ReportData.transport` waits for it (that wait is the stage's timing).

``quick`` keeps the fits and checks but validates on at most :data:`QUICK_HELD_OUT`
records per check, chosen across the test levels by :func:`quick_subset` (the report names the
records it skipped), and shrinks the transport study and the global searches.
"""

from __future__ import annotations

import hashlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.errors import DataError
from idkit.fit import maxwell_order_table
from idkit.forked import Forked, fork_call
from idkit.fit.data_set_checks import VALID_RANGE_MARGIN, data_valid_range
from idkit.fit.measurement_fit import MeasurementFit
from idkit.fit.measurement_level import fit_boucwen_measurements, fit_iwan_measurements, fit_maxwell_measurements
from idkit.fit.predictions import LoopFitPrediction, predict_loops
from idkit.io.discover import default_data_dir, find_measurement_sets
from idkit.models import GeneralizedMaxwell, HybridSystem, IwanModel
from idkit.observe.quality import MeasurementSummary, summarize_measurements
from idkit.studies.transport import TransportStudy, compute_transport_study, quick_transport_options
from idkit.validate import ValidationResult, blind_spots, validate_drops, validate_frf, validate_harmonic
from idkit.validate.history import validate_histories
from idkit.studies.drop_histories import DropHistories, drop_histories
from idkit.studies.drop_models import DropModelComparison, wire_rope_drop_models
from idkit.studies.sweep_maps import SweepMaps, sweep_maps

__all__ = [
    "QUICK_HELD_OUT",
    "QUICK_NOTE",
    "STAGES",
    "ReportData",
    "ValidationEntry",
    "compute_report_data",
    "identify_parts",
    "quick_subset",
    "refuse_missing_held_out",
    "refuse_repeated_records",
    "valid_range_of",
    "validate_wire_rope",
    "wire_rope_fit_options",
]

#: held-out records per validation in quick mode
QUICK_HELD_OUT = 8
QUICK_NOTE = (f"quick run: at most {QUICK_HELD_OUT} held-out records per validation, from the lowest to the highest "
              "test level, smaller study; not the full verdict")


def _sort_key(value) -> tuple:
    """None first, then numbers (or tuples of them) in order."""
    return (value is not None, value if value is not None else 0)


def _level_of(measurement) -> tuple:
    """The test condition of a record besides its frequency and repetition: masses, nominal
    amplitude (quantity, value), white-noise band and drop height."""
    info = measurement.info
    excitation = info.excitation
    return tuple(_sort_key(value) for value in (
        info.top_mass_kg, info.intermediate_mass_kg, info.bottom_mass_kg,
        excitation.amplitude_quantity if excitation is not None else None,
        excitation.amplitude if excitation is not None else None,
        excitation.band if excitation is not None else None,
        info.drop_height_m))


def _spread(n: int, k: int) -> list[int]:
    """``k`` of the indices ``0..n-1`` spread evenly: the middle of each of ``k`` equal strata."""
    return [int((i + 0.5) * n / k) for i in range(k)]


def _ends_first(n: int, k: int) -> list[int]:
    """``k`` of the indices ``0..n-1`` spread evenly from the first to the last (both when k >= 2)."""
    return [0] if k == 1 else sorted({int(round(i * (n - 1) / (k - 1))) for i in range(k)})


#: A stepped-sine level is judged by its resonance only with at least this many frequencies
#: (:func:`idkit.validate.validate_harmonic` skips smaller groups, and a sweep check without any
#: resonance is INCONCLUSIVE).
SWEEP_POINTS_PER_LEVEL = 3


def _measured_ratio(measurement) -> float:
    """Top over base velocity, RMS (a stepped-sine record's measured transmissibility, for its peak)."""
    base = float(np.std(measurement.v_base))
    return float(np.std(measurement.v_top)) / base if base > 0 else 0.0


def quick_subset(measurements, limit: int | None) -> tuple[list, list]:
    """The records a quick validation uses and the ones it skips (deterministic, order-free).

    The records are grouped by test level (masses, nominal amplitude, white-noise band, drop
    height: everything but frequency and repetition), the levels sorted by value. Stepped-sine
    levels need :data:`SWEEP_POINTS_PER_LEVEL` (3) records to be judged by their resonance, other
    kinds one. As many levels as ``limit`` allows at that (``limit // 3`` sweep levels, ``limit``
    others) are chosen spread evenly from the lowest level to the highest (both ends when two
    or more), and ``limit`` is shared out over them as evenly as their sizes allow. Inside a
    level, sorted by frequency, repetition and id, a sweep keeps the contiguous frequencies
    centred on its measured peak (largest RMS top over base velocity), so the level's resonance
    is bracketed; other kinds keep the middles of equal strata. So a manifest sorted by level
    (or any other order) gives the same subset, and the extreme levels are always validated.

    Parameters
    ----------
    measurements : sequence of measurements
    limit : int or None
        At most this many records (None: all).

    Returns
    -------
    chosen, skipped : list
        ``chosen`` in (level, frequency, repetition, id) order; ``skipped`` in manifest order.
    """
    records = list(measurements)
    if limit is None or len(records) <= limit:
        return records, []
    levels: dict[tuple, list] = {}
    for measurement in records:
        levels.setdefault(_level_of(measurement), []).append(measurement)
    groups = [sorted(levels[key], key=lambda m: (_sort_key(m.info.excitation.freq if m.info.excitation else None),
                                                 _sort_key(m.info.repetition), m.info.id))
              for key in sorted(levels)]
    sweep = all(m.kind == "stepped_sine" for m in records)
    need = SWEEP_POINTS_PER_LEVEL if sweep else 1
    groups = [groups[i] for i in _ends_first(len(groups), max(1, min(len(groups), int(limit) // need)))]
    counts = [0] * len(groups)
    left = int(limit)
    while left > 0 and any(count < len(group) for count, group in zip(counts, groups)):
        open_levels = [i for i, group in enumerate(groups) if counts[i] < len(group)]
        served = open_levels if len(open_levels) <= left else [open_levels[j] for j in _spread(len(open_levels), left)]
        for i in served:
            counts[i] += 1
        left -= len(served)
    chosen = []
    for group, count in zip(groups, counts):
        if sweep:
            peak = max(range(len(group)), key=lambda j: _measured_ratio(group[j]))
            first = min(max(peak - count // 2, 0), len(group) - count)
            chosen += group[first:first + count]
        else:
            chosen += [group[j] for j in _spread(len(group), count)]
    kept = {id(m) for m in chosen}
    return chosen, [m for m in records if id(m) not in kept]

#: the computing stages, in order (their names label the timings)
STAGES = (
    "loading and inspecting the data",
    "fitting the elastomer (SQP, global cross-check, order table)",
    "fitting the wire rope (three-stage Iwan, Bouc-Wen comparison)",
    "validating on held-out data",
    "transport-tool study",
)


@dataclass(frozen=True)
class ValidationEntry:
    """One validation of the report.

    Attributes
    ----------
    key : str
        Short name, e.g. ``"wire rope drops"`` (verdict tables, CSV file names).
    isolator : {"wire rope", "elastomer", "hybrid"}
        The report section it belongs to.
    observable : {"sweeps", "FRF", "drops"}
        What was compared: stepped-sine HOSIDFs, white-noise FRFs or drop peaks (it
        chooses the figure).
    result : ValidationResult
    skipped : tuple of str
        Ids of the held-out records a quick run left out (:func:`quick_subset`; empty in a
        full run).
    """

    key: str
    isolator: str
    observable: str
    result: ValidationResult
    skipped: tuple[str, ...] = ()


@dataclass(frozen=True)
class ReportData:
    """Everything ``idkit report`` shows, computed.

    Attributes
    ----------
    data_dir : Path
    seed : int
    quick : bool
    sets : dict of str to MeasurementSet
        Keyed by isolator (one set may serve several).
    inspections : dict of str to MeasurementSummary
    valid_range : (float, float)
        Deflections (m) over which the Iwan spring was required to stay valid.
    iwan, boucwen, maxwell : MeasurementFit
    iwan_loops, boucwen_loops : LoopFitPrediction
        Measured and model force along the fitted loops.
    order_table : DataFrame
        Maxwell error (7.5) for n = 1..4 (1, 2 in quick mode) and the Voigt model.
    validations : tuple of ValidationEntry
    hybrid : HybridSystem or None
        The hybrid built from the identified parts on the masses of ``hybrid_masses_from``.
    hybrid_masses_from : str or None
        Id of the hybrid sweep whose masses ``hybrid`` carries.
    transport : TransportStudy
        The transport study (a property: see ``transport_source``).
    transport_source : TransportStudy or Forked
        The study, or the forked child still computing it (:func:`compute_report_data` does
        not wait for it, so the writer can draw everything else meanwhile); the first use of
        :attr:`transport` waits for it and records the wait as the stage "transport-tool study".
    timings_s : dict
        Seconds per stage of :data:`STAGES`.
    drop_models : DropModelComparison or None
        The wire rope's held-out drops under both drop models, plain and slip-modulated Iwan.
    drop_model : str
        The drop model the drop validations used ("auto", "rig" or "conditioned").
    sweep_maps : dict of str to SweepMaps
        Per nonlinear isolator ("wire rope", "hybrid"): measured and model HOSIDFs of every
        stepped sine of its most-recorded setup, and the model's map
        (:func:`idkit.studies.sweep_maps.sweep_maps`).
    drop_histories : dict of str to DropHistories
        Per isolator: a few held-out drops (every hybrid drop is held out), measured and
        simulated over time (:func:`idkit.studies.drop_histories.drop_histories`).
    """

    data_dir: Path
    seed: int
    quick: bool
    sets: dict
    inspections: dict[str, MeasurementSummary]
    valid_range: tuple[float, float]
    iwan: MeasurementFit
    boucwen: MeasurementFit
    iwan_loops: LoopFitPrediction
    boucwen_loops: LoopFitPrediction
    maxwell: MeasurementFit
    order_table: pd.DataFrame
    validations: tuple[ValidationEntry, ...]
    hybrid: HybridSystem | None
    hybrid_masses_from: str | None
    transport_source: TransportStudy | Forked
    timings_s: dict = field(default_factory=dict)
    drop_models: DropModelComparison | None = None
    drop_model: str = "auto"
    sweep_maps: dict[str, SweepMaps] = field(default_factory=dict)
    drop_histories: dict[str, DropHistories] = field(default_factory=dict)

    @property
    def transport(self) -> TransportStudy:
        """The transport study; the first use waits for the child computing it (see ``transport_source``)."""
        source = self.transport_source
        if isinstance(source, Forked):
            started = time.perf_counter()
            try:
                study = source.result()
            finally:
                source.abandon()
            self.timings_s[STAGES[4]] = round(time.perf_counter() - started, 3)
            object.__setattr__(self, "transport_source", study)  # frozen: the one deferred field, set once
        return self.transport_source

    def abandon_transport(self) -> None:
        """Stop the child computing the transport study if nobody will wait for it (on an error)."""
        if isinstance(self.transport_source, Forked):
            self.transport_source.abandon()

    @property
    def n_measurements(self) -> int:
        """Measurements in the data set (a set serving two isolators counted once)."""
        return sum(len(s.measurements) for s in {id(s): s for s in self.sets.values()}.values())

    def validations_of(self, isolator: str) -> tuple[ValidationEntry, ...]:
        """The validations of one report section (``"wire rope"``, ``"elastomer"``, ``"hybrid"``)."""
        return tuple(entry for entry in self.validations if entry.isolator == isolator)

    @property
    def verdicts(self) -> dict[str, str]:
        """``{key: "PASS" | "INCONCLUSIVE" | "FAIL"}``."""
        return {entry.key: entry.result.verdict for entry in self.validations}


def valid_range_of(measurement_set, margin: float = VALID_RANGE_MARGIN) -> tuple[float, float]:
    """``margin`` times the lowest and highest deflection (m) of every record of the set that has one
    (:func:`idkit.fit.data_set_checks.data_valid_range` over every isolator of the set)."""
    return data_valid_range(measurement_set, isolator=None, margin=margin)


def wire_rope_fit_options(wire_rope, *, seed: int = 2026, start_state: str = "auto") -> dict:
    """Keyword arguments of the report's wire-rope fit, :func:`fit_iwan_measurements`.

    The records of isolator ``wire_rope``; the order and the model family are left to the fit's
    rules (``order="auto"``, ``family="auto"``: docs/fitting.md); the spring is kept stiff over
    every deflection of the set (:func:`valid_range_of`). The notebooks fit with the same options.

    Parameters
    ----------
    wire_rope : MeasurementSet
        The wire rope's measurement set.
    seed : int
        Seed of the fit's global searches.
    start_state : {"auto", "cycled", "virgin"}
        Start state of the loop fits.
    """
    return {"isolator": "wire_rope", "seed": int(seed), "valid_range": valid_range_of(wire_rope),
            "initial_state": start_state}


def validate_wire_rope(sweeps, drops, model, *, loop_amplitude_range=None, drop_model: str = "auto"
                       ) -> tuple[ValidationResult, ValidationResult]:
    """The report's two wire-rope validations of ``model``: held-out harmonic sweeps and drops.

    Parameters
    ----------
    sweeps, drops : iterable of Measurement
        Held-out stepped-sine and drop records.
    model : IwanModel or ModulatedIwanModel
        The identified rope.
    loop_amplitude_range : (float, float), optional
        Loop amplitudes (m) the rope was identified on; records beyond them are named in the
        verdict's notes (:attr:`MeasurementFit.loop_amplitude_range`).
    drop_model : {"auto", "rig", "conditioned"}
        :func:`idkit.validate.validate_drops`; "auto": the rig when the drops give bottom
        mass and height.

    Returns
    -------
    (ValidationResult, ValidationResult)
        Sweeps, drops.
    """
    return (validate_harmonic(sweeps, isolator=model, identified_range=loop_amplitude_range,
                              name="wire rope: harmonic sweeps (validation split)"),
            validate_drops(drops, isolator=model, drop_model=drop_model, identified_range=loop_amplitude_range,
                           name="wire rope: drops (validation split)"))


class _Stages:
    """Times the stages and announces each one."""

    def __init__(self, say: Callable[[str], None]):
        self.say = say
        self.durations: dict[str, float] = {}
        self._started: tuple[str, float] | None = None

    def start(self, name: str) -> None:
        self.finish()
        self.say(name)
        self._started = (name, time.perf_counter())

    def finish(self) -> None:
        if self._started is not None:
            name, started = self._started
            self.durations[name] = round(time.perf_counter() - started, 3)
            self._started = None


def _fingerprint(measurement) -> str:
    """SHA-256 of a record's kind and samples (every signal in SI, by name): equal for copies of one
    recording whatever their file name, compression or units."""
    digest = hashlib.sha256(measurement.kind.encode())
    for name, values in sorted(measurement.signals().items()):
        digest.update(name.encode() + b"\0" + np.ascontiguousarray(values, dtype=float).tobytes())
    return digest.hexdigest()


def refuse_repeated_records(sets: dict) -> None:
    """Refuse two records of the data folder that hold the same samples in every column.

    Two measurements never agree sample for sample (sensor noise), so such a pair is one recording
    listed twice: it would count twice in a fit or a validation, and a copy of a fit record in the
    validation split would validate the model on the data it was fitted to (a PASS that tests nothing).

    Raises
    ------
    DataError
        Naming both records (id, file, split) of every repeated recording.
    """
    seen: dict[str, tuple[str, str, str]] = {}
    repeated = []
    for measurement_set in {id(s): s for s in sets.values()}.values():
        for measurement in measurement_set.measurements:
            path = measurement.source.path
            where = (measurement.info.id, str(path) if path is not None else "in-memory data",
                     measurement.info.split or "no split")
            first = seen.setdefault(_fingerprint(measurement), where)
            if first is not where:
                repeated.append(f"{where[0]} ({where[1]}, split {where[2]}) repeats {first[0]} "
                                f"({first[1]}, split {first[2]})")
    if repeated:
        raise DataError("records holding the same samples in every column as another record: " + "; ".join(repeated)
                        + "; expected each measurement once (a repeated record counts twice, and a copy of a fit "
                          "record held out for validation validates the model on its own fit data)")


#: the records each validation of the report needs: isolator -> (kind, split) pairs (split None: any)
HELD_OUT_KINDS = {
    "wire_rope": (("stepped_sine", "validation"), ("drop", "validation")),
    "elastomer": (("white_noise", "validation"), ("stepped_sine", "validation"), ("drop", "validation")),
    "hybrid": (("stepped_sine", None), ("drop", None)),
}


def refuse_missing_held_out(sets: dict) -> None:
    """Refuse, before any fit, a data folder that holds no record for one of the report's validations.

    Raises
    ------
    DataError
        Naming the set's manifest and every (isolator, kind, split) with no record.
    """
    missing = []
    for isolator, needs in HELD_OUT_KINDS.items():
        measurement_set = sets.get(isolator)
        if measurement_set is None:
            continue  # the two required sets are checked on discovery, the hybrid is optional
        for kind, split in needs:
            if not len(measurement_set.select(kind=kind, split=split)):  # what the validations are given
                missing.append(f"{measurement_set.folder / 'manifest.json'}: no {kind} record"
                               + (" with split 'validation'" if split else "") + f" (the {isolator} set)")
    if missing:
        raise DataError("; ".join(missing) + "; expected at least one for each validation of the report "
                        "(docs/validation.md; split 'validation' is the held-out data)")


def _held_out(measurement_set, kind: str, limit: int | None, split: str | None = "validation") -> tuple[list, tuple]:
    """The records of one validation (:func:`quick_subset`) and the ids of those a quick run skips."""
    chosen, left_out = quick_subset(measurement_set.select(kind=kind, split=split), limit)
    return chosen, tuple(m.info.id for m in left_out)


def _history_check(isolator: str, measurement_set, model, limit: int | None) -> ValidationEntry | None:
    """The held-out loop / force records of one isolator scored as force histories (None when it has none)."""
    records, skipped = _held_out(measurement_set, "quasi_static", limit)
    if not records:
        return None
    return ValidationEntry(f"{isolator} force histories", isolator, "histories", validate_histories(
        model, records, split=None, name=f"{isolator}: force histories (validation split)"), skipped)


def _elastomer_checks(elastomer, elastomer_model: GeneralizedMaxwell, limit: int | None, drop_model: str,
                      static_stiffness) -> tuple[dict[str, ValidationEntry], DropHistories | None]:
    """Everything the report computes on the elastomer's held-out records, which needs no wire rope: its
    validations by key (FRF, sweeps, drops, force histories when there are such records) and its drop time
    histories. :func:`compute_report_data` runs it in a forked child beside the wire-rope fit."""
    frf, frf_skipped = _held_out(elastomer, "white_noise", limit)
    sweeps, sweeps_skipped = _held_out(elastomer, "stepped_sine", limit)
    drops, drops_skipped = _held_out(elastomer, "drop", limit)
    entries = {
        "elastomer FRF": ValidationEntry("elastomer FRF", "elastomer", "FRF", validate_frf(
            frf, isolator=elastomer_model, static_stiffness=static_stiffness,
            name="elastomer: white-noise FRFs (validation split)"), frf_skipped),
        "elastomer sweeps": ValidationEntry("elastomer sweeps", "elastomer", "sweeps", validate_harmonic(
            sweeps, isolator=elastomer_model, name="elastomer: harmonic sweeps (validation split)"), sweeps_skipped),
        "elastomer drops": ValidationEntry("elastomer drops", "elastomer", "drops", validate_drops(
            drops, isolator=elastomer_model, drop_model=drop_model, name="elastomer: drops (validation split)"),
            drops_skipped),
    }
    histories = _history_check("elastomer", elastomer, elastomer_model, limit)
    if histories is not None:
        entries[histories.key] = histories
    return entries, drop_histories(list(elastomer.select(kind="drop", split="validation")), isolator=elastomer_model)


def _validations(sets: dict, wire_model: IwanModel, elastomer_model: GeneralizedMaxwell, elastomer_entries: dict,
                 limit: int | None, drop_model: str = "auto", wire_loop_range=None
                 ) -> tuple[tuple[ValidationEntry, ...], HybridSystem | None, str | None]:
    """Every validation of the report, in page order; the elastomer's (:func:`_elastomer_checks`) are given."""
    wire_rope = sets["wire_rope"]
    (rope_sweeps, sweeps_skipped), (rope_drops, drops_skipped) = (_held_out(wire_rope, "stepped_sine", limit),
                                                                  _held_out(wire_rope, "drop", limit))
    sweeps_result, drops_result = validate_wire_rope(rope_sweeps, rope_drops, wire_model,
                                                     loop_amplitude_range=wire_loop_range, drop_model=drop_model)
    entries = [
        ValidationEntry("wire rope sweeps", "wire rope", "sweeps", sweeps_result, sweeps_skipped),
        ValidationEntry("wire rope drops", "wire rope", "drops", drops_result, drops_skipped),
        *(elastomer_entries[key] for key in ("elastomer FRF", "elastomer sweeps", "elastomer drops")),
    ]
    rope_histories = _history_check("wire rope", wire_rope, wire_model, limit)
    entries += [entry for entry in (rope_histories, elastomer_entries.get("elastomer force histories"))
                if entry is not None]
    hybrid_set = sets.get("hybrid")
    if hybrid_set is None:
        return tuple(entries), None, None
    # the hybrid's components were identified elsewhere: probe which wrong ones it would miss
    components = {"upper": elastomer_model, "lower": wire_model}
    (hybrid_sweeps, sweeps_skipped), (hybrid_drops, drops_skipped) = (_held_out(hybrid_set, "stepped_sine", limit, None),
                                                                      _held_out(hybrid_set, "drop", limit, None))

    def rerun_sweeps(**models):
        return validate_harmonic(hybrid_sweeps, name="hybrid: harmonic sweeps (all; not fitted)", **models)

    def rerun_drops(**models):
        return validate_drops(hybrid_drops, name="hybrid: drops (all; not fitted)", drop_model=drop_model, **models)

    entries.append(ValidationEntry("hybrid sweeps", "hybrid", "sweeps",
                                   blind_spots(rerun_sweeps(**components), rerun_sweeps, components), sweeps_skipped))
    entries.append(ValidationEntry("hybrid drops", "hybrid", "drops",
                                   blind_spots(rerun_drops(**components), rerun_drops, components), drops_skipped))
    sweep = next(iter(hybrid_set.select(kind="stepped_sine")))
    hybrid = HybridSystem(sweep.info.top_mass_kg, elastomer_model, sweep.info.intermediate_mass_kg, wire_model)
    return tuple(entries), hybrid, sweep.info.id


def _figures_data(sets: dict, wire_model: IwanModel, elastomer_model: GeneralizedMaxwell,
                  elastomer_histories: DropHistories | None
                  ) -> tuple[dict[str, SweepMaps], dict[str, DropHistories]]:
    """The HOSIDF maps of the nonlinear isolators and a few drop time histories per isolator (the
    elastomer's are given: :func:`_elastomer_checks`; its model is linear, its higher HOSIDFs zero)."""
    models = {"wire rope": {"isolator": wire_model}, "hybrid": {"upper": elastomer_model, "lower": wire_model}}
    maps, histories = {}, {}
    for isolator in ("wire rope", "elastomer", "hybrid"):
        if isolator == "elastomer":
            if elastomer_histories is not None:
                histories[isolator] = elastomer_histories
            continue
        measurement_set = sets.get(isolator.replace(" ", "_"))
        if measurement_set is None:
            continue
        found = sweep_maps(measurement_set.measurements, **models[isolator])
        if found is not None:
            maps[isolator] = found
        # held-out drops; nothing was fitted to the hybrid, so all of its drops are held out
        drops = list(measurement_set.select(kind="drop", split=None if isolator == "hybrid" else "validation"))
        found = drop_histories(drops, **models[isolator])
        if found is not None:
            histories[isolator] = found
    return maps, histories


def compute_report_data(data_dir=None, *, quick: bool = False, seed: int = 2026, workers: int | None = None,
                        progress: Callable[[str], None] | None = None, start_state: str = "auto",
                        drop_model: str = "auto") -> ReportData:
    """Inspect, fit, validate and study a data set (module docstring).

    Parameters
    ----------
    data_dir : path, optional
        Folder of measurement sets; default :func:`idkit.io.discover.default_data_dir`.
    quick : bool
        Validate on at most :data:`QUICK_HELD_OUT` records per check, a smaller transport
        study, Maxwell orders 1-2 in the order table and smaller global searches.
    seed : int
        Seed of every stochastic step (the fits' global searches, the random vibration).
    workers : int, optional
        Simulation threads of the transport study.
    progress : callable(message: str), optional
        Receives the name of each stage as it starts.
    start_state : {"auto", "cycled", "virgin"}
        Start state of the wire-rope loop fits (:func:`idkit.fit.fit_iwan`).
    drop_model : {"auto", "rig", "conditioned"}
        Drop model of every drop validation (:func:`idkit.validate.validate_drops`; "auto":
        the rig when the drops give bottom mass and height). Whatever it is, the wire rope's
        held-out drops are also compared under both drop models with the plain and the
        slip-modulated Iwan model (``ReportData.drop_models``).

    Returns
    -------
    ReportData
        Its transport study may still be running in a child process: read
        :attr:`ReportData.transport` (waits for it) or call :meth:`ReportData.abandon_transport`
        when it will not be used (:func:`idkit.report.main_report.write_report` does one or
        the other), so that no child outlives its use.
    """
    stages = _Stages(progress or (lambda message: None))
    data_dir = Path(data_dir) if data_dir is not None else default_data_dir()

    stages.start(STAGES[0])
    sets = find_measurement_sets(data_dir)
    refuse_repeated_records(sets)
    refuse_missing_held_out(sets)
    inspections = {isolator: summarize_measurements(s.measurements) for isolator, s in sets.items()}

    limit = QUICK_HELD_OUT if quick else None
    wire_rope = sets["wire_rope"]
    valid_range = valid_range_of(wire_rope)
    # forked children beside the fits here (idkit.forked: the same seeded computations, so the
    # same results as run here): the Bouc-Wen comparison fit from the start, and the elastomer's
    # validations, which need no wire rope, once the elastomer is fitted; the kernels they compile
    # are in the cache when the wire rope's validations need them
    boucwen_call = fork_call(fit_boucwen_measurements, wire_rope, isolator="wire_rope", seed=seed,
                             initial_state=start_state,
                             **({"global_max_evals": 800} if quick else {}))
    elastomer_call = None
    try:
        stages.start(STAGES[1])
        maxwell = fit_maxwell_measurements(sets["elastomer"], isolator="elastomer", cross_check=True, seed=seed,
                                           **({"global_max_evals": 2000} if quick else {}))
        maxwell = maxwell.with_repetition_spread()  # one refit per repetition (a fraction of a second)
        # the order table the fit's order rule chose from (scored on the FRFs the fit used)
        order_table = maxwell.order_table
        if order_table is None:
            order_table = maxwell_order_table(list(maxwell.data), k0=maxwell.k0.k0,
                                              orders=(1, 2) if quick else (1, 2, 3, 4))
        elastomer_call = fork_call(_elastomer_checks, sets["elastomer"], maxwell.model, limit, drop_model,
                                   maxwell.data.static_stiffness)

        stages.start(STAGES[2])
        iwan = fit_iwan_measurements(wire_rope, **wire_rope_fit_options(wire_rope, seed=seed, start_state=start_state))
        iwan = iwan.with_repetition_spread()  # one refit per repetition of the fit split (a few seconds)
        iwan_loops = predict_loops(iwan.model, iwan.data.small, iwan.data.large)
        boucwen = boucwen_call.result()
    except BaseException:
        if elastomer_call is not None:
            elastomer_call.abandon()
        raise
    finally:
        boucwen_call.abandon()
    boucwen_loops = predict_loops(boucwen.model, boucwen.data.small, boucwen.data.large)

    # the transport study needs only the identified parts: it runs in a forked child while
    # the validations run here (idkit.forked; the same seeded computation either way)
    options = quick_transport_options(max_speed=0.6, max_height=0.12) if quick else {}
    transport_call = fork_call(compute_transport_study, wire_rope=iwan.model, elastomer=maxwell.model, seed=seed,
                               workers=workers, **options)
    try:
        stages.start(STAGES[3])
        rope_drops = list(wire_rope.select(kind="drop", split="validation"))
        drop_models = wire_rope_drop_models(quick_subset(rope_drops, limit)[0], iwan,
                                            valid_range=valid_range) if rope_drops else None
        try:
            elastomer_entries, elastomer_histories = elastomer_call.result()
        finally:
            elastomer_call.abandon()
        validations, hybrid, masses_from = _validations(sets, iwan.model, maxwell.model, elastomer_entries, limit,
                                                        drop_model, wire_loop_range=iwan.loop_amplitude_range)
        maps, histories = _figures_data(sets, iwan.model, maxwell.model, elastomer_histories)
    except BaseException:
        transport_call.abandon()
        raise
    # not waited for here: the writer draws everything else while the study runs
    # (ReportData.transport waits on first use and times the wait)
    stages.finish()
    return ReportData(
        data_dir=data_dir, seed=int(seed), quick=bool(quick), sets=sets, inspections=inspections,
        valid_range=valid_range, iwan=iwan, boucwen=boucwen, iwan_loops=iwan_loops, boucwen_loops=boucwen_loops,
        maxwell=maxwell, order_table=order_table, validations=validations, hybrid=hybrid,
        hybrid_masses_from=masses_from, transport_source=transport_call, timings_s=stages.durations,
        drop_models=drop_models, drop_model=drop_model, sweep_maps=maps, drop_histories=histories,
    )


def identify_parts(data_dir=None, *, seed: int = 2026) -> tuple[IwanModel, GeneralizedMaxwell]:
    """The wire rope (Iwan) and elastomer (Maxwell) identified from a data folder's ``fit`` split.

    The transport study's parts when no model files are given (``idkit study transport``).

    Parameters
    ----------
    data_dir : path, optional
        Default :func:`idkit.io.discover.default_data_dir`.
    seed : int
    """
    sets = find_measurement_sets(data_dir if data_dir is not None else default_data_dir())
    return (fit_iwan_measurements(sets["wire_rope"], isolator="wire_rope", seed=seed).model,
            fit_maxwell_measurements(sets["elastomer"], isolator="elastomer", seed=seed).model)

