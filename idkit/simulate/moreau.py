"""Moreau-Jean time stepping of the parallel Coulomb-spring system (thesis 3.3.1, SPEC 1.5).

``m x'' + k (x - x_b) + c (x' - x_b') + lambda = 0`` with the set-valued friction law
``lambda in Fc Sgn(x' - x_b')`` (eq. 3.15: ``Sgn(0) = [-1, 1]``).

The scheme works on the level of velocities (impulses), so the friction force in
stick is whatever keeps the relative velocity at zero, bounded by ``Fc``; no
smoothing, no drift. One step from ``t_n`` to ``t_{n+1} = t_n + h``:

* theta rule for the smooth forces and the position,
  ``x_{n+1} = x_n + h (theta v_{n+1} + (1 - theta) v_n)``,
  ``m (v_{n+1} - v_n) = -h [k y_theta + c ydot_theta] - h lambda`` where
  ``y_theta = theta y_{n+1} + (1 - theta) y_n`` (likewise ``ydot``) and ``y = x - x_b``;
* ``lambda`` (N, the mean friction force over the step) satisfies the friction
  law at the end-of-step relative velocity, ``lambda in Fc Sgn(ydot_{n+1})``.

Everything but ``lambda`` is linear in ``v_{n+1}``: with the effective mass
``m_eff = m + h theta c + h^2 theta^2 k`` and the free relative velocity
``ydot_free`` (``lambda = 0``), ``ydot_{n+1} = ydot_free - h lambda / m_eff``. The
inclusion is then solved exactly by the projection
``lambda = proj_[-Fc, Fc](m_eff ydot_free / h)``: inside the interval the
step sticks (``ydot_{n+1} = 0`` exactly), on its boundary it slips.

``theta = 0.5`` (default) is the midpoint/trapezoidal rule: second order in the
smooth phases and energy-conserving for the spring. ``theta = 1`` is the
implicit-Euler variant of Moreau-Jean: first order, numerically dissipative.
The scheme is first order across stick-slip switches whatever theta, because a
switch falls somewhere inside a step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.checks import Instance, Real, Reals, accepts
from idkit.errors import SimulationError
from idkit.models.systems import CoulombSpringSystem
from idkit.simulate.base_motion import BaseMotion

__all__ = ["MoreauResponse", "moreau_coulomb_spring"]


@dataclass(frozen=True)
class MoreauResponse:
    """Response of :func:`moreau_coulomb_spring` at the grid times.

    Attributes
    ----------
    time : (n,) s
    displacement : (n,) m, mass displacement relative to the base (the deflection
        of spring and slider, positive = tension)
    velocity : (n,) m/s, relative velocity
    friction_force : (n,) N, force in the slider (isolator convention: positive in
        tension, so the mass feels ``-friction_force``). Entry ``i >= 1`` is the mean
        force over the step ending at ``time[i]``; entry 0 is the force of the
        initial state (``clip(-k y0, -Fc, Fc)`` when it starts at relative rest, else
        ``Fc sgn(ydot0)``).
    stick : (n,) bool, True where the step ended in stick (relative velocity 0)
    theta : float, the theta of the scheme
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    friction_force: np.ndarray
    stick: np.ndarray
    theta: float


@accepts(system=Instance((CoulombSpringSystem,)), time=Reals(unit="s", min_size=2, increasing=True),
         base=Instance((BaseMotion,), optional=True), theta=Real(ge=0.5, le=1),
         initial_displacement=Real(unit="m"), initial_velocity=Real(unit="m/s"), error=SimulationError)
def moreau_coulomb_spring(system: CoulombSpringSystem, time, *, base: BaseMotion | None = None,
                          initial_displacement: float = 0.0, initial_velocity: float = 0.0,
                          theta: float = 0.5) -> MoreauResponse:
    """Simulate the parallel Coulomb-spring system with Moreau-Jean time stepping.

    Parameters
    ----------
    system : CoulombSpringSystem
        Mass (kg), spring stiffness (N/m), friction force ``Fc`` (N) and viscous
        damping (N s/m); its ``contact_stiffness_ratio`` is not used (the slider is rigid).
    time : array_like, shape (n,)
        Strictly increasing times in s; their spacing is the step (may vary).
    base : BaseMotion, optional
        Base motion (default at rest), evaluated by ``base.on_grid(time)``.
    initial_displacement : float
        Mass displacement relative to the base at ``time[0]`` in m.
    initial_velocity : float
        Absolute velocity of the mass at ``time[0]`` in m/s.
    theta : float
        0.5 (midpoint, default) to 1 (implicit Euler), see the module docstring.

    Returns
    -------
    MoreauResponse

    Examples
    --------
    Free vibration of thesis 3.3.1: the amplitude drops by ``2 Fc / k`` each half
    cycle and the mass sticks at ``Fc / k`` with the friction force carrying the spring.

    >>> from idkit.models import CoulombSpringSystem
    >>> system = CoulombSpringSystem(mass=10.0, stiffness=9000.0, friction_force=1000.0)
    >>> run = moreau_coulomb_spring(system, np.arange(4097) / 2048, initial_displacement=1.0)
    >>> round(float(run.displacement[-1]), 3), round(float(run.friction_force[-1]))
    (0.111, -1000)
    """
    t = np.atleast_1d(time)
    x_base, v_base = (base or BaseMotion.at_rest()).on_grid(t)
    m, k, c, fc = system.mass, system.stiffness, system.damping, system.friction_force

    n = t.size
    y = np.empty(n)
    ydot = np.empty(n)
    friction = np.empty(n)
    stick = np.zeros(n, dtype=bool)
    y[0] = float(initial_displacement)
    ydot[0] = float(initial_velocity) - v_base[0]
    if ydot[0] == 0.0:
        friction[0] = np.clip(-k * y[0], -fc, fc)
        stick[0] = abs(k * y[0]) <= fc
    else:
        friction[0] = fc * np.sign(ydot[0])

    # Work in absolute position/velocity x, v; the base enters through x_b, v_b at the step ends.
    x = y[0] + x_base[0]
    v = ydot[0] + v_base[0]
    for i in range(1, n):
        h = t[i] - t[i - 1]
        yn = x - x_base[i - 1]
        ydn = v - v_base[i - 1]
        m_eff = m + h * theta * c + (h * theta) ** 2 * k
        # With lambda = 0: m (v+ - v) = -h [k (theta y+ + (1-theta) y) + c (theta yd+ + (1-theta) yd)],
        # y+ = x + h (theta v+ + (1-theta) v) - x_b+, yd+ = v+ - v_b+.
        y_pred = x + h * (1.0 - theta) * v - x_base[i]  # y+ without the theta h v+ part
        rhs = (m * v - h * (k * (theta * y_pred + (1.0 - theta) * yn)
                            + c * (-theta * v_base[i] + (1.0 - theta) * ydn)))
        v_free = rhs / m_eff
        ydot_free = v_free - v_base[i]
        lam = min(max(m_eff * ydot_free / h, -fc), fc)
        v_new = v_free - h * lam / m_eff
        ydot_new = v_new - v_base[i]
        if abs(m_eff * ydot_free / h) <= fc:
            ydot_new = 0.0  # stick: exactly zero relative velocity (remove round-off)
            v_new = v_base[i]
            stick[i] = True
        x = x + h * (theta * v_new + (1.0 - theta) * v)
        v = v_new
        y[i] = x - x_base[i]
        ydot[i] = ydot_new
        friction[i] = lam
    return MoreauResponse(time=t, displacement=y, velocity=ydot, friction_force=friction, stick=stick,
                          theta=theta)
