"""The demo job: simulate the study's systems and write figures and numbers.

Until the full report exists this is the README's main command (``idkit demo``).
"""

from __future__ import annotations

import json
import time

import numpy as np

from idkit import __version__
from idkit.models import library, save_model
from idkit.plot import (
    plot_bode,
    plot_harmonic_cross_sections,
    plot_loops,
    plot_shock_levels,
    save_figure,
)
from idkit.atomic import atomic_output_folder
from idkit.simulate import free_fall, harmonic_response

__all__ = ["run_demo"]


def _triangle(amplitude, n_points=800):
    quarter = np.linspace(0, amplitude, n_points // 4, endpoint=False)
    down = np.linspace(amplitude, -amplitude, n_points // 2, endpoint=False)
    up = np.linspace(-amplitude, amplitude, n_points // 2 + 1)
    return np.concatenate([quarter, down, up])


def run_demo(out_dir, *, force: bool = False, quick: bool = False, progress=None) -> dict:
    """Simulate the thesis systems and write figures, model files and ``summary.json``.

    Parameters
    ----------
    out_dir : path
        Output folder; must not exist unless ``force``. Written atomically.
    quick : bool
        Smaller grids (for tests).
    progress : callable(message: str), optional
        Receives one line per stage.

    Returns
    -------
    dict
        The summary written to ``summary.json``.
    """
    say = progress or (lambda message: None)
    timings = {}
    summary: dict = {"idkit_version": __version__, "quick": quick}
    with atomic_output_folder(out_dir, force=force) as folder:
        from matplotlib.figure import Figure

        # 1. quasi-static loops of the Table A.1 wire ropes
        start = time.perf_counter()
        say("loops of the Table A.1 wire ropes")
        figure = Figure(figsize=(9, 3.8), layout="constrained")
        axes = figure.subplots(1, 2, sharey=True)
        for ax, name in zip(axes, ("table_a1_symmetric", "table_a1_asymmetric")):
            model = library.get(name)
            for amplitude in (2e-3, 5e-3, 10e-3, 15e-3):
                plot_loops(_triangle(amplitude), model.force(_triangle(amplitude)), label=f"{amplitude * 1e3:g} mm", ax=ax)
            ax.set_title(library.describe(name), fontsize="small")
        axes[0].legend(fontsize="small")
        save_figure(figure, folder / "loops_table_a1.png")
        timings["loops"] = time.perf_counter() - start

        # 2. linear transmissibility of the Table B.1 elastomers (5 kg)
        start = time.perf_counter()
        say("transmissibility of the Table B.1 elastomers")
        freq = np.logspace(0, 3, 600)
        figure = Figure(figsize=(6.4, 6), layout="constrained")
        axes = figure.subplots(2, 1, sharex=True)
        resonances = {}
        for name in ("system_b1_low", "system_b1_medium", "system_b1_high"):
            system = library.get(name)
            transmissibility = system.transmissibility(freq)
            plot_bode(freq, transmissibility, label=name, axes=axes)
            resonances[name] = float(freq[np.argmax(np.abs(transmissibility))])
        axes[0].legend(fontsize="small")
        save_figure(figure, folder / "transmissibility_table_b1.png")
        summary["elastomer_resonance_hz"] = resonances
        timings["transmissibility"] = time.perf_counter() - start

        # 3. first-harmonic HOSIDF of the asymmetric hybrid over frequency and amplitude
        start = time.perf_counter()
        say("frequency-amplitude map of the asymmetric hybrid")
        n_freq = 12 if quick else 40
        freq_axis = np.logspace(0, 2, n_freq)
        amplitude_axis = np.logspace(-5, -2, 4)
        system = library.get("hybrid_asymmetric")
        response = harmonic_response(system, freq_axis[:, None], amplitude_axis[None, :])
        first = response.hosidf(1).reshape(n_freq, amplitude_axis.size)
        figure = Figure(figsize=(6.4, 6), layout="constrained")
        plot_harmonic_cross_sections(freq_axis, amplitude_axis, first, axes=figure.subplots(2, 1, sharex=True))
        save_figure(figure, folder / "hybrid_asymmetric_hosidf1.png")
        peak_freq = freq_axis[np.argmax(np.abs(first), axis=0)]
        summary["hybrid_asymmetric_resonance_hz_by_amplitude_m"] = dict(
            zip([f"{a:.0e}" for a in amplitude_axis], peak_freq.round(3).tolist()))
        summary["hybrid_map_points_converged"] = int(response.converged.sum())
        summary["hybrid_map_points"] = int(response.converged.size)
        timings["hybrid_map"] = time.perf_counter() - start

        # 4. conditioned free fall: rest shock level versus impact speed
        start = time.perf_counter()
        say("conditioned free-fall sweeps")
        speeds = np.linspace(0.02, 1.0, 10 if quick else 40)
        figure = Figure(figsize=(6.4, 4.4), layout="constrained")
        ax = figure.subplots()
        shock = {}
        for name in ("system_a1_symmetric", "system_b1_medium", "hybrid_symmetric"):
            drop = free_fall(library.get(name), impact_velocity=-speeds, duration=0.6, time_step=5e-5,
                             record_every=2)
            levels = np.max(np.abs(drop.acceleration[:, 0]), axis=1)
            plot_shock_levels(speeds, levels, label=name, ax=ax)
            shock[name] = {"impact_speed_m_s": speeds.round(4).tolist(), "rest_shock_m_s2": levels.round(4).tolist()}
        ax.legend(fontsize="small")
        save_figure(figure, folder / "rest_shock.png")
        summary["rest_shock"] = shock
        timings["shock"] = time.perf_counter() - start

        # model files of every bundled parameter set
        models = folder / "models"
        models.mkdir()
        for name in library.names():
            save_model(library.get(name), models / f"{name}.json", provenance={"source": "idkit.models.library"})
        summary["timings_s"] = {key: round(value, 3) for key, value in timings.items()}
        (folder / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary
