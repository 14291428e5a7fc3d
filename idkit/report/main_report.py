"""``idkit report``: the whole job on a data set, as one self-contained HTML page.

:func:`run_report` computes a :class:`~idkit.studies.pipeline.ReportData`
(:func:`idkit.studies.pipeline.compute_report_data`: inspect, fit, validate, transport
study; see there for the stages) and :func:`write_report` renders it: ``report.html``
(figures embedded), ``models/*.json`` (with provenance), ``tables/*.csv``, the transport
figures and ``provenance.json``, into an output folder that appears whole or not at all and
is never replaced without ``force``. Nothing here fits, validates or simulates.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from idkit import __version__
from idkit.atomic import atomic_output_folder, write_text_atomic
from idkit.models import save_model
from idkit.plot.fits import plot_frf_fit, plot_loop_fit, plot_storage_loss
from idkit.plot.validation import plot_drop_validation, plot_frf_validation, plot_harmonic_validation
from idkit.report.html import HtmlReport
from idkit.report.study_files import write_transport_files
from idkit.studies.pipeline import QUICK_NOTE, ReportData, ValidationEntry, compute_report_data

__all__ = ["REPORT_SECTIONS", "QUICK_NOTE", "ReportSummary", "run_report", "write_report"]

REPORT_SECTIONS = (
    "Summary", "Data", "Wire rope fit", "Elastomer fit", "Validation: wire rope", "Validation: elastomer",
    "Validation: hybrid", "Transport study", "Provenance",
)

#: the figure of each validated observable (:attr:`ValidationEntry.observable`)
VALIDATION_PLOTS = {"sweeps": plot_harmonic_validation, "FRF": plot_frf_validation, "drops": plot_drop_validation}

#: the validation sections: title, HTML anchor, :attr:`ValidationEntry.isolator`
_VALIDATION_SECTIONS = (("Validation: wire rope", "validation-wire-rope", "wire rope"),
                        ("Validation: elastomer", "validation-elastomer", "elastomer"),
                        ("Validation: hybrid", "validation-hybrid", "hybrid"))

WRITING = "writing the report"


@dataclass(frozen=True)
class ReportSummary:
    """What ``run_report`` wrote and found.

    Attributes
    ----------
    out_dir, html : Path
        The output folder and its ``report.html``.
    sections : tuple of str
        Section titles of the page.
    validation_passed : dict of str to bool
    timings_s : dict of str to float
        Seconds per stage, writing included.
    validation_verdicts : dict of str to str
        ``"PASS"``, ``"INCONCLUSIVE"`` or ``"FAIL"`` per validation.
    quick : bool
    """

    out_dir: Path
    html: Path
    sections: tuple[str, ...]
    validation_passed: dict
    timings_s: dict
    validation_verdicts: dict
    quick: bool = False

    @property
    def exit_status(self) -> int:
        """0 when every validation passed, 1 when one failed, 3 when none failed but one is inconclusive."""
        verdicts = set(self.validation_verdicts.values())
        return 1 if "FAIL" in verdicts else 3 if "INCONCLUSIVE" in verdicts else 0


def _metrics_csv(entry: ValidationEntry, path: Path) -> None:
    metrics = entry.result.metrics.copy()
    for column in metrics.columns:
        if metrics[column].dtype == complex:
            metrics[column] = metrics[column].astype(str)
    metrics.to_csv(path, index=False)


def _validation_section(report: HtmlReport, entry: ValidationEntry, tables_dir: Path, quick: bool) -> None:
    result = entry.result
    report.verdict(result.name + (f" ({QUICK_NOTE})" if quick else ""), result.verdict)
    report.preformatted(result.report())
    rows = [{"metric": key, "value": value, "limit": result.thresholds.get(key, np.nan),
             "ok": result.checks.get(key, "")} for key, value in result.summary.items()]
    report.table(pd.DataFrame(rows), caption="metrics (limits are the documented defaults)")
    axes = VALIDATION_PLOTS[entry.observable](result)
    report.figure(axes[0].figure, caption=result.name)
    _metrics_csv(entry, tables_dir / f"{entry.key.replace(' ', '_').replace(',', '')}.csv")


def _drop_model_section(report: HtmlReport, data: ReportData, tables_dir: Path) -> None:
    """The wire rope's held-out drops under both drop models, plain and slip-modulated Iwan."""
    comparison = data.drop_models
    model, drop = comparison.supported()
    table = comparison.table
    write_text_atomic(tables_dir / "wire_rope_drop_models.csv", table.to_csv(index=False))
    report.paragraph(f"Drop models compared on the same held-out wire-rope drops (the drop validations above use "
                     f"drop_model='{data.drop_model}'): the conditioned free fall of the study (every mass at the "
                     "impact velocity, base fixed) and the drop rig (the stack released from its statically "
                     "loaded rest state, the bottom mass bouncing on the floor), each with the plain Iwan model "
                     "and with the slip-modulated Iwan model fitted on the same loops.")
    report.table(table, caption="median and worst |relative error| of the peak top-mass acceleration per phase "
                                "and top mass; verdict of each validation")
    best = comparison.results[(model, drop)].summary
    report.paragraph(f"The held-out drops support the {model} model with the {drop} drop model: median peak "
                     f"error {best['median_peak_acceleration_compression_error']:.3f} in compression and "
                     f"{best['median_peak_acceleration_tension_error']:.3f} in tension.")
    for note in comparison.notes:
        report.paragraph(note)


