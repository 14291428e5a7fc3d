"""Prescribed base (floor) motion for time simulations.

The simulator works in absolute mass coordinates; the base enters through its
displacement and velocity at every step time (:meth:`BaseMotion.on_grid`).
A :class:`BaseMotion` provides them from whatever the user has: displacement,
velocity or acceleration, as a function of time or as samples.

* acceleration is integrated with the integrator's own (trapezoidal) rule,
  ``v+ = v + h (a + a+) / 2``, ``x+ = x + h v + h^2 (a + a+) / 4``, so a run
  driven by base acceleration is exactly the run of the same system written in
  coordinates relative to the base;
* velocity is integrated with the trapezoidal rule;
* displacement is differentiated by a cubic spline through the grid samples.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np
from scipy.interpolate import CubicSpline

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.checks import Choice, Real, Reals, Samples, accepts
from idkit.errors import SimulationError

__all__ = ["BaseMotion", "QUANTITIES", "integrate_acceleration"]

QUANTITIES = ("displacement", "velocity", "acceleration")


@dataclass(frozen=True)
class BaseMotion:
    """Base motion given as one physical quantity (SI) as a function of time (s).

    Build with :meth:`harmonic`, :meth:`from_samples`, :meth:`from_function` or
    :meth:`at_rest`; the simulator calls :meth:`on_grid`.

    Examples
    --------
    >>> motion = BaseMotion.harmonic(5.0, 1e-3)          # 1 mm at 5 Hz
    >>> displacement, velocity = motion.on_grid(np.array([0.0, 0.05]))
    >>> velocity.round(6).tolist()
    [0.031416, 0.0]
    """

    quantity: str
    function: Callable[[np.ndarray], np.ndarray]
    description: str
    initial_displacement: float = 0.0
    initial_velocity: float = 0.0
    velocity_function: Callable[[np.ndarray], np.ndarray] | None = None

    def __post_init__(self):
        if self.quantity not in QUANTITIES:
            raise SimulationError(f"base motion quantity: found {self.quantity!r}, expected one of {QUANTITIES}")

    @classmethod
    def at_rest(cls) -> BaseMotion:
        """A fixed base (drops, free vibration)."""
        return cls("displacement", np.zeros_like, "base at rest", velocity_function=np.zeros_like)

    @classmethod
    @accepts(freq=Real(unit="Hz", gt=0), amplitude=Real(), quantity=Choice(QUANTITIES), phase=Real(unit="rad"),
             error=SimulationError)
    def harmonic(cls, freq: float, amplitude: float, *, quantity: str = "displacement",
                 phase: float = 0.0) -> BaseMotion:
        """``amplitude * sin(2 pi freq t + phase)`` of the given quantity (SI units)."""
        omega = 2.0 * np.pi * freq
        power = QUANTITIES.index(quantity)
        # displacement x = X sin(w t + p) with quantity amplitude X w^power (phase-shifted by power * 90 deg)
        x_amp = amplitude / omega**power
        shift = phase - power * np.pi / 2

        return cls(
            "displacement",
            lambda t: x_amp * np.sin(omega * t + shift),
            f"harmonic {quantity} {amplitude:g} at {freq:g} Hz",
            velocity_function=lambda t: x_amp * omega * np.cos(omega * t + shift),
        )

    @classmethod
    @accepts(time=Reals(unit="s", min_size=4, increasing=True), values=Samples(min_size=4),
             quantity=Choice(QUANTITIES), initial_displacement=Real(unit="m"), initial_velocity=Real(unit="m/s"),
             error=SimulationError)
    def from_samples(cls, time, values, *, quantity: str, initial_displacement: float = 0.0,
                     initial_velocity: float = 0.0) -> BaseMotion:
        """Base motion from samples of ``quantity`` (SI) at strictly increasing ``time`` (s).

        Between samples the quantity is interpolated linearly (acceleration,
        velocity) or by a cubic spline (displacement). The initial values apply
        when the motion is given as velocity or acceleration.
        """
        t, y = np.atleast_1d(time), values
        if t.shape != y.shape:
            raise SimulationError(f"BaseMotion.from_samples: found time shape {t.shape} and values shape {y.shape}, "
                                  "expected equal 1-D shapes")
        if quantity == "displacement":
            spline = CubicSpline(t, y)
            return cls("displacement", spline, f"sampled displacement ({t.size} samples)",
                       velocity_function=spline.derivative(1))
        return cls(quantity, lambda s: np.interp(s, t, y), f"sampled {quantity} ({t.size} samples)",
                   initial_displacement=initial_displacement, initial_velocity=initial_velocity)

    @classmethod
    def from_function(cls, function: Callable, *, quantity: str, initial_displacement: float = 0.0,
                      initial_velocity: float = 0.0) -> BaseMotion:
        """Base motion from a vectorized function of time (s) returning ``quantity`` (SI)."""
        return cls(quantity, function, f"{quantity} function", initial_displacement=initial_displacement,
                   initial_velocity=initial_velocity)

    def on_grid(self, time) -> tuple[np.ndarray, np.ndarray]:
        """Base displacement (m) and velocity (m/s) at the uniform grid ``time`` (s)."""
        t = np.asarray(time, dtype=float)
        values = np.asarray(self.function(t), dtype=float) * np.ones_like(t)
        if not np.all(np.isfinite(values)):
            bad = int(np.flatnonzero(~np.isfinite(values))[0])
            raise SimulationError(f"base {self.quantity}: found a non-finite value at t = {t[bad]:g} s")
        if self.quantity == "displacement":
            if self.velocity_function is not None:
                velocity = np.asarray(self.velocity_function(t), dtype=float) * np.ones_like(t)
            else:
                velocity = CubicSpline(t, values).derivative(1)(t) if t.size >= 4 else np.gradient(values, t)
            return values, velocity
        if self.quantity == "velocity":
            displacement = self.initial_displacement + np.concatenate(
                [[0.0], np.cumsum(0.5 * (values[1:] + values[:-1]) * np.diff(t))]
            )
            return displacement, values
        step = float(t[1] - t[0]) if t.size > 1 else 0.0
        return integrate_acceleration(values, step, self.initial_displacement, self.initial_velocity)


def integrate_acceleration(acceleration, time_step: float, initial_displacement=0.0, initial_velocity=0.0):
    """Displacement and velocity from acceleration samples by the trapezoidal (Newmark) rule.

    ``acceleration`` may be 1-D (n,) or 2-D (batch, n); integration runs along the last axis.
    ``v_i = v_0 + sum_{j<i} h/2 (a_j + a_{j+1})`` and ``x_i = x_0 + sum_{j<i} h/2 (v_j + v_{j+1})``
    (the Newmark average-acceleration update ``x+ = x + h v + h^2/4 (a + a+)``), summed
    in order in one compiled pass per row, starting from ``v_0`` and ``x_0``: integrating
    the second part of a record from the first part's last values gives the same numbers,
    bit for bit, as integrating the whole record.
    """
    a = np.asarray(acceleration, dtype=float)
    h = float(time_step)
    # C-contiguous and writeable arrays only (a read-only input or broadcast is another numba type:
    # another compile of the kernel)
    rows = np.require(a.reshape(-1, a.shape[-1]), requirements=["C", "W"])
    v0 = np.broadcast_to(np.asarray(initial_velocity, dtype=float), a.shape[:-1]).reshape(-1)
    x0 = np.broadcast_to(np.asarray(initial_displacement, dtype=float), a.shape[:-1]).reshape(-1)
    displacement, velocity = np.empty_like(rows), np.empty_like(rows)
    _trapezoid_rows(rows, h, np.require(x0, requirements=["C", "W"]), np.require(v0, requirements=["C", "W"]),
                    displacement, velocity)
    return displacement.reshape(a.shape), velocity.reshape(a.shape)


@numba.njit(cache=True, nogil=True)
def _trapezoid_rows(a, h, x0, v0, displacement, velocity):
    half = 0.5 * h
    for row in range(a.shape[0]):
        n = a.shape[1]
        if n == 0:
            continue
        sum_v = v0[row]
        sum_x = x0[row]
        velocity[row, 0] = sum_v
        displacement[row, 0] = sum_x
        for i in range(1, n):
            sum_v += half * (a[row, i] + a[row, i - 1])
            velocity[row, i] = sum_v
            sum_x += half * (velocity[row, i] + velocity[row, i - 1])
            displacement[row, i] = sum_x
