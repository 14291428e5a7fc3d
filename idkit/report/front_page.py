"""The report's first screen: the outcome sentence, the verdict table, the model table and the thumbnails.

What ``idkit report`` exits with (:func:`report_exit_status`, :data:`PREDICTING_FITS`) is decided
here from the computed verdicts and fits; nothing is judged again.
"""

from __future__ import annotations

import math

from idkit import __version__
from idkit.exit_status import REPORT_EXIT_STATUSES
from idkit.report.conclusions import key_metric, parameters_cell
from idkit.report.fit_sections import bands_words, elastomer_bands, rope_model_name
from idkit.report.html import HtmlReport
from idkit.studies.pipeline import QUICK_NOTE, ReportData
from idkit.validate import Verdict

__all__ = ["PREDICTING_FITS", "fit_reasons", "front_section", "model_rows", "outcome_sentence", "report_exit_status",
           "verdict_rows"]


#: the fits whose models the report validates and predicts with (the Bouc-Wen fit is a
#: comparison of model forms on the loops and does not enter the exit status)
PREDICTING_FITS = ("wire rope (Iwan)", "elastomer (generalized Maxwell)")


def report_exit_status(verdicts: dict[str, str], flagged_fits) -> int:
    """:attr:`idkit.report.main_report.ReportSummary.exit_status` of validation verdicts and flagged fits
    (:data:`idkit.exit_status.REPORT_EXIT_STATUSES`)."""
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
            + f". idkit report exits with status {status}: {REPORT_EXIT_STATUSES[status]}")
    failed = [key for key, verdict in verdicts.items() if verdict == "FAIL"]
    inconclusive = [key for key, verdict in verdicts.items() if verdict == "INCONCLUSIVE"]
    if status == 1:  # the failed ones are what the status says; the inconclusive ones are named as such
        return text + f" ({', '.join(failed)}" + (f"; inconclusive: {', '.join(inconclusive)}" if inconclusive
                                                   else "") + ")."
    return text + (f" ({', '.join(inconclusive)})." if status == 3 else ".")


def fit_reasons(data: ReportData) -> dict[str, tuple[str, ...]]:
    """:attr:`idkit.report.main_report.ReportSummary.fit_reasons` of the fits in :data:`PREDICTING_FITS`."""
    fits = dict(zip(PREDICTING_FITS, (data.iwan, data.maxwell)))
    return {name: tuple(fit.reasons) for name, fit in fits.items()}


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
    bands = elastomer_bands(data)
    for name, fit, metric, value in (
            (f"wire rope fit ({rope_model_name(data)} {data.iwan.model.order})", data.iwan,
             "loop error small / large (7.1)",
             f"{100 * data.iwan.result.error_small:.2g} / {100 * data.iwan.result.error_large:.2g} %"),
            (f"elastomer fit (Maxwell {len(data.maxwell.model.k)})", data.maxwell, "FRF error (7.5)",
             f"{100 * data.maxwell.result.error:.2g} %")):
        notes = list(fit.reasons)
        if fit is data.maxwell and bands:
            notes.append(bands_words(bands))
        rows.append({"check": name, "key metric": metric, "value": value, "limit": "",
                     "verdict": Verdict.of_fit(fit.success),
                     "why / note": _short("; ".join(notes)) if notes else ""})
    return rows


def model_rows(data: ReportData) -> list[dict]:
    """The first screen's table of the identified models: family, parameters ± standard error, valid range."""
    lower, upper = data.iwan.model.valid_deflection_range()
    elastomer = data.maxwell.parameters_table()
    rows = [{"isolator": "wire rope", "family": f"{rope_model_name(data)}, order {data.iwan.model.order}",
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


def front_section(report: HtmlReport, data: ReportData) -> str:
    """The first screen: the outcome, the verdict and model tables and four thumbnails; returns the slot of
    the transport study's one sentence (filled by :func:`transport_section`)."""
    report.section("Summary", "summary", front=True)
    flagged = tuple(name for name, reasons in fit_reasons(data).items() if reasons)
    report.paragraph(outcome_sentence(data.verdicts, flagged) + f" Data: {data.data_dir} "
                     f"({data.n_measurements} measurements), idkit {__version__}, seed {data.seed}"
                     + (f"; {QUICK_NOTE}." if data.quick else "."))
    report.front_table(verdict_rows(data), verdict_column="verdict", numeric=("value", "limit"))
    report.front_table(model_rows(data))
    for name, label in _thumbnails(data):
        report.thumbnail(name, label)
    return report.placeholder()
