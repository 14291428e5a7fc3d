"""Reference solutions by a general-purpose stiff ODE solver (thesis 3.2-3.3, 5.1).

An independent path for cross-checking the fast kernel (:func:`idkit.simulate.simulate`):
the system is written as first-order ODEs, as the thesis did for MATLAB's
``ode15s``, with the sign functions smoothed by ``tanh`` and integrated by
:func:`scipy.integrate.solve_ivp` (BDF by default) with an analytic Jacobian.

State (absolute coordinates, top mass first): mass displacements ``q`` (m) and
velocities ``v`` (m/s), then every Jenkin force ``F_i`` (N), every Maxwell spring
elongation ``u_i`` (m) and every Bouc-Wen ``z`` (N). For an isolator with
deflection ``y`` (m, positive = tension) and deflection rate ``ydot``:

* force ``P(y) + c ydot + sum F_i + sum k_i u_i + b^(c y) (k1 y + k2 y|y| + k3 y^3 + z)``
  plus, for :class:`~idkit.models.CoulombSpringSystem`, the smoothed parallel
  slider ``Fc tanh(ydot / v_eps)``;
* Jenkin element (eqs. 3.8-3.10 with each ``sign`` replaced by a ``tanh``)::

      dF/dt = k ydot / 2 * [(1 - s) - r (1 + s)]
      s = tanh(((F/Fc)^2 - 1) / eps)           (saturation, 3.9: -1 inside, +1 outside)
      r = tanh(ydot F / (v_eps Fc))             (re-activation, 3.10: sign of ydot F)

  Inside (``s = -1``) the rate is ``k ydot``; when unloading (``r = -1``) it is
  ``k ydot`` whatever ``s``; when loading outward (``r = 1``) it is ``-k ydot s``,
  which pulls ``F`` onto ``|F| = Fc`` exactly (``s = 0``). As ``eps, v_eps -> 0`` this is
  the stop operator of SPEC 1.1. Far inside the stick range ``s`` rounds to -1, so
  the element does not creep in stick (unlike a smoothed parallel slider);
* Maxwell element: ``du_i/dt = ydot - rate_i u_i``;
* Bouc-Wen: ``dz/dt = ydot (alpha - (gamma + beta tanh(ydot z / (v_eps z_y))) |z|^n)``
  with the yield level ``z_y = (alpha / (beta + gamma))^(1/n)`` in N.

Smoothing (one knob): ``smoothing`` is the dimensionless width ``eps``; velocities
are compared with ``v_eps = smoothing * velocity_scale`` (m/s, ``velocity_scale``
defaults to 1 m/s, so by default ``v_eps`` in m/s equals ``smoothing``). Both widths
go to zero together. The price of small widths is stiffness (time scales
``eps Fc / (2 k |ydot|)`` at saturation), which BDF with the analytic Jacobian absorbs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.checks import Choice, Instance, Real, Reals, Whole, accepts
from idkit.errors import SimulationError
from idkit.models.systems import CoulombSpringSystem, HybridSystem, SDOFSystem
from idkit.gravity import gravity_acceleration
from idkit.simulate._kernel import (
    FLAG_NEGATIVE_STIFFNESS,
    FLAG_NO_CONVERGENCE,
    FLAG_NON_FINITE,
    FLAG_OK,
    FLAG_REASONS,
)
from idkit.simulate.base_motion import BaseMotion
from idkit.simulate.time_response import TimeResponse, initial_states

__all__ = ["ReferenceResponse", "ReferenceHarmonic", "solve_ivp_reference", "harmonic_reference"]

_METHODS = ("BDF", "Radau", "LSODA")


@dataclass(frozen=True)
class ReferenceResponse(TimeResponse):
    """A :class:`~idkit.simulate.TimeResponse` (batch of one) with solver details.

    Extra attributes
    ----------------
    internal_states : (n_internal, n_records)
        Jenkin forces (N), Maxwell elongations (m) and Bouc-Wen ``z`` (N), in that
        order, isolator 0 first.
    nfev, njev : int
        Right-hand side and Jacobian evaluations of the solver.
    message : str
        The solver's message.
    smoothing, velocity_width : float
        The dimensionless width ``eps`` and the velocity width ``v_eps`` (m/s) used.
    """

    internal_states: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    nfev: int = 0
    njev: int = 0
    message: str = ""
    smoothing: float = math.nan
    velocity_width: float = math.nan


@dataclass(frozen=True)
class ReferenceHarmonic:
    """Steady-state harmonic response from :func:`harmonic_reference` (one point).

    Same convention as :class:`~idkit.simulate.HarmonicResponse`: the base moves as
    ``A sin(2 pi f t)``; ``x(t) = X_0 + Re sum_{m>=1} X_m exp(i m pi f t)`` over the last
    two periods (time counted from the start of that window), ``X_2`` the first harmonic.

    Attributes
    ----------
    freq, amplitude : float, Hz and m
    coefficients : complex (2 K + 1,), m, absolute top displacement
    deflection_coefficients : complex (2 K + 1,), m, top displacement relative to the base
    half_range : float, peak-peak/2 of the top displacement in the last window, m
    change : float, max change of the coefficients between the last two windows,
        relative to the first-harmonic amplitude (steady-state indicator)
    periods : int, periods simulated
    response : ReferenceResponse, the last four periods of the run
    """

    freq: float
    amplitude: float
    coefficients: np.ndarray
    deflection_coefficients: np.ndarray
    half_range: float
    change: float
    periods: int
    response: ReferenceResponse

    @property
    def n_harmonics(self) -> int:
        return (self.coefficients.size - 1) // 2

    @accepts(order=Real(ge=0, meaning="0, 0.5, 1, ..."), error=SimulationError)
    def harmonic(self, order: float) -> complex:
        """Complex amplitude (m) of the top displacement at ``order`` x f (0, 0.5, 1, ...)."""
        index = int(round(2 * order))
        if not (0 <= index < self.coefficients.size) or abs(2 * order - index) > 1e-9:
            raise SimulationError(f"harmonic order: found {order!r}, expected 0, 0.5, 1, ..., {self.n_harmonics}")
        return complex(self.coefficients[index])

    @property
    def base_first_harmonic(self) -> complex:
        """Complex amplitude of the base displacement, ``-i A``."""
        return -1j * self.amplitude

    def hosidf(self, order: float) -> complex:
        """``order X_order / (-i A)``: k-th harmonic of the top velocity over the base velocity's first."""
        return order * self.harmonic(order) / self.base_first_harmonic


