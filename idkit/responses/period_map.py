"""The period map of a system under harmonic base displacement, its Jacobian and Floquet multipliers.

``Phi`` takes the packed state at ``t = 0`` (:class:`PeriodMap`: mass displacements and
velocities, then Jenkin forces, Maxwell elongations and Bouc-Wen ``z``) over ``p`` excitation
periods of ``x_b = A sin(2 pi f t)`` with idkit's compiled step; the shooting of
:mod:`idkit.responses.periodic` looks for its fixed points. Its Jacobian (the monodromy matrix)
is propagated through the step or taken by central differences of :data:`FD_STEP` (method and
error in :mod:`idkit.responses.periodic`).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.checks import Choice, Whole, accepts
from idkit.errors import SimulationError
from idkit.responses._sensitivity import keep_step_start, tangent_coefficients, tangent_finish, tangent_start, tangent_step
from idkit.simulate._arrays import force_scale, resolve_system, system_arrays
from idkit.simulate._parallel import run_chunked
from idkit.simulate._kernel import (
    FLAG_OK,
    _store_end_state,
    base_motion_table,
    drivers_per_structure,
    harmonic_member,
    start_member,
    structure_step,
)
from idkit.simulate._structured import structure_of
from idkit.simulate.harmonic import linear_initial_state

__all__ = ["FD_STEP", "PeriodMap", "monodromy", "period_kernel", "period_map"]

#: Relative finite-difference step of the period-map Jacobian (times each state's scale).
FD_STEP = 1e-6


def _period_kernel(structure):
    """The compiled :func:`_run_periods` of one structure: the specialised step of
    :mod:`idkit.simulate._structured` where the structure has one (the numbers of the generic
    step, in fewer operations), as the map's kernel steps."""

    def _run_periods(masses, poly, cvisc, jk, jfc, mk, mrate, bw, sm, freq, amplitude, steps_per_period,
                     n_periods, scale, q0, v0, jforce0, mstate0, bwz0, n_record, with_tangent, columns):
        """Integrate each member over ``n_periods`` excitation periods from its state at t = 0.

        Same base motion and step as :func:`idkit.simulate._kernel.run_harmonic_batch`. Returns the
        end states ``(q, v, jforce, mstate, bwz)``, ``flags``, over the first ``n_record`` steps the
        absolute mass displacements (m) and top acceleration (m/s^2) at each step start, and, if
        ``with_tangent``, the derivative of the end state with respect to the start
        (:mod:`idkit.responses._sensitivity`; no Bouc-Wen; one column per entry of ``columns``, the
        initial values of real elements; not meaningful for a flagged member), else an empty array.
        """
        batch = freq.shape[0]
        ndof = masses.shape[0]
        nj = jk.shape[1]
        nm = mk.shape[1]
        m0 = masses[0]
        m1 = masses[1] if ndof == 2 else 1.0
        q_end = np.full((batch, ndof), np.nan)
        v_end = np.full((batch, ndof), np.nan)
        j_end = np.full(jforce0.shape, np.nan)
        m_end = np.full(mstate0.shape, np.nan)
        z_end = np.full((batch, ndof), np.nan)
        rec_q = np.full((batch, ndof, n_record), np.nan)
        rec_a = np.full((batch, n_record), np.nan)
        flags = np.zeros(batch, dtype=np.int64)
        n_rows = 3 * ndof + ndof * (nj + nm) if with_tangent else 0
        n_cols = columns.shape[0] if with_tangent else 0
        tangents = np.zeros((batch, n_rows, n_cols))
        # two members of one frequency and steps per period run in step, their tangent columns side
        # by side in ``pair``: one pass over a tangent row serves both (idkit.responses._sensitivity)
        pair = np.zeros((n_rows, 2 * n_cols))
        old_q = np.zeros((2, 2))
        old_force = np.zeros((2, ndof, max(nj, 1)))
        work = np.zeros((2, 8))
        lanes = np.zeros((6, max(2 * n_cols, 1)))
        stuck = np.zeros((2, 2, max(nj, 1)))
        table_n = -1  # the base motion's table, rebuilt only when the steps per period change
        base_sin = np.empty(0)
        base_cos = np.empty(0)
        # a typed zero, not the literal 0: numba would also compile the members' helpers for the literal
        b = np.int64(0)
        while b < batch:
            paired = (with_tangent and b + 1 < batch and freq[b + 1] == freq[b]
                      and steps_per_period[b + 1] == steps_per_period[b])
            second = b + 1 if paired else b
            omega, n_per, h, amp_a, P = harmonic_member(b, freq, steps_per_period, amplitude, poly, cvisc, jk, jfc, mk,
                                                        mrate, bw, sm)
            state_a, S_a = start_member(ndof, masses, q0[b], v0[b], jforce0[b], mstate0[b], bwz0[b], 0.0, 0.0,
                                        amp_a * omega, P)
            # the second member's step and parameters are the first's (same frequency and steps)
            amp_b = amplitude[second]
            state_b, S_b = start_member(ndof, masses, q0[second], v0[second], jforce0[second], mstate0[second],
                                        bwz0[second], 0.0, 0.0, amp_b * omega, P)
            # the members' tangent block, bound once: a view made inside the step loop costs numba a
            # reference-count increment and decrement (atomic) per step
            tangent = pair if paired else tangents[b]
            split = n_cols
            if with_tangent:
                tangent_start(ndof, masses, P, state_a, tangents[b], nj, nm, columns)
                if paired:
                    tangent_start(ndof, masses, P, state_b, tangents[second], nj, nm, columns)
                    pair[:, :n_cols] = tangents[b]
                    pair[:, n_cols:] = tangents[second]
            flag_a = FLAG_OK
            flag_b = FLAG_OK if paired else -1  # -1: no second member
            if n_per != table_n:
                base_sin, base_cos = base_motion_table(n_per)  # as the map's kernel reads it
                table_n = n_per
            at = 0  # n % n_per
            for n in range(n_per * n_periods):
                if n < n_record:
                    for d in range(ndof):
                        rec_q[b, d, n] = state_a[d]
                    rec_a[b, n] = state_a[4]
                    if paired:
                        for d in range(ndof):
                            rec_q[second, d, n] = state_b[d]
                        rec_a[second, n] = state_b[4]
                base = base_sin[at]
                at = at + 1 if at + 1 < n_per else 0
                base_new = base_sin[at]
                cosine = base_cos[at]
                if flag_a == FLAG_OK:
                    if with_tangent:
                        keep_step_start(ndof, nj, state_a, S_a, old_q, old_force, 0)
                    flag_a = structure_step(structure, ndof, m0, m1, state_a, h, 0.0, amp_a * base, amp_a * base_new,
                                            amp_a * omega * cosine, P, S_a, scale[b])
                    if with_tangent and flag_a == FLAG_OK:
                        tangent_coefficients(ndof, masses, P, state_a, old_q, old_force, amp_a * base,
                                             amp_a * base_new, h, work, stuck, 0)
                if flag_b == FLAG_OK:
                    keep_step_start(ndof, nj, state_b, S_b, old_q, old_force, 1)
                    flag_b = structure_step(structure, ndof, m0, m1, state_b, h, 0.0, amp_b * base, amp_b * base_new,
                                            amp_b * omega * cosine, P, S_b, scale[second])
                    if flag_b == FLAG_OK:
                        tangent_coefficients(ndof, masses, P, state_b, old_q, old_force, amp_b * base,
                                             amp_b * base_new, h, work, stuck, 1)
                if flag_a != FLAG_OK and flag_b != FLAG_OK:
                    break
                if with_tangent:  # a flagged member's columns go on meaninglessly: its tangent is not used
                    tangent_step(ndof, masses, P, h, tangent, nj, nm, split, work, stuck, lanes, n > 0)
            if with_tangent and (flag_a == FLAG_OK or flag_b == FLAG_OK) and n_per * n_periods > 0:
                tangent_finish(ndof, P, tangent, nj, nm, lanes)
            if paired:
                tangents[b] = pair[:, :n_cols]
                tangents[second] = pair[:, n_cols:]
            flags[b] = flag_a
            if flag_a == FLAG_OK:
                _store_end_state(b, ndof, state_a, S_a, q_end, v_end, j_end, m_end, z_end)
            if paired:
                flags[second] = flag_b
                if flag_b == FLAG_OK:
                    _store_end_state(second, ndof, state_b, S_b, q_end, v_end, j_end, m_end, z_end)
            b += 2 if paired else 1
        return q_end, v_end, j_end, m_end, z_end, flags, rec_q, rec_a, tangents

    return _run_periods


