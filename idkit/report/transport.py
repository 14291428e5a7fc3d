"""The transport-tool study (SPEC 6, thesis chapter 8).

Which isolation system protects a payload best? The reference (viscous), the
elastomer, the wire rope and seven hybrids, all tuned to a 5 Hz small-amplitude
resonance (:mod:`idkit.studies.transport`), are compared on

* output acceleration PSDs for the six flat floor levels of SPEC 5
  (30 seeded realizations, Welch; :func:`idkit.responses.random_vibration.random_response`),
* the rest shock level versus impact velocity and drop height
  (:func:`idkit.responses.shock.shock_sweep`, conditioned free fall).
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from idkit import __version__
from idkit.signal.psd import PsdProfile
from idkit.responses.random_vibration import FLAT_LEVELS, random_response
from idkit.responses.shock import shock_sweep
from idkit.studies.transport import RK_VALUES, transport_systems, tuning_table
from idkit.plot import save_figure
from idkit.atomic import atomic_output_folder

__all__ = ["TransportStudy", "run_transport_study", "compute_transport_study", "write_transport_figures",
           "write_transport_tables"]


@dataclass(frozen=True)
class TransportStudy:
    """Numbers of the transport-tool study.

    Attributes
    ----------
    tuning : DataFrame
        Masses and tuning checks per system.
    rms : DataFrame
        RMS top acceleration (m/s^2) per system (rows) and flat input level (columns,
        (m/s^2)^2/Hz; the input RMS is sqrt(level x 99.9 Hz)).
    shock_velocity, shock_height : DataFrame
        Rest shock level (m/s^2) per system (columns) versus |v0| (m/s) / h (m).
    psd : dict
        ``{level: {system: (freq, output_psd)}}``, Hz and (m/s^2)^2/Hz.
    seed, n_realizations : int
    """

    tuning: pd.DataFrame
    rms: pd.DataFrame
    shock_velocity: pd.DataFrame
    shock_height: pd.DataFrame
    psd: dict
    seed: int
    n_realizations: int
    flagged_runs: int

    def summary_table(self, heights=(0.02, 0.05, 0.10)) -> pd.DataFrame:
        """RMS per system and level, and rest shock at a few drop heights (interpolated)."""
        table = self.rms.copy()
        for height in heights:
            table[f"rest shock at h = {height * 100:g} cm [m/s^2]"] = [
                float(np.interp(height, self.shock_height.index.to_numpy(), self.shock_height[name].to_numpy()))
                for name in table.index
            ]
        return table


def compute_transport_study(*, wire_rope=None, elastomer=None, levels=FLAT_LEVELS, n_realizations: int = 30,
                            seed: int = 2026, r_k_values=RK_VALUES, speeds=None, heights=None, workers=None,
                            progress=None) -> TransportStudy:
    """Run the study; models default to the study's identified parts (Tables 7.1, 7.3).

    Parameters
    ----------
    wire_rope, elastomer : IwanModel, GeneralizedMaxwell, optional
        Identified components (e.g. from ``idkit fit``).
    levels : sequence of float
        Flat floor PSD levels over 0.1-100 Hz, (m/s^2)^2/Hz.
    n_realizations, seed : int
        Random realizations per level and the seed (each level and system uses
        ``seed``; the same floor signals drive every system).
    speeds, heights : array_like, optional
        Impact speeds |v0| (m/s) and drop heights (m) of the shock sweeps
        (defaults 0.01-1.0 m/s and 0.5-15 cm).
    progress : callable(done, total), optional
    """
    systems = transport_systems(wire_rope=wire_rope, elastomer=elastomer, r_k_values=r_k_values)
    speeds = np.linspace(0.01, 1.0, 40) if speeds is None else np.asarray(speeds, dtype=float)
    heights = np.linspace(0.005, 0.15, 30) if heights is None else np.asarray(heights, dtype=float)
    total = len(systems) * (len(levels) + 2)
    done = 0
    rms_rows, psd, flagged = {}, {}, 0
    velocity_table, height_table = {}, {}
    for item in systems:
        rms_rows[item.name] = {}
        for level in levels:
            profile = PsdProfile.flat(level, f_lo=0.1, f_hi=100.0)
            result = random_response(item.system, profile, seed=seed, n_realizations=n_realizations, workers=workers)
            flagged += int((result.flags != 0).sum())
            rms_rows[item.name][level] = result.output_rms
            psd.setdefault(level, {})[item.name] = (result.freq, result.output_psd)
            done += 1
            if progress is not None:
                progress(done, total)
        by_speed = shock_sweep(item.system, impact_velocity=-speeds, workers=workers)
        velocity_table[item.name] = by_speed.rest_shock_level
        done += 1
        by_height = shock_sweep(item.system, drop_height=heights, workers=workers)
        height_table[item.name] = by_height.rest_shock_level
        flagged += int((by_speed.flags != 0).sum() + (by_height.flags != 0).sum())
        done += 1
        if progress is not None:
            progress(done, total)
    rms = pd.DataFrame(rms_rows).T
    rms.columns = [f"{level:g} [(m/s^2)^2/Hz]" for level in rms.columns]
    rms.index.name = "system"
    return TransportStudy(
        tuning=tuning_table(systems),
        rms=rms,
        shock_velocity=pd.DataFrame(velocity_table, index=pd.Index(speeds, name="impact speed [m/s]")),
        shock_height=pd.DataFrame(height_table, index=pd.Index(heights, name="drop height [m]")),
        psd=psd, seed=int(seed), n_realizations=int(n_realizations), flagged_runs=flagged,
    )


def write_transport_figures(study: TransportStudy, folder: Path) -> list[Path]:
    """PSD per level (every system), rest shock vs |v0| and vs h; returns the files."""
    from matplotlib.figure import Figure

    written = []
    levels = sorted(study.psd)
    figure = Figure(figsize=(12, 3.2 * ((len(levels) + 1) // 2)), layout="constrained")
    axes = np.atleast_1d(figure.subplots((len(levels) + 1) // 2, 2)).ravel()
    for ax, level in zip(axes, levels):
        for name, (freq, values) in study.psd[level].items():
            keep = freq > 0
            ax.loglog(freq[keep], values[keep], label=name, linewidth=1.0)
        ax.set_title(f"floor PSD {level:g} (m/s$^2$)$^2$/Hz, 0.1-100 Hz", fontsize="small")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("top acceleration PSD")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize="xx-small", ncol=2)
    for ax in axes[len(levels):]:
        ax.set_visible(False)
    written.append(save_figure(figure, folder / "transport_output_psd.png"))

    figure = Figure(figsize=(11, 4.2), layout="constrained")
    by_speed, by_height = figure.subplots(1, 2)
    for name in study.shock_velocity.columns:
        by_speed.plot(study.shock_velocity.index, study.shock_velocity[name], marker=".", label=name)
        by_height.plot(study.shock_height.index * 100, study.shock_height[name], marker=".", label=name)
    by_speed.set_xlabel("impact speed |v0| [m/s]")
    by_height.set_xlabel("drop height h [cm]")
    for ax in (by_speed, by_height):
        ax.set_ylabel("rest shock level [m/s$^2$]")
        ax.grid(True, alpha=0.3)
    by_speed.legend(fontsize="xx-small", ncol=2)
    written.append(save_figure(figure, folder / "transport_rest_shock.png"))
    return written


def write_transport_tables(study: TransportStudy, folder: Path) -> list[Path]:
    """CSV of every table and a JSON summary (numbers behind the figures)."""
    files = {
        "transport_tuning.csv": study.tuning,
        "transport_rms.csv": study.rms,
        "transport_shock_vs_velocity.csv": study.shock_velocity,
        "transport_shock_vs_height.csv": study.shock_height,
        "transport_summary.csv": study.summary_table(),
    }
    written = []
    for name, table in files.items():
        table.to_csv(folder / name, index=name not in ("transport_tuning.csv",))
        written.append(folder / name)
    psd_rows = []
    for level, systems in study.psd.items():
        for system, (freq, values) in systems.items():
            psd_rows.append(pd.DataFrame({"level [(m/s^2)^2/Hz]": level, "system": system,
                                          "freq [Hz]": freq, "output PSD [(m/s^2)^2/Hz]": values}))
    pd.concat(psd_rows).to_csv(folder / "transport_psd.csv.gz", index=False)
    written.append(folder / "transport_psd.csv.gz")
    return written


def run_transport_study(out_dir, *, force: bool = False, quick: bool = False, wire_rope=None, elastomer=None,
                        seed: int = 2026, workers=None, progress=None) -> TransportStudy:
    """Compute the study and write figures, CSV tables and ``summary.json`` atomically."""
    start = time.perf_counter()
    options = dict(levels=(1e-6, 1e-3), n_realizations=4, r_k_values=(0.2, 1.0),
                   speeds=np.linspace(0.02, 1.0, 8), heights=np.linspace(0.01, 0.15, 6)) if quick else {}
    with atomic_output_folder(out_dir, force=force) as folder:
        study = compute_transport_study(wire_rope=wire_rope, elastomer=elastomer, seed=seed, workers=workers,
                                        progress=progress, **options)
        write_transport_figures(study, folder)
        write_transport_tables(study, folder)
        summary = {
            "study": "transport", "idkit_version": __version__, "seed": seed, "quick": quick,
            "n_realizations": study.n_realizations, "flagged_runs": study.flagged_runs,
            "masses": study.tuning.to_dict(orient="records"),
            "rms_m_s2": {system: row.to_dict() for system, row in study.rms.iterrows()},
            "timings_s": {"total": round(time.perf_counter() - start, 3)},
        }
        (folder / "summary.json").write_text(json.dumps(summary, indent=1, default=float) + "\n")
    return study