# --------------------------------------------------------------------------------------------
# Compiled right-hand side and Jacobian


@numba.njit(cache=True)
def _derivatives(state, xb, vb, masses, poly, cvisc, coulomb, j_owner, j_k, j_fc, m_owner, m_k, m_rate,
                 b_owner, b_par, b_zy, eps, veps, gravity, want_jacobian, out_rate, out_jac, out_dxb, out_dvb,
                 out_force):
    """State derivative (and Jacobian) of the smoothed first-order system.

    ``out_dxb``/``out_dvb`` receive the derivative of the state rate with respect to
    the base displacement and velocity (used when those are extra states).
    ``out_force`` receives the isolator forces (N).
    """
    ndof = masses.shape[0]
    n = state.shape[0]
    nj = j_k.shape[0]
    nm = m_k.shape[0]
    nb = b_par.shape[0]
    oj = 2 * ndof
    om = oj + nj
    ob = om + nm
    # D[j, d]: dy_j/dq_d; bcoef[j]: dy_j/dx_b
    dmat = np.zeros((2, 2))
    bcoef = np.zeros(2)
    if ndof == 1:
        dmat[0, 0] = 1.0
        bcoef[0] = -1.0
    else:
        dmat[0, 0] = 1.0
        dmat[0, 1] = -1.0
        dmat[1, 1] = 1.0
        bcoef[1] = -1.0
    y = np.zeros(2)
    yd = np.zeros(2)
    for j in range(ndof):
        for d in range(ndof):
            y[j] += dmat[j, d] * state[d]
            yd[j] += dmat[j, d] * state[ndof + d]
        y[j] += bcoef[j] * xb
        yd[j] += bcoef[j] * vb
    # isolator forces and their partial derivatives
    force = np.zeros(2)
    dfdy = np.zeros(2)
    dfdyd = np.zeros(2)
    for j in range(ndof):
        g1 = poly[j, 0]
        g2 = poly[j, 1]
        g3 = poly[j, 2]
        force[j] = y[j] * (g1 + y[j] * (g2 + y[j] * g3)) + cvisc[j] * yd[j]
        dfdy[j] = g1 + y[j] * (2.0 * g2 + 3.0 * g3 * y[j])
        dfdyd[j] = cvisc[j]
        if coulomb[j] > 0.0:
            th = math.tanh(yd[j] / veps)
            force[j] += coulomb[j] * th
            dfdyd[j] += coulomb[j] * (1.0 - th * th) / veps
    for i in range(nj):
        force[j_owner[i]] += state[oj + i]
    for i in range(nm):
        force[m_owner[i]] += m_k[i] * state[om + i]
    bw_factor = np.zeros(nb)
    for i in range(nb):
        j = b_owner[i]
        yy = y[j]
        factor = b_par[i, 8] ** (b_par[i, 9] * yy)
        inner = yy * (b_par[i, 1] + b_par[i, 2] * abs(yy) + b_par[i, 3] * yy * yy) + state[ob + i]
        force[j] += factor * inner
        dfdy[j] += math.log(b_par[i, 8]) * b_par[i, 9] * factor * inner + factor * (
            b_par[i, 1] + 2.0 * b_par[i, 2] * abs(yy) + 3.0 * b_par[i, 3] * yy * yy)
        bw_factor[i] = factor
    for j in range(ndof):
        out_force[j] = force[j]
    # mechanics: q' = v, v'_d = -(1/m_d) sum_j D[j, d] f_j - g
    for d in range(ndof):
        out_rate[d] = state[ndof + d]
        acc = 0.0
        for j in range(ndof):
            acc -= dmat[j, d] * force[j]
        out_rate[ndof + d] = acc / masses[d] - gravity
    # Jenkin elements, eqs. 3.8-3.10 smoothed
    drdyd_j = np.zeros(nj)
    drdf_j = np.zeros(nj)
    for i in range(nj):
        j = j_owner[i]
        f = state[oj + i]
        fc = j_fc[i]
        ratio = f / fc
        s = math.tanh((ratio * ratio - 1.0) / eps)
        r = math.tanh(yd[j] * ratio / veps)
        bracket = (1.0 - s) - r * (1.0 + s)
        out_rate[oj + i] = 0.5 * j_k[i] * yd[j] * bracket
        if want_jacobian:
            ds_df = (1.0 - s * s) * 2.0 * ratio / (eps * fc)
            dr_dyd = (1.0 - r * r) * ratio / veps
            dr_df = (1.0 - r * r) * yd[j] / (veps * fc)
            # d(rate)/d(ydot) and d(rate)/dF
            drdyd_j[i] = 0.5 * j_k[i] * (bracket - yd[j] * (1.0 + s) * dr_dyd)
            drdf_j[i] = 0.5 * j_k[i] * yd[j] * (-ds_df * (1.0 + r) - (1.0 + s) * dr_df)
    for i in range(nm):
        j = m_owner[i]
        out_rate[om + i] = yd[j] - m_rate[i] * state[om + i]
    drdyd_b = np.zeros(nb)
    drdz_b = np.zeros(nb)
    for i in range(nb):
        j = b_owner[i]
        z = state[ob + i]
        alpha = b_par[i, 4]
        beta = b_par[i, 5]
        gamma = b_par[i, 6]
        expo = b_par[i, 7]
        rho = math.tanh(yd[j] * z / (veps * b_zy[i]))
        power = abs(z) ** expo
        slope = alpha - (gamma + beta * rho) * power
        out_rate[ob + i] = yd[j] * slope
        if want_jacobian:
            drho_dyd = (1.0 - rho * rho) * z / (veps * b_zy[i])
            drho_dz = (1.0 - rho * rho) * yd[j] / (veps * b_zy[i])
            dpower = expo * abs(z) ** (expo - 1.0) * (1.0 if z > 0 else -1.0) if z != 0.0 else 0.0
            drdyd_b[i] = slope - yd[j] * beta * drho_dyd * power
            drdz_b[i] = yd[j] * (-beta * drho_dz * power - (gamma + beta * rho) * dpower)
    if not want_jacobian:
        return
    for a in range(n):
        out_dxb[a] = 0.0
        out_dvb[a] = 0.0
        for b in range(n):
            out_jac[a, b] = 0.0
    for d in range(ndof):
        out_jac[d, ndof + d] = 1.0
    # df_j/d(state) as rows, then v' rows
    dforce = np.zeros((2, n))
    dforce_xb = np.zeros(2)
    dforce_vb = np.zeros(2)
    for j in range(ndof):
        for d in range(ndof):
            dforce[j, d] += dfdy[j] * dmat[j, d]
            dforce[j, ndof + d] += dfdyd[j] * dmat[j, d]
        dforce_xb[j] = dfdy[j] * bcoef[j]
        dforce_vb[j] = dfdyd[j] * bcoef[j]
    for i in range(nj):
        dforce[j_owner[i], oj + i] += 1.0
    for i in range(nm):
        dforce[m_owner[i], om + i] += m_k[i]
    for i in range(nb):
        dforce[b_owner[i], ob + i] += bw_factor[i]
    for d in range(ndof):
        for j in range(ndof):
            w = -dmat[j, d] / masses[d]
            if w != 0.0:
                for b in range(n):
                    out_jac[ndof + d, b] += w * dforce[j, b]
                out_dxb[ndof + d] += w * dforce_xb[j]
                out_dvb[ndof + d] += w * dforce_vb[j]
    for i in range(nj):
        j = j_owner[i]
        for d in range(ndof):
            out_jac[oj + i, ndof + d] = drdyd_j[i] * dmat[j, d]
        out_jac[oj + i, oj + i] = drdf_j[i]
        out_dvb[oj + i] = drdyd_j[i] * bcoef[j]
    for i in range(nm):
        j = m_owner[i]
        for d in range(ndof):
            out_jac[om + i, ndof + d] = dmat[j, d]
        out_jac[om + i, om + i] = -m_rate[i]
        out_dvb[om + i] = bcoef[j]
    for i in range(nb):
        j = b_owner[i]
        for d in range(ndof):
            out_jac[ob + i, ndof + d] = drdyd_b[i] * dmat[j, d]
        out_jac[ob + i, ob + i] = drdz_b[i]
        out_dvb[ob + i] = drdyd_b[i] * bcoef[j]


