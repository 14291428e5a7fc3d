"""Judge evaluated candidates against the limits: margins, probabilities, verdicts, ranking, Pareto front.

Per limit (``Environment.limits``) and candidate:

* **margin**: how far the mean model is inside the limit, as a fraction of the limit
  (``1 - value / limit``; for the resonance band, the distance of the resonance to the
  nearer band edge over that edge's frequency, negative inside the band);
* **probability**: the fraction of parameter draws that meet the limit (a flagged run
  misses); ``P(all)`` the fraction meeting every limit at once.

Verdict: ``"meets"`` when the mean model meets every limit and ``P(all)`` reaches the
required probability; ``"meets on the mean model only"`` when the mean model meets every limit
but ``P(all)`` falls short (the design is fragile to the parts' uncertainty: the report names
the probability); ``"misses"`` otherwise. Rank: verdict class, then ``P(all)`` (higher first),
then the utilisation, the largest ``value / limit`` of the mean model over the limits (lower
first). The Pareto front is over the mean models' peak (else RMS) acceleration and the
isolator travel (else the resonance frequency): no other candidate is lower in both.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from idkit.design.environment import Environment

__all__ = ["VERDICTS", "judge", "pareto_front"]

VERDICTS = ("meets", "meets on the mean model only", "misses")
_UPPER = ("rms_acceleration_m_per_s2", "peak_acceleration_m_per_s2", "max_deflection_m",
          "max_component_deflection_m", "max_dissipated_energy_j", "max_component_dissipated_energy_j")


def _meets(name: str, values, limit) -> np.ndarray:
    values = np.asarray(values, dtype=float)
    if name == "resonance_hz":
        low, high = limit
        return ~np.isnan(values) & ((values < low) | (values > high))
    return np.nan_to_num(values, nan=np.inf) <= limit


def _margin(name: str, value: float, limit) -> float:
    if name == "resonance_hz":
        low, high = limit
        if low <= value <= high:  # inside: minus the distance to the nearer edge
            return -min(value / low - 1.0, 1.0 - value / high)
        return 1.0 - value / low if value < low else value / high - 1.0
    return 1.0 - value / limit if math.isfinite(value) else -math.inf


def judge(rows: list[dict], environment: Environment) -> pd.DataFrame:
    """The ranked table (module docstring) from :func:`idkit.design.evaluation.evaluate_candidates` rows."""
    limits = {("resonance_hz" if key == "resonance_band_hz" else key): value
              for key, value in environment.limits.items() if key != "probability"}
    records = []
    for row in rows:
        record = {key: value for key, value in row.items() if not key.endswith(" draws")}
        joint = None
        utilisation = 0.0
        mean_meets = True
        for name, limit in limits.items():
            if name.startswith("max_component_") and row["kind"] != "hybrid":
                continue
            draws = row[f"{name} draws"]
            meets = _meets(name, draws, limit)
            record[f"P({name})"] = float(meets.mean()) if meets.size else float(_meets(name, [row[name]], limit)[0])
            record[f"margin {name}"] = _margin(name, row[name], limit)
            mean_meets &= bool(_meets(name, [row[name]], limit)[0])
            if name != "resonance_hz":
                utilisation = max(utilisation, row[name] / limit if math.isfinite(row[name]) else math.inf)
            joint = meets if joint is None else joint & meets
        record["P(all)"] = float(joint.mean()) if joint is not None and joint.size else float(mean_meets)
        record["utilisation"] = utilisation
        record["verdict"] = ("meets" if mean_meets and record["P(all)"] >= environment.probability
                             else "meets on the mean model only" if mean_meets else "misses")
        records.append(record)
    table = pd.DataFrame(records)
    if table.empty:
        return table
    table["verdict class"] = table["verdict"].map(VERDICTS.index)
    table = table.sort_values(["verdict class", "P(all)", "utilisation"], ascending=[True, False, True],
                              kind="stable").drop(columns="verdict class").reset_index(drop=True)
    table.insert(0, "rank", np.arange(1, len(table) + 1))
    table["pareto"] = pareto_front(table)
    return table


def pareto_front(table: pd.DataFrame) -> np.ndarray:
    """Boolean mask of the candidates no other candidate beats in both acceleration and deflection."""
    acceleration = table["peak_acceleration_m_per_s2"] if table["peak_acceleration_m_per_s2"].notna().any() \
        else table["rms_acceleration_m_per_s2"]
    deflection = table["max_deflection_m"] if table["max_deflection_m"].notna().any() else table["resonance_hz"]
    a = np.nan_to_num(acceleration.to_numpy(float), nan=np.inf)
    d = np.nan_to_num(deflection.to_numpy(float), nan=np.inf)
    front = np.ones(len(a), dtype=bool)
    for i in range(len(a)):
        better = (a <= a[i]) & (d <= d[i]) & ((a < a[i]) | (d < d[i]))
        front[i] = not better.any()
    return front
