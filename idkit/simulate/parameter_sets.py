"""Many parameter sets of one system structure in one compiled call, reduced as they run.

:func:`simulate` runs a batch of one system (the runs share its parameters). A design search
(:mod:`idkit.design`) simulates the same system structure under many parameter sets (draws from
the parts' covariances) and needs only a few numbers of each run. :func:`simulate_parameter_sets`
runs every (parameter set, input) pair of such a search in one call of a driver compiled per
structure, which calls the very steps :func:`simulate` calls (:mod:`idkit.simulate._structured`
and the generic step), with each run's own parameters, step, length, base row and force scale.
A run here is the run :func:`simulate` makes of its system with the same grid, base and initial
velocity, bit for bit (``tests/simulate/test_parameter_sets.py``).

Each run is reduced as it runs, over every step from the start (records are optional):

* the top mass's peak absolute acceleration while the top mass is below / above its position at
  the start relative to the base (compression / tension; the phases of
  :func:`idkit.signal.drop.drop_phase_peaks`: the sum of the isolator deflections against its
  start value, samples where it equals the start value belong to neither);
* the largest travel (that sum) below / above its start, and each isolator's largest
  compression / extension from its start deflection (m);
* the energy each isolator dissipated (J): the work done on it, ``sum (y1 - y0) (F0 + F1) / 2``
  over the steps (the trapezoidal rule the integrator conserves: with the base at rest and no
  gravity the masses' kinetic energy falls by exactly the work done on the isolators), less the
  change of the energy it stores (:func:`stored_energy`).

Optional records: the top mass's absolute acceleration every ``record_every`` steps from step
``record_from`` (the analysed part of a random-vibration run).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.errors import SimulationError
from idkit.simulate._arrays import force_scale, system_arrays
from idkit.simulate._generic_step import _initial_acceleration, _isolator_forces_now
from idkit.simulate._kernel import FLAG_OK, drivers_per_structure, structure_step
from idkit.simulate._layout import _BW, _GAP, _NJ, _NM, _pack, _pack_states
from idkit.simulate._structured import structure_of

__all__ = ["ParameterSets", "SetRuns", "simulate_parameter_sets", "stack_parameter_sets", "stored_energy"]


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def stored_energy(j, y, P, S):
    """Energy (J) isolator ``j`` stores at deflection ``y`` with internal states ``S``.

    The polynomial spring's potential ``g1 y^2 / 2 + g2 y^3 / 3 + g3 y^4 / 4``; each Jenkin
    element's spring ``f^2 / (2 k)`` (behind a clearance the spring carries the force passed on,
    the virtual force less its dead zone ``k gap``); each Maxwell spring ``k u^2 / 2``; a Bouc-Wen
    part's springs ``k1 y^2 / 2 + k2 |y|^3 / 3 + k3 y^4 / 4`` and its hysteretic ``z^2 / (2 alpha)``
    (the energy ``z`` releases on unloading at its initial slope ``alpha``; the asymmetry factor
    ``b^(c y)`` is left out, exact for the symmetric model ``b = 1`` or ``c = 0``). Dashpots
    store nothing. ``P`` and ``S`` are the packed parameters and states of the kernel.
    """
    energy = y * y * (0.5 * P[j, 0, 0] + y * (P[j, 0, 1] / 3.0 + 0.25 * y * P[j, 0, 2]))
    gap = P[j, 0, _GAP]
    for i in range(int(P[j, 0, _NJ])):
        stiffness = P[j, 1, i]
        force = S[j, 0, i]
        if gap > 0.0:
            force = max(abs(force) - stiffness * gap, 0.0)
        energy += 0.5 * force * force / stiffness
    for i in range(int(P[j, 0, _NM])):
        energy += 0.5 * P[j, 3, i] * S[j, 1, i] * S[j, 1, i]
    if P[j, 0, _BW] != 0.0:
        magnitude = abs(y)
        energy += y * y * (0.5 * P[j, 0, _BW + 1] + magnitude * P[j, 0, _BW + 2] / 3.0 + 0.25 * y * y * P[j, 0, _BW + 3])
        alpha = P[j, 0, _BW + 4]
        if alpha > 0.0:
            energy += 0.5 * S[j, 2, 0] * S[j, 2, 0] / alpha
    return energy


@numba.njit(cache=True, inline="always")
def _deflections(ndof, state, xb, out):
    """Isolator deflections (m) of ``state`` above a base at ``xb``, as :func:`simulate` forms them
    from its records (the displacements relative to the base first)."""
    if ndof == 1:
        out[0] = state[0] - xb
    else:
        top = state[0] - xb
        middle = state[1] - xb
        out[0] = top - middle
        out[1] = middle


def _sets_kernel(structure):
    """The compiled :func:`run_sets_batch` of one structure."""

    def run_sets_batch(masses, poly, cvisc, jk, jfc, mk, mrate, bw, sm, set_index, h, n_steps, base_disp,
                       base_vel, base_row, gravity, v0, force_scale, record_from, record_every, n_records, reduce):
        """Runs of parameter sets (module docstring); arrays float64 unless said.

        Parameters
        ----------
        masses, poly, ... sm : (n_sets, ...) the parameter sets' kernel arrays, stacked.
        set_index, base_row, n_steps, record_from : (batch,) int64; h, force_scale : (batch,)
        base_disp, base_vel : (n_base, n_max + 1); v0 : (batch, ndof) initial absolute velocities.
        record_every, n_records : int.
        reduce : bool; False skips the reductions (``peaks`` stay NaN: records only).

        Returns
        -------
        records (batch, n_records); flags, flag_step (batch,); peaks (batch, 4 + 3 ndof):
        acceleration compression, tension (NaN where the phase never occurs), travel
        compression, tension, then per isolator compression, extension and dissipated energy.
        """
        batch = set_index.shape[0]
        ndof = masses.shape[1]
        records = np.full((batch, n_records), np.nan)
        flags = np.zeros(batch, dtype=np.int64)
        flag_step = np.full(batch, -1, dtype=np.int64)
        peaks = np.full((batch, 4 + 3 * ndof), np.nan)
        frc = np.zeros(2)
        old_force = np.zeros(2)
        y = np.zeros(2)
        y_old = np.zeros(2)
        y_start = np.zeros(2)
        work = np.zeros(2)
        low = np.zeros(2)
        high = np.zeros(2)
        for b in range(batch):
            s = set_index[b]
            row = base_row[b]
            step = h[b]
            m0 = masses[s, 0]
            m1 = masses[s, 1] if ndof == 2 else 1.0
            scale = force_scale[b]
            P = _pack(poly[s], cvisc[s], jk[s], jfc[s], mk[s], mrate[s], bw[s], sm[s], step)
            state = np.zeros(6)
            for d in range(ndof):
                state[d] = base_disp[row, 0]
                state[2 + d] = v0[b, d]
            S = _pack_states(P, np.zeros((ndof, jk.shape[2])), np.zeros((ndof, mk.shape[2])), np.zeros(ndof))
            _initial_acceleration(ndof, masses[s], state, gravity, base_disp[row, 0], base_vel[row, 0], P, S)
            _isolator_forces_now(ndof, state, base_disp[row, 0], base_vel[row, 0], P, S, frc)
            _deflections(ndof, state, base_disp[row, 0], y)
            total_start = y[0] + y[1] if ndof == 2 else y[0]
            for d in range(ndof):
                y_start[d] = y[d]
                y_old[d] = y[d]
                old_force[d] = frc[d]
                work[d] = -stored_energy(d, y[d], P, S)
                low[d] = 0.0
                high[d] = 0.0
            compression = -math.inf
            tension = -math.inf
            travel_low = 0.0
            travel_high = 0.0
            r = 0
            until_record = record_from[b]  # a countdown to the next recorded step
            if until_record == 0 and n_records > 0:
                records[b, 0] = state[4]
                r = 1
                until_record = record_every
            for n in range(1, n_steps[b] + 1):
                xb_old = base_disp[row, n - 1]
                xb_new = base_disp[row, n]
                vb_new = base_vel[row, n]
                flag = structure_step(structure, ndof, m0, m1, state, step, gravity, xb_old, xb_new, vb_new, P, S, scale)
                if flag != FLAG_OK:
                    flags[b] = flag
                    flag_step[b] = n
                    break
                until_record -= 1
                if until_record == 0 and r < n_records:
                    records[b, r] = state[4]
                    r += 1
                    until_record = record_every
                if not reduce:
                    continue
                _isolator_forces_now(ndof, state, xb_new, vb_new, P, S, frc)
                _deflections(ndof, state, xb_new, y)
                for d in range(ndof):
                    work[d] += 0.5 * (old_force[d] + frc[d]) * (y[d] - y_old[d])
                    old_force[d] = frc[d]
                    y_old[d] = y[d]
                    relative = y[d] - y_start[d]
                    low[d] = min(low[d], relative)
                    high[d] = max(high[d], relative)
                relative = (y[0] + y[1] if ndof == 2 else y[0]) - total_start
                magnitude = abs(state[4])
                if relative < 0.0:
                    compression = max(compression, magnitude)
                    travel_low = min(travel_low, relative)
                elif relative > 0.0:
                    tension = max(tension, magnitude)
                    travel_high = max(travel_high, relative)
            if flags[b] == FLAG_OK and reduce:
                peaks[b, 0] = compression if compression > -math.inf else math.nan
                peaks[b, 1] = tension if tension > -math.inf else math.nan
                peaks[b, 2] = -travel_low
                peaks[b, 3] = travel_high
                for d in range(ndof):
                    peaks[b, 4 + 3 * d] = -low[d]
                    peaks[b, 5 + 3 * d] = high[d]
                    peaks[b, 6 + 3 * d] = work[d] - stored_energy(d, y[d], P, S)
        return records, flags, flag_step, peaks

    return run_sets_batch


#: :func:`_sets_kernel` compiled for a structure, one per structure and process
#: (:func:`idkit.simulate._kernel.drivers_per_structure`).
_sets_kernel_for = drivers_per_structure(_sets_kernel)


@dataclass(frozen=True)
class ParameterSets:
    """Parameter sets of one system structure, stacked for :func:`simulate_parameter_sets`.

    Attributes
    ----------
    stacked : tuple of ndarray
        The kernel arrays (:class:`~idkit.simulate._arrays.SystemArrays` fields), each with a
        leading axis over the sets.
    each : tuple of SystemArrays
        Each set's own arrays (their force scales).
    structure : int
        The kernel structure they share.
    """

    stacked: tuple
    each: tuple
    structure: int

    def __len__(self) -> int:
        return len(self.each)

    @property
    def ndof(self) -> int:
        return self.each[0].ndof


def stack_parameter_sets(systems) -> ParameterSets:
    """Stack the kernel arrays of ``systems`` (SDOF or hybrid systems of one structure: the same
    number of masses, the same parts in each isolator, the same element counts)."""
    each = tuple(system_arrays(system) for system in systems)
    if not each:
        raise SimulationError("systems: found none, expected at least one system")
    shapes = [tuple(np.shape(field) for field in arrays.as_tuple()) for arrays in each]
    structures = {structure_of(arrays) for arrays in each}
    if len(set(shapes)) > 1 or len(structures) > 1:
        index = next(i for i, shape in enumerate(shapes) if shape != shapes[0] or structure_of(each[i]) != structure_of(each[0]))
        raise SimulationError(f"systems: system {index} differs in structure from system 0 (masses, parts or element "
                              "counts); expected parameter sets of one structure (group them)")
    stacked = tuple(np.ascontiguousarray(np.stack(field)) for field in zip(*(arrays.as_tuple() for arrays in each)))
    return ParameterSets(stacked, each, structures.pop())


@dataclass(frozen=True)
class SetRuns:
    """What :func:`simulate_parameter_sets` keeps of each run (module docstring); SI units.

    Attributes
    ----------
    records : (batch, n_records) top-mass absolute acceleration records, m/s^2 (NaN after a flag)
    flags, flag_step : (batch,) 0 / -1 for a run that finished, else the kernel's flag and step
    acceleration_compression, acceleration_tension : (batch,) m/s^2, NaN for a phase that never
        occurs or a flagged run
    travel_compression, travel_tension : (batch,) m, >= 0
    isolator_compression, isolator_extension : (batch, n_isolators) m, >= 0, top isolator first
    dissipated_energy : (batch, n_isolators) J
    """

    records: np.ndarray
    flags: np.ndarray
    flag_step: np.ndarray
    acceleration_compression: np.ndarray
    acceleration_tension: np.ndarray
    travel_compression: np.ndarray
    travel_tension: np.ndarray
    isolator_compression: np.ndarray
    isolator_extension: np.ndarray
    dissipated_energy: np.ndarray

    @property
    def rest_shock_level(self) -> np.ndarray:
        """The larger of the two phase peaks, m/s^2 (as :class:`idkit.responses.ShockSweep`)."""
        with np.errstate(invalid="ignore"):
            return np.fmax(self.acceleration_compression, self.acceleration_tension)


def _integers(values, name: str, size: int, minimum: int) -> np.ndarray:
    array = np.broadcast_to(np.asarray(values), (size,))
    if not (np.issubdtype(array.dtype, np.integer) and (array >= minimum).all()):
        raise SimulationError(f"{name}: found {np.asarray(values)!r:.80}, expected whole numbers >= {minimum} "
                              f"(one, or one per run: {size})")
    return np.require(array, dtype=np.int64, requirements=["C", "W"])  # writeable (simulate_parameter_sets)


def simulate_parameter_sets(sets: ParameterSets, set_index, *, time_step, n_steps, base_displacement=None,
                            base_velocity=None, base_row=0, initial_velocity=None, acceleration_scale=0.0,
                            record_from=0, record_every: int = 1, n_records: int = 0, reduce: bool = True) -> SetRuns:
    """Run parameter sets in one compiled call (module docstring).

    Parameters
    ----------
    sets : ParameterSets
        From :func:`stack_parameter_sets`.
    set_index : array_like of int, shape (batch,)
        The parameter set of each run.
    time_step : float or array (batch,)
        Each run's step, s.
    n_steps : int or array (batch,)
        Each run's number of steps.
    base_displacement, base_velocity : array (n_base, >= max(n_steps) + 1), optional
        Absolute base motion at every step (m, m/s; e.g. :func:`~idkit.simulate.base_motion.
        integrate_acceleration` of a floor record); default at rest.
    base_row : int or array (batch,)
        The base row of each run.
    initial_velocity : array (batch, ndof) or (ndof,), optional
        Absolute initial velocities of the masses, m/s (a drop: ``v0 < 0`` for every mass);
        the isolators start unloaded, the masses where the base is.
    acceleration_scale : float or array (batch,)
        Each run's base acceleration scale, m/s^2, for its force scale
        (:func:`~idkit.simulate._arrays.force_scale`; :func:`simulate` takes the largest velocity
        change of its base over a step divided by the step).
    record_from, record_every, n_records :
        Record the top-mass acceleration at step ``record_from`` (per run) and every
        ``record_every`` steps after it, ``n_records`` records.
    reduce : bool, default True
        False: records only, the reductions skipped (the peaks, travels and energies of
        :class:`SetRuns` are NaN); the records are the same bit for bit.
    """
    set_index = _integers(set_index, "set_index", np.size(set_index), 0)
    batch = set_index.size
    if batch == 0 or set_index.max() >= len(sets):
        raise SimulationError(f"set_index: found {set_index!r:.80}, expected at least one index below {len(sets)}")
    n_steps = _integers(n_steps, "n_steps", batch, 1)
    # every array the kernel gets is C-contiguous and writeable: a read-only one (np.broadcast_to gives
    # one, kept as is when it needs no copy) is another numba type, so another compile of the driver
    h = np.require(np.broadcast_to(np.asarray(time_step, dtype=float), (batch,)), requirements=["C", "W"])
    if not (np.isfinite(h) & (h > 0)).all():
        raise SimulationError(f"time_step: found {time_step!r:.80}, expected steps > 0 s")
    ndof = sets.ndof
    if base_displacement is None:
        if base_velocity is not None:
            raise SimulationError("base_velocity: found it without base_displacement, expected both or neither")
        base_displacement = base_velocity = np.zeros((1, int(n_steps.max()) + 1))
    base_disp = np.ascontiguousarray(np.atleast_2d(np.asarray(base_displacement, dtype=float)))
    base_vel = np.ascontiguousarray(np.atleast_2d(np.asarray(base_velocity, dtype=float)))
    base_row = _integers(base_row, "base_row", batch, 0)
    if base_disp.shape != base_vel.shape or base_disp.shape[1] < n_steps.max() + 1 or base_row.max() >= len(base_disp):
        raise SimulationError(f"base_displacement, base_velocity: found shapes {base_disp.shape}, {base_vel.shape}, "
                              f"expected equal, at least {int(n_steps.max()) + 1} samples and {int(base_row.max()) + 1} "
                              "rows")
    v0 = np.zeros((batch, ndof)) if initial_velocity is None else np.asarray(initial_velocity, dtype=float)
    v0 = np.require(np.broadcast_to(v0, (batch, ndof)), requirements=["C", "W"])
    scale_of_run = np.broadcast_to(np.asarray(acceleration_scale, dtype=float), (batch,))
    scale = np.empty(batch)
    for s in np.unique(set_index):  # each run's own force scale, the runs of a set in one call
        runs = set_index == s
        scale[runs] = force_scale(sets.each[s], np.ascontiguousarray(scale_of_run[runs]))
    record_from = _integers(record_from, "record_from", batch, 0)
    record_every = int(_integers(record_every, "record_every", 1, 1)[0])
    n_records = int(_integers(n_records, "n_records", 1, 0)[0])
    kernel = _sets_kernel_for(sets.structure)
    records, flags, flag_step, peaks = kernel(*sets.stacked, set_index, h, n_steps, base_disp, base_vel, base_row,
                                              0.0, v0, scale, record_from, record_every, n_records, bool(reduce))
    return SetRuns(records=records, flags=flags, flag_step=flag_step, acceleration_compression=peaks[:, 0],
                   acceleration_tension=peaks[:, 1], travel_compression=peaks[:, 2], travel_tension=peaks[:, 3],
                   isolator_compression=peaks[:, 4::3], isolator_extension=peaks[:, 5::3],
                   dissipated_energy=peaks[:, 6::3])