# --------------------------------------------------------------------------------------------
# System description


@dataclass(frozen=True)
class _Layout:
    masses: np.ndarray
    poly: np.ndarray
    cvisc: np.ndarray
    coulomb: np.ndarray
    j_owner: np.ndarray
    j_k: np.ndarray
    j_fc: np.ndarray
    m_owner: np.ndarray
    m_k: np.ndarray
    m_rate: np.ndarray
    b_owner: np.ndarray
    b_par: np.ndarray
    b_zy: np.ndarray
    initial_internal: object  # callable(deflections) -> internal state vector

    @property
    def ndof(self) -> int:
        return int(self.masses.size)

    @property
    def n_states(self) -> int:
        return 2 * self.ndof + self.j_k.size + self.m_k.size + self.b_zy.size

    def arrays(self):
        return (self.masses, self.poly, self.cvisc, self.coulomb, self.j_owner, self.j_k, self.j_fc,
                self.m_owner, self.m_k, self.m_rate, self.b_owner, self.b_par, self.b_zy)


def _layout(system) -> _Layout:
    if isinstance(system, CoulombSpringSystem):
        empty_i = np.zeros(0, dtype=np.int64)
        empty = np.zeros(0)
        return _Layout(
            masses=np.array([system.mass]), poly=np.array([[system.stiffness, 0.0, 0.0]]),
            cvisc=np.array([system.damping]), coulomb=np.array([system.friction_force]),
            j_owner=empty_i, j_k=empty, j_fc=empty, m_owner=empty_i, m_k=empty, m_rate=empty,
            b_owner=empty_i, b_par=np.zeros((0, 10)), b_zy=empty,
            initial_internal=lambda deflections: np.zeros(0),
        )
    if not isinstance(system, (SDOFSystem, HybridSystem)):
        raise SimulationError(
            f"system: found {type(system).__name__}, expected SDOFSystem, HybridSystem or CoulombSpringSystem"
        )
    parts = [isolator.kernel_arrays() for isolator in system.isolators]
    for part in parts:
        if part.slip_modulation[0] != 0.0 or part.slip_modulation[2] != 0.0:
            raise SimulationError("system: found an isolator with modulated slip forces, which the smoothed "
                                  "reference does not model; expected constant slip forces (use simulate())")
    j_owner, j_k, j_fc, m_owner, m_k, m_rate, b_owner, b_par, b_zy = ([] for _ in range(9))
    for j, part in enumerate(parts):
        j_owner += [j] * part.jenkin_stiffness.size
        j_k += part.jenkin_stiffness.tolist()
        j_fc += part.jenkin_friction.tolist()
        m_owner += [j] * part.maxwell_stiffness.size
        m_k += part.maxwell_stiffness.tolist()
        m_rate += part.maxwell_rate.tolist()
        if part.boucwen[0] != 0.0:
            alpha, beta, gamma, expo = part.boucwen[4:8]
            b_owner.append(j)
            b_par.append(part.boucwen)
            scale = abs(beta + gamma) or abs(beta - gamma)    # z scale of the smoothed sign (hardening: beta + gamma < 0)
            b_zy.append((alpha / scale) ** (1.0 / expo))

    def initial_internal(deflections):
        jforce, mstate, bwz = initial_states(system, deflections)
        values = []
        for j, part in enumerate(parts):
            values += jforce[j, : part.jenkin_stiffness.size].tolist()
        for j, part in enumerate(parts):
            values += mstate[j, : part.maxwell_stiffness.size].tolist()
        values += [bwz[j] for j, part in enumerate(parts) if part.boucwen[0] != 0.0]
        return np.array(values, dtype=float)

    return _Layout(
        masses=np.asarray(system.masses, dtype=float),
        poly=np.array([p.poly for p in parts], dtype=float),
        cvisc=np.array([p.c_visc for p in parts], dtype=float),
        coulomb=np.zeros(len(parts)),
        j_owner=np.array(j_owner, dtype=np.int64), j_k=np.array(j_k, dtype=float),
        j_fc=np.array(j_fc, dtype=float),
        m_owner=np.array(m_owner, dtype=np.int64), m_k=np.array(m_k, dtype=float),
        m_rate=np.array(m_rate, dtype=float),
        b_owner=np.array(b_owner, dtype=np.int64), b_par=np.array(b_par, dtype=float).reshape(-1, 10),
        b_zy=np.array(b_zy, dtype=float),
        initial_internal=initial_internal,
    )


