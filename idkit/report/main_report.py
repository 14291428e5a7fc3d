"""``idkit report``: the whole job on a data set, as one self-contained HTML page.

:func:`run_report` computes a :class:`~idkit.studies.pipeline.ReportData`
(:func:`idkit.studies.pipeline.compute_report_data`: inspect, fit, validate, transport
study; see there for the stages) and :func:`write_report` renders it: ``report.html``
(figures embedded), ``models/*.json`` (with provenance), ``tables/*.csv``, the transport
figures and ``provenance.json``, into an output folder that appears whole or not at all and
is never replaced without ``force``. Nothing here fits, validates or simulates.

The page's sections are drawn by :mod:`~idkit.report.front_page` (the first screen),
:mod:`~idkit.report.fit_sections`, :mod:`~idkit.report.validation_sections` and
:mod:`~idkit.report.transport_section`; this module orders them, writes the files and
returns what ``idkit report`` exits with.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import pandas as pd

from idkit import __version__
from idkit.atomic import atomic_output_folder, write_text_atomic
from idkit.models import save_model
from idkit.report.blas_threads import one_blas_thread
from idkit.report.fit_sections import elastomer_fit_section, wire_rope_fit_section
from idkit.report.front_page import fit_reasons, front_section, report_exit_status
from idkit.report.html import HtmlReport
from idkit.report.study_files import write_transport_files
from idkit.report.transport_section import transport_section
from idkit.report.validation_sections import VALIDATION_SECTIONS, validation_isolator_section
from idkit.studies.pipeline import ReportData, compute_report_data

__all__ = ["REPORT_SECTIONS", "ReportSummary", "run_report", "write_report"]


REPORT_SECTIONS = (
    "Summary", "Data", "Wire rope fit", "Elastomer fit", "Validation: wire rope", "Validation: elastomer",
    "Validation: hybrid", "Transport study", "Provenance",
)


WRITING = "writing the report"


#: the figures' share of the writing (label of the timings)
FIGURES = "drawing and saving the figures (part of the writing)"


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
    fit_reasons : dict of str to tuple of str
        Per identified model the report predicts with (:data:`PREDICTING_FITS`): why its fit is
        not a success (empty when it is).
    validation_notes : dict of str to tuple of str
        Per validation, the findings that explain its verdict without changing it
        (:attr:`idkit.validate.ValidationResult.notes`, e.g. levels outside the loops the model
        was identified on).
    validation_reasons : dict of str to tuple of str
        Per validation, what keeps its verdict from PASS (:attr:`idkit.validate.ValidationResult.why`:
        the metrics beyond their limits, the reasons it is inconclusive); empty for a PASS.
    """

    out_dir: Path
    html: Path
    sections: tuple[str, ...]
    validation_passed: dict
    timings_s: dict
    validation_verdicts: dict
    quick: bool = False
    fit_reasons: dict = field(default_factory=dict)
    validation_notes: dict = field(default_factory=dict)
    validation_reasons: dict = field(default_factory=dict)

    @property
    def flagged_fits(self) -> tuple[str, ...]:
        """The predicting models whose fit is not a success."""
        return tuple(name for name, reasons in self.fit_reasons.items() if reasons)

    @property
    def exit_status(self) -> int:
        """0 when everything passed: 1 when a validation failed, 3 when none failed but one is
        inconclusive, 4 when every validation passed but a fit the report predicts with is not a
        success (:data:`idkit.exit_status.REPORT_EXIT_STATUSES`)."""
        return report_exit_status(self.validation_verdicts, self.flagged_fits)


def _provenance_section(report: HtmlReport, data: ReportData, timings: dict, hashes: dict) -> None:
    report.section("Provenance", "provenance", collapsed=True)
    report.summarize(f"idkit {__version__}, seed {data.seed}, data files and their SHA-256, timings")
    report.paragraph(f"idkit {__version__}; seed {data.seed}; quick {data.quick}; drop model {data.drop_model}; "
                     f"data {data.data_dir}. Models in models/, tables in tables/, figures in figures/ (PNG and "
                     "SVG); provenance.json holds everything below.")
    report.table(pd.DataFrame([{"stage": stage, "duration [s]": seconds} for stage, seconds in timings.items()]),
                 caption="timings (durations in seconds)", name="timings")
    report.table(pd.DataFrame([{"isolator": isolator, "file": name, "sha256": digest}
                               for isolator, digests in hashes.items() for name, digest in digests.items()]),
                 caption=f"data files and their SHA-256 ({sum(len(d) for d in hashes.values())} files)",
                 name="data files sha256")


def _write_models(data: ReportData, models_dir: Path) -> None:
    data.iwan.save(models_dir / "wire_rope_iwan.json")
    data.boucwen.save(models_dir / "wire_rope_bouc_wen.json")
    data.maxwell.save(models_dir / "elastomer_maxwell.json")
    if data.hybrid is not None:
        save_model(data.hybrid, models_dir / "hybrid.json",
                   provenance={"built_from": ["wire_rope_iwan.json", "elastomer_maxwell.json"],
                               "masses_from": data.hybrid_masses_from, "idkit_version": __version__})


def write_report(data: ReportData, folder, *, pdf: bool = False, render_processes: int | None = None) -> ReportSummary:
    """Render ``data`` into an existing, empty ``folder`` (module docstring); returns what was written.

    The page's timings table lists every stage's duration; the writing itself is still
    running when that table is drawn and is labelled "(until this table)"; the figures'
    share of it is "drawing the figures". ``provenance.json`` holds the full durations.
    Figures are rendered by up to ``render_processes`` child processes (default: the usable
    cores; :class:`~idkit.report.html.HtmlReport`).
    """
    started = time.perf_counter()
    folder = Path(folder)
    models_dir, tables_dir, figures_dir = folder / "models", folder / "tables", folder / "figures"
    for directory in (models_dir, tables_dir, figures_dir):
        directory.mkdir()
    _write_models(data, models_dir)

    report = HtmlReport(f"idkit report: {data.data_dir}", figures_dir=figures_dir, tables_dir=tables_dir,
                        keep_figures=pdf, render_processes=_usable_cores() if render_processes is None
                        else int(render_processes))
    try:
        return _write_report(data, report, folder, started, pdf=pdf)
    finally:
        report.abandon_figures()  # no child may still write into the folder after this returns
        data.abandon_transport()


def _usable_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _data_section(report: HtmlReport, data: ReportData) -> str:
    rows = []
    for isolator, inspection in data.inspections.items():
        counts = inspection.table["kind"].value_counts(sort=False)
        rows.append({"set": isolator, "folder": str(data.sets[isolator].folder),
                     "measurements": ", ".join(f"{n} {kind}" for kind, n in counts.items()),
                     "warnings": str(len(inspection.warnings))})
    report.front_table(rows)
    warnings = warning_rows(data)
    total = sum(len(inspection.warnings) for inspection in data.inspections.values())
    if warnings:
        with report.folded(f"show the {total} data warning(s), {len(warnings)} distinct"):
            report.front_table(warnings)
    for isolator, inspection in data.inspections.items():
        report.preformatted(inspection.report(), label=f"show the inspection of the {isolator} set")
    return (f"{data.n_measurements} measurements in {len(data.inspections)} set(s); {total} data warning(s)"
            + (f", {len(warnings)} distinct" if warnings else ""))


def warning_rows(data: ReportData) -> list[dict]:
    """The data warnings of every set, one row per distinct (kind, message) with the records that raised it."""
    grouped: dict[tuple[str, str], list[str]] = {}
    for inspection in data.inspections.values():
        for warning in inspection.warnings:
            records = grouped.setdefault((warning.kind, warning.message), [])
            if warning.measurement_id not in records:
                records.append(warning.measurement_id)
    return [{"kind": kind, "message": message, "records": f"{len(records)}: " + "; ".join(records)}
            for (kind, message), records in grouped.items()]


