"""``idkit report``: the whole job on a data set, as one self-contained HTML page.

:func:`run_report` computes a :class:`~idkit.studies.pipeline.ReportData`
(:func:`idkit.studies.pipeline.compute_report_data`: inspect, fit, validate, transport
study; see there for the stages) and :func:`write_report` renders it: ``report.html``
(figures embedded), ``models/*.json`` (with provenance), ``tables/*.csv``, the transport
figures and ``provenance.json``, into an output folder that appears whole or not at all and
is never replaced without ``force``. Nothing here fits, validates or simulates.
"""

from __future__ import annotations

import math

import json
import os
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pandas as pd

from idkit import __version__
from idkit.atomic import atomic_output_folder, write_text_atomic
from idkit.fit import ORDER_RULE_FACTOR
from idkit.fit.data_set_checks import VALID_RANGE_MARGIN
from idkit.models import save_model
from idkit.plot.equivalent import (
    plot_complex_stiffness_comparison,
    plot_drop_shock_spectra,
    plot_equivalent_linearization,
    plot_frf_residuals,
    plot_loop_residuals,
)
from idkit.plot.fits import plot_frf_fit, plot_loop_fit, plot_parameter_spread, plot_storage_loss
from idkit.plot.histories import plot_history_validation
from idkit.plot.studies import plot_transport_psd, plot_transport_ranking, plot_transport_rest_shock
from idkit.plot.validation import (
    plot_drop_histories,
    plot_drop_validation,
    plot_frf_validation,
    plot_harmonic_validation,
    plot_sweep_bode,
    plot_sweep_maps,
)
from idkit.gravity import STANDARD_GRAVITY
from idkit.report.conclusions import (
    drop_model_sentence,
    fit_sentence,
    key_metric,
    parameters_cell,
    rest_shock_ends,
    transport_conclusions,
    validation_sentence,
)
from idkit.report.blas_threads import one_blas_thread
from idkit.report.html import HtmlReport, file_stem
from idkit.report.study_files import write_transport_files
from idkit.studies.equivalent import complex_stiffness_comparison, drop_shock_spectra, equivalent_linearization
from idkit.studies.residuals import NOISE_MULTIPLE, systematic_residual_bands
from idkit.exit_status import REPORT_EXIT_STATUSES
from idkit.studies.pipeline import QUICK_NOTE, ReportData, ValidationEntry, compute_report_data
from idkit.validate import Verdict

__all__ = ["EXIT_STATUSES", "PREDICTING_FITS", "QUICK_NOTE", "REPORT_SECTIONS", "ReportSummary", "run_report",
           "write_report"]

REPORT_SECTIONS = (
    "Summary", "Data", "Wire rope fit", "Elastomer fit", "Validation: wire rope", "Validation: elastomer",
    "Validation: hybrid", "Transport study", "Provenance",
)

#: the figure of each validated observable (:attr:`ValidationEntry.observable`)
VALIDATION_PLOTS = {"sweeps": plot_harmonic_validation, "FRF": plot_frf_validation, "drops": plot_drop_validation,
                    "histories": plot_history_validation}

#: the validation sections: title, HTML anchor, :attr:`ValidationEntry.isolator`
_VALIDATION_SECTIONS = (("Validation: wire rope", "validation-wire-rope", "wire rope"),
                        ("Validation: elastomer", "validation-elastomer", "elastomer"),
                        ("Validation: hybrid", "validation-hybrid", "hybrid"))

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
        success (:data:`EXIT_STATUSES`)."""
        return report_exit_status(self.validation_verdicts, self.flagged_fits)


def report_exit_status(verdicts: dict[str, str], flagged_fits) -> int:
    """:attr:`ReportSummary.exit_status` of validation verdicts and flagged fits (:data:`EXIT_STATUSES`)."""
    found = set(verdicts.values())
    if "FAIL" in found:
        return 1
    if "INCONCLUSIVE" in found:
        return 3
    return 4 if flagged_fits else 0


def outcome_sentence(verdicts: dict[str, str], flagged_fits) -> str:
    """The report's outcome in one sentence: the exit status ``idkit report`` returns and why."""
    status = report_exit_status(verdicts, flagged_fits)
    counts = [f"{sum(v == verdict for v in verdicts.values())} {verdict}" for verdict in ("PASS", "INCONCLUSIVE", "FAIL")
              if verdict in verdicts.values()]
    text = (f"Outcome: {', '.join(counts) or 'no validation'} of {len(verdicts)} validation(s)"
            + (f"; not a success: {', '.join(flagged_fits)}" if flagged_fits else "")
            + f". idkit report exits with status {status}: {EXIT_STATUSES[status]}")
    failed = [key for key, verdict in verdicts.items() if verdict == "FAIL"]
    inconclusive = [key for key, verdict in verdicts.items() if verdict == "INCONCLUSIVE"]
    if status == 1:  # the failed ones are what the status says; the inconclusive ones are named as such
        return text + f" ({', '.join(failed)}" + (f"; inconclusive: {', '.join(inconclusive)}" if inconclusive
                                                   else "") + ")."
    return text + (f" ({', '.join(inconclusive)})." if status == 3 else ".")