class _Base:
    """Base displacement and velocity as functions of time, or as extra ODE states.

    Displacement with a velocity function: evaluated directly. Displacement without
    one: a cubic spline through the samples at the output grid (the same
    interpolation :meth:`BaseMotion.on_grid` uses). Velocity: ``x_b`` becomes an
    extra state. Acceleration: ``x_b`` and ``v_b`` become extra states.
    """

    def __init__(self, base: BaseMotion | None, grid: np.ndarray):
        base = base or BaseMotion.at_rest()
        self.motion = base
        self.n_extra = 0
        if base.quantity == "displacement":
            if base.velocity_function is not None:
                self._x, self._v = base.function, base.velocity_function
            else:
                if grid.size < 4:
                    raise SimulationError("time_eval: found fewer than 4 times, expected at least 4 to "
                                          "interpolate a base displacement given without its velocity")
                spline = CubicSpline(grid, np.asarray(base.function(grid), dtype=float) * np.ones_like(grid))
                self._x, self._v = spline, spline.derivative(1)
        elif base.quantity == "velocity":
            self.n_extra = 1
        else:
            self.n_extra = 2
        self.initial = [base.initial_displacement, base.initial_velocity][: self.n_extra]

    def at(self, t: float, extra) -> tuple[float, float]:
        if self.n_extra == 0:
            return float(self._x(t)), float(self._v(t))
        if self.n_extra == 1:
            return float(extra[0]), float(self.motion.function(np.asarray(t)))
        return float(extra[0]), float(extra[1])

    def extra_rate(self, t: float, extra) -> list[float]:
        if self.n_extra == 1:
            return [float(self.motion.function(np.asarray(t)))]
        if self.n_extra == 2:
            return [float(extra[1]), float(self.motion.function(np.asarray(t)))]
        return []


