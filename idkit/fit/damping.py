"""Viscous damping of a wire rope from the resonance of one stepped-sine level.

Quasi-static loops carry no rate information, so an Iwan model fitted to them has
``c_visc = 0``. Where the fitted elements do not slip, such a model dissipates
nothing: the simulated resonance has no damping to settle on (thousands of
periods) and its peak is far too high. The rule here identifies ``c_visc`` from
data the study measures anyway:

1. take the stepped-sine points of one excitation level, by default the largest
   (``level="largest"``), and reduce each to its first-order HOSIDF
   ``H1 = V_top,1 / V_base,1``, as the validation does;
2. locate the measured resonance peak ``|H1|`` (parabola in log f through the
   three highest points);
3. find ``c_visc`` such that the simulated peak of the same points (same top
   mass, same first-harmonic base amplitudes, the fitted hysteresis kept) equals the
   measured one: bisection in ``log c`` (the peak falls monotonically with damping).

If the hysteresis alone already damps the simulated peak below the measured one,
``c_visc = 0`` and the result says so. The measured peak is a maximum over the
points, so it depends on the frequency spacing near resonance; the parabola
corrects most of that.

**Why the largest level.** ``c_visc`` stands for rate-dependent losses only. At the
largest level the fitted elements slip as they did in the loops, so the fitted
hysteresis accounts for the friction loss and the remainder is viscous. At small
levels a real rope also dissipates by micro-slip, which a low-order model may not
hold (its first element may slip only beyond the level's deflection): matching the
peak there would load that hysteretic loss onto ``c_visc`` and over-damp every
larger level. The peak-matching value of every level is
reported (:attr:`ViscousDamping.per_level`) so that a reader sees how
much damping the hysteresis model misses at small amplitude.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from idkit.signal.harmonics import hosidf, resonance_peak
from idkit.errors import FitError
from idkit.models import IwanModel, SDOFSystem
from idkit.simulate import harmonic_response

__all__ = ["ViscousDamping", "fit_viscous_damping"]

BISECTION_STEPS = 30  # log-bisection over 9 decades: 30 halvings resolve the peak to ~1e-6 in log c
PEAK_TOLERANCE = 1e-3  # relative mismatch of the peak at which the search stops


@dataclass(frozen=True)
class ViscousDamping:
    """Result of :func:`fit_viscous_damping`.

    Attributes
    ----------
    c_visc : float
        Identified viscous damping, N s/m (0 when the hysteresis alone damps enough).
    level : float
        Excitation level used (nominal amplitude of the points, their unit).
    points : int
        Stepped-sine points of that level.
    peak_frequency_hz, peak_measured : float
        Measured resonance (Hz) and peak |H1| (-).
    peak_simulated : float
        Simulated peak |H1| with the identified ``c_visc``.
    damping_ratio : float
        ``c_visc / (2 sqrt(K_stuck m))`` with the model's stuck stiffness and the top mass.
    message : str
        How the value was reached.
    per_level : dict
        Level -> the ``c_visc`` that would match that level's peak alone (N s/m), for
        every level with a resonance inside its sweep (the spread is the amplitude
        dependence of the damping that the hysteresis model does not hold).
    unsettled_points : int
        Points of the level whose simulation with the identified ``c_visc`` did not reach
        a steady state within the harmonic runs' period limit: where it is not 0,
        ``peak_simulated`` is read off transients and the match that set ``c_visc`` is not
        reliable (the measurement fit then is not a success).
    """

    c_visc: float
    level: float
    points: int
    peak_frequency_hz: float
    peak_measured: float
    peak_simulated: float
    damping_ratio: float
    message: str
    per_level: dict
    unsettled_points: int = 0

    def model(self, fitted: IwanModel) -> IwanModel:
        """``fitted`` with this viscous damping."""
        return type(fitted).from_params({**fitted.params(), "c_visc": self.c_visc})


def _first_harmonics(measurements):
    rows = []
    for measurement in measurements:
        info = measurement.info
        if info.excitation is None or info.excitation.freq is None:
            raise FitError(f"{info.id}: excitation frequency missing, needed to read the first harmonic")
        if info.top_mass_kg is None:
            raise FitError(f"{info.id}: top_mass_kg missing, needed to simulate the sweep")
        freq = float(info.excitation.freq)
        fs = 1.0 / float(np.median(np.diff(measurement.time)))
        point = hosidf(measurement.v_base, measurement.v_top, fs=fs, freq=freq, n_harmonics=1, subharmonic=False)
        level = info.excitation.amplitude if info.excitation.amplitude is not None else point.input_amplitude
        rows.append((float(level), float(info.top_mass_kg), freq, float(point.input_amplitude),
                     abs(complex(point.hosidf[0]))))
    return rows


def fit_viscous_damping(model: IwanModel, measurements, *, level="largest", tolerance: float = 1e-3,
                        workers: int | None = None) -> ViscousDamping:
    """Identify ``c_visc`` of a fitted Iwan model from one stepped-sine level (module docstring).

    Parameters
    ----------
    model : IwanModel
        The rope fitted to quasi-static loops (its ``c_visc`` is replaced).
    measurements : sequence of SteppedSineMeasurement
        Stepped-sine points of the rope on one top mass (fit split); at least three
        per level, with the resonance inside their frequency range.
    level : {"largest", "smallest"} or float
        The excitation level whose resonance peak is matched.
    tolerance : float
        Steady-state tolerance of the harmonic runs.

    Raises
    ------
    FitError
        No points, several top masses in a level, fewer than three points, a level
        that is not measured, or a measured peak at the edge of its sweep.
    """
    rows = _first_harmonics(list(measurements))
    if not rows:
        raise FitError("stepped-sine measurements: found none, expected the sweep points of the wire rope")
    levels = sorted({row[0] for row in rows})
    if level == "largest":
        chosen_level = levels[-1]
    elif level == "smallest":
        chosen_level = levels[0]
    else:
        matches = [value for value in levels if math.isclose(value, float(level), rel_tol=1e-6)]
        if not matches:
            raise FitError(f"level: found {level!r}, expected 'largest', 'smallest' or one of {levels}")
        chosen_level = matches[0]
    per_level, chosen = {}, None
    for value in levels:
        points = [row for row in rows if math.isclose(row[0], value, rel_tol=1e-6)]
        try:
            fitted = _match_level(model, value, points, tolerance, workers)
        except FitError:
            if value == chosen_level:
                raise
            continue
        per_level[value] = fitted.c_visc
        if value == chosen_level:
            chosen = fitted
    return ViscousDamping(**{**chosen.__dict__, "per_level": per_level})


def _match_level(model, level, rows, tolerance, workers) -> ViscousDamping:
    masses = {row[1] for row in rows}
    if len(masses) != 1:
        raise FitError(f"level {level:g}: found top masses {sorted(masses)}, expected one")
    if len(rows) < 3:
        raise FitError(f"level {level:g}: found {len(rows)} points, expected at least 3")
    mass = masses.pop()
    freq = np.array([row[2] for row in rows])
    base_amplitude = np.array([row[3] for row in rows]) / (2 * np.pi * freq)
    measured = np.array([row[4] for row in rows])
    order = np.argsort(freq)
    freq, base_amplitude, measured = freq[order], base_amplitude[order], measured[order]
    top = int(np.argmax(measured))
    if top in (0, freq.size - 1):
        raise FitError(f"level {level:g}: the measured |H1| peaks at the edge of the sweep "
                       f"({freq[top]:g} Hz), expected the resonance inside {freq[0]:g}-{freq[-1]:g} Hz")
    f_peak, peak_measured = resonance_peak(freq, measured)

    unsettled = {}  # c_visc -> points whose run did not settle

    def simulated_peak(c_visc: float) -> float:
        trial = type(model).from_params({**model.params(), "c_visc": c_visc})
        response = harmonic_response(SDOFSystem(mass, trial), freq, base_amplitude, n_harmonics=1,
                                     tolerance=tolerance, start="linear", workers=workers)
        unsettled[c_visc] = int(np.count_nonzero(~response.converged))
        return resonance_peak(freq, np.abs(response.hosidf(1)))[1]

    def not_settled(c_visc: float) -> str:
        count = unsettled[c_visc]
        return (f"; {count} of {freq.size} simulated points did not settle with it (peak read off transients)"
                if count else "")

    critical = 2.0 * math.sqrt(float(model.stuck_stiffness) * mass)
    low, high = 1e-6 * critical, 1e3 * critical
    peak_low = simulated_peak(low)
    if peak_low <= peak_measured:
        peak_zero = simulated_peak(0.0)
        return ViscousDamping(0.0, level, len(rows), f_peak, peak_measured, peak_zero, 0.0,
                              f"the hysteresis alone gives a peak {peak_low:.4g} <= measured {peak_measured:.4g}: "
                              "c_visc = 0" + not_settled(0.0), {}, unsettled[0.0])
    value, peak = low, peak_low
    for step in range(BISECTION_STEPS):
        value = math.sqrt(low * high)
        peak = simulated_peak(value)
        if abs(peak / peak_measured - 1.0) < PEAK_TOLERANCE:
            break
        if peak > peak_measured:
            low = value
        else:
            high = value
    return ViscousDamping(value, level, len(rows), f_peak, peak_measured, peak, value / critical,
                          f"peak matched to {abs(peak / peak_measured - 1):.1e} after {step + 1} bisections"
                          + not_settled(value), {}, unsettled[value])
