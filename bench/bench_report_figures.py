"""Benchmark: CPU of rendering the report's figures (layout, PNG and SVG), per figure, on one core.

    python bench/bench_report_figures.py [--full] [--repeat N] [--data DIR] [--seed N]

Computes the report's data once (:func:`idkit.studies.pipeline.compute_report_data` on the
bundled data or ``--data``: the quick report unless ``--full``; its child processes use the
cores as ``idkit report`` does), then, with this process pinned to one core and one BLAS
thread, writes the report ``--repeat`` times into temporary folders with every figure rendered
in this process (:func:`idkit.report.main_report.write_report` with ``render_processes=1``).

Printed, in CPU seconds of this process (``time.process_time``: other users of the machine
inflate it far less than the wall time), min and median over the repetitions:

- per figure, its rendering (``idkit.report.html._render_figure``: the layout, the PNG at
  90 dpi, the SVG) and the size of its SVG;
- the sum over the figures, and the whole ``write_report`` (building the figures and tables,
  encoding, writing the files) beside it.

Each repetition builds its figures anew, so no figure is rendered twice; the first one also
warms matplotlib's font caches (the min leaves it out). Nothing is asserted.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
os.environ.setdefault("MPLBACKEND", "Agg")

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import idkit.report.html as html_module
from idkit.report.blas_threads import one_blas_thread
from idkit.report.main_report import write_report
from idkit.studies.pipeline import compute_report_data

DATA = Path(__file__).resolve().parents[1] / "data"


class FigureTimer:
    """Records, for each figure the report draws, its name and the CPU seconds of its rendering.

    Installed around ``HtmlReport.figure`` (for the name) and ``html._render_figure`` (for
    the time) for the ``with`` block only.
    """

    def __init__(self):
        self.renders: list[tuple[str, float, int]] = []
        self._name = None

    def __enter__(self):
        self._figure, self._render = html_module.HtmlReport.figure, html_module._render_figure
        timer, figure, render = self, self._figure, self._render

        def named_figure(report, fig, *, caption, name, alt=None):
            timer._name = name
            return figure(report, fig, caption=caption, name=name, alt=alt)

        def timed_render(fig, *, with_svg):
            started = time.process_time()
            png, svg = render(fig, with_svg=with_svg)
            timer.renders.append((timer._name, time.process_time() - started, len(svg or b"")))
            return png, svg

        html_module.HtmlReport.figure = named_figure
        html_module._render_figure = timed_render
        return self

    def __exit__(self, *exc):
        html_module.HtmlReport.figure, html_module._render_figure = self._figure, self._render


def one_write(data) -> tuple[float, list[tuple[str, float, int]]]:
    """CPU seconds of one ``write_report`` into a new temporary folder, and its figures' renders."""
    with tempfile.TemporaryDirectory() as root, FigureTimer() as timer:
        folder = Path(root) / "report"
        folder.mkdir()
        started = time.process_time()
        write_report(data, folder, render_processes=1)
        return time.process_time() - started, timer.renders


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="the full report's data (default: --quick)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--data", type=Path, default=DATA)
    parser.add_argument("--seed", type=int, default=2026)
    args = parser.parse_args()

    started = time.perf_counter()
    with one_blas_thread():
        data = compute_report_data(args.data, quick=not args.full, seed=args.seed)
        data.transport  # waits for the study's child process
    print(f"report data ({'full' if args.full else 'quick'}) computed in {time.perf_counter() - started:.1f} s wall")

    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    writes, renders = [], []
    with one_blas_thread():
        for _ in range(args.repeat):
            seconds, figures = one_write(data)
            writes.append(seconds)
            renders.append(figures)

    names = [name for name, _, _ in renders[0]]
    print(f"{len(names)} figures, {args.repeat} repetitions, CPU seconds of one core "
          f"(load average {os.getloadavg()[0]:.2f})")
    print(f"{'min':>7} {'median':>7} {'SVG kB':>7}  figure")
    for index, name in enumerate(names):
        seconds = [figures[index][1] for figures in renders]
        print(f"{min(seconds):7.3f} {statistics.median(seconds):7.3f} {renders[0][index][2] / 1e3:7.0f}  {name}")
    totals = [sum(seconds for _, seconds, _ in figures) for figures in renders]
    print(f"{min(totals):7.2f} {statistics.median(totals):7.2f} {'':>7}  all figures rendered")
    print(f"{min(writes):7.2f} {statistics.median(writes):7.2f} {'':>7}  write_report (figures built and rendered, "
          "tables, files)")


if __name__ == "__main__":
    main()
