"""Evaluate design candidates with the batched simulator, uncertainty carried by parameter draws.

Per candidate and per draw (draw 0 is the mean model, draws 1..n from the parts' covariances,
:func:`idkit.design.candidates.draw_models`; the candidate's own seeded stream, so the draws do
not depend on the executor or the order):

* **random vibration** per floor profile: what :func:`idkit.responses.random_response` gives
  with one realization (seed + draw index: the same floor for every candidate) at the study's
  resolution (800 Hz, 0.05 Hz lines), ``method="auto"`` (linear systems, and hysteretic ones
  whose elements stay stuck under that floor, exactly in the frequency domain); settling
  :func:`~idkit.responses.random_vibration.settle_records_for`; the payload RMS acceleration,
  worst profile;
* **drops**: the conditioned free falls of :func:`idkit.responses.shock_sweep` over the
  environment's heights: the peak payload acceleration (rest shock level), the isolator travel
  and (hybrid) each component's own peak deflection, and the energy the isolator (the sum over
  a hybrid's components) and each component dissipated
  (:mod:`idkit.simulate.parameter_sets`), worst height;
* **first resonance**: the small-amplitude resonance of the draw's system
  (:func:`idkit.simulate.small_amplitude_resonance`).

A run flagged by the simulator (the model left its valid range) counts as a draw that misses
every limit it would have been judged on.

**Batched** (the default): a candidate's draws are one parameter-set batch
(:func:`idkit.simulate.parameter_sets.simulate_parameter_sets`): one compiled call runs every
draw's floor record that needs the time domain (records only, one call per settling length;
the RMS by :func:`~idkit.signal.psd.welch_rms`), one runs every draw's drops; the
frequency-domain parts (resonances, the stays-stuck test, the linear responses; the transfer
once per candidate for every floor profile) are array operations over the draws. The draws'
floors and the integrated base motion of a set of slipping draws are kept per process: every
candidate meets the same floors. ``batched=False`` runs one draw at a time through the public
one-system functions (``random_response``, ``shock_sweep``; the dissipated energy from the
free falls' records and final states): the same numbers, the kernel runs bit for bit and the
frequency-domain ones to round-off (``tests/design/test_batched.py``).

**Screening** (``screening=True``): every draw settles for the mean model's settling time (its
half-power band searched on 2e4 points: ``zeta`` resolved from about 0.01 at 5 Hz, below which
the settling is one record anyway) and drops with the mean model's step, five times the default
(400 steps a period; the draws' resonances differ by their parameters' few per cent, and a
sampled peak is within ``1 - cos(pi / 400)`` = 3e-5 of the true one) over its own four
small-amplitude periods (the window of the dissipated energy); the random runs
integrate at 800 Hz (``oversample=1``, the thesis's own signals; the trapezoidal warping lowers
``|H|^2`` by about ``(omega h)^2 / 3``: under 0.2 % up to 10 Hz, where a 5 Hz design's response
lives). The ranked top is then re-simulated in full (``screening=False``: 4x oversampling, each
draw's own settling and drop grid) with the same draws; ``tests/design/test_batched.py`` states
the screen's accuracy against the full simulation.
"""

from __future__ import annotations

import math
import multiprocessing
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from idkit.checks import Flag, Instance, Whole, accepts, unchecked
from idkit.design.candidates import Candidate, candidate_rng, draw_models
from idkit.design.environment import Environment
from idkit.errors import SimulationError
from idkit.gravity import impact_velocity_from_height
from idkit.responses import random_response, shock_sweep
from idkit.responses.frequency_domain import frequency_domain_rms, small_amplitude_transfer
from idkit.responses.random_vibration import WELCH_OVERLAP, settle_records_for
from idkit.responses.shock import default_shock_grid
from idkit.signal.harmonics import resonance_grid_maxima
from idkit.signal.psd import synthesize_random, welch_rms
from idkit.simulate import free_fall, small_amplitude_resonance
from idkit.simulate._kernel import _pack, _pack_states
from idkit.simulate._arrays import system_arrays
from idkit.simulate.base_motion import integrate_acceleration
from idkit.simulate.harmonic import RESONANCE_BAND_HZ, RESONANCE_GRID_POINTS
from idkit.simulate.parameter_sets import simulate_parameter_sets, stack_parameter_sets, stored_energy
from idkit.simulate.time_response import _steps_covering

