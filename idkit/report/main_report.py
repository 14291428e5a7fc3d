"""``idkit report``: the whole job on a data set, as one self-contained HTML page.

Stages (each timed and listed under *Provenance*):

1. load and inspect every measurement set under the data folder (one folder with a
   ``manifest.json`` per isolator: ``wire_rope``, ``elastomer``, ``hybrid``);
2. fit the wire rope (three-stage Iwan; Bouc-Wen for comparison) and the elastomer
   (bounded SQP with a global cross-check; order table n = 1..4 and Voigt) on the
   ``fit`` split; the Iwan parameters with their standard errors and their spread over
   one refit per repetition (:meth:`~idkit.fit.MeasurementFit.with_repetition_spread`);
3. validate both on the ``validation`` split and the hybrid built from them on all
   hybrid sweeps and drops (nothing was fitted to the hybrid);
4. run the transport-tool study with the identified parts;
5. write ``report.html`` (figures embedded), ``models/*.json`` (with provenance),
   ``tables/*.csv`` and ``provenance.json`` into an output folder that appears whole
   or not at all and is never replaced without ``force``.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from idkit import __version__
from idkit.observe.quality import summarize_measurements
from idkit.errors import DataError
from idkit.fit import maxwell_order_table
from idkit.fit.measurements import (
    fit_boucwen_measurements,
    fit_iwan_measurements,
    fit_maxwell_measurements,
    transmissibility_sets,
)
from idkit.io import load_measurement_set
from idkit.models import HybridSystem, save_model
from idkit.plot.fits import plot_storage_loss
from idkit.plot.fits import plot_frf_fit, plot_loop_fit
from idkit.plot.validation import plot_drop_validation, plot_frf_validation, plot_harmonic_validation
from idkit.report.html import HtmlReport
from idkit.atomic import atomic_output_folder
from idkit.report.transport import compute_transport_study, write_transport_figures, write_transport_tables
from idkit.validate import blind_spots, validate_drops, validate_frf, validate_harmonic

__all__ = ["run_report", "ReportSummary", "find_measurement_sets", "default_data_dir", "REPORT_SECTIONS"]

REPORT_SECTIONS = (
    "Summary", "Data", "Wire rope fit", "Elastomer fit", "Validation: wire rope", "Validation: elastomer",
    "Validation: hybrid", "Transport study", "Provenance",
)


@dataclass(frozen=True)
class ReportSummary:
    """What ``run_report`` wrote and found."""

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


def default_data_dir() -> Path:
    """``./data`` if it exists (the README runs from the repository root), else the source tree's ``data``."""
    local = Path("data")
    if (local / "README.md").exists() or any(local.glob("*/manifest.json")):
        return local
    return Path(__file__).resolve().parents[2] / "data"


def find_measurement_sets(data_dir) -> dict:
    """Load every measurement set below ``data_dir``, keyed by the isolator its records name."""
    data_dir = Path(data_dir)
    if not data_dir.is_dir():
        raise DataError(f"{data_dir}: not a folder, expected a data folder holding measurement sets")
    folders = sorted({path.parent for path in data_dir.glob("*/manifest.json")})
    if (data_dir / "manifest.json").exists():
        folders.insert(0, data_dir)
    if not folders:
        raise DataError(f"{data_dir}: no manifest.json in it or its sub-folders, expected measurement sets "
                        "(see docs/data-format.md)")
    sets = {}
    for folder in folders:
        measurement_set = load_measurement_set(folder)
        for isolator in sorted({m.info.isolator for m in measurement_set.measurements if m.info.isolator}):
            if isolator in sets:
                raise DataError(f"{folder}: isolator {isolator!r} also found in {sets[isolator].folder}; "
                                "expected one set per isolator")
            sets[isolator] = measurement_set
    for required in ("wire_rope", "elastomer"):
        if required not in sets:
            raise DataError(f"{data_dir}: no measurements of isolator {required!r} found, expected "
                            "wire_rope and elastomer sets (hybrid optional)")
    return sets


def _figure(*args, **kwargs):
    from matplotlib.figure import Figure

    return Figure(*args, layout="constrained", **kwargs)


def _loop_figure(fit, title):
    figure = _figure(figsize=(11, 4))
    plot_loop_fit(fit.model, fit.data.small, fit.data.large, axes=figure.subplots(1, 2), label=title)
    return figure


def _frf_figure(fit):
    figure = _figure(figsize=(10, 6))
    plot_frf_fit(fit.model, list(fit.data), axes=figure.subplots(2, 1, sharex=True))
    return figure


def _stiffness_figure(model):
    figure = _figure(figsize=(8, 6))
    plot_storage_loss(model, axes=figure.subplots(2, 1, sharex=True))
    return figure


