"""Every command prints its results on stdout and its file notices ("wrote ...") on stderr.

``fit``, ``simulate``, ``library``, ``report`` and ``study`` did; ``inspect --plots``,
``shock -o`` and ``data init`` printed their "wrote" lines on stdout, mixed into the
results a user redirects (``idkit inspect SET --plots DIR > summary.txt``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tests.cli.hostile import check, run_main

DATA = Path(__file__).resolve().parents[2] / "data"


def _notices_on_stderr_only(outcome, results_word):
    check(outcome, "ok")
    assert results_word in outcome.stdout, outcome.stdout
    assert "wrote" not in outcome.stdout, outcome.stdout
    assert "wrote" in outcome.stderr, outcome.stderr


def test_inspect_plots_notices_go_to_stderr(tmp_path):
    outcome = run_main(["inspect", DATA / "hybrid", "--plots", tmp_path / "plots"], inputs=[DATA / "hybrid"])
    _notices_on_stderr_only(outcome, "measurements")


def test_shock_output_notice_goes_to_stderr(tmp_path):
    time = np.arange(2000) / 1e5
    accel = np.where((time > 2e-3) & (time < 3e-3), 100 * np.sin(np.pi * (time - 2e-3) / 1e-3), 0.0)
    record = tmp_path / "shot.csv"
    record.write_text("time [s],t1 [m/s^2]\n" + "".join(f"{t!r},{a!r}\n" for t, a in zip(time.tolist(), accel.tolist())))
    outcome = run_main(["shock", record, "-o", tmp_path / "out"], inputs=[record])
    _notices_on_stderr_only(outcome, "velocity_change")


def test_data_init_notice_goes_to_stderr(tmp_path):
    source = next((DATA / "wire_rope" / "quasi_static").iterdir())
    (tmp_path / source.name).write_bytes(source.read_bytes())
    outcome = run_main(["data", "init", tmp_path, "--kind", "quasi_static"], inputs=[tmp_path / source.name])
    check(outcome, "ok")
    assert "wrote" not in outcome.stdout, outcome.stdout
    assert "wrote" in outcome.stderr and "manifest.json" in outcome.stderr, outcome.stderr