#: exit statuses of ``idkit report`` (:mod:`idkit.exit_status`)
EXIT_STATUSES = REPORT_EXIT_STATUSES

#: the fits whose models the report validates and predicts with (the Bouc-Wen fit is a
#: comparison of model forms on the loops and does not enter the exit status)
PREDICTING_FITS = ("wire rope (Iwan)", "elastomer (generalized Maxwell)")


def _metrics_frame(result) -> pd.DataFrame:
    metrics = result.metrics.copy()
    for column in metrics.columns:
        if metrics[column].dtype == complex:
            metrics[column] = metrics[column].astype(str)
    return metrics


#: the one-line caption of each validation figure: what to look at
_VALIDATION_CAPTIONS = {
    "sweeps": "Markers measured, lines model, per amplitude level: look at where the model's resonance and peak "
              "height leave the markers (right panel: the error in dB).",
    "FRF": "Dots measured H1, lines model, per top mass (at most three a column): look at the resonance frequency "
           "and the peak height.",
    "histories": "Grey measured, blue model, per held-out record (worst first): force against deflection and against "
                 "time, the strong-motion window shaded; look at where the blue leaves the grey.",
    "drops": "Filled markers measured, open markers model, in compression, in tension and for the stroke: look at "
             "how far the open markers sit from the filled ones as the impact speed grows.",
}


def _skipped_sentence(entry: ValidationEntry) -> str:
    """Which held-out records a quick run left out of one validation (idkit.studies.pipeline.quick_subset)."""
    return (f"Quick run: {len(entry.skipped)} held-out record(s) of this check were skipped (the subset is spread "
            f"over the test levels and frequencies): {', '.join(entry.skipped)}.")


def _validation_section(report: HtmlReport, entry: ValidationEntry, quick: bool) -> None:
    result = entry.result
    report.heading(entry.key)
    verdict, text = validation_sentence(entry.key, result, quick_note=QUICK_NOTE if quick else "")
    report.items([(verdict, text)])
    if entry.skipped:
        report.paragraph(_skipped_sentence(entry))
    rows = [{"metric": key, "value": value, "limit": result.thresholds.get(key, np.nan),
             "ok": result.checks.get(key, "")} for key, value in result.summary.items()]
    report.table(pd.DataFrame(rows), caption="metrics (limits are the documented defaults)",
                 name=f"{entry.key} summary")
    axes = VALIDATION_PLOTS[entry.observable](result)
    report.figure(np.ravel(axes)[0].figure, caption=_VALIDATION_CAPTIONS[entry.observable], name=f"validation {entry.key}",
                  alt=f"{result.name}: measured against simulated")
    if report.tables_dir is not None:
        write_text_atomic(report.tables_dir / f"{file_stem(entry.key)}.csv", _metrics_frame(result).to_csv(index=False))


def _drop_model_section(report: HtmlReport, data: ReportData) -> None:
    """The wire rope's held-out drops under both drop models, plain and slip-modulated Iwan."""
    comparison = data.drop_models
    rope_drops = next((entry.result for entry in data.validations if entry.key == "wire rope drops"), None)
    resolved = rope_drops.summary.get("drop_model") if rope_drops is not None else None
    used = (f"drop_model='{data.drop_model}', here the {resolved}" if resolved and resolved != data.drop_model
            else f"drop_model='{data.drop_model}'")
    report.heading("drop models compared")
    report.paragraph(f"Drop models compared on the same held-out wire-rope drops (the drop validations above use "
                     f"{used}): the conditioned free fall of the study (every mass at the "
                     "impact velocity, base fixed) and the drop rig (the stack released from its statically "
                     "loaded rest state, the bottom mass bouncing on the floor), each with the plain Iwan model "
                     "and with the slip-modulated Iwan model fitted on the same loops.")
    report.table(comparison.table, caption="median and worst |relative error| of the peak top-mass acceleration per "
                                           "phase and top mass; verdict of each validation",
                 name="wire rope drop models")
    report.paragraph(_drop_model_words(data))
    if len(comparison.loop_errors) > 1:
        report.paragraph(_loop_form_words(data))
    for note in comparison.notes:
        report.paragraph(note)


def _rope_model_name(data: ReportData) -> str:
    """The identified wire-rope model's family: "slip-modulated Iwan" or "plain Iwan"."""
    return "slip-modulated Iwan" if data.iwan.result.settings.family == "modulated" else "plain Iwan"


