"""Overview and data-quality warnings of a set of measurements (``idkit inspect``)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.io import (
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
)
from idkit.observe.white_noise import frf_from_white_noise
from idkit.observe.stepped_sine import stepped_sine_sweep
from idkit.observe.quasi_static import cycle_statistics
from idkit.errors import FitError


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
                     f"fs {span('sample_rate [Hz]', unit='Hz')}",
                     f"duration {span('duration [s]', unit='s')}"]
            for column, label, scale, unit in (("top_mass [kg]", "top mass", 1, "kg"),
                                               ("drop_height [m]", "height", 100, "cm"),
                                               ("freq [Hz]", "freq", 1, "Hz"),
                                               ("nominal_amplitude", "nominal amplitude", 1, ""),
                                               ("deflection_range [mm]", "peak-to-peak deflection", 1, "mm")):
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
        fs = m.sample_rate_hz
        row = {"id": m.id, "kind": m.kind, "isolator": info.isolator, "split": info.split,
               "sample_rate [Hz]": fs, "duration [s]": float(m.time[-1] - m.time[0]),
               "n_samples": m.n_samples, "top_mass [kg]": info.top_mass_kg,
               "drop_height [m]": info.drop_height_m,
               "freq [Hz]": None if exc is None else exc.freq,
               "nominal_amplitude": None if exc is None else exc.amplitude,
               "deflection_range [mm]": None}
        if getattr(m, "deflection", None) is not None:
            row["deflection_range [mm]"] = float(np.ptp(m.deflection)) * 1e3
        rows.append(row)
        for name, values in m.signals().items():
            if name == "time":
                continue
            run, level = find_clipping(values, min_run=clip_run)
            if run:
                warnings.append(InspectionWarning(
                    m.id, "clipped", f"{name} stays at its extreme {level:.6g} (SI) for {run} "
                    f"consecutive samples; expected a signal that does not saturate"))
        if isinstance(m, QuasiStaticMeasurement):
            try:
                stats = cycle_statistics(m)
            except FitError:  # no complete cycle: nothing to say about loops
                stats = None
            for finding in stats.findings() if stats is not None else ():
                kind = "loop_drift" if finding.startswith("loop centre") else "force_offset"
                warnings.append(InspectionWarning(
                    m.id, kind, f"{finding}; expected loops centred on a fixed point and zero force there "
                    "(fit with --remove-offsets / remove_offsets=True to remove it, recorded in the provenance)"))
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
