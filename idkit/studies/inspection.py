"""``idkit inspect``: what a folder or file of measurements holds, and the observables of its overview.

Compute only: :func:`inspect_path` loads the measurements (:func:`idkit.io.discover.load_measurements`)
and summarizes them with data-quality warnings (:func:`idkit.observe.quality.summarize_measurements`);
:meth:`Inspection.overview` turns them into the observables the overview figures draw
(:mod:`idkit.plot.inspect`), with the same observers ``fit`` and ``validate`` use.
"""

from __future__ import annotations

from dataclasses import dataclass

from idkit.io.discover import load_measurements
from idkit.observe.drop import DropMeasurementResult, process_drop_measurement
from idkit.observe.quality import MeasurementSummary, summarize_measurements
from idkit.observe.stepped_sine import SteppedSineSweep, stepped_sine_sweep
from idkit.observe.white_noise import WhiteNoiseFrf, frf_from_white_noise

__all__ = ["ComplexTableInspection", "Inspection", "InspectionOverview", "inspect_complex_table", "inspect_path",
           "overview"]


@dataclass(frozen=True)
class InspectionOverview:
    """Observables of a list of measurements, one entry per kind present (None when absent).

    Attributes
    ----------
    quasi_static : tuple of QuasiStaticMeasurement or None
        The raw records (their loops are drawn as recorded).
    white_noise : tuple of WhiteNoiseFrf or None
        H1 and coherence of every white-noise run.
    stepped_sine : SteppedSineSweep or None
        HOSIDFs (3 harmonics) and input flatness per sweep.
    drop : dict or None
        ``{(isolator, top mass kg): [DropMeasurementResult, ...]}``, sorted by impact speed.
    """

    quasi_static: tuple | None = None
    white_noise: tuple[WhiteNoiseFrf, ...] | None = None
    stepped_sine: SteppedSineSweep | None = None
    drop: dict[tuple, list[DropMeasurementResult]] | None = None

    @property
    def kinds(self) -> tuple[str, ...]:
        """Kinds present, alphabetical."""
        return tuple(kind for kind in ("drop", "quasi_static", "stepped_sine", "white_noise")
                     if getattr(self, kind) is not None)


def overview(measurements) -> InspectionOverview:
    """The overview observables of ``measurements`` (module docstring)."""
    by_kind: dict[str, list] = {}
    for measurement in measurements:
        by_kind.setdefault(measurement.kind, []).append(measurement)
    drops = None
    if "drop" in by_kind:
        drops = {}
        for measurement in by_kind["drop"]:
            key = (measurement.info.isolator, measurement.info.top_mass_kg)
            drops.setdefault(key, []).append(process_drop_measurement(measurement))
        for results in drops.values():
            results.sort(key=lambda result: abs(result.impact_velocity))
    return InspectionOverview(
        quasi_static=tuple(by_kind["quasi_static"]) if "quasi_static" in by_kind else None,
        white_noise=tuple(frf_from_white_noise(m) for m in by_kind["white_noise"]) if "white_noise" in by_kind
        else None,
        stepped_sine=stepped_sine_sweep(by_kind["stepped_sine"], n_harmonics=3) if "stepped_sine" in by_kind
        else None,
        drop=drops,
    )


@dataclass(frozen=True)
class Inspection:
    """A folder or file of measurements and its summary.

    Attributes
    ----------
    title : str
        The set's name or the file name.
    measurements : tuple
    summary : MeasurementSummary
        Counts, ranges and data-quality warnings (``summary.report()``).
    """

    title: str
    measurements: tuple
    summary: MeasurementSummary

    @property
    def kinds(self) -> tuple[str, ...]:
        """Kinds present, alphabetical."""
        return tuple(sorted({m.kind for m in self.measurements}))

    def overview(self) -> InspectionOverview:
        """The observables of the overview figures (:func:`overview`)."""
        return overview(self.measurements)


def inspect_path(path, *, kind: str | None = None) -> Inspection:
    """Load a measurement-set folder or a data file and summarize it.

    Parameters
    ----------
    path : path
        A folder with ``manifest.json`` or one data file.
    kind : str, optional
        Kind of a lone data file (default: from its manifest or header).
    """
    title, measurements = load_measurements(path, kind)
    return Inspection(title, tuple(measurements), summarize_measurements(measurements))