def _drop_model_words(data: ReportData) -> str:
    rope_drops = next((entry.result for entry in data.validations if entry.key == "wire rope drops"), None)
    used_drop = rope_drops.summary.get("drop_model") if rope_drops is not None else None
    return drop_model_sentence(data.drop_models, used=(_rope_model_name(data), used_drop))


def _loop_form_words(data: ReportData) -> str:
    """The two rope models' loop errors on the same fit loops and the family the fit chose (the report
    reads the family rule's decision, :func:`idkit.fit.family.choose_iwan_family`; it does not judge again)."""
    errors = data.drop_models.loop_errors
    parts = [f"{name} {100 * small:.2f} / {100 * large:.2f} %" for name, (small, large) in errors.items()]
    chosen = _rope_model_name(data)
    return ("Loop error (7.1, small / large) on the same fit loops: " + ", ".join(parts)
            + f": the family rule (docs/fitting.md) chose the {chosen} model.")


def _valid_range_words(data: ReportData) -> str:
    lower, upper = data.iwan.model.valid_deflection_range()
    if math.isfinite(lower) and math.isfinite(upper):
        span = f"{1e3 * lower:.1f} mm <= x <= {1e3 * upper:.1f} mm"
    elif math.isfinite(lower):
        span = f"x >= {1e3 * lower:.1f} mm (no upper limit)"
    elif math.isfinite(upper):
        span = f"x <= {1e3 * upper:.1f} mm (no lower limit)"
    else:
        span = None
    where = "every deflection" if span is None else f"deflections {span}"
    return (f"valid for {where} (its parallel spring's "
            f"local stiffness stays >= 0, SPEC 1.2; required: {1e3 * data.valid_range[0]:.1f} to "
            f"{1e3 * data.valid_range[1]:.1f} mm, {VALID_RANGE_MARGIN:g} times the data set's deflections)")


#: the first screen's thumbnails: (figure name, label); a figure the data set does not give is left out
def _thumbnails(data: ReportData) -> list[tuple[str, str]]:
    thumbnails = [("wire rope iwan loops", "wire rope loops"), ("elastomer frf fit", "elastomer FRF")]
    drops = next((isolator for isolator in ("wire rope", "hybrid", "elastomer") if isolator in data.drop_histories),
                 None)
    if drops is not None:
        thumbnails.append((f"{drops} drop time histories", f"{drops} drops"))
    thumbnails.append(("transport ranking", "transport ranking"))
    return thumbnails


def _short(text: str, limit: int = 110) -> str | tuple[str, str]:
    """``text``, or its first ``limit`` characters and the whole as a tooltip (a first-screen table cell)."""
    return text if len(text) <= limit else (text[:limit - 1].rstrip() + "…", text)


def _metric_value(value: float) -> str:
    return "n/a" if not math.isfinite(value) else f"{value:.3g}"


def verdict_rows(data: ReportData) -> list[dict]:
    """The first screen's verdict table: one row per validation (its key metric, :func:`key_metric`) and per
    fit the report predicts with; verdicts as computed, never judged again."""
    rows = []
    for entry in data.validations:
        result = entry.result
        metric, value, limit = key_metric(result)
        why = result.why or result.notes
        rows.append({"check": entry.key, "key metric": metric, "value": _metric_value(value),
                     "limit": f"{limit:g}" if math.isfinite(limit) else "", "verdict": result.verdict,
                     "why / note": _short("; ".join(why)) if why else ""})
    bands = _elastomer_bands(data)
    for name, fit, metric, value in (
            (f"wire rope fit ({_rope_model_name(data)} {data.iwan.model.order})", data.iwan,
             "loop error small / large (7.1)",
             f"{100 * data.iwan.result.error_small:.2g} / {100 * data.iwan.result.error_large:.2g} %"),
            (f"elastomer fit (Maxwell {len(data.maxwell.model.k)})", data.maxwell, "FRF error (7.5)",
             f"{100 * data.maxwell.result.error:.2g} %")):
        notes = list(fit.reasons)
        if fit is data.maxwell and bands:
            notes.append(_bands_words(bands))
        rows.append({"check": name, "key metric": metric, "value": value, "limit": "",
                     "verdict": Verdict.of_fit(fit.success),
                     "why / note": _short("; ".join(notes)) if notes else ""})
    return rows


