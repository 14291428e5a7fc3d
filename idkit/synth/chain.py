"""A small explicit time-stepper for the synthetic experiments: a vertical chain of masses.

The bundled data need physics that the fitted models deliberately lack (deflection-dependent
Iwan slip forces, an internal elastomer mass, a bottom mass that bounces on the floor), so the
generator integrates its own equations instead of calling :func:`idkit.simulate.simulate`.

Chain: masses ``m[0..n-1]`` top first, absolute positions ``x`` (m, up positive). Link ``j``
connects mass ``j`` (above) with mass ``j + 1`` or, for the last link of a shaker chain, with the
prescribed base. Link deflection ``y_j = x_j - x_below`` (positive = tension); link force
``F_j`` (positive = tension) pulls mass ``j`` down and the mass below up. A drop chain has no
base link: its bottom mass touches the floor (height 0) through a unilateral penalty contact
``max(0, k_c p - c_c pdot)`` with penetration ``p = -x_bottom``, so it can bounce and lift off.

Link laws (all rate forms integrated exactly over a step with piecewise-linear deflection):

* ``LINK_WIRE_ROPE``: ``P(y) + sum_i F_i + c ydot`` with ``P(y) = g1 y + g2 y^2 + g3 y^3 -
  k_bot max(0, -y - y_bot)^3`` (a bottoming stiffener in deep compression) and Jenkin forces
  by the stop operator with **deflection-dependent** slip forces ``s(y) fc_i``,
  ``s(y) = 1 + beta tanh(-y / y_ref)``: loops widen in compression and narrow in tension.
* ``LINK_WIRE_ROPE_MODULATED``: ``P(y) + m(y) sum_i F_i + c ydot`` with constant slip forces
  ``fc_i`` and the **whole** hysteretic force scaled by ``m(y) = 1 + beta tanh^2(y / y_ref)``:
  loops widen at large deflection in both directions (truth "b").
* ``LINK_ELASTOMER``: ``k0 y (1 - alpha tanh^2(min(y, 0) / y_soft)) + sum_i k_i u_i`` with the
  exact exponential Maxwell update ``u <- e u + (dy / h)(1 - e) / rate``, ``e = exp(-rate h)``
  (SPEC 1.4): softening in compression only.

Integration: leapfrog (velocity Verlet in kick-drift form); the viscous term uses the last
half-step velocity. The step must resolve the stiffest oscillation (``omega h << 1``); the
generator uses 20-50 kHz for resonances below 1 kHz.
"""

from __future__ import annotations

import math

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.models.laws import jenkin_step, scaled_jenkin_step

__all__ = ["LINK_ELASTOMER", "LINK_WIRE_ROPE", "LINK_WIRE_ROPE_MODULATED", "ChainRun", "link_force_path", "run_chain"]

LINK_WIRE_ROPE = 0
LINK_ELASTOMER = 1
LINK_WIRE_ROPE_MODULATED = 2

# scalar parameter slots of a link
#  wire rope (both kinds): g1, g2, g3, c_visc, k_bot, y_bot, beta, y_ref
#  elastomer: k0, alpha, y_soft, (unused) ...
N_SCALARS = 8


