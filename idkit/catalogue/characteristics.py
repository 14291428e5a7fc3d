"""Side-by-side characteristics of catalogue parts, with uncertainty bands from their covariance.

Per part, for its mean model and ``n_draws`` draws (:func:`idkit.catalogue.uncertainty.draw_models`):

* **secant stiffness and loss factor versus amplitude**: the model driven by a sinusoidal
  deflection of amplitude ``X`` at :data:`CYCLE_FREQ_HZ` (two cycles from rest, the second
  one read): ``k_eq = (F_max - F_min) / (2 X)`` and ``eta_eq = W / (pi k_eq X^2)`` with ``W``
  the loop's enclosed energy (the definitions of :mod:`idkit.studies.equivalent`);
* **loops** at the common amplitudes, force against deflection, mean model;
* **transmissibility** ``|H(f)|`` of the small-amplitude model under a common payload per mount.

Bands: the 5 and 95 % quantiles over the draws.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.catalogue.uncertainty import draw_models
from idkit.models import SDOFSystem
from idkit.studies.equivalent import loss_factor_of_cycles

__all__ = ["CYCLE_FREQ_HZ", "PartCharacteristics", "part_characteristics"]

#: Frequency (Hz) of the sinusoidal cycles the equivalent stiffness and loss factor are read on.
CYCLE_FREQ_HZ = 5.0
_POINTS_PER_CYCLE = 400


@dataclass(frozen=True)
class PartCharacteristics:
    """Curves of one part (module docstring); ``*_band`` arrays are (2, n): 5 and 95 % quantiles."""

    part: str
    family: str
    amplitude_m: np.ndarray
    secant_stiffness: np.ndarray
    secant_stiffness_band: np.ndarray
    loss_factor: np.ndarray
    loss_factor_band: np.ndarray
    loop_amplitudes_m: np.ndarray
    loops: tuple  # ((deflection, force), ...) per loop amplitude
    freq_hz: np.ndarray
    transmissibility: np.ndarray
    transmissibility_band: np.ndarray
    payload_per_mount_kg: float


def _cycle(model, amplitude: float):
    """Deflection and force of the second of two sinusoidal cycles from rest."""
    time = np.arange(2 * _POINTS_PER_CYCLE + 1) / (_POINTS_PER_CYCLE * CYCLE_FREQ_HZ)
    deflection = amplitude * np.sin(2.0 * np.pi * CYCLE_FREQ_HZ * time)
    force = np.asarray(model.force(deflection, time), dtype=float)
    return deflection[_POINTS_PER_CYCLE:], force[_POINTS_PER_CYCLE:]


def _equivalent(model, amplitudes) -> tuple[np.ndarray, np.ndarray]:
    stiffness, loss = [], []
    for amplitude in amplitudes:
        deflection, force = _cycle(model, amplitude)
        k_eq = (force.max() - force.min()) / (2.0 * amplitude)
        energy = abs(float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(deflection))))
        stiffness.append(k_eq)
        loss.append(float(loss_factor_of_cycles(energy, k_eq, amplitude)))
    return np.array(stiffness), np.array(loss)


def part_characteristics(part: str, family: str, model, covariance_names=(), covariance=None, *,
                         amplitudes_m=np.geomspace(5e-5, 1.5e-2, 16), loop_amplitudes_m=(5e-4, 2e-3, 8e-3),
                         freq_hz=np.geomspace(1.0, 100.0, 300), payload_per_mount_kg: float = 5.0,
                         n_draws: int = 20, seed: int = 0) -> PartCharacteristics:
    """The curves of one part with bands over ``n_draws`` parameter draws (module docstring)."""
    amplitudes = np.asarray(amplitudes_m, dtype=float)
    freq = np.asarray(freq_hz, dtype=float)
    rng = np.random.default_rng(seed)
    covariance = np.zeros((0, 0)) if covariance is None else np.asarray(covariance, dtype=float)
    drawn = draw_models(model, covariance_names, covariance, n_draws, rng) if n_draws else []
    stiffness, loss = _equivalent(model, amplitudes)
    draws = [_equivalent(m, amplitudes) for m in drawn]

    def band(values, fallback):
        return np.quantile(np.array(values), [0.05, 0.95], axis=0) if values else np.vstack([fallback, fallback])

    gain = np.abs(SDOFSystem(payload_per_mount_kg, model).transmissibility(freq))
    gains = [np.abs(SDOFSystem(payload_per_mount_kg, m).transmissibility(freq)) for m in drawn]
    return PartCharacteristics(
        part=part, family=family, amplitude_m=amplitudes, secant_stiffness=stiffness,
        secant_stiffness_band=band([d[0] for d in draws], stiffness), loss_factor=loss,
        loss_factor_band=band([d[1] for d in draws], loss), loop_amplitudes_m=np.asarray(loop_amplitudes_m, float),
        loops=tuple(_cycle(model, a) for a in loop_amplitudes_m), freq_hz=freq, transmissibility=gain,
        transmissibility_band=band(gains, gain), payload_per_mount_kg=float(payload_per_mount_kg))
