"""Metadata of one measurement (what a manifest entry says besides its file)."""

from __future__ import annotations

from dataclasses import dataclass, fields

from idkit.checks import Choice, Field, Instance, Real, Reals, Text, Whole, check_fields
from idkit.errors import DataError

__all__ = ["ISOLATORS", "MAX_REPETITION", "SPLITS", "Excitation", "MeasurementInfo"]

#: Isolator types idkit models; other free-text names are allowed.
ISOLATORS: tuple[str, ...] = ("wire_rope", "elastomer", "hybrid")

#: Allowed values of ``split``.
SPLITS: tuple[str, ...] = ("fit", "validation")

#: Largest repetition number: integers above 2^53 - 1 are not exact in JSON readers that hold
#: numbers as IEEE doubles (RFC 8259, section 6), so a manifest would not say the same everywhere.
MAX_REPETITION = 2**53 - 1

#: Quantities a nominal stepped-sine amplitude may have.
AMPLITUDE_QUANTITIES: tuple[str, ...] = ("velocity", "length", "acceleration", "voltage")

#: The contract of each :class:`Excitation` field (its unit and meaning in the spec).
EXCITATION_FIELDS: tuple[Field, ...] = (
    Field("freq", Real(unit="Hz", gt=0, optional=True, meaning="stepped-sine excitation frequency")),
    Field("amplitude", Real(gt=0, optional=True, meaning="nominal amplitude in the SI unit of its quantity")),
    Field("amplitude_quantity", Choice(AMPLITUDE_QUANTITIES, optional=True)),
    Field("band", Reals(unit="Hz", ge=0, min_size=2, max_size=2, increasing=True, optional=True,
                        meaning="white-noise band [low, high]")),
)


@dataclass(frozen=True)
class Excitation:
    """Nominal shaker excitation of a run (SPEC section 3).

    Parameters
    ----------
    freq : float or None
        Stepped sine: excitation frequency in Hz (> 0).
    amplitude : float or None
        Stepped sine: nominal amplitude in the SI unit of
        ``amplitude_quantity`` (m/s, m, m/s^2 or V).
    amplitude_quantity : str or None
        ``"velocity"``, ``"length"``, ``"acceleration"`` or ``"voltage"``;
        required when ``amplitude`` is given.
    band : tuple of float or None
        White noise: (low, high) frequency band in Hz, ``0 <= low < high``.

    Examples
    --------
    >>> Excitation(freq=20.0, amplitude=0.01, amplitude_quantity="velocity").freq
    20.0
    """

    freq: float | None = None
    amplitude: float | None = None
    amplitude_quantity: str | None = None
    band: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        checked = check_fields({f.name: getattr(self, f.name) for f in fields(self)}, EXCITATION_FIELDS, "excitation")
        if checked["band"] is not None:
            checked["band"] = (float(checked["band"][0]), float(checked["band"][1]))
        for name, value in checked.items():
            object.__setattr__(self, name, value)
        if (self.amplitude is None) != (self.amplitude_quantity is None):
            raise DataError(
                f"excitation: amplitude={self.amplitude!r} and "
                f"amplitude_quantity={self.amplitude_quantity!r} must be given together"
            )


@dataclass(frozen=True)
class MeasurementInfo:
    """What is known about a measurement besides its samples.

    Parameters
    ----------
    id : str
        Identifier, unique within a measurement set.
    isolator : str or None
        ``"wire_rope"``, ``"elastomer"``, ``"hybrid"`` or free text.
    top_mass_kg, intermediate_mass_kg, bottom_mass_kg : float or None
        Masses in kg (> 0) as applicable.
    drop_height_m : float or None
        Drop height in m (> 0), drops only.
    repetition : int or None
        Repetition number (>= 1) of the same test condition.
    sample_rate_hz : float or None
        Declared sample rate in Hz; checked against the time column
        (tolerance 1 %, see :data:`SAMPLE_RATE_TOLERANCE`).
    split : str or None
        ``"fit"`` or ``"validation"``.
    notes : str
        Free-form notes.
    excitation : Excitation or None
        Shaker excitation (stepped sine: frequency and nominal amplitude;
        white noise: band).
    """

    id: str = ""
    isolator: str | None = None
    top_mass_kg: float | None = None
    intermediate_mass_kg: float | None = None
    bottom_mass_kg: float | None = None
    drop_height_m: float | None = None
    repetition: int | None = None
    sample_rate_hz: float | None = None
    split: str | None = None
    notes: str = ""
    excitation: Excitation | None = None

    def __post_init__(self) -> None:
        checked = check_fields({f.name: getattr(self, f.name) for f in fields(self)}, INFO_FIELDS, "")
        for name, value in checked.items():
            object.__setattr__(self, name, value)


_MASS = Real(unit="kg", gt=0, optional=True)

#: The contract of each :class:`MeasurementInfo` field; a manifest entry's metadata keys are these.
INFO_FIELDS: tuple[Field, ...] = (
    Field("id", Text()),
    Field("isolator", Text(nonempty=True, optional=True,
                           what=f"a non-empty string (one of {', '.join(ISOLATORS)} or free text)")),
    Field("top_mass_kg", _MASS), Field("intermediate_mass_kg", _MASS), Field("bottom_mass_kg", _MASS),
    Field("drop_height_m", Real(unit="m", gt=0, optional=True, meaning="drop height")),
    Field("repetition", Whole(ge=1, le=MAX_REPETITION, optional=True,
                              meaning="2^53 - 1 at most: larger ones are not exact in JSON readers")),
    Field("sample_rate_hz", Real(unit="Hz", gt=0, optional=True, meaning="declared sample rate")),
    Field("split", Choice(SPLITS, optional=True)),
    Field("notes", Text()),
    Field("excitation", Instance((Excitation,), optional=True)),
)