@dataclass(frozen=True)
class ComplexTableInspection:
    """What a complex stiffness / DMA table holds, with data-quality warnings.

    Attributes
    ----------
    table : ComplexStiffnessTable
    shift_estimate : ShiftFactorEstimate or None
        Shift factors estimated from the isotherms (tables with a temperature column).
    warnings : tuple of str
    """

    table: object
    shift_estimate: object
    warnings: tuple[str, ...]

    def report(self) -> str:
        t = self.table
        eta = t.loss / t.storage
        lines = [f"{t.freq.size} points, {t.quantity} in {t.unit}, frequency {t.freq.min():.4g}-{t.freq.max():.4g} Hz, "
                 f"storage {t.storage.min():.4g}-{t.storage.max():.4g} {t.unit}, loss factor {eta.min():.3g}-"
                 f"{eta.max():.3g}"]
        if self.shift_estimate is None:
            lines.append("no temperature column: a master curve (or one isotherm) as given")
        else:
            est = self.shift_estimate
            lines.append(f"{est.temperature_k.size} isotherms, {est.temperature_k.min() - 273.15:.1f} to "
                         f"{est.temperature_k.max() - 273.15:.1f} C; shift factors estimated from them (reference "
                         f"{est.reference_temperature_k - 273.15:.2f} C):")
            lines.append(est.to_dataframe().round(4).to_string(index=False))
            lines.append(f"pairwise superposition residual (log10 |E*|): max {est.pair_residual_decades.max():.4f} "
                         "decades")
        lines.extend(f"warning: {w}" for w in self.warnings) if self.warnings else lines.append("no warnings")
        return "\n".join(lines)


def inspect_complex_table(table, *, reference_temperature_k: float | None = None) -> ComplexTableInspection:
    """Summarize a complex stiffness / DMA table: ranges, isotherms, estimated shift factors, warnings.

    Warnings: a negative storage or loss part (not a passive material), storage falling with
    frequency inside an isotherm (against linear viscoelasticity), an isotherm with fewer
    than 4 points, a pair of isotherms that superposes worse than 0.02 decades of |E*|.
    """
    import numpy as np

    from idkit.signal.shift_factors import estimate_shift_factors, group_isotherms

    warnings = []
    for name, column in (("storage", table.storage), ("loss", table.loss)):
        bad = np.flatnonzero(column <= 0 if name == "storage" else column < 0)
        if bad.size:
            rule = "storage > 0" if name == "storage" else "loss >= 0"
            warnings.append(f"{bad.size} row(s) with a {'non-positive' if name == 'storage' else 'negative'} "
                            f"{name} part (first: {table.source.row_label(int(bad[0]))}); a passive material has "
                            f"{rule}")
    estimate = None
    if table.temperature is not None:
        labels, temps = group_isotherms(table.temperature)
        for i, temperature in enumerate(temps):
            rows = np.flatnonzero(labels == i)
            order = rows[np.argsort(table.freq[rows])]
            if rows.size < 4:
                warnings.append(f"isotherm at {temperature - 273.15:.1f} C has {rows.size} points (< 4)")
            falling = int(np.sum(np.diff(table.storage[order]) < 0))
            if falling:
                warnings.append(f"isotherm at {temperature - 273.15:.1f} C: storage falls with frequency at "
                                f"{falling} step(s)")
        if temps.size >= 2 and not any("non-positive" in w for w in warnings):
            reference = reference_temperature_k
            if reference is None:
                reference = float(temps[np.argmin(np.abs(temps - np.median(table.temperature)))])
            estimate = estimate_shift_factors(table.freq, table.storage, table.loss, table.temperature,
                                              reference_temperature_k=reference,
                                              source=str(table.source.path or "table"))
            for i, residual in enumerate(estimate.pair_residual_decades):
                if residual > 0.02:
                    warnings.append(f"isotherms {temps[i] - 273.15:.1f} C and {temps[i + 1] - 273.15:.1f} C superpose "
                                    f"to {residual:.3f} decades of |E*| only (> 0.02): not thermorheologically simple "
                                    "there, or a measurement problem")
    return ComplexTableInspection(table=table, shift_estimate=estimate, warnings=tuple(warnings))