def _parameters_table(fit) -> pd.DataFrame:
    """Value, stderr (residual Jacobian, or why none) and spread across repetitions side by side."""
    return fit.parameters_table()


QUICK_NOTE = "quick run: at most 8 held-out records per validation, smaller study; not the full verdict"


def _validation_section(report: HtmlReport, result, plot, tables_dir: Path, stem: str, quick: bool = False) -> bool:
    report.verdict(result.name + (f" ({QUICK_NOTE})" if quick else ""), result.verdict)
    report.preformatted(result.report())
    summary_rows = [{"metric": key, "value": value, "limit": result.thresholds.get(key, np.nan),
                     "ok": result.checks.get(key, "")} for key, value in result.summary.items()]
    report.table(pd.DataFrame(summary_rows), caption="metrics (limits are the documented defaults)")
    axes = plot(result)
    report.figure(axes[0].figure, caption=result.name)
    metrics = result.metrics.copy()
    for column in metrics.columns:
        if metrics[column].dtype == complex:
            metrics[column] = metrics[column].astype(str)
    metrics.to_csv(tables_dir / f"{stem}.csv", index=False)
    return result.passed


def run_report(data_dir=None, out_dir="idkit-report", *, force: bool = False, quick: bool = False,
               seed: int = 2026, workers=None, progress=None, start_state: str = "auto") -> ReportSummary:
    """Inspect, fit, validate, study and write the HTML report (module docstring).

    Parameters
    ----------
    data_dir : path, optional
        Folder of measurement sets; default :func:`default_data_dir` (the bundled data).
    out_dir : path
        Output folder; refused if it exists unless ``force``.
    quick : bool
        Smaller transport study and fewer validation points (for tests); the
        fits and checks are the same.
    seed : int
        Seed of every stochastic step (fits' global search, bootstrap, random vibration).
    progress : callable(message: str), optional
        Receives one line per stage.
    start_state : {"auto", "cycled", "virgin"}
        Start state of the wire-rope loop fits (:func:`idkit.fit.fit_iwan`); recorded in
        the model files' provenance with the state each record was scored from.
    """
    say = progress or (lambda message: None)
    timings: dict[str, float] = {}
    data_dir = Path(data_dir) if data_dir is not None else default_data_dir()

    def stage(name):
        timings[name] = time.perf_counter()
        say(name)

    finished: set[str] = set()

    def done(name):
        timings[name] = round(time.perf_counter() - timings[name], 3)
        finished.add(name)

    def durations():
        """Stage durations in s; a stage still running counts up to now."""
        now = time.perf_counter()
        return {k: v if k in finished else round(now - v, 3) for k, v in timings.items()}

    stage("loading and inspecting the data")
    sets = find_measurement_sets(data_dir)
    inspections = {isolator: summarize_measurements(s.measurements) for isolator, s in sets.items()}
    done("loading and inspecting the data")

    with atomic_output_folder(out_dir, force=force) as folder:
        models_dir = folder / "models"
        tables_dir = folder / "tables"
        models_dir.mkdir()
        tables_dir.mkdir()
        report = HtmlReport(f"idkit report: {data_dir}")

        stage("fitting the wire rope (three-stage Iwan, Bouc-Wen comparison)")
        wire_rope = sets["wire_rope"]
        # the identified spring must stay valid over every deflection the data set shows
        # (drops compress far beyond the quasi-static loops), with a 25 % margin
        seen = [m.deflection for m in wire_rope.measurements if getattr(m, "deflection", None) is not None]
        valid_range = (1.25 * min(float(d.min()) for d in seen), 1.25 * max(float(d.max()) for d in seen))
        iwan = fit_iwan_measurements(wire_rope, seed=seed, valid_range=valid_range, initial_state=start_state)
        iwan = iwan.with_repetition_spread()  # one refit per repetition of the fit split (a few seconds)
        boucwen = fit_boucwen_measurements(wire_rope, seed=seed, initial_state=start_state,
                                           **({"global_max_evals": 800} if quick else {}))
        iwan.save(models_dir / "wire_rope_iwan.json")
        boucwen.save(models_dir / "wire_rope_bouc_wen.json")
        done("fitting the wire rope (three-stage Iwan, Bouc-Wen comparison)")

        stage("fitting the elastomer (SQP, global cross-check, order table)")
        elastomer = sets["elastomer"]
        maxwell = fit_maxwell_measurements(elastomer, cross_check=True, seed=seed,
                                           **({"global_max_evals": 2000} if quick else {}))
        maxwell.save(models_dir / "elastomer_maxwell.json")
        frfs, _ = transmissibility_sets(elastomer)
        order_table = maxwell_order_table(list(frfs), k0=maxwell.k0.k0, orders=(1, 2) if quick else (1, 2, 3, 4))
        order_table.to_csv(tables_dir / "maxwell_order_table.csv", index=False)
        done("fitting the elastomer (SQP, global cross-check, order table)")

        wire_model, elastomer_model = iwan.model, maxwell.model
        validations = {}
        stage("validating on held-out data")
        limit = 8 if quick else None

        def held_out(measurement_set, kind, split="validation"):
            chosen = measurement_set.select(kind=kind, split=split)
            return list(chosen)[:limit] if limit else list(chosen)

        validations["wire rope sweeps"] = validate_harmonic(held_out(wire_rope, "stepped_sine"), isolator=wire_model,
                                                            name="wire rope: harmonic sweeps (validation split)")
        validations["wire rope drops"] = validate_drops(held_out(wire_rope, "drop"), isolator=wire_model,
                                                        name="wire rope: drops (validation split)")
        validations["wire rope drops, relaxation"] = validate_drops(
            held_out(wire_rope, "drop"), isolator=wire_model, relaxation=True,
            name="wire rope: drops with relaxation (validation split)")
        validations["elastomer FRF"] = validate_frf(held_out(elastomer, "white_noise"), isolator=elastomer_model,
                                                    name="elastomer: white-noise FRFs (validation split)")
        validations["elastomer sweeps"] = validate_harmonic(held_out(elastomer, "stepped_sine"),
                                                            isolator=elastomer_model,
                                                            name="elastomer: harmonic sweeps (validation split)")
        validations["elastomer drops"] = validate_drops(held_out(elastomer, "drop"), isolator=elastomer_model,
                                                        name="elastomer: drops (validation split)")
        hybrid_set = sets.get("hybrid")
        if hybrid_set is not None:
            # the hybrid's components were identified elsewhere: probe which wrong ones it would miss
            components = {"upper": elastomer_model, "lower": wire_model}
            hybrid_sweeps, hybrid_drops = held_out(hybrid_set, "stepped_sine", None), held_out(hybrid_set, "drop", None)

            def rerun_sweeps(**models):
                return validate_harmonic(hybrid_sweeps, name="hybrid: harmonic sweeps (all; not fitted)", **models)

            def rerun_drops(**models):
                return validate_drops(hybrid_drops, name="hybrid: drops (all; not fitted)", **models)

            validations["hybrid sweeps"] = blind_spots(rerun_sweeps(**components), rerun_sweeps, components)
            validations["hybrid drops"] = blind_spots(rerun_drops(**components), rerun_drops, components)
            sweep = next(iter(hybrid_set.select(kind="stepped_sine")))
            hybrid = HybridSystem(sweep.info.top_mass_kg, elastomer_model, sweep.info.intermediate_mass_kg, wire_model)
            save_model(hybrid, models_dir / "hybrid.json",
                       provenance={"built_from": ["wire_rope_iwan.json", "elastomer_maxwell.json"],
                                   "masses_from": sweep.info.id, "idkit_version": __version__})
        done("validating on held-out data")

        stage("transport-tool study")
        options = dict(levels=(1e-6, 1e-3), n_realizations=4, r_k_values=(0.2, 1.0),
                       speeds=np.linspace(0.02, 0.6, 8), heights=np.linspace(0.01, 0.12, 6)) if quick else {}
        transport = compute_transport_study(wire_rope=wire_model, elastomer=elastomer_model, seed=seed,
                                            workers=workers, **options)
        figures = write_transport_figures(transport, folder)
        write_transport_tables(transport, tables_dir)
        done("transport-tool study")

        stage("writing the report")
        passed = {name: result.passed for name, result in validations.items()}
        verdicts = {name: result.verdict for name, result in validations.items()}
        report.section("Summary", "summary")
        report.paragraph(f"Data: {data_dir} ({sum(len(s.measurements) for s in set(sets.values()))} measurements). "
                         f"idkit {__version__}, seed {seed}{', quick mode' if quick else ''}.")
        report.table(pd.DataFrame([
            {"item": "wire rope (Iwan, order 2)", "result": f"small {100 * iwan.result.error_small:.2f} %, "
                                                            f"large {100 * iwan.result.error_large:.2f} % (eq. 7.1)"},
            {"item": "wire rope (Bouc-Wen)", "result": f"small {100 * boucwen.result.error_small:.2f} %, "
                                                       f"large {100 * boucwen.result.error_large:.2f} %"},
            {"item": "elastomer (Maxwell, order 2)", "result": f"{100 * maxwell.result.error:.2f} % (eq. 7.5)"},
            *({"item": name, "result": verdict + (f" ({QUICK_NOTE})" if quick else "")
               + (f"; cannot see: {'; '.join(validations[name].cannot_see)}" if validations[name].cannot_see else "")}
              for name, verdict in verdicts.items()),
        ]), caption="identification errors and validation verdicts")

        report.section("Data", "data")
        for isolator, inspection in inspections.items():
            report.paragraph(f"{isolator}: {sets[isolator].folder}")
            report.preformatted(inspection.report())

        report.section("Wire rope fit", "wire-rope-fit")
        lower, upper = wire_model.valid_deflection_range()
        report.paragraph(f"Valid range of the identified Iwan model: its parallel spring's local stiffness "
                         f"g1 + 2 g2 x + 3 g3 x^2 stays >= 0 for {1e3 * lower:.1f} mm <= x <= {1e3 * upper:.1f} mm "
                         f"(SPEC 1.2). The fit was required to keep it valid over "
                         f"{1e3 * valid_range[0]:.1f} to {1e3 * valid_range[1]:.1f} mm, 1.25 times the deflections "
                         f"in the data set; simulations beyond the valid range are flagged, and validations count "
                         f"them as failures.")
        report.preformatted(iwan.report())
        report.table(_parameters_table(iwan),
                     caption="Iwan parameters: stderr from the residual Jacobian at the optimum (the spread "
                             "within this data set; stderr_note says why one is missing) beside the spread across "
                             "repetitions (std of one refit per repetition, repetition_values)"
                             + (f"; {iwan.spread_note}" if iwan.spread_note else ""))
        report.figure(_loop_figure(iwan, "Iwan"), caption="measured and fitted loops (Iwan)")
        report.preformatted(boucwen.report())
        report.figure(_loop_figure(boucwen, "Bouc-Wen"), caption="measured and fitted loops (Bouc-Wen)")

        report.section("Elastomer fit", "elastomer-fit")
        report.preformatted(maxwell.report())
        report.table(_parameters_table(maxwell), caption="Maxwell parameters (k0 from the quasi-static loops)")
        report.table(order_table, caption="order selection: error (7.5) for n = 1..4 and the Voigt model")
        report.figure(_frf_figure(maxwell), caption="measured H1 and fitted transmissibility per top mass")
        report.figure(_stiffness_figure(elastomer_model), caption="complex stiffness and loss factor")

        plots = {"sweeps": plot_harmonic_validation, "FRF": plot_frf_validation, "drops": plot_drop_validation}
        for title, anchor, prefix in (("Validation: wire rope", "validation-wire-rope", "wire rope"),
                                      ("Validation: elastomer", "validation-elastomer", "elastomer"),
                                      ("Validation: hybrid", "validation-hybrid", "hybrid")):
            report.section(title, anchor)
            chosen = {name: result for name, result in validations.items() if name.startswith(prefix)}
            if not chosen:
                report.paragraph("no measurements of this isolator in the data set")
            for name, result in chosen.items():
                plot = next(function for key, function in plots.items() if key in name)
                _validation_section(report, result, plot, tables_dir, name.replace(" ", "_").replace(",", ""),
                                    quick=quick)

        report.section("Transport study", "transport-study")
        report.table(transport.tuning, caption="systems tuned to a 5 Hz small-amplitude resonance (SPEC 6)")
        report.table(transport.summary_table(), index=True,
                     caption="RMS top acceleration [m/s^2] per floor level and rest shock per drop height")
        for path in figures:
            report.image_file(path, caption=path.stem.replace("_", " "))

        provenance = {
            "idkit_version": __version__, "seed": seed, "quick": quick, "data_dir": str(data_dir),
            "data_files_sha256": {isolator: s.hashes() for isolator, s in sets.items()},
            "timings_s": timings, "models": sorted(p.name for p in models_dir.iterdir()),
        }
        report.section("Provenance", "provenance")
        report.paragraph(f"idkit {__version__}; seed {seed}; models in models/, tables in tables/.")
        report.table(pd.DataFrame([{"stage": k + ("" if k in finished else " (until this table)"), "seconds": v}
                                   for k, v in durations().items()]), caption="timings (durations)")
        hashes = [{"isolator": isolator, "file": name, "sha256": digest}
                  for isolator, digests in provenance["data_files_sha256"].items() for name, digest in digests.items()]
        report.table(pd.DataFrame(hashes), caption="data files and their SHA-256")
        done("writing the report")
        (folder / "provenance.json").write_text(json.dumps(provenance, indent=1, default=str) + "\n")
        html_path = folder / "report.html"
        html_path.write_text(report.render(), encoding="utf-8")
        sections = tuple(report.section_titles)
    out_dir = Path(out_dir)
    return ReportSummary(out_dir=out_dir, html=out_dir / "report.html", sections=sections,
                         validation_passed=passed, timings_s=timings, validation_verdicts=verdicts, quick=quick)