def _summary_section(report: HtmlReport, data: ReportData) -> None:
    report.section("Summary", "summary")
    report.paragraph(f"Data: {data.data_dir} ({data.n_measurements} measurements). "
                     f"idkit {__version__}, seed {data.seed}{', quick mode' if data.quick else ''}.")
    iwan, boucwen, maxwell = data.iwan.result, data.boucwen.result, data.maxwell.result
    rows = [
        {"item": "wire rope (Iwan, order 2)",
         "result": f"small {100 * iwan.error_small:.2f} %, large {100 * iwan.error_large:.2f} % (eq. 7.1)"},
        {"item": "wire rope (Bouc-Wen)",
         "result": f"small {100 * boucwen.error_small:.2f} %, large {100 * boucwen.error_large:.2f} %"},
        {"item": "elastomer (Maxwell, order 2)", "result": f"{100 * maxwell.error:.2f} % (eq. 7.5)"},
    ]
    for entry in data.validations:
        cannot_see = entry.result.cannot_see
        rows.append({"item": entry.key, "result": entry.result.verdict + (f" ({QUICK_NOTE})" if data.quick else "")
                     + (f"; cannot see: {'; '.join(cannot_see)}" if cannot_see else "")})
    report.table(pd.DataFrame(rows), caption="identification errors and validation verdicts")


def _fit_sections(report: HtmlReport, data: ReportData) -> None:
    report.section("Wire rope fit", "wire-rope-fit")
    lower, upper = data.iwan.model.valid_deflection_range()
    report.paragraph(f"Valid range of the identified Iwan model: its parallel spring's local stiffness "
                     f"g1 + 2 g2 x + 3 g3 x^2 stays >= 0 for {1e3 * lower:.1f} mm <= x <= {1e3 * upper:.1f} mm "
                     f"(SPEC 1.2). The fit was required to keep it valid over "
                     f"{1e3 * data.valid_range[0]:.1f} to {1e3 * data.valid_range[1]:.1f} mm, 1.25 times the "
                     f"deflections in the data set; simulations beyond the valid range are flagged, and validations "
                     f"count them as failures.")
    report.preformatted(data.iwan.report())
    report.table(data.iwan.parameters_table(),
                 caption="Iwan parameters: stderr from the residual Jacobian at the optimum (the spread "
                         "within this data set; stderr_note says why one is missing) beside the spread across "
                         "repetitions (std of one refit per repetition, repetition_values)"
                         + (f"; {data.iwan.spread_note}" if data.iwan.spread_note else ""))
    report.figure(plot_loop_fit(data.iwan_loops, label="Iwan")[0].figure, caption="measured and fitted loops (Iwan)")
    report.preformatted(data.boucwen.report())
    report.figure(plot_loop_fit(data.boucwen_loops, label="Bouc-Wen")[0].figure,
                  caption="measured and fitted loops (Bouc-Wen)")

    report.section("Elastomer fit", "elastomer-fit")
    report.preformatted(data.maxwell.report())
    report.table(data.maxwell.parameters_table(), caption="Maxwell parameters (k0 from the quasi-static loops)")
    report.table(data.order_table, caption="order selection: error (7.5) for n = 1..4 and the Voigt model")
    report.figure(plot_frf_fit(data.maxwell.model, list(data.maxwell.data))[0].figure,
                  caption="measured H1 and fitted transmissibility per top mass")
    report.figure(plot_storage_loss(data.maxwell.model)[0].figure, caption="complex stiffness and loss factor")


def _write_models(data: ReportData, models_dir: Path) -> None:
    data.iwan.save(models_dir / "wire_rope_iwan.json")
    data.boucwen.save(models_dir / "wire_rope_bouc_wen.json")
    data.maxwell.save(models_dir / "elastomer_maxwell.json")
    if data.hybrid is not None:
        save_model(data.hybrid, models_dir / "hybrid.json",
                   provenance={"built_from": ["wire_rope_iwan.json", "elastomer_maxwell.json"],
                               "masses_from": data.hybrid_masses_from, "idkit_version": __version__})


