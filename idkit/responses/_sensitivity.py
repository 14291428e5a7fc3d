"""Sensitivities of the period map propagated through the compiled step (numba).

The step of :mod:`idkit.simulate._kernel` solves ``R(q; old) = 0`` for the new positions
(average-acceleration Newmark, residual ``M a + f``). At the converged ``q`` the implicit
function theorem gives ``dq = -J^-1 dR/d(old) d(old)`` with ``J`` the step's own Newton
matrix; velocities and accelerations follow linearly, and the internal states by
differentiating their exact updates: a Jenkin element that sticks in the step
(``|F + k dy| <= Fc``) carries ``dF + k d(dy)``, a slipping one 0 (its force is pinned at the
limit); a Maxwell element ``e du + g d(dy)``. The derivative is exact for the discrete map
except where a Jenkin trial force lands exactly on its limit (a kink: the one-sided slope of
the kernel's branch is taken). Bouc-Wen ``z`` (Runge-Kutta sub-steps) is not differentiated
here: systems with Bouc-Wen elements use finite differences.

Tangent layout (rows): ``q (ndof), v (ndof), a (ndof), F (ndof x nj), u (ndof x nm)``;
columns: the independent initial values ``q, v, F, u`` of real elements (the initial
acceleration follows from equilibrium; see :func:`tangent_start`). The functions here never
call the step itself: the period-map kernels (:func:`idkit.responses.period_map.period_kernel`)
call them around it, :func:`tangent_start` before a run, :func:`tangent_coefficients` after every
member's step, :func:`tangent_step` after the steps of the one or two members run together (their
columns side by side, one pass over each row for both) and :func:`tangent_finish` after the last (a
Maxwell row's update is made in the next step's pass over the row, which reads it anyway: one pass
over each of those rows a step instead of two).
"""

from __future__ import annotations

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.models.laws import polynomial_spring_stiffness


@numba.njit(cache=True)
def tangent_start(ndof, masses, P, state, tangent, nj, nm, columns):
    """Identity on the independent initial values; acceleration rows from equilibrium at t = 0
    (``a0 = -f0 / m0``, ``a1 = (f0 - f1) / m1``, base at rest at zero). Column ``k`` of
    ``tangent`` is the derivative by the initial value ``columns[k]`` of the layout above
    (``q, v, F, u`` of real elements only: the padding of the parameter arrays is left out)."""
    row_a = 2 * ndof
    row_f = 3 * ndof
    row_u = 3 * ndof + ndof * nj
    tangent[:, :] = 0.0
    for k in range(columns.shape[0]):
        column = columns[k]
        tangent[column if column < 2 * ndof else row_f + column - 2 * ndof, k] = 1.0
    slope = np.zeros(2)
    for j in range(ndof):
        y = state[0] - state[1] if (ndof == 2 and j == 0) else state[j]
        slope[j] = polynomial_spring_stiffness(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2])
    df = np.zeros(2)
    for c in range(columns.shape[0]):
        for j in range(ndof):
            if ndof == 2 and j == 0:
                dy = tangent[0, c] - tangent[1, c]
                dvrel = tangent[ndof, c] - tangent[ndof + 1, c]
            else:
                dy = tangent[j, c]
                dvrel = tangent[ndof + j, c]
            value = slope[j] * dy + P[j, 0, 3] * dvrel
            for i in range(int(P[j, 0, 5])):
                value += tangent[row_f + j * nj + i, c]
            for i in range(int(P[j, 0, 6])):
                value += P[j, 3, i] * tangent[row_u + j * nm + i, c]
            df[j] = value
        tangent[row_a, c] = -df[0] / masses[0]
        if ndof == 2:
            tangent[row_a + 1, c] = (df[0] - df[1]) / masses[1]


@numba.njit(cache=True, _nrt=False, inline="always")
def keep_step_start(ndof, nj, state, S, old_q, old_force, member):
    """Copy one member's positions (m) and Jenkin forces (N) before its step into row ``member`` of
    ``old_q`` and ``old_force``: what :func:`tangent_coefficients` differentiates the step from."""
    old_q[member, 0] = state[0]
    old_q[member, 1] = state[1]
    for d in range(ndof):
        for i in range(nj):
            old_force[member, d, i] = S[d, 0, i]


