"""Force-driven Bouc-Wen oscillator: force samples in, displacement out.

The system of the Noel & Schoukens hysteretic benchmark (2016), written with
idkit's modified Bouc-Wen force (SPEC 1.3, :class:`~idkit.models.BoucWenModel`):

``m x'' + b^(c x) (k1 x + k2 sgn(x) x^2 + k3 x^3 + z) + c_visc x' = u(t)``,
``z' = x' (alpha - (gamma + beta sgn(x' z)) |z|^n)``, times the pinching factor of a
:class:`~idkit.models.PinchedBoucWenModel` (:func:`idkit.models.laws.pinching_factor`).

The benchmark's own law ``m y'' + c y' + k y + z = u``,
``z' = alpha y' - beta_B (gamma_B |y'| |z|^(nu-1) z + delta_B y' |z|^nu)`` is the
case ``k1 = k``, ``c_visc = c``, ``k2 = k3 = 0``, ``b = 1``, ``n = nu``,
``beta = beta_B gamma_B`` and ``gamma = beta_B delta_B`` (:func:`benchmark_truth`).

Integration: classical Runge-Kutta (order 4) on the state ``(x, x', z)`` with
``substeps`` steps per force sample. The benchmark's data were generated at
20 steps per sample (750 Hz x 20 = 15 kHz, Newmark); :data:`SUBSTEPS_PER_SAMPLE`
keeps that rate. The ``sgn(x' z)`` switch kinks the right-hand side at every
velocity reversal, so RK4 converges at about order 2.3 there: against
``solve_ivp`` (DOP853, rtol 1e-10) on the same force the largest error is
5e-5 of the peak displacement at 20 steps per sample, 6e-6 at 40, 1e-4 at 10
(tests/simulate/test_force_driven.py), smaller for smoother laws.

Between samples the force is reconstructed (``interpolation``):

* ``"fourier"``: band-limited periodic interpolation (zero-padded FFT). Exact
  for a record holding whole periods of a multisine sampled above twice its
  band, which is how the benchmark's multisines were made (designed on the
  15 kHz grid, then every 20th sample kept).
* ``"cubic"``: not-a-knot cubic spline through the samples, for non-periodic
  records (sweeps, transients). Relative error about ``(2 pi f / fs)^4 / 384``
  at frequency ``f``: 8e-5 at 50 Hz and 750 Hz.
* ``"linear"`` and ``"hold"`` (zero-order hold: ``u(t) = u_k`` on
  ``[t_k, t_k+1)``): for inputs that really are piecewise linear or held. A held
  input lags the band-limited one by half a sample, which is why a zero-order-hold
  re-simulation of the benchmark misses its data unless shifted by half a
  sample.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
from scipy.interpolate import CubicSpline

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.checks import Choice, Real, Samples, Whole, accepts
from idkit.errors import ParameterError, SimulationError
from idkit.models.boucwen import BoucWenModel
from idkit.models.boucwen_pinched import PinchedBoucWenModel
from idkit.models.laws import kernel_array, pinching_factor

__all__ = [
    "INTERPOLATIONS",
    "SUBSTEPS_PER_SAMPLE",
    "ForceDrivenResponse",
    "ForceInput",
    "benchmark_truth",
    "force_driven_rates",
    "simulate_force_driven",
]

#: Runge-Kutta steps per force sample (the benchmark's own 20x internal rate).
SUBSTEPS_PER_SAMPLE = 20
#: Force reconstructions between samples (module docstring).
INTERPOLATIONS = ("cubic", "fourier", "linear", "hold")
#: A displacement beyond this (m) is taken as a run-away simulation.
RUNAWAY_DISPLACEMENT = 1e3


def benchmark_truth() -> tuple[BoucWenModel, float]:
    """The generating model of the Noel & Schoukens benchmark in idkit's parameters.

    Returns
    -------
    model : BoucWenModel
        ``k1 = 5e4`` N/m, ``c_visc = 10`` N s/m, ``alpha = 5e4`` N/m,
        ``beta = 1e3 * 0.8 = 800`` 1/m, ``gamma = 1e3 * (-1.1) = -1100`` 1/m,
        ``n = 1`` (Noel & Schoukens 2016, Table 1).
    mass_kg : float
        2 kg.

    Examples
    --------
    >>> model, mass_kg = benchmark_truth()
    >>> round(model.beta + model.gamma), mass_kg
    (-300, 2.0)
    """
    model = BoucWenModel(k1=5e4, k2=0.0, k3=0.0, alpha=5e4, beta=1e3 * 0.8, gamma=1e3 * -1.1, n=1.0,
                         c_visc=10.0)
    return model, 2.0


@dataclass(frozen=True, eq=False)
class ForceInput:
    """Force samples and their reconstruction on the integrator's grid.

    Build with :meth:`from_samples`. ``grid`` holds the force in N at every
    half Runge-Kutta step: ``(n_samples - 1) * 2 * substeps + 1`` values.

    Examples
    --------
    >>> force = ForceInput.from_samples(np.sin(np.arange(8) * np.pi / 4), 750.0, interpolation="fourier",
    ...                                 substeps=2)
    >>> force.grid[:3].round(4).tolist()                     # sin at 0, 1/4 and 1/2 sample
    [0.0, 0.1951, 0.3827]
    """

    force: np.ndarray
    sample_rate_hz: float
    interpolation: str
    substeps: int
    grid: np.ndarray = field(repr=False)

    @classmethod
    @accepts(force=Samples(unit="N", min_size=4), sample_rate_hz=Real(unit="Hz", gt=0),
             interpolation=Choice(INTERPOLATIONS), substeps=Whole(ge=1), error=SimulationError)
    def from_samples(cls, force, sample_rate_hz: float, *, interpolation: str = "cubic",
                     substeps: int = SUBSTEPS_PER_SAMPLE) -> ForceInput:
        """Reconstruct ``force`` (N, sampled at ``sample_rate_hz``) between its samples.

        Parameters
        ----------
        force : array_like
            Force samples in N (at least 4, finite).
        sample_rate_hz : float
            Sample rate in Hz (> 0).
        interpolation : {"cubic", "fourier", "linear", "hold"}
            Reconstruction between samples (module docstring).
        substeps : int
            Runge-Kutta steps per sample (>= 1).

        Raises
        ------
        SimulationError
            On a bad force array, rate, interpolation or substep count.
        """
        values, rate = force, sample_rate_hz
        points = 2 * substeps
        n_grid = (values.size - 1) * points + 1
        if interpolation == "fourier":
            grid = _fourier_upsample(values, points)[:n_grid]
        else:
            position = np.arange(n_grid) / points                      # in samples
            if interpolation == "cubic":
                grid = CubicSpline(np.arange(values.size), values)(position)
            elif interpolation == "linear":
                grid = np.interp(position, np.arange(values.size), values)
            else:
                grid = values[np.minimum(np.floor(position + 1e-9).astype(np.int64), values.size - 1)]
        values = values.copy()
        values.setflags(write=False)
        return cls(values, rate, interpolation, substeps, kernel_array(grid))


def _fourier_upsample(values: np.ndarray, factor: int) -> np.ndarray:
    """Band-limited periodic interpolation of ``values`` to ``factor`` times the rate."""
    n = values.size
    spectrum = np.fft.rfft(values)
    padded = np.zeros(n * factor // 2 + 1, dtype=complex)
    padded[:spectrum.size] = spectrum
    if n % 2 == 0:
        padded[n // 2] *= 0.5                       # split the Nyquist bin between +/- frequencies
    return np.fft.irfft(padded, n * factor) * factor


@dataclass(frozen=True, eq=False)
class ForceDrivenResponse:
    """Response of the force-driven Bouc-Wen oscillator at the force samples.

    Parameters
    ----------
    time : numpy.ndarray
        Sample times in s from 0.
    force : numpy.ndarray
        Applied force samples in N.
    displacement, velocity : numpy.ndarray
        In m and m/s (NaN after a failure).
    hysteretic_force : numpy.ndarray
        ``z`` in N.
    substeps : int
        Runge-Kutta steps per sample.
    interpolation : str
        Force reconstruction between samples.
    success : bool
        False if the run stopped (non-finite or run-away state).
    reasons : tuple of str
        Why ``success`` is False.
    """

    time: np.ndarray
    force: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    hysteretic_force: np.ndarray
    substeps: int
    interpolation: str
    success: bool
    reasons: tuple[str, ...] = ()


@accepts(mass_kg=Real(unit="kg", gt=0), error=ParameterError)
def force_driven_rates(model: BoucWenModel, mass_kg: float) -> np.ndarray:
    """Kernel parameter vector ``[m, c_visc, k1, k2, k3, alpha, beta, gamma, n, c ln b, pinch,
    width, shift]`` (the last three the pinching of a :class:`~idkit.models.PinchedBoucWenModel`,
    width and shift in N; zeros without pinching).

    Parameters
    ----------
    model : BoucWenModel
        Restoring force.
    mass_kg : float
        Moving mass in kg (> 0, finite).

    Returns
    -------
    numpy.ndarray
        The 13 numbers the compiled kernel reads (SI).

    Examples
    --------
    >>> force_driven_rates(*benchmark_truth())[:3].tolist()
    [2.0, 10.0, 50000.0]
    """
    mass = mass_kg
    pinching = model.pinching() if isinstance(model, PinchedBoucWenModel) else (0.0, 0.0, 0.0)
    return np.array([mass, model.c_visc, model.k1, model.k2, model.k3, model.alpha, model.beta, model.gamma,
                     model.n, model.c * math.log(model.b), *pinching])


@accepts(initial_displacement=Real(unit="m"), initial_velocity=Real(unit="m/s"), initial_z=Real(unit="N"),
         error=SimulationError)
def simulate_force_driven(model: BoucWenModel, mass_kg: float, force, sample_rate_hz: float | None = None, *,
                          interpolation: str = "cubic", substeps: int = SUBSTEPS_PER_SAMPLE,
                          initial_displacement: float = 0.0, initial_velocity: float = 0.0,
                          initial_z: float = 0.0) -> ForceDrivenResponse:
    """Displacement of a mass on a Bouc-Wen element driven by a sampled force.

    Parameters
    ----------
    model : BoucWenModel
        Restoring force (stiffness, viscous damping, hysteresis).
    mass_kg : float
        Moving mass in kg.
    force : array_like or ForceInput
        Force samples in N, or a :class:`ForceInput` already reconstructed
        (then ``sample_rate_hz``, ``interpolation`` and ``substeps`` come from it).
    sample_rate_hz : float
        Sample rate of ``force`` in Hz (required with an array).
    interpolation : {"cubic", "fourier", "linear", "hold"}
        Force between samples (module docstring).
    substeps : int
        Runge-Kutta steps per sample.
    initial_displacement, initial_velocity, initial_z : float
        State at the first sample (m, m/s, N); default at rest.

    Returns
    -------
    ForceDrivenResponse
        Displacement, velocity and ``z`` at every force sample.

    Examples
    --------
    >>> model, mass_kg = benchmark_truth()
    >>> ramp = np.linspace(0.0, 10.0, 3000)               # 0 -> 10 N in 4 s: quasi-static
    >>> response = simulate_force_driven(model, mass_kg, ramp, 750.0)
    >>> round(float(response.displacement[-1]) * 1e3, 4)  # root of k1 x + (alpha/300)(exp(300 x) - 1) = 10 N
    0.0993
    """
    if not isinstance(force, ForceInput):
        if sample_rate_hz is None:
            raise SimulationError("sample_rate_hz: found None, expected the force sample rate in Hz")
        force = ForceInput.from_samples(force, sample_rate_hz, interpolation=interpolation, substeps=substeps)
    rates = force_driven_rates(model, mass_kg)
    initial = np.array([initial_displacement, initial_velocity, initial_z], dtype=float)
    states, completed = _run(rates, force.grid, force.substeps, 1.0 / (force.sample_rate_hz * force.substeps),
                             initial, RUNAWAY_DISPLACEMENT)
    n_samples = force.force.size
    reasons = ()
    if completed < n_samples:
        reasons = ((f"the state became non-finite or |x| exceeded {RUNAWAY_DISPLACEMENT:g} m at sample {completed} "
                   f"of {n_samples} (t = {completed / force.sample_rate_hz:g} s)"),)
    return ForceDrivenResponse(
        time=np.arange(n_samples) / force.sample_rate_hz, force=force.force, displacement=states[:, 0],
        velocity=states[:, 1], hysteretic_force=states[:, 2], substeps=force.substeps,
        interpolation=force.interpolation, success=not reasons, reasons=reasons)


@numba.njit(cache=True)
def _rates(x, v, z, u, p):
    """``(x', v', z')`` of the force-driven oscillator; ``p`` from :func:`force_driven_rates`."""
    product = v * z
    if product > 0.0:
        sign = 1.0
    elif product < 0.0:
        sign = -1.0
    else:
        sign = 0.0
    magnitude = abs(z) if p[8] == 1.0 else abs(z) ** p[8]          # the power is the costly part
    z_rate = v * (p[5] - (p[7] + p[6] * sign) * magnitude)
    if p[10] != 0.0:  # Baber-Noori pinching (idkit.models.boucwen_pinched)
        z_rate *= pinching_factor(z, 1.0 if v > 0.0 else -1.0 if v < 0.0 else 0.0, p[10], p[11], p[12])
    elastic = x * (p[2] + p[3] * abs(x) + p[4] * x * x)
    restoring = math.exp(p[9] * x) * (elastic + z) + p[1] * v
    return v, (u - restoring) / p[0], z_rate


@numba.njit(cache=True)
def _run(p, grid, substeps, step, initial, runaway):
    """RK4 over the force grid; returns the state at each sample and how many samples are valid."""
    n_samples = (grid.shape[0] - 1) // (2 * substeps) + 1
    states = np.full((n_samples, 3), np.nan)
    x, v, z = initial[0], initial[1], initial[2]
    states[0, 0], states[0, 1], states[0, 2] = x, v, z
    half = 0.5 * step
    for k in range(1, n_samples):
        for j in range(substeps):
            i = 2 * ((k - 1) * substeps + j)
            u0, um, u1 = grid[i], grid[i + 1], grid[i + 2]
            ax, av, az = _rates(x, v, z, u0, p)
            bx, bv, bz = _rates(x + half * ax, v + half * av, z + half * az, um, p)
            cx, cv, cz = _rates(x + half * bx, v + half * bv, z + half * bz, um, p)
            dx, dv, dz = _rates(x + step * cx, v + step * cv, z + step * cz, u1, p)
            x += step / 6.0 * (ax + 2.0 * bx + 2.0 * cx + dx)
            v += step / 6.0 * (av + 2.0 * bv + 2.0 * cv + dv)
            z += step / 6.0 * (az + 2.0 * bz + 2.0 * cz + dz)
        if not (abs(x) <= runaway and math.isfinite(v) and math.isfinite(z)):
            return states, k
        states[k, 0], states[k, 1], states[k, 2] = x, v, z
    return states, n_samples
