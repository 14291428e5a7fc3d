"""Flatten a system into the arrays the compiled kernel reads."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.errors import SimulationError
from idkit.limits import MAX_FORCE_SCALE
from idkit.models.systems import CoulombSpringSystem, HybridSystem, SDOFSystem
from idkit.gravity import STANDARD_GRAVITY



@dataclass(frozen=True)
class SystemArrays:
    masses: np.ndarray  # (ndof,) kg, top first
    poly: np.ndarray  # (ndof, 3)
    cvisc: np.ndarray  # (ndof,)
    jk: np.ndarray  # (ndof, nj)
    jfc: np.ndarray
    mk: np.ndarray  # (ndof, nm)
    mrate: np.ndarray
    bw: np.ndarray  # (ndof, 13) Bouc-Wen [active, k1, k2, k3, alpha, beta, gamma, n, b, c], pinching
    #                 [pinch, width N, shift N] (idkit.models.boucwen_pinched)
    sm: np.ndarray  # (ndof, 6) slip laws: modulation a [-], y_ref [m], b [-]; clearance gap [m];
    #                 rate dependence r [-], v_ref [m/s] (idkit.models.clearance, rate_dependent)

    @property
    def ndof(self) -> int:
        return int(self.masses.size)

    @property
    def slip_limits_vary(self) -> np.ndarray:
        """Per isolator: its Jenkin elements are not the plain stop operator of constant limits
        (slip modulation, clearance or rate-dependent slip forces), shape ``(ndof,)``."""
        return (self.sm[:, 0] != 0.0) | (self.sm[:, 2] != 0.0) | (self.sm[:, 3] != 0.0) | (self.sm[:, 4] != 0.0)

    def as_tuple(self):
        return (self.masses, self.poly, self.cvisc, self.jk, self.jfc, self.mk, self.mrate, self.bw, self.sm)


def resolve_system(system):
    """Accept SDOF, hybrid or Coulomb-spring systems; return an SDOF/hybrid system."""
    if isinstance(system, CoulombSpringSystem):
        return system.as_sdof()
    if isinstance(system, (SDOFSystem, HybridSystem)):
        return system
    raise SimulationError(
        f"system: found {type(system).__name__}, expected SDOFSystem, HybridSystem or CoulombSpringSystem "
        "(wrap an isolator model in SDOFSystem(mass, isolator))"
    )


def system_arrays(system) -> SystemArrays:
    """Flat, padded parameter arrays of ``system`` (isolator j sits below mass j)."""
    system = resolve_system(system)
    parts = [isolator.kernel_arrays() for isolator in system.isolators]
    ndof = len(parts)
    nj = max(1, max(p.jenkin_stiffness.size for p in parts))
    nm = max(1, max(p.maxwell_stiffness.size for p in parts))
    jk = np.zeros((ndof, nj))
    jfc = np.zeros((ndof, nj))
    mk = np.zeros((ndof, nm))
    mrate = np.ones((ndof, nm))
    for j, part in enumerate(parts):
        jk[j, : part.jenkin_stiffness.size] = part.jenkin_stiffness
        jfc[j, : part.jenkin_friction.size] = part.jenkin_friction
        mk[j, : part.maxwell_stiffness.size] = part.maxwell_stiffness
        mrate[j, : part.maxwell_rate.size] = part.maxwell_rate
    return SystemArrays(
        masses=np.array(system.masses, dtype=float),
        poly=np.array([p.poly for p in parts], dtype=float),
        cvisc=np.array([p.c_visc for p in parts], dtype=float),
        jk=jk, jfc=jfc, mk=mk, mrate=mrate,
        bw=np.array([np.concatenate([p.boucwen, p.pinching]) for p in parts], dtype=float).reshape(ndof, 13),
        sm=np.array([np.concatenate([p.slip_modulation, [p.clearance], p.slip_rate]) for p in parts],
                    dtype=float).reshape(ndof, 6),
    )




def force_scale(arrays: SystemArrays, accel_scale):
    """A force magnitude (N) for convergence tests: total mass times an acceleration scale
    (m/s^2) plus the slip forces; a float, or an array of one per run for an array of scales
    (each run's own, so that no run's tolerance depends on the others of its batch).

    Raises
    ------
    SimulationError
        When it reaches :data:`MAX_FORCE_SCALE` (``sqrt`` of the largest float64, 1.3e154 N;
        a mass of 1e300 kg, a base amplitude of 1e200 m): each step's Newton iteration takes
        the norm of its force residual as ``sqrt(r0 * r0 + r1 * r1)``, which overflows to
        infinity for residuals of that size, and convergence tests against an infinite force
        would pass whatever the state, so the run would mean nothing (it ended as "Newton
        iteration did not converge" or "not settled" instead of being refused).
    """
    with np.errstate(over="ignore"):
        scale = arrays.masses.sum() * (np.abs(accel_scale) + STANDARD_GRAVITY) + arrays.jfc.sum()
    if not (scale < MAX_FORCE_SCALE).all():
        accel = float(np.max(np.abs(accel_scale)))
        raise SimulationError(f"system: masses {arrays.masses.tolist()} kg times the acceleration scale "
                              f"{accel + STANDARD_GRAVITY:.3g} m/s^2 (plus slip forces {arrays.jfc.sum():.3g} N) "
                              f"give forces of {float(np.max(scale)):.3g} N, whose squares overflow float64 in "
                              f"the integrator's residual norm; expected forces below {MAX_FORCE_SCALE:.3g} N "
                              "(sqrt of the largest float64)")
    return float(scale) if np.ndim(scale) == 0 else np.ascontiguousarray(scale, dtype=float)