def model_rows(data: ReportData) -> list[dict]:
    """The first screen's table of the identified models: family, parameters ± standard error, valid range."""
    lower, upper = data.iwan.model.valid_deflection_range()
    elastomer = data.maxwell.parameters_table()
    rows = [{"isolator": "wire rope", "family": f"{_rope_model_name(data)}, order {data.iwan.model.order}",
             "parameters (± standard error)": parameters_cell(data.iwan.parameters_table()),
             "valid range": _range_words(lower, upper)},
            {"isolator": "wire rope (comparison only)", "family": "Bouc-Wen",
             "parameters (± standard error)": parameters_cell(data.boucwen.parameters_table()),
             "valid range": "-"},
            {"isolator": "elastomer", "family": f"generalized Maxwell, order {len(data.maxwell.model.k)}",
             "parameters (± standard error)": f"k0 = {data.maxwell.k0.k0:.3g} ± {data.maxwell.k0.stderr:.2g} N/m "
             "(quasi-static loops); " + parameters_cell(elastomer[elastomer["parameter"] != "k0"]),
             "valid range": "linear: no limit of its own; validated over the held-out amplitudes"}]
    return rows


def _range_words(lower: float, upper: float) -> str:
    if math.isfinite(lower) and math.isfinite(upper):
        return f"{1e3 * lower:.1f} to {1e3 * upper:.1f} mm"
    if math.isfinite(lower):
        return f"from {1e3 * lower:.1f} mm"
    if math.isfinite(upper):
        return f"up to {1e3 * upper:.1f} mm"
    return "every deflection"


def _elastomer_bands(data: ReportData):
    return systematic_residual_bands(data.maxwell.model, list(data.maxwell.data), level=data.maxwell.result.error)


def _bands_words(bands) -> str:
    """The elastomer fit's systematic residual bands in a few words."""
    spans = ", ".join(f"{band.low_hz:.3g}-{band.high_hz:.3g} Hz" for band in bands)
    return (f"systematic residual over {spans} on every top mass (up to {100 * max(b.peak for b in bands):.2g} % of "
            "|H|): the model lacks a feature of the data there")


def _front_section(report: HtmlReport, data: ReportData) -> str:
    """The first screen: the outcome, the verdict and model tables and four thumbnails; returns the slot of
    the transport study's one sentence (filled by :func:`_transport_section`)."""
    report.section("Summary", "summary", front=True)
    flagged = tuple(name for name, reasons in _fit_reasons(data).items() if reasons)
    report.paragraph(outcome_sentence(data.verdicts, flagged) + f" Data: {data.data_dir} "
                     f"({data.n_measurements} measurements), idkit {__version__}, seed {data.seed}"
                     + (f"; {QUICK_NOTE}." if data.quick else "."))
    report.front_table(verdict_rows(data), verdict_column="verdict", numeric=("value", "limit"))
    report.front_table(model_rows(data))
    for name, label in _thumbnails(data):
        report.thumbnail(name, label)
    return report.placeholder()


def _spread_figure(report: HtmlReport, fit, isolator: str, model: str) -> None:
    refits = "" if fit.spread is not None else f" ({fit.spread_note or 'no refits'})"
    report.figure(plot_parameter_spread(fit, title=f"{isolator} ({model})").figure,
                  name=f"{isolator} {model.lower()} parameter spread",
                  caption=f"Uncertainty of each fitted {model} parameter in percent of its value: bars +-1 and +-2 "
                          f"standard errors from the residual Jacobian, dots one refit per repetition{refits}; a dot "
                          "outside the bars means the repetitions differ more than the fit's residual explains.",
                  alt=f"relative standard errors and per-repetition refits of the {isolator} {model} parameters")


def _sweep_figures(report: HtmlReport, data: ReportData, isolator: str) -> None:
    maps = data.sweep_maps.get(isolator)
    if maps is not None:
        unsettled = int((maps.order(1.0)["status"] != "ok").sum())
        missing = int((~maps.model.valid).sum())
        report.figure(plot_sweep_maps(maps)[0, 0].figure, name=f"{isolator} hosidf maps",
                      caption=f"|HOSIDF| of orders 1, 2, 3 and 1/2 over frequency and base amplitude ({isolator}, "
                              f"{maps.setup}, every stepped sine of the data set): cells the model, squares the "
                              "measured records on the same colour scale (4 decades); a square that stands out from "
                              "its cells is a point the model misses; the measured higher orders cannot fall below "
                              "the noise floor of the records"
                              + (f"; {missing} blank cells: the model went invalid or did not settle there"
                                 if missing else "") + ".",
                      alt=f"top-view colour maps of the measured and model HOSIDFs of the {isolator}")
        report.figure(plot_sweep_bode(maps)[0].figure, name=f"{isolator} bode sections",
                      caption=f"First HOSIDF, magnitude and phase, at each excitation level ({isolator}, "
                              f"{maps.setup}; model at each record's frequency and measured base amplitude): look "
                              "at how the resonance moves down and flattens as the level grows"
                              + (f"; {unsettled} model points that did not settle are left out" if unsettled
                                 else "") + ".",
                      alt=f"Bode magnitude and phase of the first HOSIDF per excitation level, {isolator}")
    histories = data.drop_histories.get(isolator)
    if histories is not None:
        ended = [drop for drop in histories.drops if drop.status != "ok"]
        report.figure(plot_drop_histories(histories)[0].figure, name=f"{isolator} drop time histories",
                      caption=f"Held-out drops of the {isolator} ({histories.setup}; lowest, middle and highest "
                              f"height), measured and simulated on the drop rig (contact restitution "
                              f"{histories.contact.restitution:.2f} read off the records): look at the ringing "
                              "frequency and the rebound into tension"
                              + (f"; {len(ended)} model curve(s) end where the model went invalid" if ended else "")
                              + ".",
                      alt=f"top acceleration and deflection versus time for measured and simulated {isolator} drops")


