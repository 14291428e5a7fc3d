"""Typed measurements: the four kinds of SPEC section 3, plus acceleration records.

All arrays are SI (s, m, N, m/s, m/s^2, V), 1-D float64, read-only copies.
Deflection is ``x_top - x_base``: positive = tension. Constructors check
their inputs against each kind's declared columns (:class:`idkit.io.contract.Column`:
same length, finite values; the time column's :class:`~idkit.io.contract.Axis`: at
least two samples, strictly increasing, declared sample rate consistent with it) and
raise :class:`~idkit.errors.DataError` naming the source file, column and
1-based row. Nothing is altered, dropped or clipped.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import pandas as pd

from idkit.checks import Instance, Real, Reals
from idkit.errors import DataError
from idkit.io.columns import KIND
from idkit.io.contract import TIME_AXIS, UNIFORM_TIME_AXIS, Column, as_signal, read_record
from idkit.io.info import MeasurementInfo
from idkit.io.provenance import Source
from idkit.io.units import SI_UNITS

__all__ = [
    "AccelerationRecord",
    "DropMeasurement",
    "Measurement",
    "QuasiStaticMeasurement",
    "SteppedSineMeasurement",
    "WhiteNoiseMeasurement",
    "measurement_class",
]

# SI unit of each signal field, used by to_dataframe() and the writer.
SIGNAL_QUANTITIES: dict[str, str] = {
    "time": "time", "deflection": "length", "force": "force", "v_rel": "velocity",
    "v_base": "velocity", "v_top": "velocity", "x_base": "length", "u_in": "voltage",
    "a_base": "acceleration", "a_top": "acceleration", "a_top_1": "acceleration",
    "a_top_2": "acceleration",
}


def check_excitation_resolved(measurement) -> None:
    """Refuse a stated excitation the samples cannot hold (a manifest's ``freq_hz`` or ``band_hz``).

    A stepped-sine frequency must lie below the Nyquist frequency (half the sample rate read off the
    time column: at or above it the sine aliases or has no resolved phase); a white-noise band may
    end at it. The bounds are declared as specs of the one message template.

    Raises
    ------
    DataError
        Naming the file, the stated value and the Nyquist frequency.
    """
    excitation = measurement.info.excitation
    if excitation is None:
        return
    nyquist = measurement.sample_rate_hz / 2
    samples = f"the Nyquist frequency {nyquist:.6g} Hz of its {2 * nyquist:.6g} Hz samples"
    where = measurement.source.where()
    if measurement.kind == "stepped_sine":
        Real(unit="Hz", lt=nyquist, meaning=f"below {samples}: a sine there aliases or has no resolved phase"
             ).check(excitation.freq, f"{where}: excitation freq_hz", DataError)
    if measurement.kind == "white_noise" and excitation.band is not None:
        Reals(unit="Hz", le=_NYQUIST_SLACK * nyquist, meaning=f"up to {samples}").check(
            excitation.band, f"{where}: excitation band_hz", DataError)


#: A white-noise band may end at the Nyquist frequency; the sample rate is read off the median
#: time step, so its round-off (relative 1e-9 covers time columns written with 10 digits) is allowed.
_NYQUIST_SLACK = 1.0 + 1e-9


#: Every measurement kind's time column, in s, with the time axis rule.
_TIME = Column("time", required=True, axis=TIME_AXIS)

_INFO = Instance((MeasurementInfo,))
_SOURCE = Instance((Source,))


@dataclass(frozen=True, eq=False)
class _SignalMeasurement:
    """Common machinery of the time-series measurements (not public)."""

    kind: ClassVar[str] = ""
    #: The record's columns (name, required or paired); their units are :data:`SIGNAL_QUANTITIES`'.
    _columns: ClassVar[tuple[Column, ...]] = ()

    def _validate(self) -> None:
        _INFO.check(self.info, "info", DataError)
        _SOURCE.check(self.source, "source", DataError)
        for name, array in read_record({c.name: getattr(self, c.name) for c in self._columns}, self._columns,
                                       self.source, self.info.sample_rate_hz).items():
            object.__setattr__(self, name, array)

    @property
    def sample_rate_hz(self) -> float:
        """Sample rate in Hz from the median time step (the one rule, :meth:`Axis.rate_hz`;
        ``info.sample_rate_hz``, when declared, has been checked against it within
        :data:`~idkit.io.contract.SAMPLE_RATE_TOLERANCE`)."""
        return TIME_AXIS.rate_hz(self.time)

    @property
    def n_samples(self) -> int:
        """Number of samples."""
        return int(self.time.size)

    @property
    def id(self) -> str:
        """The measurement's id (``info.id``)."""
        return self.info.id

    def signals(self) -> dict[str, np.ndarray]:
        """The signals present, by column name, in SI units."""
        return {column.name: getattr(self, column.name) for column in self._columns
                if getattr(self, column.name) is not None}

    def to_dataframe(self) -> pd.DataFrame:
        """The signals as a DataFrame with headers ``name [SI unit]``.

        Returns
        -------
        pandas.DataFrame
            One column per signal present, e.g. ``time [s]``, ``force [N]``;
            metadata stays on the object (not stored as DataFrame attributes).
        """
        return pd.DataFrame({
            f"{name} [{SI_UNITS[SIGNAL_QUANTITIES[name]]}]": np.array(values)
            for name, values in self.signals().items()
        })


@dataclass(frozen=True, eq=False)
class QuasiStaticMeasurement(_SignalMeasurement):
    """Quasi-static force-deflection measurement (lathe; SPEC section 3).

    Parameters
    ----------
    time : numpy.ndarray
        Time in s, strictly increasing.
    deflection : numpy.ndarray
        Deflection ``x_top - x_base`` in m, positive = tension.
    force : numpy.ndarray
        Isolator force in N.
    v_rel : numpy.ndarray or None
        Relative velocity (rate of deflection) in m/s, if recorded.
    info : MeasurementInfo
        Metadata.
    source : Source
        Provenance (file, SHA-256, declared columns).

    Examples
    --------
    >>> import numpy as np
    >>> m = QuasiStaticMeasurement(time=np.array([0.0, 0.1]),
    ...                            deflection=np.array([0.0, 1e-3]), force=np.array([0.0, 3.0]))
    >>> m.n_samples
    2
    """

    time: np.ndarray
    deflection: np.ndarray
    force: np.ndarray
    v_rel: np.ndarray | None = None
    info: MeasurementInfo = field(default_factory=MeasurementInfo)
    source: Source = field(default_factory=Source)

    kind: ClassVar[str] = "quasi_static"
    _columns: ClassVar[tuple[Column, ...]] = (_TIME, Column("deflection", required=True),
                                              Column("force", required=True), Column("v_rel"))

    def __post_init__(self) -> None:
        self._validate()


@dataclass(frozen=True, eq=False)
class WhiteNoiseMeasurement(_SignalMeasurement):
    """Shaker run with white-noise base excitation (elastomer; SPEC section 3).

    Either both velocities or both accelerations (or all four) are present.

    Parameters
    ----------
    time : numpy.ndarray
        Time in s.
    v_base, v_top : numpy.ndarray or None
        Base and top-mass velocity in m/s.
    a_base, a_top : numpy.ndarray or None
        Base and top-mass acceleration in m/s^2.
    info : MeasurementInfo
        Metadata; ``info.excitation.band`` holds the band in Hz if declared.
    source : Source
        Provenance.
    """

    time: np.ndarray
    v_base: np.ndarray | None = None
    v_top: np.ndarray | None = None
    a_base: np.ndarray | None = None
    a_top: np.ndarray | None = None
    info: MeasurementInfo = field(default_factory=MeasurementInfo)
    source: Source = field(default_factory=Source)

    kind: ClassVar[str] = "white_noise"
    _columns: ClassVar[tuple[Column, ...]] = (_TIME, Column("v_base", pair="velocity"),
                                              Column("v_top", pair="velocity"), Column("a_base", pair="acceleration"),
                                              Column("a_top", pair="acceleration"))

    def __post_init__(self) -> None:
        self._validate()

    @property
    def band(self) -> tuple[float, float] | None:
        """Declared excitation band in Hz, if any."""
        return None if self.info.excitation is None else self.info.excitation.band


@dataclass(frozen=True, eq=False)
class SteppedSineMeasurement(_SignalMeasurement):
    """One (frequency, amplitude) point of a stepped-sine shaker run.

    The frequency and nominal amplitude are metadata
    (``info.excitation``); the frequency is required.

    Parameters
    ----------
    time : numpy.ndarray
        Time in s.
    v_base : numpy.ndarray
        Base velocity in m/s.
    v_top : numpy.ndarray
        Top-mass velocity in m/s.
    x_base : numpy.ndarray or None
        Base position in m.
    u_in : numpy.ndarray or None
        Shaker drive voltage in V.
    info : MeasurementInfo
        Metadata; ``info.excitation.freq`` (Hz) must be set.
    source : Source
        Provenance.
    """

    time: np.ndarray
    v_base: np.ndarray
    v_top: np.ndarray
    x_base: np.ndarray | None = None
    u_in: np.ndarray | None = None
    info: MeasurementInfo = field(default_factory=MeasurementInfo)
    source: Source = field(default_factory=Source)

    kind: ClassVar[str] = "stepped_sine"
    _columns: ClassVar[tuple[Column, ...]] = (_TIME, Column("v_base", required=True),
                                              Column("v_top", required=True), Column("x_base"), Column("u_in"))

    def __post_init__(self) -> None:
        if self.info.excitation is None or self.info.excitation.freq is None:
            raise DataError(f"{self.source.where()}: stepped-sine point without a frequency; "
                            "expected info.excitation.freq in Hz (manifest: excitation.freq_hz)")
        self._validate()

    @property
    def freq(self) -> float:
        """Excitation frequency in Hz."""
        return float(self.info.excitation.freq)

    @property
    def nominal_amplitude(self) -> float | None:
        """Nominal amplitude in the SI unit of ``info.excitation.amplitude_quantity``."""
        return self.info.excitation.amplitude


@dataclass(frozen=True, eq=False)
class DropMeasurement(_SignalMeasurement):
    """Drop test (SPEC section 3): deflection over the isolator and top accelerations.

    Parameters
    ----------
    time : numpy.ndarray
        Time in s.
    deflection : numpy.ndarray
        Relative displacement ``x_top - x_base`` in m (positive = tension).
    a_top_1, a_top_2 : numpy.ndarray
        The two vertical accelerometers on the top mass, m/s^2.
    v_rel : numpy.ndarray or None
        Relative velocity in m/s (laser vibrometer), if recorded.
    info : MeasurementInfo
        Metadata (drop height, masses).
    source : Source
        Provenance.
    """

    time: np.ndarray
    deflection: np.ndarray
    a_top_1: np.ndarray
    a_top_2: np.ndarray
    v_rel: np.ndarray | None = None
    info: MeasurementInfo = field(default_factory=MeasurementInfo)
    source: Source = field(default_factory=Source)

    kind: ClassVar[str] = "drop"
    _columns: ClassVar[tuple[Column, ...]] = (_TIME, Column("deflection", required=True),
                                              Column("a_top_1", required=True), Column("a_top_2", required=True),
                                              Column("v_rel"))

    def __post_init__(self) -> None:
        self._validate()

    @property
    def a_top_mean(self) -> np.ndarray:
        """Mean of the two top-mass accelerations in m/s^2 (SPEC: use their mean)."""
        return 0.5 * (self.a_top_1 + self.a_top_2)


#: Any of the four measurement dataclasses (for annotations).
Measurement = (QuasiStaticMeasurement | WhiteNoiseMeasurement | SteppedSineMeasurement
               | DropMeasurement)

_CLASSES = {cls.kind: cls for cls in (QuasiStaticMeasurement, WhiteNoiseMeasurement,
                                       SteppedSineMeasurement, DropMeasurement)}


def measurement_class(kind: str) -> type:
    """The measurement dataclass of a kind.

    Parameters
    ----------
    kind : str
        ``"quasi_static"``, ``"white_noise"``, ``"stepped_sine"`` or ``"drop"``.

    Returns
    -------
    type
        E.g. :class:`QuasiStaticMeasurement`.

    Raises
    ------
    DataError
        For an unknown kind.
    """
    return _CLASSES[KIND.check(kind, "kind", DataError)]


@dataclass(frozen=True, eq=False)
class AccelerationRecord:
    """Repeated acceleration records of one channel on a common time base.

    Used for shock data such as the AFRL drop-tower set (one accelerometer,
    several repeated tests).

    Parameters
    ----------
    time : numpy.ndarray
        Time in s, shape ``(n_samples,)``, strictly increasing.
    accel : numpy.ndarray
        Acceleration in m/s^2, shape ``(n_samples, n_tests)``.
    channel : str
        Name of the accelerometer channel.
    source : Source
        Provenance.
    """

    time: np.ndarray
    accel: np.ndarray
    channel: str = ""
    source: Source = field(default_factory=Source)

    def __post_init__(self) -> None:
        time = as_signal(self.time, "time", self.source)
        try:
            accel = np.array(self.accel, dtype=np.float64, copy=True)
        except (TypeError, ValueError) as exc:
            raise DataError(f"{self.source.where('accel')}: not numbers ({exc})") from exc
        if accel.ndim == 1:
            accel = accel[:, None]
        if accel.ndim != 2 or accel.shape[0] != time.size:
            raise DataError(f"{self.source.where('accel')}: found shape {accel.shape}, "
                            f"expected ({time.size}, n_tests)")
        for j in range(accel.shape[1]):
            as_signal(accel[:, j], f"test {j + 1}", self.source)
        accel.setflags(write=False)
        UNIFORM_TIME_AXIS.check(time, "time", self.source)
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "accel", accel)

    @property
    def n_tests(self) -> int:
        """Number of repeated tests (columns of ``accel``)."""
        return int(self.accel.shape[1])

    @property
    def sample_rate_hz(self) -> float:
        """Sample rate in Hz from the median time step (:meth:`Axis.rate_hz`)."""
        return TIME_AXIS.rate_hz(self.time)

    def to_dataframe(self) -> pd.DataFrame:
        """Time and one acceleration column per test (``test_1 [m/s^2]`` ...)."""
        data = {"time [s]": np.array(self.time)}
        for j in range(self.n_tests):
            data[f"test_{j + 1} [m/s^2]"] = np.array(self.accel[:, j])
        return pd.DataFrame(data)
