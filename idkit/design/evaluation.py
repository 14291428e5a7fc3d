"""Evaluate design candidates with the batched simulator, uncertainty carried by parameter draws.

Per candidate and per draw (draw 0 is the mean model, draws 1..n from the parts' covariances,
:func:`idkit.design.candidates.draw_models`; the candidate's own seeded stream, so the draws do
not depend on the executor or the order):

* **random vibration** per floor profile: :func:`idkit.responses.random_response` with one
  realization at the study's resolution (800 Hz, 0.05 Hz lines), ``method="auto"`` (linear
  systems, and hysteretic ones whose elements stay stuck under that floor, exactly in the
  frequency domain); settling :func:`~idkit.responses.random_vibration.settle_records_for`;
  the payload RMS acceleration, worst profile;
* **drops**: :func:`idkit.responses.shock_sweep` over the environment's heights: the peak
  payload acceleration (rest shock level), the isolator travel and (hybrid) each component's
  own peak deflection, worst height;
* **first resonance**: the small-amplitude resonance of the draw's system.

A run flagged by the simulator (the model left its valid range) counts as a draw that misses
every limit it would have been judged on.

**Screening** (``screening=True``): every draw settles for the mean model's settling time; the
random runs integrate at 800 Hz (``oversample=1``, the
thesis's own signals; the trapezoidal warping lowers ``|H|^2`` by about ``(omega h)^2 / 3``:
under 0.2 % up to 10 Hz, where a 5 Hz design's response lives) and the drops at a step 5x the
default (400 points per small-amplitude period: a sampled peak within ``1 - cos(pi / 400)``
= 3e-5 of the true one). The ranked top is then re-simulated in full (``screening=False``:
4x oversampling, the default drop grid) with the same draws.
"""

from __future__ import annotations

import math
import multiprocessing
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from idkit.design.candidates import Candidate, candidate_rng, draw_models
from idkit.design.environment import Environment
from idkit.errors import SimulationError
from idkit.responses import random_response, shock_sweep
from idkit.responses.random_vibration import settle_records_for
from idkit.responses.shock import default_shock_grid
from idkit.simulate import small_amplitude_resonance

__all__ = ["METRICS", "SCREENING_STEP_FACTOR", "evaluate_candidate", "evaluate_candidates"]

#: Metrics computed per draw (SI; NaN where the environment does not ask for it or a run was flagged).
METRICS = ("rms_acceleration_m_per_s2", "peak_acceleration_m_per_s2", "max_deflection_m",
           "max_component_deflection_m", "resonance_hz")
#: Drop time step of the screening path, as a multiple of the default grid's step.
SCREENING_STEP_FACTOR = 5.0


def _draw_metrics(system, environment: Environment, *, screening: bool, seed: int, settle=None) -> dict:
    out = {name: math.nan for name in METRICS}
    out["flagged"] = 0
    out["resonance_hz"] = small_amplitude_resonance(system)
    if environment.profiles:
        worst = -math.inf
        for profile in environment.profiles.values():
            try:
                response = random_response(system, profile, seed=seed, n_realizations=1, method="auto",
                                           oversample=1 if screening else 4,
                                           settle_records=settle_records_for(system) if settle is None else settle,
                                           workers=1)
            except SimulationError:  # every realization left the valid range
                out["flagged"] += 1
                worst = math.inf
                continue
            out["flagged"] += int((response.flags != 0).sum())
            worst = max(worst, response.output_rms)
        out["rms_acceleration_m_per_s2"] = worst
    if environment.drop_heights_m:
        duration, step = default_shock_grid(system)
        sweep = shock_sweep(system, drop_height=np.asarray(environment.drop_heights_m), duration=duration,
                            time_step=step * (SCREENING_STEP_FACTOR if screening else 1.0), workers=1)
        flagged = sweep.flags != 0
        out["flagged"] += int(flagged.sum())
        if flagged.any():
            out["peak_acceleration_m_per_s2"] = math.inf
            out["max_deflection_m"] = math.inf
            out["max_component_deflection_m"] = math.inf
        else:
            out["peak_acceleration_m_per_s2"] = float(np.max(sweep.rest_shock_level))
            out["max_deflection_m"] = float(np.max(np.fmax(sweep.travel_compression, sweep.travel_tension)))
            if sweep.peak_compression.shape[1] > 1:
                out["max_component_deflection_m"] = float(np.max(np.fmax(sweep.peak_compression,
                                                                         sweep.peak_tension)))
    return out