def _iwan_tables(report: HtmlReport, data: ReportData) -> None:
    report.table(data.iwan.parameters_table(),
                 caption="Iwan parameters: stderr from the residual Jacobian at the optimum (the spread "
                         "within this data set; stderr_note says why one is missing) beside the spread across "
                         "repetitions (std of one refit per repetition, repetition_values)"
                         + (f"; {data.iwan.spread_note}" if data.iwan.spread_note else ""),
                 name="wire rope iwan parameters")
    if data.iwan.order_table is not None:
        secant = float(data.iwan.order_table["smallest_loop_secant [N/m]"].iloc[0])  # one value: in the caption
        # model_form_only: said by the reasons already (the order rule's fallback, docs/fitting.md)
        report.table(data.iwan.order_table.drop(columns=["smallest_loop_secant [N/m]", "model_form_only"],
                                                errors="ignore"),
                     caption=f"Iwan order table: the order rule (lowest successful order within "
                             f"{ORDER_RULE_FACTOR:g} x the best mean loop error) among the plain rows; when the plain "
                             "model misses the loops' noise floor by more than 2 points, the family rule adds "
                             "slip-modulated rows (lowest order within 2 points of the floor) and keeps one if it is "
                             f"better by the same factor (docs/fitting.md); fit 'loops' rows are the loops' own "
                             "fits the rule compares, a 'valid-range refit' row the chosen order refitted with the "
                             "valid-range barrier; the recommended row, "
                             f"{data.iwan.result.settings.family} order {data.iwan.model.order}, is the model used "
                             "(its loop errors are the ones quoted above); "
                             f"stuck stiffness g1 + sum k_i beside the secant of the shortest measured branch, "
                             f"{secant:.4g} N/m",
                     name="wire rope iwan order table")


def _wire_rope_fit_section(report: HtmlReport, data: ReportData) -> str:
    iwan, boucwen = data.iwan, data.boucwen
    report.items([fit_sentence(f"Iwan fit ({_rope_model_name(data)} order {iwan.model.order}; loop error small "
                               f"{100 * iwan.result.error_small:.2f} %, large {100 * iwan.result.error_large:.2f} %, "
                               "eq. 7.1)", iwan),
                  fit_sentence(f"Bouc-Wen comparison (small {100 * boucwen.result.error_small:.2f} %, large "
                               f"{100 * boucwen.result.error_large:.2f} %)", boucwen, comparison=True)])
    report.paragraph(f"Valid range of the identified {_rope_model_name(data)} model: {_valid_range_words(data)}; "
                     "simulations beyond the valid range are flagged, and validations count them as failures.")
    report.preformatted(data.iwan.report(), label="show the Iwan fit log")
    with report.folded("show the Iwan parameter table (stderr, spread across repetitions) and the order table"):
        _iwan_tables(report, data)
    _spread_figure(report, data.iwan, "wire rope", "Iwan")
    report.figure(plot_loop_fit(data.iwan_loops, label="Iwan")[0].figure, name="wire rope iwan loops",
                  caption="Grey measured, dashed Iwan model: look at the loop tips and the width of the small loops.",
                  alt="measured and fitted force-deflection loops (Iwan), small and large")
    report.figure(plot_loop_residuals(data.iwan_loops, label="Iwan")[0].figure, name="wire rope iwan residuals",
                  caption="Iwan force minus measured force along every loop set: look for a pattern at the loop "
                          "tips (the loop shape is wrong there) above the noise band.",
                  alt="force residuals of the Iwan fit versus deflection, small and large loops")
    linear = equivalent_linearization(
        [m for m in data.sets["wire_rope"].measurements if m.kind == "quasi_static"], data.iwan.model)
    report.figure(plot_equivalent_linearization(linear, label="Iwan")[0].figure,
                  name="wire rope equivalent stiffness and loss factor",
                  caption="Secant stiffness and loss factor of every measured cycle (fit and validation records) "
                          "against the Iwan model on the same deflection history: look at the small amplitudes, "
                          "where the stiffness rises and the loss factor falls.",
                  alt="equivalent stiffness and loss factor versus cycle amplitude, measured and Iwan model")
    report.table(linear.to_dataframe(), name="wire rope equivalent linearization",
                 caption="per cycle: amplitude, secant stiffness and loss factor, measured and model")
    report.preformatted(data.boucwen.report(), label="show the Bouc-Wen fit log")
    report.figure(plot_loop_fit(data.boucwen_loops, label="Bouc-Wen")[0].figure, name="wire rope bouc-wen loops",
                  caption="Grey measured, dashed Bouc-Wen model: compare the loop tips with the Iwan figure above.",
                  alt="measured and fitted force-deflection loops (Bouc-Wen), small and large")
    return (f"{_rope_model_name(data)} order {iwan.model.order}, loop error {100 * iwan.result.error_small:.2f} / "
            f"{100 * iwan.result.error_large:.2f} % (small / large); "
            + ("fit succeeded" if iwan.success else "fit not a success"))


