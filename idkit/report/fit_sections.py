"""The report's two fit sections: the wire rope (Iwan, Bouc-Wen comparison) and the elastomer (Maxwell).

Each builder draws its section from :class:`~idkit.studies.pipeline.ReportData` and returns the
one-line gist shown on its collapsed header; nothing here fits.
"""

from __future__ import annotations

import math

import numpy as np

from idkit.fit import ORDER_RULE_FACTOR
from idkit.fit.data_set_checks import VALID_RANGE_MARGIN
from idkit.plot.equivalent import (
    plot_complex_stiffness_comparison,
    plot_equivalent_linearization,
    plot_frf_residuals,
    plot_loop_residuals,
)
from idkit.plot.fits import plot_frf_fit, plot_loop_fit, plot_parameter_spread, plot_storage_loss
from idkit.report.conclusions import fit_sentence
from idkit.report.html import HtmlReport
from idkit.studies.equivalent import complex_stiffness_comparison, equivalent_linearization
from idkit.studies.pipeline import ReportData
from idkit.studies.residuals import NOISE_MULTIPLE, systematic_residual_bands

__all__ = ["bands_words", "elastomer_bands", "elastomer_fit_section", "rope_model_name", "wire_rope_fit_section"]


def rope_model_name(data: ReportData) -> str:
    """The identified wire-rope model's family: "slip-modulated Iwan" or "plain Iwan"."""
    return "slip-modulated Iwan" if data.iwan.result.settings.family == "modulated" else "plain Iwan"


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


def elastomer_bands(data: ReportData):
    return systematic_residual_bands(data.maxwell.model, list(data.maxwell.data), level=data.maxwell.result.error)


def bands_words(bands) -> str:
    """The elastomer fit's systematic residual bands in a few words."""
    spans = ", ".join(f"{band.low_hz:.3g}-{band.high_hz:.3g} Hz" for band in bands)
    return (f"systematic residual over {spans} on every top mass (up to {100 * max(b.peak for b in bands):.2g} % of "
            "|H|): the model lacks a feature of the data there")


def _spread_figure(report: HtmlReport, fit, isolator: str, model: str) -> None:
    refits = "" if fit.spread is not None else f" ({fit.spread_note or 'no refits'})"
    report.figure(plot_parameter_spread(fit, title=f"{isolator} ({model})").figure,
                  name=f"{isolator} {model.lower()} parameter spread",
                  caption=f"Uncertainty of each fitted {model} parameter in percent of its value: bars +-1 and +-2 "
                          f"standard errors from the residual Jacobian, dots one refit per repetition{refits}; a dot "
                          "outside the bars means the repetitions differ more than the fit's residual explains.",
                  alt=f"relative standard errors and per-repetition refits of the {isolator} {model} parameters")


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


def wire_rope_fit_section(report: HtmlReport, data: ReportData) -> str:
    iwan, boucwen = data.iwan, data.boucwen
    report.items([fit_sentence(f"Iwan fit ({rope_model_name(data)} order {iwan.model.order}; loop error small "
                               f"{100 * iwan.result.error_small:.2f} %, large {100 * iwan.result.error_large:.2f} %, "
                               "eq. 7.1)", iwan),
                  fit_sentence(f"Bouc-Wen comparison (small {100 * boucwen.result.error_small:.2f} %, large "
                               f"{100 * boucwen.result.error_large:.2f} %)", boucwen, comparison=True)])
    report.paragraph(f"Valid range of the identified {rope_model_name(data)} model: {_valid_range_words(data)}; "
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
    return (f"{rope_model_name(data)} order {iwan.model.order}, loop error {100 * iwan.result.error_small:.2f} / "
            f"{100 * iwan.result.error_large:.2f} % (small / large); "
            + ("fit succeeded" if iwan.success else "fit not a success"))


def elastomer_fit_section(report: HtmlReport, data: ReportData) -> str:
    maxwell = data.maxwell
    bands = elastomer_bands(data)
    report.items([fit_sentence(f"Maxwell fit (order {len(maxwell.model.k)}, FRF error "
                               f"{100 * maxwell.result.error:.2f} %, eq. 7.5)", maxwell)])
    if bands:
        report.paragraph(f"Residual: {bands_words(bands)} (the log-magnitude residual keeps one sign on every top "
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
            + ("; systematic residual over " + ", ".join(f"{b.low_hz:.3g}-{b.high_hz:.3g} Hz" for b in bands)
               if bands else ""))
