"""Equivalent linear stiffness and loss factor of hysteresis loops versus amplitude, measured and model.

Definitions (per cycle of a quasi-static record, :func:`idkit.observe.quasi_static.cycle_statistics`):

* amplitude ``X`` = half the cycle's deflection range (m);
* secant stiffness ``k_eq = (F_max - F_min) / (x_max - x_min)`` (N/m);
* loss factor ``eta_eq = W / (pi k_eq X^2)`` with ``W`` the energy the loop encloses (J):
  the loss factor of the linear viscoelastic element that dissipates the same energy per
  cycle at the same peak force (equivalent viscous damping ratio ``zeta_eq = eta_eq / 2``).

For one Jenkin element (spring ``k``, slip force ``fc``) cycled at ``X > fc / k``:
``k_eq = fc / X`` and ``eta_eq = 4 (X - fc / k) / (pi X)`` (a parallelogram loop); for a linear
spring ``k`` with a dashpot ``c`` at frequency ``w``: ``k_eq = sqrt(k^2 + (c w)^2)`` and
``eta_eq = c w / k_eq`` (an ellipse). The model's values come from its force on the measured
deflection history of every record, through the same cycles: measured and model points are
paired cycle by cycle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.io import QuasiStaticMeasurement
from idkit.observe.quasi_static import cycle_statistics, process_quasi_static

__all__ = ["ComplexStiffnessComparison", "DropShockSpectra", "EquivalentLinearization", "MIN_DISTANCE_FROM_ONE",
           "complex_stiffness_comparison", "drop_shock_spectra", "equivalent_linearization", "loss_factor_of_cycles"]


def loss_factor_of_cycles(energy_j, secant_stiffness_n_per_m, amplitude_m) -> np.ndarray:
    """``eta_eq = W / (pi k_eq X^2)`` (dimensionless; NaN where ``k_eq X^2`` is 0).

    Examples
    --------
    >>> round(float(loss_factor_of_cycles(4 * 10.0 * (2e-3 - 1e-3), 10.0 / 2e-3, 2e-3)), 6)  # Jenkin
    0.63662
    """
    energy = np.asarray(energy_j, dtype=float)
    stiffness = np.asarray(secant_stiffness_n_per_m, dtype=float)
    amplitude = np.asarray(amplitude_m, dtype=float)
    denominator = np.pi * stiffness * amplitude ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(denominator > 0, energy / denominator, np.nan)


@dataclass(frozen=True)
class EquivalentLinearization:
    """Per-cycle equivalent stiffness and loss factor, measured and model (module docstring).

    Attributes
    ----------
    record : tuple of str
        Measurement id of each cycle.
    amplitude_m : numpy.ndarray
    secant_stiffness_n_per_m, loss_factor : numpy.ndarray
        Measured.
    model_secant_stiffness_n_per_m, model_loss_factor : numpy.ndarray
        The model on the same deflection history and cycles.
    """

    record: tuple[str, ...]
    amplitude_m: np.ndarray
    secant_stiffness_n_per_m: np.ndarray
    loss_factor: np.ndarray
    model_secant_stiffness_n_per_m: np.ndarray
    model_loss_factor: np.ndarray

    def to_dataframe(self):
        import pandas as pd

        return pd.DataFrame({"record": list(self.record), "amplitude [m]": self.amplitude_m,
                             "secant stiffness measured [N/m]": self.secant_stiffness_n_per_m,
                             "secant stiffness model [N/m]": self.model_secant_stiffness_n_per_m,
                             "loss factor measured [-]": self.loss_factor,
                             "loss factor model [-]": self.model_loss_factor})


def equivalent_linearization(measurements, model) -> EquivalentLinearization:
    """Equivalent stiffness and loss factor of every cycle of quasi-static records and of ``model``.

    Parameters
    ----------
    measurements : sequence of QuasiStaticMeasurement
    model : IsolatorModel
        Its ``force(deflection, time)`` on each record's deflection (elements start unloaded
        at the record's first sample, as a record that starts unloaded does).

    Returns
    -------
    EquivalentLinearization
    """
    columns = {name: [] for name in ("record", "amplitude", "k", "eta", "k_model", "eta_model")}
    for measurement in measurements:
        cycles = process_quasi_static(measurement)
        measured = cycle_statistics(measurement, result=cycles)
        simulated = QuasiStaticMeasurement(time=measurement.time, deflection=measurement.deflection,
                                           force=model.force(measurement.deflection, measurement.time))
        predicted = cycle_statistics(simulated, result=cycles)
        columns["record"] += [measurement.id] * measured.amplitude.size
        columns["amplitude"].append(measured.amplitude)
        columns["k"].append(measured.secant_stiffness)
        columns["eta"].append(loss_factor_of_cycles(measured.dissipated_energy, measured.secant_stiffness,
                                                    measured.amplitude))
        columns["k_model"].append(predicted.secant_stiffness)
        columns["eta_model"].append(loss_factor_of_cycles(predicted.dissipated_energy, predicted.secant_stiffness,
                                                          predicted.amplitude))
    joined = {key: np.concatenate(value) if value else np.empty(0)
              for key, value in columns.items() if key != "record"}
    order = np.argsort(joined["amplitude"], kind="stable")
    return EquivalentLinearization(
        record=tuple(columns["record"][i] for i in order), amplitude_m=joined["amplitude"][order],
        secant_stiffness_n_per_m=joined["k"][order], loss_factor=joined["eta"][order],
        model_secant_stiffness_n_per_m=joined["k_model"][order], model_loss_factor=joined["eta_model"][order])


#: Frequencies where the measured transmissibility is within this distance of 1 are left out
#: of the measured complex stiffness: a relative error e of H becomes e |H| / |H - 1| in k*
#: (at most 5 e |H| here).
MIN_DISTANCE_FROM_ONE = 0.2


@dataclass(frozen=True)
class ComplexStiffnessComparison:
    """The elastomer's complex stiffness read off each measured FRF, beside the model's.

    Attributes
    ----------
    mass_kg : tuple of float
        Top mass of each FRF (one FRF per top mass: the first repetition).
    freq_hz : tuple of numpy.ndarray
    measured : tuple of numpy.ndarray
        ``k* = M w^2 H / (H - 1)`` with ``M`` the top mass plus the model's ``m_eff`` (N/m),
        NaN where ``|H - 1| <`` :data:`MIN_DISTANCE_FROM_ONE`.
    model : tuple of numpy.ndarray
        The model's ``k*`` at the same frequencies (N/m).
    """

    mass_kg: tuple
    freq_hz: tuple
    measured: tuple
    model: tuple


def complex_stiffness_comparison(frfs, model) -> ComplexStiffnessComparison:
    """Measured complex stiffness of every top mass (first repetition each) and the model's.

    Parameters
    ----------
    frfs : sequence of TransmissibilitySet
    model : GeneralizedMaxwell or VoigtModel
        Supplies ``m_eff`` for the moving mass and ``complex_stiffness``.
    """
    from idkit.models.laws import stiffness_from_transmissibility

    first = {}
    for frf in frfs:
        first.setdefault(float(frf.mass), frf)
    masses, freqs, measured, predicted = [], [], [], []
    for mass, frf in sorted(first.items()):
        omega = 2 * np.pi * np.asarray(frf.freq)
        h = np.asarray(frf.transmissibility)
        k = stiffness_from_transmissibility(h, mass + model.m_eff, omega)
        k = np.where(np.abs(h - 1.0) >= MIN_DISTANCE_FROM_ONE, k, np.nan + 0j)
        masses.append(mass)
        freqs.append(np.asarray(frf.freq))
        measured.append(k)
        predicted.append(model.complex_stiffness(frf.freq))
    return ComplexStiffnessComparison(tuple(masses), tuple(freqs), tuple(measured), tuple(predicted))


@dataclass(frozen=True)
class DropShockSpectra:
    """Absolute-acceleration SRS of measured drops of one isolator and top mass, one per height.

    Attributes
    ----------
    isolator : str
    top_mass_kg : float
    height_m : tuple of float
        Drop height of each spectrum (the first repetition at each height).
    freq_hz : numpy.ndarray
        Natural frequencies of the SRS (Hz).
    acceleration : tuple of numpy.ndarray
        Maximax absolute acceleration of a 5 %-damped oscillator on the top mass (m/s^2),
        from the mean of the two top accelerometers.
    damping_ratio : float
    model_acceleration : tuple of numpy.ndarray, optional
        The same of the model's simulated top acceleration, per height (with ``histories``).
    input_acceleration : tuple of numpy.ndarray, optional
        The same of the impact itself, per height: the oscillators mounted rigidly on the
        bottom mass, whose velocity changes by ``(1 + e) sqrt(2 g h)`` at the impact (``e`` the
        contact's restitution read off the records), taken as an impulse: what a component
        without the isolator would see.
    """

    isolator: str
    top_mass_kg: float
    height_m: tuple
    freq_hz: np.ndarray
    acceleration: tuple
    damping_ratio: float
    model_acceleration: tuple | None = None
    input_acceleration: tuple | None = None


def drop_shock_spectra(measurements, *, histories=None, damping_ratio: float = 0.05,
                       points: int = 60) -> DropShockSpectra | None:
    """SRS of the measured top acceleration of every drop height, for the top mass with most heights.

    The band runs from 1 Hz to the highest natural frequency the sampling resolves
    (``fs /`` :data:`idkit.signal.srs.MIN_SAMPLES_PER_PERIOD`). Returns None when there are
    no drop records.

    Parameters
    ----------
    measurements : sequence of DropMeasurement
        Drops of one isolator.
    histories : DropHistories, optional
        Measured and simulated drops (:func:`idkit.studies.drop_histories.drop_histories`):
        then the spectra are those of its drops (their records found in ``measurements`` by
        id), with the model's and the impact's (:class:`DropShockSpectra`).
    damping_ratio : float
        Damping of the SRS oscillators (default 0.05, ISO 18431-4's usual value).
    points : int
        Logarithmically spaced natural frequencies.
    """
    from idkit.gravity import STANDARD_GRAVITY
    from idkit.signal.srs import MIN_SAMPLES_PER_PERIOD, shock_spectra

    drops = [m for m in measurements if m.kind == "drop"]
    if not drops:
        return None
    if histories is not None:
        by_id = {drop.info.id: drop for drop in drops}
        chosen = [(history, by_id[history.id]) for history in histories.drops if history.id in by_id]
    else:
        chosen = []
    if chosen:
        by_height = {float(drop.info.drop_height_m): drop for _, drop in chosen}
        mass = round(float(chosen[0][1].info.top_mass_kg), 6)
    else:
        by_mass = {}
        for drop in drops:
            by_mass.setdefault(round(float(drop.info.top_mass_kg), 6), {}).setdefault(float(drop.info.drop_height_m),
                                                                                    drop)
        mass, by_height = max(by_mass.items(), key=lambda item: (len(item[1]), item[0]))
    heights = sorted(by_height)
    fs = min(by_height[h].sample_rate_hz for h in heights)
    freq = np.geomspace(1.0, fs / MIN_SAMPLES_PER_PERIOD, points)

    def srs(acceleration, rate):
        return shock_spectra(acceleration, fs=rate, freq=freq, damping_ratio=damping_ratio).absolute_acceleration

    spectra = [srs(0.5 * (np.asarray(by_height[h].a_top_1) + np.asarray(by_height[h].a_top_2)),
                   by_height[h].sample_rate_hz) for h in heights]
    if not chosen:
        return DropShockSpectra(isolator=str(drops[0].info.isolator), top_mass_kg=mass, height_m=tuple(heights),
                                freq_hz=freq, acceleration=tuple(spectra), damping_ratio=damping_ratio)
    models, impacts = [], []
    histories_by_height = {float(drop.info.drop_height_m): history for history, drop in chosen}
    for height in heights:
        history = histories_by_height[height]
        step = float(np.median(np.diff(history.simulated_time)))
        models.append(srs(history.simulated_acceleration, 1.0 / step))
        # the impact as an impulse: one sample carrying the velocity change (a triangle of
        # width 2 steps to the ramp-invariant filter), at the model's time step
        impulse = np.zeros(int(round(1.0 / (freq[0] * step))) + 2)
        impulse[1] = (1.0 + histories.contact.restitution) * np.sqrt(2.0 * STANDARD_GRAVITY * height) / step
        impacts.append(srs(impulse, 1.0 / step))
    return DropShockSpectra(isolator=str(drops[0].info.isolator), top_mass_kg=mass, height_m=tuple(heights),
                            freq_hz=freq, acceleration=tuple(spectra), damping_ratio=damping_ratio,
                            model_acceleration=tuple(models), input_acceleration=tuple(impacts))