def _elastomer_fit_section(report: HtmlReport, data: ReportData) -> str:
    maxwell = data.maxwell
    bands = _elastomer_bands(data)
    report.items([fit_sentence(f"Maxwell fit (order {len(maxwell.model.k)}, FRF error "
                               f"{100 * maxwell.result.error:.2f} %, eq. 7.5)", maxwell)])
    if bands:
        report.paragraph(f"Residual: {_bands_words(bands)} (the log-magnitude residual keeps one sign on every top "
                         f"mass and repetition, beyond {NOISE_MULTIPLE:g} times the H1 random error, and reaches the "
                         "fit's own error there; see the residual figure below). The fit's success does not vouch "
                         "for the model in that band.")
    report.preformatted(maxwell.report(), label="show the Maxwell fit log")
    with report.folded("show the Maxwell parameter table and the order table"):
        report.table(data.maxwell.parameters_table(), caption="Maxwell parameters (k0 from the quasi-static loops)",
                     name="elastomer maxwell parameters")
        report.table(data.order_table, caption=f"order selection: error (7.5) for n = 1..4 and the Voigt model; the "
                                               f"order rule (lowest successful order within {ORDER_RULE_FACTOR:g} x "
                                               f"the best) chose order {data.maxwell.model.order}",
                     name="maxwell order table")
    _spread_figure(report, data.maxwell, "elastomer", "Maxwell")
    report.figure(np.ravel(plot_frf_fit(data.maxwell.model, list(data.maxwell.data)))[0].figure, name="elastomer frf fit",
                  caption="Thin measured H1 (every repetition), dashed model, per top mass (at most three a column): "
                          "look at the resonance peaks.",
                  alt="measured and fitted transmissibility magnitude and phase per top mass")
    report.figure(plot_storage_loss(data.maxwell.model)[0].figure, name="elastomer complex stiffness",
                  caption="Storage and loss stiffness and loss factor of the identified model over 0.1-1000 Hz: look "
                          "at how fast the stiffness rises with frequency.",
                  alt="complex stiffness and loss factor of the identified elastomer model")
    report.figure(plot_frf_residuals(data.maxwell.model, list(data.maxwell.data), systematic=bands).figure,
                  name="elastomer frf residuals",
                  caption="Relative complex residual of the Maxwell fit per top mass (the quantity objective 7.5 "
                          "averages): look at where in frequency the error comes from, and whether it is the same "
                          "for every top mass" + ("; shaded: where it is systematic (same sign on every top mass, "
                                                  "beyond the noise)" if bands else "") + ".",
                  alt="relative FRF residual of the Maxwell fit versus frequency per top mass")
    measured = complex_stiffness_comparison(list(data.maxwell.data), data.maxwell.model)
    report.figure(plot_complex_stiffness_comparison(measured)[0].figure, name="elastomer measured complex stiffness",
                  caption="Complex stiffness read off each top mass's measured H1 (k* = M w^2 H / (H - 1), M the top "
                          "mass plus m_eff; left out where |H - 1| < 0.2) against the model (dashed): the measured "
                          "curves should overlap one another and the model between the resonances.",
                  alt="measured complex stiffness magnitude and loss factor per top mass against the Maxwell model")
    return (f"generalized Maxwell order {len(maxwell.model.k)}, FRF error {100 * maxwell.result.error:.2f} %; "
            + ("fit succeeded" if maxwell.success else "fit not a success")
            + (f"; systematic residual over " + ", ".join(f"{b.low_hz:.3g}-{b.high_hz:.3g} Hz" for b in bands)
               if bands else ""))