def write_report(data: ReportData, folder) -> ReportSummary:
    """Render ``data`` into an existing, empty ``folder`` (module docstring); returns what was written.

    The provenance table of the page lists every stage's duration; the writing itself is
    still running when that table is drawn and is labelled "(until this table)";
    ``provenance.json`` holds its full duration.
    """
    started = time.perf_counter()
    folder = Path(folder)
    models_dir, tables_dir = folder / "models", folder / "tables"
    models_dir.mkdir()
    tables_dir.mkdir()
    _write_models(data, models_dir)
    data.order_table.to_csv(tables_dir / "maxwell_order_table.csv", index=False)
    transport_files = write_transport_files(data.transport, folder, tables_dir=tables_dir)

    report = HtmlReport(f"idkit report: {data.data_dir}")
    _summary_section(report, data)
    report.section("Data", "data")
    for isolator, inspection in data.inspections.items():
        report.paragraph(f"{isolator}: {data.sets[isolator].folder}")
        report.preformatted(inspection.report())
    _fit_sections(report, data)
    for title, anchor, isolator in _VALIDATION_SECTIONS:
        report.section(title, anchor)
        entries = data.validations_of(isolator)
        if not entries:
            report.paragraph("no measurements of this isolator in the data set")
        for entry in entries:
            _validation_section(report, entry, tables_dir, data.quick)
        if isolator == "wire rope" and data.drop_models is not None:
            _drop_model_section(report, data, tables_dir)

    report.section("Transport study", "transport-study")
    report.table(data.transport.tuning, caption="systems tuned to a 5 Hz small-amplitude resonance (SPEC 6)")
    report.table(data.transport.summary_table(), index=True,
                 caption="RMS top acceleration [m/s^2] per floor level and rest shock per drop height")
    for path in transport_files:
        if path.suffix == ".png":
            report.image_file(path, caption=path.stem.replace("_", " "))

    report.section("Provenance", "provenance")
    report.paragraph(f"idkit {__version__}; seed {data.seed}; models in models/, tables in tables/.")
    so_far = {**data.timings_s, f"{WRITING} (until this table)": round(time.perf_counter() - started, 3)}
    report.table(pd.DataFrame([{"stage": stage, "duration [s]": seconds} for stage, seconds in so_far.items()]),
                 caption="timings (durations)")
    hashes = {isolator: s.hashes() for isolator, s in data.sets.items()}
    report.table(pd.DataFrame([{"isolator": isolator, "file": name, "sha256": digest}
                               for isolator, digests in hashes.items() for name, digest in digests.items()]),
                 caption="data files and their SHA-256")
    html_path = folder / "report.html"
    html_path.write_text(report.render(), encoding="utf-8")
    timings = {**data.timings_s, WRITING: round(time.perf_counter() - started, 3)}
    provenance = {
        "idkit_version": __version__, "seed": data.seed, "quick": data.quick, "data_dir": str(data.data_dir),
        "data_files_sha256": hashes, "timings_s": timings, "models": sorted(p.name for p in models_dir.iterdir()),
    }
    (folder / "provenance.json").write_text(json.dumps(provenance, indent=1, default=str) + "\n")
    verdicts = data.verdicts
    return ReportSummary(out_dir=folder, html=html_path, sections=tuple(report.section_titles),
                         validation_passed={entry.key: entry.result.passed for entry in data.validations},
                         timings_s=timings, validation_verdicts=verdicts, quick=data.quick)


def run_report(data_dir=None, out_dir="idkit-report", *, force: bool = False, quick: bool = False,
               seed: int = 2026, workers=None, progress=None, start_state: str = "auto",
               drop_model: str = "auto") -> ReportSummary:
    """Inspect, fit, validate, study (:func:`~idkit.studies.pipeline.compute_report_data`) and write the report.

    Parameters
    ----------
    data_dir : path, optional
        Folder of measurement sets; default :func:`idkit.io.discover.default_data_dir` (the bundled data).
    out_dir : path
        Output folder; refused if it exists unless ``force``.
    force : bool
        Replace an existing output folder (only once the new one is complete).
    quick : bool
        Fewer validation points and a smaller transport study (for tests); the fits and
        checks are the same.
    seed : int
        Seed of every stochastic step (the fits' global searches, the random vibration).
    workers : int, optional
        Simulation threads of the transport study (default: all usable cores).
    progress : callable(message: str), optional
        Receives one line per stage.
    start_state : {"auto", "cycled", "virgin"}
        Start state of the wire-rope loop fits (:func:`idkit.fit.fit_iwan`); recorded in
        the model files' provenance with the state each record was scored from.
    drop_model : {"auto", "rig", "conditioned"}
        Drop model of the drop validations (:func:`idkit.validate.validate_drops`).

    Returns
    -------
    ReportSummary
    """
    say = progress or (lambda message: None)
    with atomic_output_folder(out_dir, force=force) as folder:
        data = compute_report_data(data_dir, quick=quick, seed=seed, workers=workers, progress=say,
                                   start_state=start_state, drop_model=drop_model)
        say(WRITING)
        summary = write_report(data, folder)
    out_dir = Path(out_dir)
    return ReportSummary(out_dir=out_dir, html=out_dir / "report.html", sections=summary.sections,
                         validation_passed=summary.validation_passed, timings_s=summary.timings_s,
                         validation_verdicts=summary.validation_verdicts, quick=summary.quick)