# --------------------------------------------------------------------------------------------
# Public API


#: The contracts of the solver options both reference paths take.
_SOLVER_OPTIONS = dict(smoothing=Real(gt=0), velocity_scale=Real(unit="m/s", gt=0), method=Choice(_METHODS),
                       rtol=Real(ge=1e-13, lt=1), error=SimulationError)


def _solve(system, t_start: float, time_eval: np.ndarray, base, initial_velocity, initial_deflection, gravity,
           smoothing, velocity_scale, method, rtol, atol, max_step) -> ReferenceResponse:
    layout = _layout(system)
    ndof = layout.ndof
    eps, veps = smoothing, smoothing * velocity_scale
    base_path = _Base(base, time_eval)
    n_mech = layout.n_states
    n_total = n_mech + base_path.n_extra

    v0 = np.zeros(ndof) if initial_velocity is None else initial_velocity.reshape(-1)
    y0 = np.zeros(ndof) if initial_deflection is None else initial_deflection.reshape(-1)
    for name, values in (("initial_velocity", v0), ("initial_deflection", y0)):
        if values.shape != (ndof,):
            raise SimulationError(f"{name}: found shape {values.shape}, expected ({ndof},) (one per mass/isolator)")
    gravity_value = gravity_acceleration(gravity)

    xb0, _ = base_path.at(t_start, base_path.initial)
    q0 = xb0 + (y0 if ndof == 1 else np.array([y0[0] + y0[1], y0[1]]))
    state0 = np.concatenate([q0, v0, layout.initial_internal(y0), base_path.initial])

    if atol is None:
        atol = 1e-3 * rtol
    atol_array = np.broadcast_to(np.asarray(atol, dtype=float), (n_total,)) if np.ndim(atol) == 0 \
        else np.asarray(atol, dtype=float)
    if atol_array.shape != (n_total,) or np.any(~(atol_array > 0)):
        raise SimulationError(f"atol: found {atol!r}, expected a positive number or {n_total} positive numbers")

    arrays = layout.arrays()
    work_rate = np.zeros(n_mech)
    work_jac = np.zeros((n_mech, n_mech))
    work_dxb = np.zeros(n_mech)
    work_dvb = np.zeros(n_mech)
    work_force = np.zeros(ndof)
    n_extra = base_path.n_extra

    def rhs(t, state):
        xb, vb = base_path.at(t, state[n_mech:])
        _derivatives(state[:n_mech], xb, vb, *arrays, eps, veps, gravity_value, False, work_rate, work_jac,
                     work_dxb, work_dvb, work_force)
        if n_extra == 0:
            return work_rate.copy()
        return np.concatenate([work_rate, base_path.extra_rate(t, state[n_mech:])])

    def jacobian(t, state):
        xb, vb = base_path.at(t, state[n_mech:])
        _derivatives(np.ascontiguousarray(state[:n_mech]), xb, vb, *arrays, eps, veps, gravity_value, True,
                     work_rate, work_jac, work_dxb, work_dvb, work_force)
        if n_extra == 0:
            return work_jac.copy()
        full = np.zeros((n_total, n_total))
        full[:n_mech, :n_mech] = work_jac
        full[:n_mech, n_mech] = work_dxb  # x_b is extra state 0
        if n_extra == 1:  # v_b is a known function of time
            return full
        full[:n_mech, n_mech + 1] = work_dvb
        full[n_mech, n_mech + 1] = 1.0  # x_b' = v_b
        return full

    events = []
    has_polynomial = np.any(layout.poly[:, 1:] != 0.0)
    if has_polynomial:
        def stiffness_event(t, state):
            q = state[:ndof]
            xb, _ = base_path.at(t, state[n_mech:])
            deflections = [q[0] - xb] if ndof == 1 else [q[0] - q[1], q[1] - xb]
            return min(layout.poly[j, 0] + y * (2.0 * layout.poly[j, 1] + 3.0 * layout.poly[j, 2] * y)
                       for j, y in enumerate(deflections))
        stiffness_event.terminal = True
        stiffness_event.direction = -1
        events.append(stiffness_event)

    options = dict(method=method, t_eval=time_eval, rtol=rtol, atol=atol_array, events=events or None)
    options["jac"] = jacobian
    if max_step is not None:
        options["max_step"] = float(max_step)
    solution = solve_ivp(rhs, (t_start, float(time_eval[-1])), state0, **options)

    n_out = time_eval.size
    states = np.full((n_total, n_out), np.nan)
    states[:, : solution.y.shape[1]] = solution.y
    flag, flag_time = FLAG_OK, math.nan
    if solution.status == 1:
        flag, flag_time = FLAG_NEGATIVE_STIFFNESS, float(solution.t_events[0][0])
    elif solution.status != 0:
        flag = FLAG_NON_FINITE if not np.all(np.isfinite(solution.y)) else FLAG_NO_CONVERGENCE
        flag_time = float(solution.t[-1]) if solution.t.size else t_start
    displacement = np.full((1, ndof, n_out), np.nan)
    velocity = np.full((1, ndof, n_out), np.nan)
    acceleration = np.full((1, ndof, n_out), np.nan)
    deflection = np.full((1, ndof, n_out), np.nan)
    force = np.full((1, ndof, n_out), np.nan)
    for i in range(solution.y.shape[1]):
        state = np.ascontiguousarray(states[:, i])
        xb, vb = base_path.at(time_eval[i], state[n_mech:])
        _derivatives(state[:n_mech], xb, vb, *arrays, eps, veps, gravity_value, False, work_rate, work_jac,
                     work_dxb, work_dvb, work_force)
        q, v = state[:ndof], state[ndof:2 * ndof]
        displacement[0, :, i] = q - xb
        velocity[0, :, i] = v - vb
        acceleration[0, :, i] = work_rate[ndof:2 * ndof]
        deflection[0, :, i] = [q[0] - xb] if ndof == 1 else [q[0] - q[1], q[1] - xb]
        force[0, :, i] = work_force
    return ReferenceResponse(
        time=time_eval, displacement=displacement, velocity=velocity, acceleration=acceleration,
        deflection=deflection, isolator_force=force, flags=np.array([flag]), flag_time=np.array([flag_time]),
        reasons=(FLAG_REASONS[flag],), internal_states=states[2 * ndof:n_mech],
        nfev=int(solution.nfev), njev=int(solution.njev), message=str(solution.message),
        smoothing=eps, velocity_width=veps,
    )