def _transport_section(report: HtmlReport, data: ReportData, summary_slot: str) -> str:
    study = data.transport  # waits for the study's child process (ReportData.transport)
    with report.filling(summary_slot):
        report.paragraph(transport_gist(study))
    conclusions = transport_conclusions(study)
    limit = rope_limit_sentence(data, study)
    report.items(conclusions + ([limit] if limit else []))
    report.figure(np.ravel(plot_transport_ranking(study))[0].figure, name="transport ranking",
                  caption="The systems ranked (lowest on top protects best): RMS top acceleration at the highest floor "
                          "level, rest shock after a 5 cm drop; 'model invalid' where a model left its valid range.",
                  alt="bar charts of the RMS top acceleration and the rest shock of every tuned system")
    report.table(study.tuning, caption="systems tuned to a 5 Hz small-amplitude resonance (SPEC 6)",
                 name="transport tuning")
    report.table(study.summary_table(), index=True, name="transport summary",
                 caption="RMS top acceleration [m/s^2] per floor level and rest shock per drop height")
    if study.failures:
        report.paragraph("Not computed (every realization left the model's valid range; RMS shown as NaN): "
                         + "; ".join(study.failures) + ".")
    unsettled = study.unsettled()
    if unsettled:
        report.paragraph(
            "Not settled (settling error above the study's limit, the change of the response over one periodic "
            "record relative to the signal; the PSD and RMS of these runs are uncertain by about that much): "
            + "; ".join(f"{system} at {level}: {value:.2g}" for system, level, value in unsettled) + ".")
    if study.settling is not None:
        with report.folded("show the settling errors of the random runs"):
            report.table(study.settling, index=True, name="transport settling", float_format="{:.2g}",
                         caption="largest settling error of the random runs per system and floor level (0: linear, "
                                 "solved in the frequency domain)")
    axes = plot_transport_psd(study)
    report.figure(axes.flat[0].figure, name="transport output psd",
                  caption="Top acceleration PSD per floor level (rows), at most six systems a panel, over the floor "
                          "band 0.1-100 Hz and 12 decades below each row's peak: the lowest curve above the "
                          "resonance isolates best.",
                  alt="output acceleration PSD of every tuned system at every floor level")
    ends = rest_shock_ends(study)
    note = ("; " + "; ".join(f"the {name} curve stops {where}, where its model leaves its valid range"
                             for name, where in ends.items())) if ends else ""
    report.figure(np.ravel(plot_transport_rest_shock(study))[0].figure, name="transport rest shock",
                  caption="Rest shock level versus impact speed (top) and drop height (bottom), at most six systems "
                          "a column (the reference repeated beside the hybrids): the lowest curve protects best"
                          + note + ".",
                  alt="rest shock level of every system versus impact speed and drop height")
    return transport_gist(study)


def transport_gist(study) -> str:
    """The transport study in one sentence: the best system at the floor levels and at a 5 cm drop."""
    best: dict[str, list[str]] = {}  # system -> the floor levels ("<level> [unit]") where it is lowest
    for column in study.rms.columns:
        if study.rms[column].notna().any():
            best.setdefault(study.rms[column].astype(float).idxmin(), []).append(str(column))
    if len(best) == 1:
        levels = f"{next(iter(best))} at every floor level"
    else:
        unit = next(iter(best.values()))[0].partition(" ")[2]
        levels = ", ".join(f"{name} at {', '.join(level.partition(' ')[0] for level in found)}"
                           for name, found in best.items()) + f" {unit}"
    shock = study.rest_shock_at(0.05).astype(float).dropna()
    text = f"Transport study ({len(study.rms)} systems tuned to 5 Hz): lowest RMS top acceleration: {levels}"
    if not shock.empty:
        text += f"; lowest rest shock after a 5 cm drop: {shock.idxmin()}"
    return text + "."


