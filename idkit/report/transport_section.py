"""The report's transport-study section: its conclusions, figures and tables, and the one sentence the first
screen shows (:func:`transport_gist`). The study itself may still be running when the page is built
(:attr:`idkit.studies.pipeline.ReportData.transport` waits for it).
"""

from __future__ import annotations

import math

import numpy as np

from idkit.gravity import STANDARD_GRAVITY
from idkit.plot.studies import plot_transport_psd, plot_transport_ranking, plot_transport_rest_shock
from idkit.report.conclusions import rest_shock_ends, transport_conclusions
from idkit.report.fit_sections import rope_model_name
from idkit.report.html import HtmlReport
from idkit.studies.pipeline import ReportData

__all__ = ["rope_limit_sentence", "transport_gist", "transport_section"]


def transport_section(report: HtmlReport, data: ReportData, summary_slot: str) -> str:
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
            f"{rope_model_name(data)} model identified from this data set (not the library's Table 7.1 rope); "
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