#: :func:`_period_kernel` compiled for a structure, one per structure and process
#: (:func:`idkit.simulate._kernel.drivers_per_structure`).
period_kernel = drivers_per_structure(_period_kernel)


class PeriodMap:
    """The period map of a system under harmonic base displacement, on packed state vectors.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    periods : int
        Excitation periods per map application (1, or 2 for the 1/2 subharmonic).

    Attributes
    ----------
    state_names : tuple of str
        Name and unit of every state component (``"x1 [m]"`` top mass first, ``"v1 [m/s]"``,
        ``"F_J1.2 [N]"`` Jenkin element 2 of isolator 1, ``"u_M1.3 [m]"``, ``"z1 [N]"``);
        isolator 1 is the one below the top mass.
    """

    @accepts(periods=Whole(ge=1, le=2, meaning="2 for the 1/2 subharmonic"),
             jacobian=Choice(("auto", "exact", "finite differences")), error=SimulationError)
    def __init__(self, system, periods: int = 1, *, jacobian: str = "auto"):
        self.system = resolve_system(system)
        self.arrays = system_arrays(self.system)
        self.periods = periods
        arrays = self.arrays
        ndof = arrays.ndof
        self.ndof = ndof
        self.jenkin = np.argwhere(arrays.jk > 0)
        self.maxwell = np.argwhere(arrays.mk > 0)
        self.boucwen = np.flatnonzero(arrays.bw[:, 0] != 0)
        names = [f"x{d + 1} [m]" for d in range(ndof)] + [f"v{d + 1} [m/s]" for d in range(ndof)]
        names += [f"F_J{j + 1}.{i + 1} [N]" for j, i in self.jenkin]
        names += [f"u_M{j + 1}.{i + 1} [m]" for j, i in self.maxwell]
        names += [f"z{j + 1} [N]" for j in self.boucwen]
        self.state_names = tuple(names)
        self.size = len(names)
        self._kernel_arrays = arrays.as_tuple()
        self._kernel = period_kernel(structure_of(arrays))
        if jacobian == "exact" and self.boucwen.size:
            raise SimulationError("jacobian: found 'exact' for a system with Bouc-Wen elements, expected "
                                  "'finite differences' (z is not differentiated through its sub-steps)")
        # slip limits that follow the deflection or its rate, or elements behind a clearance
        modulated = bool(np.any(arrays.slip_limits_vary))
        if jacobian == "exact" and modulated:
            raise SimulationError("jacobian: found 'exact' for a system with modulated, rate-dependent or clearance "
                                  "slip elements, expected 'finite differences' (the exact sensitivities assume the "
                                  "plain stop operator)")
        self.jacobian_method = ("finite differences" if jacobian == "finite differences" or self.boucwen.size
                                or modulated else "exact")
        nj, nm = arrays.jk.shape[1], arrays.mk.shape[1]
        jenkin_flat = [j * nj + i for j, i in self.jenkin]
        maxwell_flat = [j * nm + i for j, i in self.maxwell]
        # rows of the compiled tangent in packed order, and the initial values its columns follow
        # (see idkit.responses._sensitivity)
        self._tangent_rows = np.array(list(range(2 * ndof)) + [3 * ndof + k for k in jenkin_flat]
                                      + [3 * ndof + ndof * nj + k for k in maxwell_flat], dtype=int)
        self._tangent_columns = np.array(list(range(2 * ndof)) + [2 * ndof + k for k in jenkin_flat]
                                         + [2 * ndof + ndof * nj + k for k in maxwell_flat], dtype=int)

    # -- packing -----------------------------------------------------------------------------
    def pack(self, q, v, jforce, mstate, bwz) -> NDArray[np.float64]:
        """State vectors (batch, size) from kernel-shaped arrays (batch, ndof[, n])."""
        parts = [q, v, jforce[:, self.jenkin[:, 0], self.jenkin[:, 1]],
                 mstate[:, self.maxwell[:, 0], self.maxwell[:, 1]], bwz[:, self.boucwen]]
        return np.concatenate([np.asarray(p, dtype=float).reshape(q.shape[0], -1) for p in parts], axis=1)

    def unpack(self, states):
        """Kernel-shaped ``q, v, jforce, mstate, bwz`` from state vectors (batch, size)."""
        states = np.atleast_2d(states)
        batch, ndof = states.shape[0], self.ndof
        q = np.ascontiguousarray(states[:, :ndof])
        v = np.ascontiguousarray(states[:, ndof:2 * ndof])
        position = 2 * ndof
        jforce = np.zeros((batch,) + self.arrays.jk.shape)
        jforce[:, self.jenkin[:, 0], self.jenkin[:, 1]] = states[:, position:position + len(self.jenkin)]
        position += len(self.jenkin)
        mstate = np.zeros((batch,) + self.arrays.mk.shape)
        mstate[:, self.maxwell[:, 0], self.maxwell[:, 1]] = states[:, position:position + len(self.maxwell)]
        position += len(self.maxwell)
        bwz = np.zeros((batch, ndof))
        bwz[:, self.boucwen] = states[:, position:]
        return q, v, jforce, mstate, bwz

    def push(self, state, mechanical):
        """``state`` with displacements and velocities moved by ``mechanical`` (2 ndof values), the
        Jenkin forces following as in stick (``k dy``, clipped to ``+-Fc``), other internal states
        kept: the friction memory ``F - k y`` of a sticking element is unchanged."""
        pushed = np.array(state, dtype=float)
        ndof = self.ndof
        pushed[:2 * ndof] += mechanical
        dq = np.asarray(mechanical[:ndof], dtype=float)
        deflection_change = np.array([dq[0] - dq[1], dq[1]]) if ndof == 2 else dq
        for column, (j, i) in enumerate(self.jenkin):
            position = 2 * ndof + column
            limit = self.arrays.jfc[j, i]
            pushed[position] = np.clip(pushed[position] + self.arrays.jk[j, i] * deflection_change[j], -limit, limit)
        return pushed

    def conserved_gradients(self, scale):
        """``(gradients (n, n_jenkin, size), rows (n_jenkin,))``: in the variables scaled by ``scale``
        (n, size), the gradients of the quantities a Jenkin element conserves while it sticks,
        ``F - k y`` (``y`` its isolator's deflection; the base is at zero at t = 0), over the element's
        force scale (the friction memory, whose multiplier is exactly +1 when the element sticks for
        the whole period), and the state row of each element's force (a unit entry of its gradient)."""
        scale = np.atleast_2d(scale)
        gradients = np.zeros((scale.shape[0], len(self.jenkin), self.size))
        for column, (j, i) in enumerate(self.jenkin):
            position = 2 * self.ndof + column
            weight = self.arrays.jk[j, i] / scale[:, position]
            gradients[:, column, position] = 1.0
            if self.ndof == 2 and j == 0:  # the top isolator: y = x1 - x2
                gradients[:, column, 0] = -weight * scale[:, 0]
                gradients[:, column, 1] = weight * scale[:, 1]
            else:
                gradients[:, column, j] = -weight * scale[:, j]
        return gradients, 2 * self.ndof + np.arange(len(self.jenkin))

    def linear_guess(self, freq, amplitude) -> NDArray[np.float64]:
        """Small-amplitude (all stuck, linearized) steady state at t = 0, packed (batch, size)."""
        return self.pack(*linear_initial_state(self.system, np.atleast_1d(freq), np.atleast_1d(amplitude)))

    def scales(self, freq, amplitude, length) -> NDArray[np.float64]:
        """Scale of every state component for a response of displacement scale ``length`` (m)."""
        freq, amplitude, length = (np.atleast_1d(np.asarray(value, dtype=float)) for value in (freq, amplitude, length))
        length = np.maximum(length, amplitude)
        omega = 2.0 * np.pi * freq
        columns = [length] * self.ndof + [omega * length] * self.ndof
        arrays = self.arrays
        columns += [np.minimum(arrays.jfc[j, i], arrays.jk[j, i] * length) for j, i in self.jenkin]
        columns += [length] * len(self.maxwell)
        columns += [max(arrays.bw[j, 4], 1.0) * length for j in self.boucwen]
        return np.column_stack(np.broadcast_arrays(*columns))

    # -- evaluation ----------------------------------------------------------------------------
    def run(self, freq, amplitude, states, steps_per_period, *, n_periods=None, n_record=0, with_tangent=False):
        """Integrate packed states; returns ``(end_states, flags, record_q, record_a)``, or
        ``(end_states, flags, tangents)`` with ``with_tangent`` (compiled-tangent layout)."""
        states = np.atleast_2d(np.asarray(states, dtype=float))
        batch = states.shape[0]
        freq, amplitude, steps = (np.ascontiguousarray(np.broadcast_to(value, (batch,)))
                                  for value in (np.asarray(freq, dtype=float), np.asarray(amplitude, dtype=float),
                                                np.asarray(steps_per_period, dtype=np.int64)))
        scale = np.atleast_1d(force_scale(self.arrays, amplitude * (2 * np.pi * freq) ** 2))
        n_periods = self.periods if n_periods is None else int(n_periods)
        q, v, jforce, mstate, bwz = (np.ascontiguousarray(value) for value in self.unpack(states))
        q_end, v_end, j_end, m_end, z_end, flags, rec_q, rec_a, tangents = self._kernel(
            *self._kernel_arrays, freq.astype(float), amplitude.astype(float), steps.astype(np.int64),
            n_periods, scale, q, v, jforce, mstate, bwz, int(n_record), bool(with_tangent), self._tangent_columns)
        end = self.pack(q_end, v_end, j_end, m_end, z_end)
        if with_tangent:
            return end, flags, tangents
        return end, flags, rec_q, rec_a

    def jacobian(self, freq, amplitude, state, scale, steps_per_period, *, parameter=None):
        """Map value and central-difference Jacobian, in scaled variables.

        Returns ``(phi, jacobian, parameter_derivative, flag)``: ``phi = Phi(x)`` (unscaled),
        ``jacobian[i, k] = d(Phi_i / s_i) / d(x_k / s_k)``, and, when ``parameter`` is
        ``"freq"`` or ``"amplitude"``, ``d(Phi_i / s_i) / d ln(parameter)`` (else None).
        """
        if self.jacobian_method == "exact":
            return self._exact_jacobian(freq, amplitude, state, scale, steps_per_period, parameter)
        n = self.size
        perturbation = FD_STEP * scale
        members = [state]
        for k in range(n):
            for sign in (1.0, -1.0):
                shifted = state.copy()
                shifted[k] += sign * perturbation[k]
                members.append(shifted)
        freqs = [freq] * (2 * n + 1)
        amplitudes = [amplitude] * (2 * n + 1)
        if parameter is not None:
            for sign in (1.0, -1.0):
                members.append(state)
                factor = math.exp(sign * FD_STEP)
                freqs.append(freq * factor if parameter == "freq" else freq)
                amplitudes.append(amplitude * factor if parameter == "amplitude" else amplitude)
        end, flags, _, _ = self.run(np.array(freqs), np.array(amplitudes), np.array(members), steps_per_period)
        flag = int(flags.max(initial=0)) if np.any(flags) else FLAG_OK
        phi = end[0]
        plus = end[1:2 * n + 1:2]
        minus = end[2:2 * n + 2:2]
        jacobian = ((plus - minus) / (2.0 * FD_STEP)).T / scale[:, None]
        derivative = None
        if parameter is not None:
            derivative = (end[-2] - end[-1]) / (2.0 * FD_STEP) / scale
        return phi, jacobian, derivative, flag


    def _exact_jacobian(self, freq, amplitude, state, scale, steps_per_period, parameter):
        """As :meth:`jacobian`, the state derivatives propagated through the step
        (:mod:`idkit.responses._sensitivity`); the parameter derivative by
        central differences of ``ln(parameter)`` (step :data:`FD_STEP`)."""
        end, flags, tangents = self.run(freq, amplitude, state[None], steps_per_period, with_tangent=True)
        phi, flag = end[0], int(flags[0])
        jacobian = tangents[0][self._tangent_rows] * scale[None, :] / scale[:, None]
        derivative = None
        if parameter is not None and flag == FLAG_OK:
            factors = np.exp([FD_STEP, -FD_STEP])
            freqs = freq * factors if parameter == "freq" else np.full(2, freq)
            amplitudes = amplitude * factors if parameter == "amplitude" else np.full(2, amplitude)
            end, flags, _, _ = self.run(freqs, amplitudes, np.array([state, state]), steps_per_period)
            flag = int(flags.max())
            derivative = (end[0] - end[1]) / (2.0 * FD_STEP) / scale
        return phi, jacobian, derivative, int(flag)