@numba.njit(cache=True, _nrt=False)
def tangent_coefficients(ndof, masses, P, state, old_q, old_force, base_old, base_new, h, work, stuck, member):
    """The coefficients of one member's converged step that :func:`tangent_step` needs, into row
    ``member`` of ``work`` (2, 8) and ``stuck`` (2, 2, max(nj, 1)).

    ``state`` holds the member's new positions (``[q0, q1, ...]``), ``old_q[member]`` (2, 2) and
    ``old_force[member]`` (2, ndof, max(nj, 1)) its positions (m) and Jenkin forces (N) before the step
    (indexed here rather than passed as views: a view made in a step loop costs reference counting),
    ``base_old``/``base_new`` the base displacement (m) at its ends, ``h`` the step (s).
    ``work[member]``: the spring slopes (0, 1) and the stiffnesses of the sticking elements and the
    spring-in-series terms (2, 3) of the isolators, then the step's Newton matrix ``j00, j01, j11``
    (4-6) and the inverse of its determinant (7); ``stuck[member, j, i]`` 1 where Jenkin element
    ``i`` of isolator ``j`` sticks in the step, else 0.
    """
    m0 = masses[0]
    m1 = masses[1] if ndof == 2 else 1.0
    c2 = 2.0 / h
    c4 = c2 * c2
    for j in range(ndof):
        if ndof == 2 and j == 0:
            y = state[0] - state[1]
            step_dy = y - (old_q[member, 0] - old_q[member, 1])
        elif ndof == 2:
            y = state[1] - base_new
            step_dy = (state[1] - old_q[member, 1]) - (base_new - base_old)
        else:
            y = state[0] - base_new
            step_dy = (state[0] - old_q[member, 0]) - (base_new - base_old)
        work[member, j] = polynomial_spring_stiffness(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2])
        total = P[j, 0, 4]
        for i in range(int(P[j, 0, 5])):
            trial = old_force[member, j, i] + P[j, 1, i] * step_dy
            stuck[member, j, i] = 0.0
            if -P[j, 2, i] <= trial <= P[j, 2, i]:  # the kernel's stick test
                stuck[member, j, i] = 1.0
                total += P[j, 1, i]
        work[member, 2 + j] = total
    t0 = work[member, 0] + P[0, 0, 3] * c2 + work[member, 2]
    j00 = c4 * m0 + t0
    j01 = 0.0
    j11 = 1.0
    if ndof == 2:
        j01 = -t0
        j11 = c4 * m1 + t0 + work[member, 1] + P[1, 0, 3] * c2 + work[member, 3]
    work[member, 4] = j00
    work[member, 5] = j01
    work[member, 6] = j11
    work[member, 7] = 1.0 / (j00 * j11 - j01 * j01)


@numba.njit(cache=True, _nrt=False, inline="always")
def _end_of_step_columns(q, v, a, new, c2, c4, n):
    """The trapezoidal rule's end of step on ``n`` tangent columns of one mass: positions ``q``
    set to ``new``, velocities ``v`` and accelerations ``a`` from the change (``c2 = 2 / h``,
    ``c4 = c2^2``); the columns' analogue of :func:`idkit.simulate._structured.end_of_step`."""
    for c in range(n):
        change = new[c] - q[c]
        a[c] = c4 * change - 2.0 * c2 * v[c] - a[c]
        v[c] = c2 * change - v[c]
        q[c] = new[c]


