"""White-noise runs -> transmissibility H1/H2 and coherence (SPEC 3).

The one transmissibility estimate of a white-noise run: :func:`frf_from_white_noise`
(Welch, Hann window, segments of ``1 / resolution_hz`` s, sample rate from the time
column, velocities first). ``idkit inspect``, the Maxwell fit
(:func:`transmissibility_sets`) and the FRF validation (:func:`idkit.validate.validate_frf`)
all call it, with :data:`FRF_RESOLUTION_HZ` by default, so they see the same H1.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.checks import Choice, Instance, Real, accepts
from idkit.errors import DataError, FitError
from idkit.io import WhiteNoiseMeasurement
from idkit.io.selection import DataProvenance, select_measurements
from idkit.signal.frf import FrfEstimate, estimate_frf

__all__ = ["FRF_RESOLUTION_HZ", "WhiteNoiseFrf", "frf_from_white_noise", "TransmissibilitySet",
           "transmissibility_sets"]

#: Default frequency resolution (Hz) of every white-noise H1 estimate (``idkit inspect``, the
#: Maxwell fit and the FRF validation alike): 4 s segments, 7 Welch averages at 50 % overlap
#: on a 16 s record. The -3 dB width of a resonance is ``2 zeta f_n`` (0.43 Hz for
#: zeta = 0.02 at 11 Hz) and the window bias of a peak is about
#: ``-(1.5 df / (2 zeta f_n))^2 / 3`` (:func:`idkit.signal.frf.estimate_frf`): 0.5 Hz lines
#: read such a mount's damping 1-4 dB off, 0.25 Hz keeps it within 1 dB.
FRF_RESOLUTION_HZ = 0.25


# ---------------------------------------------------------------------------------------------
# white noise


@dataclass(frozen=True)
class WhiteNoiseFrf:
    """Transmissibility estimate of one white-noise run.

    Attributes
    ----------
    measurement_id : str
        ``info.id``.
    top_mass_kg : float or None
        Top mass, kg.
    signals : str
        ``"velocity"`` (v_base -> v_top) or ``"acceleration"`` (a_base -> a_top).
    estimate : FrfEstimate
        Frequencies (Hz), H1, H2, coherence, Welch settings.
    band : tuple of float
        Band kept, Hz (the requested band clipped to the Nyquist frequency).
    notes : tuple of str
        What was changed from the request, e.g. the band clipped to the Nyquist frequency
        (also issued as a :class:`UserWarning`).
    """

    measurement_id: str
    top_mass_kg: float | None
    signals: str
    estimate: FrfEstimate
    band: tuple[float, float]
    notes: tuple[str, ...] = ()

    @property
    def freq(self) -> np.ndarray:
        """Frequencies, Hz."""
        return self.estimate.freq

    @property
    def h1(self) -> np.ndarray:
        """H1 transmissibility (dimensionless)."""
        return self.estimate.h1

    @property
    def h2(self) -> np.ndarray:
        """H2 transmissibility (dimensionless)."""
        return self.estimate.h2

    @property
    def coherence(self) -> np.ndarray:
        """Ordinary coherence in [0, 1]."""
        return self.estimate.coherence

    @property
    def min_coherence(self) -> float:
        """Lowest coherence in the band."""
        return float(self.coherence.min())

    @property
    def mean_coherence(self) -> float:
        """Mean coherence in the band."""
        return float(self.coherence.mean())

    def to_dataframe(self) -> pd.DataFrame:
        """One row per frequency (see :meth:`FrfEstimate.to_dataframe`)."""
        table = self.estimate.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table

    def report(self) -> str:
        """Short text summary."""
        peak = int(np.argmax(np.abs(self.h1)))
        return (f"{self.measurement_id}: {self.band[0]:g}-{self.band[1]:g} Hz, peak |H1| "
                f"{abs(self.h1[peak]):.3g} at {self.freq[peak]:.3g} Hz, coherence mean "
                f"{self.mean_coherence:.3f} min {self.min_coherence:.3f}, "
                f"{self.estimate.n_segments} segments of {self.estimate.nperseg}")


#: The declared frequency step of the H1 estimates.
RESOLUTION = Real(unit="Hz", gt=0, meaning="frequency step")


@accepts(measurement=Instance((WhiteNoiseMeasurement,)), signals=Choice(("velocity", "acceleration"), optional=True),
         resolution_hz=RESOLUTION, error=DataError)
def frf_from_white_noise(measurement: WhiteNoiseMeasurement, *,
                         band: tuple[float, float] | None = None,
                         resolution_hz: float = FRF_RESOLUTION_HZ, overlap: float = 0.5,
                         signals: str | None = None) -> WhiteNoiseFrf:
    """H1, H2 and coherence of a white-noise shaker run (Welch, Hann window).

    Parameters
    ----------
    measurement : WhiteNoiseMeasurement
        Base and top-mass velocities (or accelerations).
    band : (float, float), optional
        Band kept, Hz. Default: the declared excitation band (``info.excitation.band``), or
        0 - Nyquist. An upper edge above the Nyquist frequency is clipped to it with a
        :class:`UserWarning` and a line in :attr:`WhiteNoiseFrf.notes` (never silently).
        SPEC 3 identifies on (1, 100).
    resolution_hz : float, default :data:`FRF_RESOLUTION_HZ` (0.25 Hz)
        Frequency step: ``nperseg = round(fs / resolution_hz)`` samples per segment, capped
        at a quarter of the record (at least 4 segments, 7 averages at 50 % overlap).
    overlap : float, default 0.5
        Segment overlap fraction.
    signals : {"velocity", "acceleration"}, optional
        Which pair to use; default velocity when present, else acceleration.

    Returns
    -------
    WhiteNoiseFrf

    Raises
    ------
    DataError
        Wrong measurement type, requested signals missing, a non-positive resolution, or
        the errors of :func:`~idkit.signal.frf.estimate_frf`.

    Notes
    -----
    The sample rate is the measurement's ``sample_rate_hz`` (1 / median step of the time
    column, :meth:`idkit.io.contract.Axis.rate_hz`) to 10 significant digits;
    a declared ``info.sample_rate_hz`` was checked against it to 1 % when the measurement was
    built.

    Examples
    --------
    >>> from idkit.io import MeasurementInfo, WhiteNoiseMeasurement
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(20000) / 1000.0
    >>> v = rng.standard_normal(t.size)
    >>> run = WhiteNoiseMeasurement(time=t, v_base=v, v_top=0.5 * v, info=MeasurementInfo(id="wn"))
    >>> frf = frf_from_white_noise(run, band=(1.0, 100.0))
    >>> float(frf.freq[1] - frf.freq[0]), round(float(np.abs(frf.h1).mean()), 6)
    (0.25, 0.5)
    """
    if signals is None:
        signals = "velocity" if measurement.v_base is not None else "acceleration"
    if signals == "velocity":
        base, top = measurement.v_base, measurement.v_top
    else:
        base, top = measurement.a_base, measurement.a_top
    if base is None or top is None:
        raise DataError(f"{measurement.id}: no {signals} signals in the measurement")
    # the rate of the time column to 10 significant digits: a time column written as decimals
    # reads a hair off the exact rate, which would move every frequency line and drop a line
    # at a band edge that the exact rate keeps
    fs = float(f"{measurement.sample_rate_hz:.10g}")
    nyquist = fs / 2
    notes = []
    if band is None:
        declared = measurement.band
        band = (0.0, nyquist) if declared is None else (declared[0], declared[1])
    band = (float(band[0]), float(band[1]))
    if band[1] > nyquist:
        note = (f"{measurement.id or 'white-noise run'}: band upper edge {band[1]:g} Hz above the Nyquist "
                f"frequency {nyquist:g} Hz (sample rate {fs:g} Hz), clipped to {nyquist:g} Hz")
        warnings.warn(note, UserWarning, stacklevel=2)
        notes.append(note)
        band = (band[0], nyquist)
    nperseg = int(min(round(fs / resolution_hz), base.size // 4))
    estimate = estimate_frf(base, top, fs=fs, nperseg=nperseg, overlap=overlap, f_lo=band[0], f_hi=band[1])
    return WhiteNoiseFrf(measurement_id=measurement.id, top_mass_kg=measurement.info.top_mass_kg,
                         signals=signals, estimate=estimate, band=band, notes=tuple(notes))


# ---------------------------------------------------------------------------------------------
# transmissibility sets for the fits


@dataclass(frozen=True)
class TransmissibilitySet:
    """Measured complex transmissibility of one top mass on the isolator.

    Attributes
    ----------
    mass : float
        Top mass in kg.
    freq : ndarray
        Frequencies in Hz.
    transmissibility : ndarray (complex)
        Top-mass motion over base motion (any consistent kinematic quantity).
    name : str
    static_stiffness : float or None
        Tangent static stiffness (N/m) at the deflection the top mass's weight causes,
        read off the quasi-static loops (:func:`~idkit.observe.k0.static_operating_point`);
        small-amplitude motion around that preload sees it in place of ``k0``. None: ``k0``.
    random_error : ndarray or None
        Normalized random error of the H1 estimate at each frequency,
        ``sqrt(1 - gamma^2) / (|gamma| sqrt(2 n_d))`` (:attr:`~idkit.signal.frf.FrfEstimate.random_error`,
        from the coherence and the number of averages); None when unknown (a given table).
        The Maxwell fit reads its noise floor off it (:func:`idkit.fit.frf_objective.frf_noise_floor`).
    """

    mass: float
    freq: np.ndarray
    transmissibility: np.ndarray
    name: str = ""
    static_stiffness: float | None = None
    random_error: np.ndarray | None = None


@accepts(resolution_hz=RESOLUTION, error=FitError)
def transmissibility_sets(
    measurements,
    *,
    isolator: str | None = "elastomer",
    split: str | None = "fit",
    band=(1.0, 100.0),
    resolution_hz: float = FRF_RESOLUTION_HZ,
    overlap: float = 0.5,
) -> tuple[tuple[TransmissibilitySet, ...], DataProvenance]:
    """White-noise records -> H1 transmissibility of every top mass and repetition.

    Each record's H1 is :func:`frf_from_white_noise` (top over base velocity, or
    acceleration when the record has no velocities).

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
        Selected by :func:`idkit.io.selection.select_measurements`.
    isolator : str or None, default "elastomer"
    split : {"fit", "validation", "all", None}, default "fit"
    band : (float, float), default (1, 100)
        Band in Hz (clipped to the Nyquist frequency with a warning).
    resolution_hz : float, default :data:`FRF_RESOLUTION_HZ`
    overlap : float, default 0.5

    Returns
    -------
    (tuple of TransmissibilitySet, DataProvenance)

    Raises
    ------
    FitError
        A record without ``top_mass_kg``, a non-positive resolution, an unusable FRF.
    DataError
        No matching record.
    """
    records, provenance = select_measurements(measurements, kind="white_noise", isolator=isolator, split=split)
    low, high = (float(v) for v in band)
    sets = []
    for position, record in enumerate(records, start=1):
        name = record.id or f"record{position}"
        mass = record.info.top_mass_kg
        if mass is None:
            raise FitError(f"{record.source.where()}: measurement {name!r} has no top_mass_kg, "
                           "expected the top mass in kg (manifest key top_mass_kg)")
        try:
            frf = frf_from_white_noise(record, band=(low, high), resolution_hz=resolution_hz, overlap=overlap)
        except DataError as problem:
            raise FitError(f"{record.source.where()}: {problem}") from None
        sets.append(TransmissibilitySet(float(mass), frf.freq, frf.h1, name,
                                        random_error=np.asarray(frf.estimate.random_error, dtype=float)))
    return tuple(sets), provenance