@accepts(time_eval=Reals(unit="s", min_size=2, increasing=True), base=Instance((BaseMotion,), optional=True), initial_velocity=Reals(unit="m/s", optional=True),
         initial_deflection=Reals(unit="m", optional=True), **_SOLVER_OPTIONS)
def solve_ivp_reference(system, time_eval, *, base: BaseMotion | None = None, initial_velocity=None,
                        initial_deflection=None, gravity: bool | float = False, smoothing: float = 1e-4,
                        velocity_scale: float = 1.0, method: str = "BDF", rtol: float = 1e-6, atol=None,
                        max_step: float | None = None) -> ReferenceResponse:
    """Simulate ``system`` with a smoothed first-order model and a stiff ODE solver.

    The cross-check of :func:`idkit.simulate.simulate` (same inputs, same output
    fields). The model and its smoothing are described in the module docstring.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
        A Coulomb-spring system keeps its rigid slider, smoothed as ``Fc tanh(ydot / v_eps)``
        (its ``contact_stiffness_ratio`` is not used).
    time_eval : array_like, shape (n,)
        Strictly increasing output times in s; the run starts at ``time_eval[0]``.
    base : BaseMotion, optional
        Base motion (default: at rest). Given as displacement it is evaluated
        exactly (with its velocity function, else a cubic spline through
        ``time_eval``); given as velocity or acceleration it is integrated along
        with the system.
    initial_velocity : array_like (ndof,), optional
        Absolute mass velocities in m/s at ``time_eval[0]``, top first. Default at rest.
    initial_deflection : array_like (n_isolators,), optional
        Initial isolator deflections in m; internal states as in
        :func:`idkit.simulate.initial_states`. Default unloaded.
    gravity : bool or float
        True for 9.80665 m/s^2 downward, or a value in m/s^2.
    smoothing : float
        Dimensionless ``tanh`` width ``eps`` (> 0): Jenkin saturation is smoothed over
        relative force ``(F/Fc)^2 - 1 ~ eps``; velocity signs over ``v_eps = smoothing * velocity_scale``.
    velocity_scale : float
        Velocity in m/s that ``smoothing`` multiplies to give ``v_eps``. Default 1 m/s.
    method : {"BDF", "Radau", "LSODA"}
        :func:`scipy.integrate.solve_ivp` method, all given the analytic Jacobian. BDF is the
        family of the thesis's ``ode15s``; LSODA (compiled) is 5-10x faster on the hybrid
        system and agrees with BDF to about 1e-8 of the peak response.
    rtol : float
        Relative tolerance of the solver.
    atol : float or array_like, optional
        Absolute tolerance in SI units of each state (m, m/s, N); default ``1e-3 * rtol``,
        suited to motions of about a millimetre and more.
    max_step : float, optional
        Largest solver step in s.

    Returns
    -------
    ReferenceResponse
        A :class:`~idkit.simulate.TimeResponse` with batch size 1 plus solver details.
        A run that leaves the model's valid range (negative local stiffness of a
        polynomial spring) stops there: ``flags[0] = 1`` and NaN afterwards.

    Examples
    --------
    >>> from idkit.models import SDOFSystem, VoigtModel
    >>> system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.0))
    >>> run = solve_ivp_reference(system, np.linspace(0, 0.2, 3), initial_deflection=[1e-3], rtol=1e-9)
    >>> np.round(run.displacement[0, 0] * 1e3, 4).tolist()  # cos(2 pi 5 t) in mm
    [1.0, -1.0, 1.0]
    """
    return _solve(system, float(time_eval[0]), time_eval, base, initial_velocity, initial_deflection, gravity, smoothing,
                  velocity_scale, method, rtol, atol, max_step)


