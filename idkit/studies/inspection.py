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

__all__ = ["Inspection", "InspectionOverview", "inspect_path", "overview"]


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