def rope_limit_sentence(data: ReportData, study) -> str:
    """Why the wire rope's rest-shock curve stops, in one sentence (empty when it runs to the end of its sweeps).

    The study's rope is the one identified from this data set, valid only where its spring's
    local stiffness is >= 0; tuned to 5 Hz on its stuck stiffness, it carries a top mass whose
    weight is compared with the force the rope holds at the compression edge of that range
    (its virgin loading curve from rest, :meth:`~idkit.models.IwanModel.force`).
    """
    ends = rest_shock_ends(study)
    if "wire rope" not in ends or "wire rope" not in set(study.tuning["system"]):
        return ""
    model = data.iwan.model
    lower, upper = model.valid_deflection_range()
    row = study.tuning.set_index("system").loc["wire rope"]
    mass, stiffness = float(row["moving mass [kg]"]), float(row["stiffness at target [N/m]"])
    weight = mass * STANDARD_GRAVITY
    text = (f"Why the wire rope's curve stops {ends['wire rope'].split(' (')[0]}: the study's rope is the "
            f"{_rope_model_name(data)} model identified from this data set (not the library's Table 7.1 rope); "
            f"tuned to 5 Hz on its stuck stiffness ({stiffness:.3g} N/m) it carries {mass:.3g} kg")
    if not math.isfinite(lower):
        return text + ", and its model turns invalid under the drop's deflection (the simulator flags the runs)."
    path = np.linspace(0.0, lower, 400)
    held = float(abs(model.force(path, np.linspace(0.0, 1.0, path.size))[-1]))
    if held < weight:
        return text + (f", whose weight ({weight:.4g} N) is {weight / held:.2g} times the {held:.3g} N the rope holds "
                       f"at the compression edge of its valid range ({1e3 * lower:.1f} mm, where its spring's local "
                       "stiffness turns negative, SPEC 1.2): its elements slip under that load and the deflection "
                       "runs past the edge.")
    return text + (f"; it holds that weight ({weight:.4g} N) inside its valid range, which ends at {1e3 * lower:.1f} mm "
                   "(its spring's local stiffness turns negative there, SPEC 1.2), and the drops push it past that "
                   "edge.")


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


def _validation_isolator_section(report: HtmlReport, data: ReportData, isolator: str) -> str:
    entries = data.validations_of(isolator)
    if not entries:
        report.paragraph("no measurements of this isolator in the data set")
    for entry in entries:
        _validation_section(report, entry, data.quick)
    _sweep_figures(report, data, isolator)
    if isolator == "wire rope" and data.drop_models is not None:
        _drop_model_section(report, data)
    spectra = drop_shock_spectra(list(data.sets[isolator.replace(" ", "_")].measurements),
                                 histories=data.drop_histories.get(isolator))
    if spectra is not None:
        compared = spectra.model_acceleration is not None
        report.figure(plot_drop_shock_spectra(spectra).figure, name=f"{isolator} drop srs",
                      caption=f"Shock response spectrum (5 % damping) of the top acceleration ({isolator}, "
                              f"{spectra.top_mass_kg:.2f} kg, " + (
                                  "the held-out drops of the time histories): solid measured, dashed model, dotted "
                                  "the impact itself, (1 + e) sqrt(2 g h) as an impulse (a component mounted without "
                                  "the isolator); look at how far the solid curve sits below the dotted one, and "
                                  "whether the dashed one follows the solid." if compared else
                                  "every drop height, measured): what a component of that natural frequency on the "
                                  "payload would see; look at how the peak moves with the drop height."),
                      alt=f"absolute-acceleration shock response spectra of the {isolator} drops"
                          + (", measured, model and impact" if compared else ", measured"))
    return ", ".join(f"{entry.key} {entry.result.verdict}" for entry in entries) or "no measurements"


def _section_builders() -> tuple:
    """The collapsed sections between the first screen and the transport study, in page order:
    ``(title, anchor, builder)``; ``builder(report, data)`` draws its section and returns the one-line gist
    shown on its collapsed header. A new section is one more row (:data:`REPORT_SECTIONS` lists every title)."""
    def validation(isolator):
        return lambda report, data: _validation_isolator_section(report, data, isolator)

    return (("Data", "data", _data_section),
            ("Wire rope fit", "wire-rope-fit", _wire_rope_fit_section),
            ("Elastomer fit", "elastomer-fit", _elastomer_fit_section),
            *((title, anchor, validation(isolator)) for title, anchor, isolator in _VALIDATION_SECTIONS))


def _write_report(data: ReportData, report: HtmlReport, folder: Path, started: float, *, pdf: bool) -> ReportSummary:
    models_dir, tables_dir, figures_dir = folder / "models", folder / "tables", folder / "figures"
    # everything that does not need the transport study first: it is still running in a child
    # process (ReportData.transport), and these figures render meanwhile
    summary_slot = _front_section(report, data)
    for title, anchor, build in _section_builders():
        report.section(title, anchor, collapsed=True)
        report.summarize(build(report, data))
    write_transport_files(data.transport, folder, tables_dir=tables_dir, figures=False)
    report.section("Transport study", "transport-study", collapsed=True)
    report.summarize(_transport_section(report, data, summary_slot))

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
                         fit_reasons=_fit_reasons(data),
                         validation_notes={entry.key: entry.result.notes for entry in data.validations},
                         validation_reasons={entry.key: entry.result.why for entry in data.validations})


def _fit_reasons(data: ReportData) -> dict[str, tuple[str, ...]]:
    """:attr:`ReportSummary.fit_reasons` of the fits in :data:`PREDICTING_FITS`."""
    fits = dict(zip(PREDICTING_FITS, (data.iwan, data.maxwell)))
    return {name: tuple(fit.reasons) for name, fit in fits.items()}


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