__all__ = ["METRICS", "SCREENING_STEP_FACTOR", "evaluate_candidate", "evaluate_candidates"]

#: Metrics computed per draw (SI; NaN where the environment does not ask for it or a run was flagged).
METRICS = ("rms_acceleration_m_per_s2", "peak_acceleration_m_per_s2", "max_deflection_m",
           "max_component_deflection_m", "max_dissipated_energy_j", "max_component_dissipated_energy_j",
           "resonance_hz")
_DROP_METRICS = METRICS[1:6]
#: Drop time step of the screening path, as a multiple of the default grid's step.
SCREENING_STEP_FACTOR = 5.0
#: Points of the screening path's settling search (:func:`settle_records_for`).
SCREENING_SETTLE_POINTS = 20_001
_FS, _FREQ_STEP = 800.0, 0.05  # the study's resolution


def _screening_settle(system) -> float:
    """The screen's settling (records): the mean model's, searched on a grid of 2e4 points."""
    return settle_records_for(system, n_points=SCREENING_SETTLE_POINTS)


def _drop_grid(system, screening: bool) -> tuple[float, float]:
    """Duration and step (s) of the drops: :func:`default_shock_grid`, the step 5x on the screen."""
    duration, step = default_shock_grid(system)
    return duration, step * (SCREENING_STEP_FACTOR if screening else 1.0)


def _screening_grids(mean_grid: tuple[float, float], mean_resonance: float, resonances) -> list:
    """The screen's drop grid of each draw: the mean model's step (5x the default), and the draw's own
    duration (the mean model's scaled by the ratio of resonances: four of the draw's own periods, the
    window its dissipated energy is summed over, as in the full simulation)."""
    duration, step = mean_grid
    return [(duration * mean_resonance / float(resonance), step) for resonance in resonances]


def _empty_metrics() -> dict:
    out = {name: math.nan for name in METRICS}
    out["flagged"] = 0
    return out


def _drop_energy(system, heights, duration: float, step: float) -> np.ndarray:
    """Energy (J) each isolator dissipated in each conditioned free fall, from the records of
    :func:`idkit.simulate.free_fall`: the trapezoidal work ``(y1 - y0) (F0 + F1) / 2`` over the
    records less the energy stored at the end (:func:`~idkit.simulate.parameter_sets.stored_energy`
    of the final states). Shape (heights, isolators); NaN for a flagged run."""
    response = free_fall(system, drop_height=np.asarray(heights), duration=duration, time_step=step, workers=1)
    y, force = response.deflection, response.isolator_force
    work = (0.5 * (force[..., 1:] + force[..., :-1]) * np.diff(y, axis=-1)).sum(axis=-1)
    arrays = system_arrays(system)
    packed = _pack(*arrays.as_tuple()[1:], float(np.diff(response.time).mean()))
    final = response.final_state
    energy = np.full(work.shape, np.nan)
    for run in np.flatnonzero(response.flags == 0):
        states = _pack_states(packed, final.jenkin_force[run], final.maxwell_elongation[run], final.boucwen_z[run])
        for j in range(work.shape[1]):
            energy[run, j] = work[run, j] - stored_energy(j, y[run, j, -1], packed, states)
    return energy