def evaluate_candidate(candidate: Candidate, environment: Environment, *, n_draws: int = 30, seed: int = 0,
                       screening: bool = True) -> dict:
    """Metrics of the mean model and of ``n_draws`` parameter draws of one candidate.

    Returns
    -------
    dict
        ``name``, ``kind``, ``count``, ``parts``, and per metric of :data:`METRICS` the
        mean model's value (``metric``) and the draws' values (``metric draws``, a list), plus
        ``flagged`` runs in all.
    """
    rng = candidate_rng(candidate, seed)
    drawn = [draw_models(part, n_draws, rng) for part in candidate.parts]
    systems = [candidate.system()] + [candidate.system([models[i] for models in drawn]) for i in range(n_draws)]
    # one floor realization per draw, the same for every candidate (seed + draw index)
    # screening: every draw settles as long as the mean model needs (the draws' resonances differ
    # by their parameters' few per cent; searching each one's half-power band cost 60 % of the time)
    settle = settle_records_for(systems[0]) if screening and environment.profiles else None
    results = [_draw_metrics(system, environment, screening=screening, seed=int(seed) + index, settle=settle)
               for index, system in enumerate(systems)]
    row = {"name": candidate.name, "kind": candidate.kind, "count": candidate.count,
           "parts": " + ".join(part.name for part in candidate.parts),
           "predicted parts": sum(part.predicted for part in candidate.parts),
           "payload per mount [kg]": candidate.payload_mass_kg / candidate.count,
           "flagged": int(sum(r["flagged"] for r in results)), "screening": bool(screening), "draws": int(n_draws)}
    for name in METRICS:
        row[name] = results[0][name]
        row[f"{name} draws"] = [r[name] for r in results[1:]]
    return row


def _evaluate_chunk(entries: list, environment: dict, n_draws: int, seed: int, screening: bool) -> list:
    env = Environment.from_dict(environment)
    return [evaluate_candidate(Candidate.from_dict(entry), env, n_draws=n_draws, seed=seed, screening=screening)
            for entry in entries]


def evaluate_candidates(candidates, environment: Environment, *, n_draws: int = 30, seed: int = 0,
                        screening: bool = True, workers: int = 1, executor=None, chunk_size: int | None = None,
                        ) -> list[dict]:
    """:func:`evaluate_candidate` over many candidates, serially, in processes or on an executor.

    ``executor``: any ``concurrent.futures``-style executor (``submit(fn, *args)``; a
    ``dask.distributed.Client`` included); chunks of ``chunk_size`` candidates (default about
    four per worker) are submitted as picklable dictionaries. The rows come back in the
    candidates' order and do not depend on how they were run.
    """
    candidates = list(candidates)
    if isinstance(workers, bool) or not (isinstance(workers, int) and workers >= 1):
        raise SimulationError(f"workers: found {workers!r}, expected a whole number >= 1")
    if isinstance(n_draws, bool) or not (isinstance(n_draws, int) and n_draws >= 0):
        raise SimulationError(f"n_draws: found {n_draws!r}, expected a whole number >= 0")
    if executor is None and workers == 1:
        return [evaluate_candidate(c, environment, n_draws=n_draws, seed=seed, screening=screening)
                for c in candidates]
    size = max(1, chunk_size or -(-len(candidates) // (4 * max(workers, 1))))
    chunks = [[c.to_dict() for c in candidates[i:i + size]] for i in range(0, len(candidates), size)]
    env = environment.to_dict()
    if executor is not None:
        futures = [executor.submit(_evaluate_chunk, chunk, env, n_draws, seed, screening) for chunk in chunks]
        return [row for future in futures for row in future.result()]
    context = multiprocessing.get_context("forkserver")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(_evaluate_chunk, chunk, env, n_draws, seed, screening) for chunk in chunks]
        return [row for future in futures for row in future.result()]