@numba.njit(cache=True, _nrt=False)
def tangent_step(ndof, masses, P, h, tangent, nj, nm, split, work, stuck, lanes, pending):
    """Carry the tangent columns of one or two members over one converged step of each.

    ``tangent``: the columns of the first member (``[0, split)``) then those of the second
    (``[split, n)``; none when ``split`` is the column count), each as :func:`tangent_start` made
    them; the two members run the same step ``h`` (s) and parameters ``P`` (one frequency and steps
    per period), their step's coefficients in rows 0 and 1 of ``work`` and ``stuck``
    (:func:`tangent_coefficients`). Every column gets the arithmetic of its own member, so a column's
    values do not depend on the columns beside it; one pass over a row serves both members. ``lanes``
    (6, columns): scratch of the caller's (per-column derivatives), so that a step allocates nothing
    and, compiled without reference counting, takes no atomic operation per call. ``pending``: the
    Maxwell rows still owe the previous step's update (every step of a run but its first; ``lanes``
    rows 4 and 5 hold that step's deflection increments), which this step makes as it reads them;
    after a run's last step, :func:`tangent_finish` makes it.
    """
    m0 = masses[0]
    m1 = masses[1] if ndof == 2 else 1.0
    row_f = 3 * ndof
    row_u = 3 * ndof + ndof * nj
    c2 = 2.0 / h
    c4 = c2 * c2
    n_jenkin0 = int(P[0, 0, 5])
    n_maxwell0 = int(P[0, 0, 6])
    n_jenkin1 = int(P[ndof - 1, 0, 5])
    n_maxwell1 = int(P[ndof - 1, 0, 6])
    # column by column the same arithmetic, written row by row over all the columns at once (the
    # inner loops run along contiguous memory and vectorise; a member's coefficient is chosen per
    # column by a comparison with ``split``); lanes: derivatives of the isolator forces (0, 1), of
    # the new positions (2, 3) and of the deflection increments (4, 5)
    n = tangent.shape[1]
    for j in range(ndof):
        force = lanes[j]
        damping = P[j, 0, 3]
        stiffness_a = work[0, 2 + j]
        stiffness_b = work[1, 2 + j]
        if ndof == 2 and j == 0:  # the branch outside the loops over the columns: they vectorise
            for c in range(n):
                stiffness = stiffness_a if c < split else stiffness_b
                ddy = -(tangent[0, c] - tangent[1, c])
                dvrel = -(c2 * tangent[0, c] + tangent[2, c]) + (c2 * tangent[1, c] + tangent[3, c])
                force[c] = damping * dvrel + stiffness * ddy
        else:
            for c in range(n):
                stiffness = stiffness_a if c < split else stiffness_b
                ddy = -tangent[j, c]
                dvrel = -(c2 * tangent[j, c] + tangent[ndof + j, c])
                force[c] = damping * dvrel + stiffness * ddy
        for i in range(n_jenkin0 if j == 0 else n_jenkin1):
            weight_a = stuck[0, j, i]
            weight_b = stuck[1, j, i]
            index = row_f + j * nj + i
            for c in range(n):
                force[c] += (weight_a if c < split else weight_b) * tangent[index, c]
        increment = lanes[4 + j]
        for i in range(n_maxwell0 if j == 0 else n_maxwell1):
            # the Maxwell rows still owe the previous step's update (see tangent_finish): made here,
            # in the pass that reads them
            decay = P[j, 4, i]
            gain = P[j, 5, i]
            weight = P[j, 3, i] * P[j, 4, i]
            index = row_u + j * nm + i
            if pending:
                for c in range(n):
                    value = decay * tangent[index, c] + gain * increment[c]
                    tangent[index, c] = value
                    force[c] += weight * value
            else:
                for c in range(n):
                    force[c] += weight * tangent[index, c]
    # the mechanical rows, per number of masses, in passes that each write few rows (a loop that
    # writes many rows of an array is not vectorised: their distances are not known when compiled)
    j00_a, j01_a, j11_a, inverse_a = work[0, 4], work[0, 5], work[0, 6], work[0, 7]
    j00_b, j01_b, j11_b, inverse_b = work[1, 4], work[1, 5], work[1, 6], work[1, 7]
    if ndof == 2:
        q0, q1, v0, v1, a0, a1 = tangent[0], tangent[1], tangent[2], tangent[3], tangent[4], tangent[5]
        force0, force1, new0, new1 = lanes[0], lanes[1], lanes[2], lanes[3]
        for c in range(n):
            first = c < split
            j00 = j00_a if first else j00_b
            j01 = j01_a if first else j01_b
            j11 = j11_a if first else j11_b
            inverse = inverse_a if first else inverse_b
            r0 = -m0 * (c4 * q0[c] + 2.0 * c2 * v0[c] + a0[c]) + force0[c]
            r1 = -m1 * (c4 * q1[c] + 2.0 * c2 * v1[c] + a1[c]) - force0[c] + force1[c]
            new0[c] = -(j11 * r0 - j01 * r1) * inverse
            new1[c] = -(j00 * r1 - j01 * r0) * inverse
        increment0, increment1 = lanes[4], lanes[5]
        for c in range(n):
            increment0[c] = (new0[c] - new1[c]) - (q0[c] - q1[c])
            increment1[c] = new1[c] - q1[c]
        _end_of_step_columns(q0, v0, a0, new0, c2, c4, n)
        _end_of_step_columns(q1, v1, a1, new1, c2, c4, n)
    else:
        q0, v0, a0 = tangent[0], tangent[1], tangent[2]
        force0, new0, increment0 = lanes[0], lanes[2], lanes[4]
        for c in range(n):
            new0[c] = -(-m0 * (c4 * q0[c] + 2.0 * c2 * v0[c] + a0[c]) + force0[c]) / (j00_a if c < split else j00_b)
        for c in range(n):
            increment0[c] = new0[c] - q0[c]
        _end_of_step_columns(q0, v0, a0, new0, c2, c4, n)
    for j in range(ndof):
        increment = lanes[4 + j]
        for i in range(n_jenkin0 if j == 0 else n_jenkin1):
            weight_a = stuck[0, j, i]
            weight_b = stuck[1, j, i]
            stiffness = P[j, 1, i]
            index = row_f + j * nj + i
            for c in range(n):
                tangent[index, c] = (weight_a if c < split else weight_b) * (tangent[index, c] + stiffness * increment[c])


@numba.njit(cache=True, _nrt=False)
def tangent_finish(ndof, P, tangent, nj, nm, lanes):
    """Complete the Maxwell rows after the last :func:`tangent_step` of a run.

    :func:`tangent_step` updates a Maxwell row (``e du + g d(dy)``) in the next step's pass over
    it, which reads it for the isolator force anyway (one pass over the row a step instead of
    two); after the last step that update is still owed, and made here.
    """
    row_u = 3 * ndof + ndof * nj
    n = tangent.shape[1]
    for j in range(ndof):
        increment = lanes[4 + j]
        for i in range(int(P[j, 0, 6])):
            decay = P[j, 4, i]
            gain = P[j, 5, i]
            index = row_u + j * nm + i
            for c in range(n):
                tangent[index, c] = decay * tangent[index, c] + gain * increment[c]
