"""``idkit report FILE``: the report of one data file (what it holds, the model it gives).

The main report (:mod:`idkit.report.main_report`) needs a folder of measurement sets (wire
rope, elastomer, hybrid). A single file gets a report of what it can support:

* a DMA / complex stiffness table: isotherms and the shift factors estimated from them
  (checked against given ones), the master curve, the pruned Prony series as a modulus
  (or stiffness) model, the fit's verdict with its reasons (:func:`idkit.fit.fit_dma_table`);
* a quasi-static loop record: the Iwan fit of its loops as a one-amplitude test (or small
  and large groups when its manifest says so), with the loops drawn against the model;
* any other measurement: the inspection summary and its overview figures.

Output folder (built in a staging folder, swapped in when complete): ``report.html``
(self-contained), ``model.json`` (fits), ``tables/*.csv``, ``figures/*.png`` and ``*.svg``,
``provenance.json`` (input path and SHA-256, idkit version, settings, durations).
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from idkit.atomic import atomic_output_folder, write_text_atomic
from idkit.io.provenance import file_sha256
from idkit.plot._figure import new_axes
from idkit.report.html import HtmlReport

__all__ = ["FileReportSummary", "write_file_report"]


@dataclass(frozen=True)
class FileReportSummary:
    """What :func:`write_file_report` wrote and decided."""

    html: Path
    kind: str
    success: bool
    reasons: tuple[str, ...]

    @property
    def exit_status(self) -> int:
        """0 when the fit (if any) is a success, 1 otherwise."""
        return 0 if self.success else 1


def _dma_section(report: HtmlReport, fit) -> list[tuple[str, object]]:
    from idkit.plot.fits import plot_storage_loss
    from idkit.plot.responses import plot_complex_stiffness

    figures = []
    master = fit.master
    report.section("Model", "model")
    word = "PASS" if fit.success else "FLAGGED"
    report.verdict(f"{fit.model.quantity} model, order {fit.model.order}, RMS relative error "
                   f"{100 * fit.result.error:.2f} % on the master curve", word)
    for reason in fit.reasons:
        report.paragraph("Not a success: " + reason)
    if fit.shift_estimate is not None:
        report.section("Shift factors", "shift")
        report.preformatted("\n".join(fit.shift_lines()))
        axes = new_axes()
        est = fit.shift_estimate
        axes.errorbar(est.temperature_k - 273.15, est.log_a_t, yerr=est.log_a_t_stderr, fmt="o", ms=3,
                      label="estimated from the isotherms")
        for law in (fit.wlf, fit.polynomial):
            if law is not None:
                axes.plot(est.temperature_k - 273.15, law.log_a_t(est.temperature_k), label=law.law)
        if fit.check is not None:
            frame = fit.check.table
            axes.plot(frame["temperature [K]"] - 273.15, frame["given log_aT [-]"], "x", label="given")
        axes.set_xlabel("temperature [C]")
        axes.set_ylabel("log10 aT [-]")
        axes.legend(fontsize="small")
        axes.grid(True, alpha=0.3)
        figures.append(("shift_factors", axes.figure, "Shift factors with one standard error; a given set "
                                                      "that leaves the error bars is not these isotherms'"))
        report.table(est.to_dataframe(), caption="Shift factors estimated from the isotherms")
    report.section("Master curve and model", "master")
    stiffness_ax, loss_ax = new_axes(2, 1, sharex=True, figsize=(7.0, 6.0))
    plot_complex_stiffness(master.freq, master.storage + 1j * master.loss, label="measured",
                           axes=(stiffness_ax, loss_ax), quantity=master.quantity)
    for line in (*stiffness_ax.lines, *loss_ax.lines):
        line.set_linestyle("none")
        line.set_marker(".")
    plot_storage_loss(fit.model, master.freq, axes=(stiffness_ax, loss_ax), label="model")
    figures.append(("master_curve", stiffness_ax.figure,
                    "Measured master curve (dots) and the fitted series: the model should run through the dots "
                    "over the whole reduced-frequency range"))
    if hasattr(fit.prony, "table"):
        report.table(fit.prony.table.drop(columns=["reasons"]), caption=f"Prony order table (kept: fewest terms "
                     f"within {fit.prony.factor:g} x the best error)")
    report.preformatted(fit.result.report())
    return figures


def _loop_section(report: HtmlReport, fit) -> list[tuple[str, object]]:
    from idkit.fit.predictions import predict_fit
    from idkit.plot.fits import plot_loop_fit

    report.section("Model", "model")
    report.verdict(f"Iwan order {fit.model.order}", "PASS" if fit.success else "FLAGGED")
    for reason in fit.reasons:
        report.paragraph("Not a success: " + reason)
    prediction = predict_fit(fit, landscape=False)
    axes = plot_loop_fit(prediction.loops)
    report.preformatted(fit.report())
    return [("loops", axes[0].figure, "Measured loops and the fitted Iwan model: the model loops should lie on "
                                    "the measured ones at every amplitude")]


def write_file_report(path, output, *, table=None, force: bool = False, seed: int = 0,
                      progress=None, order="auto") -> FileReportSummary:
    """Write the report of one data file into ``output`` (replaced only with ``force``).

    Parameters
    ----------
    path : path
        The data file.
    output : path
        Output folder.
    table : ComplexStiffnessTable, optional
        The file read as a DMA / complex stiffness table (the CLI reads it, in idkit's or
        pyvisco's layout); None for a measurement file.
    force : bool
        Replace an existing output folder.
    seed : int
        Seed of the fit.
    order : int or "auto", default "auto"
        Order of the fit (Prony terms of a table, Jenkin elements of a loop record), as
        ``idkit fit``'s ``--order``; ``"auto"`` lets the order rule choose.
    progress : callable, optional
        Called with one line per stage.
    """
    from idkit import __version__

    say = progress or (lambda message: None)
    path = Path(path)
    timings = {}
    start = time.perf_counter()
    report = HtmlReport(f"idkit report: {path.name}")
    figures, tables, model_fit = [], {}, None
    if table is not None:
        from idkit.fit import fit_dma_table

        say("fitting the table (shift factors, master curve, Prony order search)")
        fit = fit_dma_table(table, order=order, seed=seed)
        kind, model_fit = "complex_stiffness", fit
        report.section("Data", "data")
        from idkit.studies.inspection import inspect_complex_table

        report.preformatted(inspect_complex_table(table).report())
        figures += _dma_section(report, fit)
        tables["master_curve"] = fit.master.to_dataframe()
    else:
        from idkit.io.discover import load_measurements
        from idkit.observe.quality import summarize_measurements

        _, measurements = load_measurements(path)
        kind = measurements[0].kind
        report.section("Data", "data")
        summary = summarize_measurements(measurements)
        report.preformatted(summary.report())
        if kind == "quasi_static":
            from idkit.fit import fit_iwan_measurements

            say("fitting the loops (Iwan)")
            model_fit = fit_iwan_measurements(measurements, isolator=None, split="all", seed=seed, order=order)
            figures += _loop_section(report, model_fit)
        else:
            from idkit.plot.inspect import overview_figures
            from idkit.studies.inspection import overview

            for name, figure in overview_figures(overview(measurements)).items():
                figures.append((name, figure, f"Overview of the {name.replace('_', ' ')} record(s)"))
    timings["compute"] = time.perf_counter() - start
    success = True if model_fit is None else bool(model_fit.success)
    reasons = () if model_fit is None else tuple(model_fit.reasons)
    with atomic_output_folder(output, force=force) as staging:
        (staging / "figures").mkdir()
        (staging / "tables").mkdir()
        report.figures_dir = staging / "figures"
        for name, figure, caption in figures:
            report.figure(figure, caption=caption, name=name)
        for name, frame in tables.items():
            write_text_atomic(staging / "tables" / f"{name}.csv", frame.to_csv(index=False))
        if model_fit is not None:
            model_fit.save(staging / "model.json")
        timings["total"] = time.perf_counter() - start
        report.section("Provenance", "provenance", collapsed=True)
        provenance = {"idkit_version": __version__, "input": {"path": str(path), "sha256": file_sha256(path)},
                      "kind": kind, "seed": seed, "success": success, "reasons": list(reasons),
                      "durations_s": {k: round(v, 3) for k, v in timings.items()}}
        report.table(pd.DataFrame({"item": ["input", "SHA-256", "idkit", "seed", "compute", "total"],
                                   "value": [str(path), provenance["input"]["sha256"], __version__, str(seed),
                                             f"{timings['compute']:.1f} s", f"{timings['total']:.1f} s"]}))
        write_text_atomic(staging / "provenance.json", json.dumps(provenance, indent=2))
        write_text_atomic(staging / "report.html", report.render())
    return FileReportSummary(html=Path(output) / "report.html", kind=kind, success=success, reasons=reasons)
