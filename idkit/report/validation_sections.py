"""The report's validation sections (wire rope, elastomer, hybrid): each held-out check's verdict, metrics
and figure, the HOSIDF maps, the drop time histories and shock response spectra, and the wire rope's two
drop models compared.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from idkit.atomic import write_text_atomic
from idkit.plot.equivalent import plot_drop_shock_spectra
from idkit.plot.histories import plot_history_validation
from idkit.plot.validation import (
    plot_drop_histories,
    plot_drop_validation,
    plot_frf_validation,
    plot_harmonic_validation,
    plot_sweep_bode,
    plot_sweep_maps,
)
from idkit.report.conclusions import drop_model_sentence, validation_sentence
from idkit.report.fit_sections import rope_model_name
from idkit.report.html import HtmlReport, file_stem
from idkit.studies.equivalent import drop_shock_spectra
from idkit.studies.pipeline import QUICK_NOTE, ReportData, ValidationEntry

__all__ = ["VALIDATION_PLOTS", "VALIDATION_SECTIONS", "validation_isolator_section"]


#: the figure of each validated observable (:attr:`ValidationEntry.observable`)
VALIDATION_PLOTS = {"sweeps": plot_harmonic_validation, "FRF": plot_frf_validation, "drops": plot_drop_validation,
                    "histories": plot_history_validation}


#: the validation sections: title, HTML anchor, :attr:`ValidationEntry.isolator`
VALIDATION_SECTIONS = (("Validation: wire rope", "validation-wire-rope", "wire rope"),
                        ("Validation: elastomer", "validation-elastomer", "elastomer"),
                        ("Validation: hybrid", "validation-hybrid", "hybrid"))


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


def _drop_model_words(data: ReportData) -> str:
    rope_drops = next((entry.result for entry in data.validations if entry.key == "wire rope drops"), None)
    used_drop = rope_drops.summary.get("drop_model") if rope_drops is not None else None
    return drop_model_sentence(data.drop_models, used=(rope_model_name(data), used_drop))


def _loop_form_words(data: ReportData) -> str:
    """The two rope models' loop errors on the same fit loops and the family the fit chose (the report
    reads the family rule's decision, :func:`idkit.fit.family.choose_iwan_family`; it does not judge again)."""
    errors = data.drop_models.loop_errors
    parts = [f"{name} {100 * small:.2f} / {100 * large:.2f} %" for name, (small, large) in errors.items()]
    chosen = rope_model_name(data)
    return ("Loop error (7.1, small / large) on the same fit loops: " + ", ".join(parts)
            + f": the family rule (docs/fitting.md) chose the {chosen} model.")


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


def validation_isolator_section(report: HtmlReport, data: ReportData, isolator: str) -> str:
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