def _draw_metrics(system, environment: Environment, *, screening: bool, seed: int, settle=None,
                  drop_grid=None) -> dict:
    """One draw through the one-system functions (module docstring: ``batched=False``)."""
    out = _empty_metrics()
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
        duration, step = _drop_grid(system, screening) if drop_grid is None else drop_grid
        sweep = shock_sweep(system, drop_height=np.asarray(environment.drop_heights_m), duration=duration,
                            time_step=step, workers=1)
        flagged = sweep.flags != 0
        out["flagged"] += int(flagged.sum())
        if flagged.any():
            for name in _DROP_METRICS:
                if len(system.isolators) > 1 or not name.startswith("max_component_"):
                    out[name] = math.inf
        else:
            energy = _drop_energy(system, environment.drop_heights_m, duration, step)
            out["peak_acceleration_m_per_s2"] = float(np.max(sweep.rest_shock_level))
            out["max_deflection_m"] = float(np.max(np.fmax(sweep.travel_compression, sweep.travel_tension)))
            out["max_dissipated_energy_j"] = float(np.max(energy.sum(axis=1)))
            if sweep.peak_compression.shape[1] > 1:
                out["max_component_deflection_m"] = float(np.max(np.fmax(sweep.peak_compression,
                                                                         sweep.peak_tension)))
                out["max_component_dissipated_energy_j"] = float(np.max(energy))
    return out


# ------------------------------------------------------------------------------------------
# batched: every draw of a candidate at once

_SIGNALS: dict = {}
_SIGNALS_KEPT = 128
_FLOORS: dict = {}
_BASES: dict = {}
_STACKS_KEPT = 4  # stacked floors, and integrated base motions, kept per process