@numba.njit(cache=True)
def _link_force(kind, scalars, k, b, n, state, y_old, y_new, ydot, h):
    """Advance the internal state of one link from ``y_old`` to ``y_new``; return its force."""
    dy = y_new - y_old
    if kind == LINK_WIRE_ROPE:
        g1, g2, g3, c_visc = scalars[0], scalars[1], scalars[2], scalars[3]
        k_bot, y_bot, beta, y_ref = scalars[4], scalars[5], scalars[6], scalars[7]
        scale = 1.0 + beta * math.tanh(-y_new / y_ref)
        total = y_new * (g1 + y_new * (g2 + y_new * g3))
        deep = -y_new - y_bot
        if deep > 0.0:
            total -= k_bot * deep * deep * deep
        scaled_jenkin_step(state[:n], k[:n], b[:n], scale, dy)
        for i in range(n):
            total += state[i]
        return total + c_visc * ydot
    if kind == LINK_WIRE_ROPE_MODULATED:
        # a branch of its own: the sums of LINK_WIRE_ROPE keep their rounding order bit for bit
        g1, g2, g3, c_visc = scalars[0], scalars[1], scalars[2], scalars[3]
        k_bot, y_bot, beta, y_ref = scalars[4], scalars[5], scalars[6], scalars[7]
        spring = y_new * (g1 + y_new * (g2 + y_new * g3))
        deep = -y_new - y_bot
        if deep > 0.0:
            spring -= k_bot * deep * deep * deep
        hysteretic = jenkin_step(state[:n], k[:n], b[:n], dy)
        width = math.tanh(y_new / y_ref)
        return spring + (1.0 + beta * width * width) * hysteretic + c_visc * ydot
    k0, alpha, y_soft = scalars[0], scalars[1], scalars[2]
    compression = y_new if y_new < 0.0 else 0.0
    soft = math.tanh(compression / y_soft)
    total = k0 * y_new * (1.0 - alpha * soft * soft)
    for i in range(n):
        rate = b[i]
        if h > 0.0:
            decay = math.exp(-rate * h)
            state[i] = decay * state[i] + (dy / h) * (1.0 - decay) / rate
        total += k[i] * state[i]
    return total


@numba.njit(cache=True)
def link_force_path(kind, scalars, k, b, n, state0, deflection, time):
    """Force (N) of one link along a deflection history (m) at times (s); state from ``state0``."""
    state = state0.copy()
    out = np.empty(deflection.size)
    out[0] = _link_force(kind, scalars, k, b, n, state, deflection[0], deflection[0], 0.0, 0.0)
    for i in range(1, deflection.size):
        h = time[i] - time[i - 1]
        ydot = (deflection[i] - deflection[i - 1]) / h
        out[i] = _link_force(kind, scalars, k, b, n, state, deflection[i - 1], deflection[i], ydot, h)
    return out, state


@numba.njit(cache=True)
def _run(masses, kinds, scalars, ks, bs, ns, state, x, v, base_x, base_v, h, n_steps, gravity,
         floor, k_contact, c_contact, record_every, rec_x, rec_v, rec_a, rec_y, rec_f, rec_contact):
    n_mass = masses.size
    n_link = kinds.size
    y_old = np.empty(n_link)
    y_new = np.empty(n_link)
    ydot = np.empty(n_link)
    force = np.empty(n_link)
    acc = np.empty(n_mass)
    v_half = v.copy()
    for j in range(n_link):
        below = x[j + 1] if j + 1 < n_mass else base_x[0]
        y_old[j] = x[j] - below
    record = 0
    for step in range(n_steps + 1):
        # forces at x(step)
        for j in range(n_link):
            if j + 1 < n_mass:
                y_new[j] = x[j] - x[j + 1]
                ydot[j] = v_half[j] - v_half[j + 1]
            else:
                y_new[j] = x[j] - base_x[step]
                ydot[j] = v_half[j] - base_v[step]
            force[j] = _link_force(kinds[j], scalars[j], ks[j], bs[j], ns[j], state[j],
                                   y_old[j], y_new[j], ydot[j], h if step > 0 else 0.0)
            y_old[j] = y_new[j]
        for i in range(n_mass):
            acc[i] = -gravity
        for j in range(n_link):
            acc[j] -= force[j] / masses[j]
            if j + 1 < n_mass:
                acc[j + 1] += force[j] / masses[j + 1]
        contact = 0.0
        if floor:
            depth = -x[n_mass - 1]
            if depth > 0.0:
                contact = k_contact * depth - c_contact * v_half[n_mass - 1]
                if contact < 0.0:
                    contact = 0.0
                acc[n_mass - 1] += contact / masses[n_mass - 1]
        if step == 0:
            for i in range(n_mass):
                v_half[i] = v[i] - 0.5 * h * acc[i]
        if step % record_every == 0 and record < rec_x.shape[1]:
            for i in range(n_mass):
                rec_x[i, record] = x[i]
                rec_v[i, record] = v_half[i] + 0.5 * h * acc[i]
                rec_a[i, record] = acc[i]  # kinematic (gravity included in the forces)
            for j in range(n_link):
                rec_y[j, record] = y_new[j]
                rec_f[j, record] = force[j]
            rec_contact[record] = contact
            record += 1
        if step == n_steps:
            break
        for i in range(n_mass):
            v_half[i] += h * acc[i]
            x[i] += h * v_half[i]
    return record


