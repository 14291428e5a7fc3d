"""``idkit simulate harmonic|drop --plots DIR``: the map and the drops drawn from the tables."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from idkit.plot.simulations import harmonic_table_grid, plot_harmonic_table_map
from tests.cli.hostile import check, run_main


def _linear_table(freq, amplitudes, natural_hz=8.0, damping_ratio=0.05):
    """A harmonic grid table of a linear isolator (the base-excitation transmissibility, the same
    at every amplitude), frequency-major as idkit writes it."""
    rows = []
    for f in freq:
        r = f / natural_hz
        ratio = np.sqrt((1 + (2 * damping_ratio * r) ** 2) / ((1 - r**2) ** 2 + (2 * damping_ratio * r) ** 2))
        for a in amplitudes:
            rows.append({"freq [Hz]": f, "amplitude [m]": a, "|H0.5| [-]": 0.0, "|H1| [-]": ratio,
                         "|H2| [-]": 1e-3 * ratio, "status": "ok"})
    return pd.DataFrame(rows)


def test_the_resonance_line_is_the_transmissibility_peak():
    """Peak of the linear transmissibility: r = sqrt(sqrt(1 + 8 zeta^2) - 1) / (2 zeta) (zeta 0.05:
    r = 0.99751). The parabola through three samples 0.01 decade apart locates it within 0.2 %
    (about a tenth of the 2.3 % sample spacing; the parabola's error is the cubic term)."""
    zeta, natural = 0.05, 8.0
    freq = np.logspace(0.0, 2.0, 201)
    grid = harmonic_table_grid(_linear_table(freq, [1e-4, 1e-3], natural, zeta))
    peak = natural * np.sqrt(np.sqrt(1 + 8 * zeta**2) - 1) / (2 * zeta)
    np.testing.assert_allclose(grid.resonance(), peak, rtol=2e-3)


def test_points_not_ok_are_blank_and_repeated_points_keep_the_first():
    table = _linear_table([2.0, 5.0, 9.0], [1e-4, 1e-3])
    table.loc[1, "status"] = "max_steps"      # (2 Hz, 1e-3 m) did not settle
    repeat = table.iloc[[4]].assign(**{"|H1| [-]": -1.0})  # (9 Hz, 1e-4 m) computed again
    grid = harmonic_table_grid(pd.concat([table, repeat], ignore_index=True))
    assert grid.freq.tolist() == [2.0, 5.0, 9.0] and grid.amplitude.tolist() == [1e-4, 1e-3]
    assert np.isnan(grid.magnitude[1.0][0, 1]) and grid.magnitude[1.0][2, 0] > 0
    axes = plot_harmonic_table_map(table)
    assert len(axes) == 3 and "1 points not ok" in axes[0].get_title()  # |H1|, then 1/2 and 2
    with pytest.raises(ValueError, match="at least 2 of each"):
        plot_harmonic_table_map(table[table["amplitude [m]"] == 1e-4])


def test_simulate_harmonic_and_drop_write_their_figures(tmp_path):
    model = tmp_path / "elastomer.json"
    check(run_main(["library", "system_b1_medium", "-o", model]), "ok")
    plots, grid = tmp_path / "plots", tmp_path / "grid.csv"
    harmonic = ["simulate", "harmonic", model, "--freq", "3", "6", "12", "--amplitude", "1e-4", "1e-3",
                "--harmonics", "2", "--quiet", "-o", grid, "--plots", plots]
    check(run_main(harmonic, inputs=[model]), "ok", ["wrote", "harmonic_map.png"])
    for name in ("harmonic_map.png", "harmonic_sections.png"):
        assert (plots / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # a figure is never replaced: refused before simulating, the table not written
    again = tmp_path / "again.csv"
    outcome = run_main([*harmonic[:-4], "-o", again, "--plots", plots], inputs=[model, plots], must_not_exist=[again])
    check(outcome, "error", ["refusing to overwrite existing plot(s)", "harmonic_map.png"])
    outcome = run_main([*harmonic[:-4], "-o", again, "--plots", again], inputs=[model], must_not_exist=[again])
    check(outcome, "error", ["--plots", "is the table -o"])
    drops = tmp_path / "drops"
    check(run_main(["simulate", "drop", model, "--height", "0.01", "0.03", "--duration", "0.1", "--plots", drops],
                   inputs=[model]), "ok", ["drop_histories.png"])
    assert sorted(p.name for p in drops.iterdir()) == ["drop_histories.png", "drop_peaks.png"]
