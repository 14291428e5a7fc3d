"""The design tool: candidates from a catalogue, screened, ranked, the best re-simulated and written.

:func:`run_design` evaluates every candidate on the screening path
(:mod:`idkit.design.evaluation`), judges them (:func:`idkit.design.ranking.judge`), re-simulates
the ``top`` ranked ones in full with the same draws, judges those again (the verdicts the
report states are the full ones) and, with ``output``, writes::

    candidates.csv           every candidate, screened: metrics, margins, probabilities, verdict
    best.csv                 the top candidates re-simulated in full
    best/<rank>.json         each top design as a system model file (per mount), provenance = its row
    pareto.png               acceleration vs deflection of every candidate, front and top marked
    design.md                the report section: environment, limits, top designs, verdicts
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from idkit.atomic import write_bytes_atomic, write_text_atomic
from idkit.design.candidates import Candidate
from idkit.design.environment import Environment
from idkit.design.evaluation import evaluate_candidates
from idkit.design.ranking import judge
from idkit.errors import OutputError
from idkit.models import save_model

__all__ = ["DesignResult", "run_design"]


@dataclass(frozen=True)
class DesignResult:
    """Screened table, the top re-simulated in full, and the candidates by name."""

    screened: pd.DataFrame
    best: pd.DataFrame
    candidates: dict
    environment: Environment

    @property
    def chosen(self) -> str | None:
        """Name of the best design re-simulated in full whose verdict is ``"meets"`` (None if none)."""
        meets = self.best[self.best["verdict"] == "meets"]
        return None if meets.empty else str(meets.iloc[0]["name"])

    def report(self) -> str:
        """The report section (Markdown)."""
        env = self.environment
        lines = [f"# Design: {env.name or 'environment'}", "",
                 f"{len(self.screened)} candidates screened, {int(self.best['draws'].iloc[0]) if len(self.best) else 0}"
                 " parameter draws each; the top re-simulated in full. Limits: "
                 + ", ".join(f"{k} = {v}" for k, v in env.limits.items()) + ".", ""]
        chosen = self.chosen
        lines.append(f"Chosen: **{chosen}**." if chosen else
                     "No candidate meets every limit with the required probability.")
        lines += ["", "| rank | design | verdict | P(all) | utilisation | peak acc. [m/s^2] | RMS acc. [m/s^2] | "
                      "travel [mm] | dissipated [J] | resonance [Hz] |", "|---|---|---|---|---|---|---|---|---|---|"]
        for _, row in self.best.iterrows():
            lines.append(f"| {row['rank']} | {row['name']} | {row['verdict']} | {row['P(all)']:.2f} | "
                         f"{row['utilisation']:.3g} | {row['peak_acceleration_m_per_s2']:.4g} | "
                         f"{row['rms_acceleration_m_per_s2']:.4g} | {1e3 * row['max_deflection_m']:.4g} | "
                         f"{row['max_dissipated_energy_j']:.4g} | {row['resonance_hz']:.3g} |")
        fragile = self.best[self.best["verdict"] == "meets on the mean model only"]
        for _, row in fragile.iterrows():
            lines.append(f"\n{row['name']} meets every limit on the mean model but only with probability "
                         f"{row['P(all)']:.2f} under the parts' covariance (required {env.probability:g}).")
        return "\n".join(lines) + "\n"


def run_design(candidates, environment: Environment, *, n_draws: int = 30, seed: int = 0, top: int = 3,
               output=None, workers: int = 1, executor=None, progress=None) -> DesignResult:
    """Screen, rank, re-simulate the top ``top`` in full and (with ``output``) write the results.

    Parameters
    ----------
    candidates : sequence of Candidate
        From :func:`idkit.design.make_candidates` (or built by hand).
    environment : Environment
    n_draws : int, default 30
        Parameter draws per candidate (besides the mean model).
    seed : int
        Seed of the draws (per candidate by its name) and of the floor realizations.
    top : int, default 3
        Ranked candidates re-simulated in full.
    output : path, optional
        A new folder for the files of the module docstring (never replaced).
    workers, executor :
        See :func:`idkit.design.evaluation.evaluate_candidates`.
    """
    candidates = list(candidates)
    if not candidates or not all(isinstance(c, Candidate) for c in candidates):
        raise OutputError("candidates: expected a non-empty list of Candidate (make_candidates)")
    names = [c.name for c in candidates]
    if len(set(names)) != len(names):
        raise OutputError("candidates: names must be unique (they seed the draws)")
    if output is not None and Path(output).exists():
        raise OutputError(f"{output}: exists; expected a new output folder")
    screened = judge(evaluate_candidates(candidates, environment, n_draws=n_draws, seed=seed, screening=True,
                                         workers=workers, executor=executor), environment)
    by_name = dict(zip(names, candidates))
    chosen = [by_name[name] for name in screened["name"].head(top)]
    full_rows = evaluate_candidates(chosen, environment, n_draws=n_draws, seed=seed, screening=False,
                                    workers=workers, executor=executor)
    best = judge(full_rows, environment)
    result = DesignResult(screened, best, by_name, environment)
    if output is not None:
        _write(result, Path(output))
    return result


def _write(result: DesignResult, folder: Path) -> None:
    folder.mkdir(parents=True)
    (folder / "best").mkdir()
    write_bytes_atomic(folder / "candidates.csv", result.screened.to_csv(index=False).encode())
    write_bytes_atomic(folder / "best.csv", result.best.to_csv(index=False).encode())
    for _, row in result.best.iterrows():
        candidate = result.candidates[row["name"]]
        provenance = {"design": {key: (None if isinstance(v, float) and not math.isfinite(v) else v)
                                 for key, v in row.items()},
                      "payload_mass_kg": candidate.payload_mass_kg, "mounts": candidate.count,
                      "parts": [part.name for part in candidate.parts],
                      "environment": result.environment.to_dict(), "note": "system per mount: the payload share "
                      "M / N on one mount (N identical mounts in parallel under a rigid payload)"}
        save_model(candidate.system(), folder / "best" / f"{int(row['rank'])}.json",
                   provenance=json.loads(json.dumps(provenance, default=str)))
    from idkit.design.figures import plot_pareto

    import matplotlib.pyplot as plt

    from idkit.plot._figure import save_figure

    figure = plot_pareto(result.screened, best=result.best)
    try:
        save_figure(figure, folder / "pareto.png", overwrite=False)
    finally:
        plt.close(figure)
    write_text_atomic(folder / "design.md", result.report())