def _section_builders() -> tuple:
    """The collapsed sections between the first screen and the transport study, in page order:
    ``(title, anchor, builder)``; ``builder(report, data)`` draws its section and returns the one-line gist
    shown on its collapsed header. A new section is one more row (:data:`REPORT_SECTIONS` lists every title)."""
    def validation(isolator):
        return lambda report, data: validation_isolator_section(report, data, isolator)

    return (("Data", "data", _data_section),
            ("Wire rope fit", "wire-rope-fit", wire_rope_fit_section),
            ("Elastomer fit", "elastomer-fit", elastomer_fit_section),
            *((title, anchor, validation(isolator)) for title, anchor, isolator in VALIDATION_SECTIONS))


def _write_report(data: ReportData, report: HtmlReport, folder: Path, started: float, *, pdf: bool) -> ReportSummary:
    models_dir, tables_dir, figures_dir = folder / "models", folder / "tables", folder / "figures"
    # everything that does not need the transport study first: it is still running in a child
    # process (ReportData.transport), and these figures render meanwhile
    summary_slot = front_section(report, data)
    for title, anchor, build in _section_builders():
        report.section(title, anchor, collapsed=True)
        report.summarize(build(report, data))
    write_transport_files(data.transport, folder, tables_dir=tables_dir, figures=False)
    report.section("Transport study", "transport-study", collapsed=True)
    report.summarize(transport_section(report, data, summary_slot))

    hashes = {isolator: s.hashes() for isolator, s in data.sets.items()}
    so_far = {**data.timings_s, FIGURES: round(report.figure_seconds, 3),
              f"{WRITING} (until this table)": round(time.perf_counter() - started, 3)}
    _provenance_section(report, data, so_far, hashes)
    html_path = folder / "report.html"
    write_text_atomic(html_path, report.render())  # waits for the figures still rendering
    if pdf:
        from idkit.report.pdf import write_pdf

        write_pdf(report, folder / "report.pdf")
    timings = {**data.timings_s, FIGURES: round(report.figure_seconds, 3),
               WRITING: round(time.perf_counter() - started, 3)}
    provenance = {
        "idkit_version": __version__, "seed": data.seed, "quick": data.quick, "data_dir": str(data.data_dir),
        "drop_model": data.drop_model, "data_files_sha256": hashes, "timings_s": timings,
        "quick_skipped_records": {entry.key: list(entry.skipped) for entry in data.validations if entry.skipped},
        "models": sorted(p.name for p in models_dir.iterdir()),
        "figures": sorted(p.name for p in figures_dir.iterdir()),
        "tables": sorted(p.name for p in tables_dir.iterdir()),
    }
    write_text_atomic(folder / "provenance.json", json.dumps(provenance, indent=1, default=str) + "\n")
    verdicts = data.verdicts
    return ReportSummary(out_dir=folder, html=html_path, sections=tuple(report.section_titles),
                         validation_passed={entry.key: entry.result.passed for entry in data.validations},
                         timings_s=timings, validation_verdicts=verdicts, quick=data.quick,
                         fit_reasons=fit_reasons(data),
                         validation_notes={entry.key: entry.result.notes for entry in data.validations},
                         validation_reasons={entry.key: entry.result.why for entry in data.validations})


def run_report(data_dir=None, out_dir="idkit-report", *, force: bool = False, quick: bool = False,
               seed: int = 2026, workers=None, progress=None, start_state: str = "auto",
               drop_model: str = "auto", pdf: bool = False) -> ReportSummary:
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
    pdf : bool
        Also write ``report.pdf`` (:mod:`idkit.report.pdf`).

    Returns
    -------
    ReportSummary
    """
    say = progress or (lambda message: None)
    # the report's own processes share the cores: one BLAS thread each (idkit.report.blas_threads)
    with one_blas_thread(), atomic_output_folder(out_dir, force=force) as folder:
        data = compute_report_data(data_dir, quick=quick, seed=seed, workers=workers, progress=say,
                                   start_state=start_state, drop_model=drop_model)
        say(WRITING)
        summary = write_report(data, folder, pdf=pdf)
    out_dir = Path(out_dir)
    return replace(summary, out_dir=out_dir, html=out_dir / "report.html")