class ChainRun:
    """Recorded chain response (arrays ``(n_masses or n_links, n_records)``, SI).

    Attributes: ``time`` (s), ``position``/``velocity``/``acceleration`` of the masses
    (absolute; acceleration kinematic, m/s^2), ``deflection``/``force`` of the links,
    ``contact`` floor force on the bottom mass (N).
    """

    def __init__(self, time, position, velocity, acceleration, deflection, force, contact):
        self.time = time
        self.position = position
        self.velocity = velocity
        self.acceleration = acceleration
        self.deflection = deflection
        self.force = force
        self.contact = contact


def pack_links(links):
    """Pack ``(kind, scalars, k, b)`` tuples into the kernel's arrays."""
    n_max = max(1, max(len(link[2]) for link in links))
    kinds = np.array([link[0] for link in links], dtype=np.int64)
    scalars = np.zeros((len(links), N_SCALARS))
    ks = np.zeros((len(links), n_max))
    bs = np.ones((len(links), n_max))
    ns = np.zeros(len(links), dtype=np.int64)
    for j, (_, values, k, b) in enumerate(links):
        scalars[j, : len(values)] = values
        ks[j, : len(k)] = k
        bs[j, : len(b)] = b
        ns[j] = len(k)
    return kinds, scalars, ks, bs, ns


def run_chain(masses, links, *, time_step, n_steps, x0, v0, state0=None, base_x=None, base_v=None,
              gravity=0.0, floor=False, k_contact=0.0, c_contact=0.0, record_every=1) -> ChainRun:
    """Integrate a chain; see the module docstring for the conventions.

    Parameters
    ----------
    masses : array_like, shape (n,)
        Masses in kg, top first.
    links : sequence of (kind, scalars, k, b)
        Link laws, top first; ``b`` is the slip force (N) or the rate (1/s).
    time_step : float
        Integration step in s.
    n_steps : int
        Number of steps.
    x0, v0 : array_like, shape (n,)
        Initial absolute positions (m) and velocities (m/s).
    state0 : ndarray, shape (n_links, n_max), optional
        Initial Jenkin forces (N) or Maxwell elongations (m).
    base_x, base_v : ndarray, shape (n_steps + 1,), optional
        Base displacement (m) and velocity (m/s) at every step (shaker chains).
    gravity : float
        Gravitational acceleration in m/s^2 acting downward.
    floor, k_contact, c_contact : bool, float, float
        Unilateral floor contact of the bottom mass: stiffness N/m and damping N s/m.
    record_every : int
        Record every n-th step.
    """
    masses = np.asarray(masses, dtype=float)
    kinds, scalars, ks, bs, ns = pack_links(links)
    state = np.zeros_like(ks) if state0 is None else np.array(state0, dtype=float)
    if base_x is None:
        base_x = np.zeros(n_steps + 1)
        base_v = np.zeros(n_steps + 1)
    n_records = n_steps // record_every + 1
    shape_m = (masses.size, n_records)
    shape_l = (kinds.size, n_records)
    rec_x, rec_v, rec_a = np.empty(shape_m), np.empty(shape_m), np.empty(shape_m)
    rec_y, rec_f = np.empty(shape_l), np.empty(shape_l)
    rec_contact = np.empty(n_records)
    x = np.array(x0, dtype=float)
    v = np.array(v0, dtype=float)
    _run(masses, kinds, scalars, ks, bs, ns, state, x, v, np.ascontiguousarray(base_x, dtype=float),
         np.ascontiguousarray(base_v, dtype=float), float(time_step), int(n_steps), float(gravity),
         bool(floor), float(k_contact), float(c_contact), int(record_every), rec_x, rec_v, rec_a,
         rec_y, rec_f, rec_contact)
    time = np.arange(n_records) * (record_every * time_step)
    return ChainRun(time, rec_x, rec_v, rec_a, rec_y, rec_f, rec_contact)