@accepts(freq=Real(unit="Hz", gt=0), amplitude=Real(unit="m", gt=0), n_periods=Whole(ge=4, even=True),
         n_harmonics=Whole(ge=1), samples_per_period=Whole(ge=4, even=True), **_SOLVER_OPTIONS)
def harmonic_reference(system, freq: float, amplitude: float, *, n_periods: int = 40, n_harmonics: int = 3,
                       smoothing: float = 1e-4, velocity_scale: float = 1.0, rtol: float = 1e-8,
                       atol=None, samples_per_period: int = 256, method: str = "BDF") -> ReferenceHarmonic:
    """Harmonic base displacement ``A sin(2 pi f t)`` from rest, analysed like :func:`harmonic_response`.

    The system starts at rest with unloaded isolators at ``t = 0``, runs
    ``n_periods`` excitation periods, and the top displacement is sampled
    ``samples_per_period`` times per period; the complex amplitudes at
    multiples ``m/2`` of ``f`` come from the last two periods (a DFT of the samples
    at ``t = (n_periods - 2 + n / samples_per_period) / f``).

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    freq : float
        Excitation frequency in Hz.
    amplitude : float
        Base displacement amplitude in m.
    n_periods : int
        Even number of periods to simulate (>= 4).
    n_harmonics : int
        Highest harmonic K; orders 0, 1/2, ..., K.
    smoothing, velocity_scale, rtol, atol, method : see :func:`solve_ivp_reference`.
    samples_per_period : int
        Even number of output samples per period (>= 4 K + 2 to avoid aliasing).

    Returns
    -------
    ReferenceHarmonic
    """
    n_coeff = 2 * n_harmonics + 1
    if samples_per_period < 2 * n_coeff:
        raise SimulationError(
            f"samples_per_period: found {samples_per_period!r}, expected an even integer >= {2 * n_coeff}"
        )
    per = int(samples_per_period)
    period = 1.0 / float(freq)
    # output: the last four periods (two windows) plus the end point
    samples = np.arange(4 * per + 1)
    time_eval = (int(n_periods) - 4) * period + samples * (period / per)
    run = _solve(system, 0.0, time_eval, BaseMotion.harmonic(freq, amplitude), None, None, False, smoothing,
                 velocity_scale, method, rtol, atol, None)
    if run.flags[0] != FLAG_OK:
        raise SimulationError(
            f"harmonic_reference: the run at {freq:g} Hz, {amplitude:g} m failed ({run.reasons[0]}) "
            f"at t = {run.flag_time[0]:g} s"
        )
    relative_top = run.displacement[0, 0]
    base_displacement = float(amplitude) * np.sin(2.0 * np.pi * float(freq) * time_eval)
    top = relative_top + base_displacement
    window = 2 * per
    n = np.arange(window)
    twiddle = np.exp(-2j * np.pi * np.outer(np.arange(n_coeff), n) / window)
    scale = np.full(n_coeff, 2.0 / window)
    scale[0] = 1.0 / window

    def coefficients(values):
        return scale * (twiddle @ values)

    previous = coefficients(top[:window])
    current = coefficients(top[window:2 * window])
    deflection = coefficients(relative_top[window:2 * window])
    first = abs(current[2]) if n_coeff > 2 else abs(current[0])
    change = float(np.max(np.abs(current - previous)) / max(first, 1e-300))
    last = top[window:2 * window]
    return ReferenceHarmonic(
        freq=float(freq), amplitude=float(amplitude), coefficients=current, deflection_coefficients=deflection,
        half_range=0.5 * float(last.max() - last.min()), change=change, periods=int(n_periods), response=run,
    )