def _floor_record(profile, seed: int, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """The one floor realization of a draw (as :func:`random_response` synthesizes it with
    ``n_realizations=1``) and its one-sided line amplitudes, kept: every candidate of a search is
    driven by the same draws' floors."""
    key = (profile.freq.tobytes(), profile.level.tobytes(), int(seed), float(rate))
    found = _SIGNALS.get(key)
    if found is None:
        if len(_SIGNALS) >= _SIGNALS_KEPT:
            _SIGNALS.clear()
        signal = synthesize_random(profile, seed=int(seed), fs=rate, freq_step=_FREQ_STEP, n_realizations=1)
        lines = np.fft.rfft(signal, axis=1)[:, 1:] * (2.0 / signal.shape[1])  # as stays_stuck takes them
        found = (signal[0], lines[0])
        for values in found:
            values.setflags(write=False)
        _SIGNALS[key] = found
    return found


def _kept(store: dict, key, compute):
    """``store[key]``, computed (and the store emptied when full) the first time."""
    found = store.get(key)
    if found is None:
        if len(store) >= _STACKS_KEPT:
            store.clear()
        found = store[key] = compute()
    return found


def _floor_records(profile, seed: int, count: int, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_floor_record` of draws ``0 .. count - 1`` (seeds ``seed + draw``), stacked: the records
    (count, samples) and their line amplitudes, kept for the next candidate."""
    def stack():
        records = [_floor_record(profile, seed + index, rate) for index in range(count)]
        out = (np.array([r[0] for r in records]), np.array([r[1] for r in records]))
        for values in out:
            values.setflags(write=False)
        return out

    return _kept(_FLOORS, (profile.freq.tobytes(), profile.level.tobytes(), int(seed), int(count), float(rate)), stack)


def _floor_motion(profile, seed: int, count: int, draws: tuple, rate: float, total: int):
    """The base motion :func:`simulate` integrates from the floor records of ``draws`` (of
    :func:`_floor_records`) repeated over ``total`` steps at ``rate``: its step (s), displacements and
    velocities (draws, total + 1) and each row's acceleration scale (m/s^2), kept for the next
    candidate (whose draws slip alike under a floor: often all of them)."""
    def integrate():
        signals, _ = _floor_records(profile, seed, count, rate)
        rows = signals[list(draws)]
        drive = np.tile(rows, total // rows.shape[1] + 1)[:, :total + 1]
        h = float(np.diff(np.arange(total + 1) / rate).mean())  # simulate's step of this grid
        disp, vel = integrate_acceleration(drive, h)
        # left writable: the compiled drivers take writable arrays (a read-only one is another signature)
        return h, disp, vel, np.abs(np.diff(vel, axis=1)).max(axis=1) / h

    return _kept(_BASES, (profile.freq.tobytes(), profile.level.tobytes(), int(seed), int(count), tuple(draws),
                          float(rate), int(total)), integrate)


def _resonances(systems) -> np.ndarray:
    """:func:`small_amplitude_resonance` of each system, every system's transmissibility evaluated
    at once on the same grid (:func:`idkit.signal.harmonics.resonance_grid_maxima`, the grid part
    of the search, not refined)."""
    masses = np.array([system.masses for system in systems])
    grid, _, index = resonance_grid_maxima(lambda freq: np.abs(small_amplitude_transfer(systems, masses, freq)[0]),
                                           f_min=RESONANCE_BAND_HZ[0], f_max=RESONANCE_BAND_HZ[1],
                                           n_grid=RESONANCE_GRID_POINTS)
    return grid[index]


def _floor_transfer(systems, profiles, rate: float):
    """The systems' small-amplitude transfer on every line of the floor records (at ``rate``) where
    a profile has power: one computation for every profile
    (:func:`~idkit.responses.frequency_domain.frequency_domain_rms`'s ``transfer``)."""
    freq = np.fft.rfftfreq(round(rate / _FREQ_STEP), d=1.0 / rate)[1:]  # the records' lines
    powered = np.zeros(freq.size, dtype=bool)
    for profile in profiles:
        powered |= np.asarray(profile(freq), dtype=float) > 0
    top, middle = small_amplitude_transfer(systems, np.array([system.masses for system in systems]), freq[powered])
    return freq[powered], top, middle


def _random_rms(systems, sets, profile, *, seed: int, oversample: int, settle, transfer) -> tuple[np.ndarray,
                                                                                                 np.ndarray]:
    """Payload RMS acceleration of each draw under its own floor record, and which were flagged: the
    frequency domain where it applies (:func:`~idkit.responses.frequency_domain.frequency_domain_rms`),
    one compiled call for the others (``sets``: a callable giving the systems' parameter sets)."""
    rate = _FS * oversample
    signals, lines = _floor_records(profile, seed, len(systems), rate)
    rms = frequency_domain_rms(systems, profile, signals, fs=_FS, freq_step=_FREQ_STEP, oversample=oversample,
                               lines=lines, transfer=transfer)
    flagged = np.isinf(rms)
    timed = np.flatnonzero(np.isnan(rms))
    if timed.size:
        rms[timed], flagged[timed] = _timed_rms(systems, sets(), timed, profile, seed=seed, oversample=oversample,
                                                settle=settle)
    return rms, flagged


def _timed_rms(systems, sets, timed, profile, *, seed: int, oversample: int, settle) -> tuple[np.ndarray, np.ndarray]:
    """The time method of :func:`random_response` for draws ``timed`` (each under its own record, seed
    ``seed + draw``), one compiled call per settling length."""
    rate = _FS * oversample
    step = int(oversample)
    record = round(rate / _FREQ_STEP) // step
    overlap = round(WELCH_OVERLAP * record)
    analysed = record + overlap
    firsts = np.array([round(float(settle_records_for(systems[i]) if settle is None else settle()) * record)
                       for i in timed])
    totals = (firsts + analysed) * step
    rms, flagged = np.full(timed.size, np.inf), np.zeros(timed.size, dtype=bool)
    for total in np.unique(totals):
        mine = np.flatnonzero(totals == total)
        draws = timed[mine]
        h, disp, vel, scales = _floor_motion(profile, seed, len(systems), tuple(draws.tolist()), rate, int(total))
        runs = simulate_parameter_sets(sets, draws, time_step=h, n_steps=int(total), base_displacement=disp,
                                       base_velocity=vel, base_row=np.arange(draws.size), acceleration_scale=scales,
                                       record_from=firsts[mine] * step, record_every=step, n_records=analysed,
                                       reduce=False)
        ok = runs.flags == 0
        flagged[mine] = ~ok
        if ok.any():
            rms[mine[ok]] = welch_rms(runs.records[ok], fs=_FS, nperseg=record, overlap=WELCH_OVERLAP)
    return rms, flagged


def _drop_metrics(sets, heights, grids) -> dict:
    """Drop metrics of every draw (``sets``: their parameter sets; ``grids``: each draw's duration and
    step), one compiled call."""
    v0 = np.atleast_1d(impact_velocity_from_height(np.asarray(heights)))
    n_heights = v0.size
    set_index = np.repeat(np.arange(len(sets)), n_heights)
    n_steps = np.array([_steps_covering(duration, step) for duration, step in grids])
    # free_fall's grid and simulate's step on it
    h = np.array([float(np.diff(np.arange(n + 1) * step).mean()) for n, (_, step) in zip(n_steps, grids)])
    runs = simulate_parameter_sets(sets, set_index, time_step=np.repeat(h, n_heights),
                                   n_steps=np.repeat(n_steps, n_heights),
                                   initial_velocity=np.repeat(np.tile(v0, len(sets))[:, None], sets.ndof, axis=1))
    shape = (len(sets), n_heights)
    flagged = (runs.flags != 0).reshape(shape)
    energy = runs.dissipated_energy.reshape(*shape, sets.ndof)
    travel = np.fmax(runs.travel_compression, runs.travel_tension).reshape(shape)
    component = np.fmax(runs.isolator_compression, runs.isolator_extension).reshape(*shape, sets.ndof)
    out = {"flagged": flagged.sum(axis=1),
           "peak_acceleration_m_per_s2": np.max(runs.rest_shock_level.reshape(shape), axis=1),
           "max_deflection_m": np.max(travel, axis=1), "max_dissipated_energy_j": np.max(energy.sum(axis=2), axis=1)}
    if sets.ndof > 1:
        out["max_component_deflection_m"] = np.max(component, axis=(1, 2))
        out["max_component_dissipated_energy_j"] = np.max(energy, axis=(1, 2))
    for name in _DROP_METRICS:
        if name in out:
            out[name] = np.where(flagged.any(axis=1), np.inf, out[name])
    return out


class _Once:
    """A value computed at its first call only (the mean model's settling: only time runs need it)."""

    def __init__(self, compute):
        self._compute, self._value = compute, None

    def __call__(self):
        if self._value is None:
            self._value = self._compute()
        return self._value


def _batched_metrics(systems, environment: Environment, *, screening: bool, seed: int) -> list[dict]:
    """:func:`_draw_metrics` of every system (draw index = position) at once."""
    results = [_empty_metrics() for _ in systems]
    resonances = _resonances(systems)
    for result, value in zip(results, resonances):
        result["resonance_hz"] = float(value)
    sets = _Once(lambda: stack_parameter_sets(systems))
    if environment.profiles:
        settle = _Once(lambda: _screening_settle(systems[0])) if screening else None
        oversample = 1 if screening else 4
        transfer = _floor_transfer(systems, environment.profiles.values(), _FS * oversample)
        worst = np.full(len(systems), -np.inf)
        for profile in environment.profiles.values():
            rms, flagged = _random_rms(systems, sets, profile, seed=int(seed), oversample=oversample, settle=settle,
                                       transfer=transfer)
            worst = np.maximum(worst, np.where(flagged, np.inf, rms))
            for result, bad in zip(results, flagged):
                result["flagged"] += int(bad)
        for result, value in zip(results, worst):
            result["rms_acceleration_m_per_s2"] = float(value)
    if environment.drop_heights_m:
        grids = _screening_grids(_drop_grid(systems[0], True), resonances[0], resonances) if screening else \
            [_drop_grid(system, False) for system in systems]
        drops = _drop_metrics(sets(), environment.drop_heights_m, grids)
        for index, result in enumerate(results):
            result["flagged"] += int(drops["flagged"][index])
            for name in _DROP_METRICS:
                if name in drops:
                    result[name] = float(drops[name][index])
    return results


#: ``n_draws``: parameter draws per candidate, besides its mean model.
_DRAWS = Whole(ge=0, meaning="parameter draws per candidate")


@accepts(candidate=Instance((Candidate,)), environment=Instance((Environment,)), n_draws=_DRAWS, screening=Flag(),
         batched=Flag(), error=SimulationError)
def evaluate_candidate(candidate: Candidate, environment: Environment, *, n_draws: int = 30, seed: int = 0,
                       screening: bool = True, batched: bool = True) -> dict:
    """Metrics of the mean model and of ``n_draws`` parameter draws of one candidate.

    ``batched=False``: one draw at a time through the one-system functions (module docstring).

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
    if batched:
        results = _batched_metrics(systems, environment, screening=screening, seed=int(seed))
    else:
        # screening: every draw settles as long as, and drops on the grid of, the mean model
        settle = _screening_settle(systems[0]) if screening and environment.profiles else None
        grids = [None] * len(systems)
        if screening and environment.drop_heights_m:
            grids = _screening_grids(_drop_grid(systems[0], True), small_amplitude_resonance(systems[0]),
                                     [small_amplitude_resonance(system) for system in systems])
        results = [_draw_metrics(system, environment, screening=screening, seed=int(seed) + index, settle=settle,
                                 drop_grid=grid) for index, (system, grid) in enumerate(zip(systems, grids))]
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


def _chunk_bounds(count: int, workers: int) -> list[tuple[int, int]]:
    """Guided chunks of ``count`` items for ``workers``: each ``ceil(remaining / (2 workers))``
    items, so the chunk a worker takes last is short (one item at the end) and no worker waits
    long for another's last chunk."""
    bounds, start = [], 0
    while start < count:
        size = -(-(count - start) // (2 * workers))
        bounds.append((start, start + size))
        start += size
    return bounds


@accepts(environment=Instance((Environment,)), n_draws=_DRAWS, screening=Flag(), workers=Whole(ge=1),
         chunk_size=Whole(ge=1, optional=True), error=SimulationError)
def evaluate_candidates(candidates, environment: Environment, *, n_draws: int = 30, seed: int = 0,
                        screening: bool = True, workers: int = 1, executor=None, chunk_size: int | None = None,
                        ) -> list[dict]:
    """:func:`evaluate_candidate` over many candidates, serially, in processes or on an executor.

    ``executor``: any ``concurrent.futures``-style executor (``submit(fn, *args)``; a
    ``dask.distributed.Client`` included; ``workers``: how many it runs at once, for the chunks).
    Chunks of candidates are submitted as picklable dictionaries: ``chunk_size`` each, or by
    default shrinking as they go (each a ``2 workers``-th of the candidates not yet chunked, at
    least one: :func:`_chunk_bounds`), so that the last ones are short and every worker finishes
    at about the same time whatever the candidates cost (a hybrid whose floor runs in the
    frequency domain costs a fraction of a rope that slips); with an executor and ``workers=1``
    four equal chunks. The rows come back in the candidates' order and do not depend on how they
    were run.
    """
    candidates = list(candidates)
    if executor is None and workers == 1:
        return [unchecked(evaluate_candidate)(c, environment, n_draws=n_draws, seed=seed, screening=screening)
                for c in candidates]
    if chunk_size is not None or (executor is not None and workers == 1):
        size = max(1, chunk_size or -(-len(candidates) // 4))
        bounds = [(i, min(i + size, len(candidates))) for i in range(0, len(candidates), size)]
    else:
        bounds = _chunk_bounds(len(candidates), workers)
    chunks = [[c.to_dict() for c in candidates[start:stop]] for start, stop in bounds]
    env = environment.to_dict()
    if executor is not None:
        futures = [executor.submit(_evaluate_chunk, chunk, env, n_draws, seed, screening) for chunk in chunks]
        return [row for future in futures for row in future.result()]
    context = multiprocessing.get_context("forkserver")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(_evaluate_chunk, chunk, env, n_draws, seed, screening) for chunk in chunks]
        return [row for future in futures for row in future.result()]