def monodromy(period_map: PeriodMap, freq, amplitude, states, steps_per_period, *, workers=None, with_ends=False):
    """Closing error and Floquet multipliers of many approximate orbits at once.

    ``states`` (n, size): packed states at t = 0 (a settled time run's end states). Over
    ``period_map.periods`` periods, returns ``(closing, multipliers, jacobians, flags)``:
    ``closing`` (n,) ``max |Phi(x) - x| / scale``, ``multipliers`` (n, size) complex, by
    decreasing modulus, ``jacobians`` (n, size, size) the monodromy matrices in scaled
    variables (as :meth:`PeriodMap.jacobian`), ``flags`` (n,), and with ``with_ends`` the states
    ``Phi(x)`` after the periods (n, size). The monodromy matrix is propagated through the steps (or
    central differences, :meth:`PeriodMap.jacobian`), one compiled batch over every point
    (chunks on ``workers`` threads); multipliers do not depend on the variables' scaling.
    """
    states = np.atleast_2d(np.asarray(states, dtype=float))
    n, size = states.shape
    freq, amplitude, steps = (np.ascontiguousarray(np.broadcast_to(value, (n,))) for value in (
        np.asarray(freq, dtype=float), np.asarray(amplitude, dtype=float), np.asarray(steps_per_period, np.int64)))
    length = np.maximum(amplitude, np.max(np.abs(states[:, :period_map.ndof]), axis=1))
    scale = period_map.scales(freq, amplitude, length)
    if period_map.jacobian_method == "exact":
        def task(part):
            end, flags, tangents = period_map.run(freq[part], amplitude[part], states[part], steps[part],
                                                  with_tangent=True)
            return end, flags, tangents
        end, flags, tangents = run_chunked(task, n, workers=workers)
        jacobian = tangents[:, period_map._tangent_rows]  # a copy, scaled in place
        jacobian *= scale[:, None, :]
        jacobian /= scale[:, :, None]
    else:
        members = np.repeat(states[:, None, :], 2 * size + 1, axis=1)
        offsets = FD_STEP * scale
        for k in range(size):
            members[:, 1 + 2 * k, k] += offsets[:, k]
            members[:, 2 + 2 * k, k] -= offsets[:, k]
        repeat = (lambda values: np.repeat(values, 2 * size + 1))

        def task(part):
            out, out_flags, _, _ = period_map.run(repeat(freq)[part], repeat(amplitude)[part],
                                                  members.reshape(-1, size)[part], repeat(steps)[part])
            return out, out_flags
        out, out_flags = run_chunked(task, n * (2 * size + 1), workers=workers)
        out = out.reshape(n, 2 * size + 1, size)
        end = out[:, 0]
        flags = out_flags.reshape(n, -1).max(axis=1)
        jacobian = np.transpose((out[:, 1::2] - out[:, 2::2]) / (2.0 * FD_STEP), (0, 2, 1)) / scale[:, :, None]
    closing = np.max(np.abs(end - states) / scale, axis=1)
    good = (np.asarray(flags) == FLAG_OK) & np.isfinite(jacobian).all(axis=(1, 2))

    def eigen(part):  # on the workers too (LAPACK releases the GIL): as costly as the tangent runs
        values = np.full((part.stop - part.start, size), np.nan, dtype=complex)
        valid = good[part]
        if valid.any():
            found = np.linalg.eigvals(jacobian[part][valid])
            values[valid] = np.take_along_axis(found, np.argsort(-np.abs(found), axis=1, kind="stable"), axis=1)
        return (values,)
    (multipliers,) = run_chunked(eigen, n, workers=workers)
    closing[~good] = np.nan
    if with_ends:
        return closing, multipliers, jacobian, np.asarray(flags), end
    return closing, multipliers, jacobian, np.asarray(flags)


def period_map(system, periods: int = 1) -> PeriodMap:
    """The :class:`PeriodMap` of ``system`` over ``periods`` excitation periods (1 or 2)."""
    return PeriodMap(system, periods)
