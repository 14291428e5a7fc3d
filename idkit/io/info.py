"""Metadata of one measurement (what a manifest entry says besides its file)."""

from __future__ import annotations

import math
from dataclasses import dataclass

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


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _check_positive(name: str, value: float | None) -> None:
    if value is None:
        return
    if not _is_number(value) or not math.isfinite(value) or value <= 0:
        raise DataError(f"{name}: found {value!r}, expected a finite number > 0")


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
        _check_positive("excitation freq [Hz]", self.freq)
        _check_positive("excitation amplitude", self.amplitude)
        if (self.amplitude is None) != (self.amplitude_quantity is None):
            raise DataError(
                f"excitation: amplitude={self.amplitude!r} and "
                f"amplitude_quantity={self.amplitude_quantity!r} must be given together"
            )
        quantity = self.amplitude_quantity
        if quantity is not None and quantity not in AMPLITUDE_QUANTITIES:
            raise DataError(
                f"excitation amplitude_quantity: found {self.amplitude_quantity!r}, "
                f"expected one of {', '.join(AMPLITUDE_QUANTITIES)}"
            )
        if self.band is not None:
            band = tuple(self.band)
            if (len(band) != 2 or not all(_is_number(b) and math.isfinite(b) for b in band)
                    or not 0 <= band[0] < band[1]):
                raise DataError(
                    f"excitation band [Hz]: found {self.band!r}, expected [low, high] "
                    "with 0 <= low < high"
                )
            object.__setattr__(self, "band", (float(band[0]), float(band[1])))


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
        if not isinstance(self.id, str):
            raise DataError(f"id: found {self.id!r}, expected a string")
        isolator = self.isolator
        if isolator is not None and (not isinstance(isolator, str) or not isolator.strip()):
            raise DataError(f"isolator: found {self.isolator!r}, expected a non-empty string "
                            f"(one of {', '.join(ISOLATORS)} or free text)")
        for name in ("top_mass_kg", "intermediate_mass_kg", "bottom_mass_kg",
                     "drop_height_m", "sample_rate_hz"):
            _check_positive(name, getattr(self, name))
        if self.repetition is not None and (
            not isinstance(self.repetition, int) or isinstance(self.repetition, bool)
            or not 1 <= self.repetition <= MAX_REPETITION
        ):
            found = (repr(self.repetition) if not isinstance(self.repetition, int) or self.repetition < 10**20
                     else f"an integer of {len(str(self.repetition))} digits")
            raise DataError(f"repetition: found {found}, expected an integer from 1 to 2^53 - 1 = {MAX_REPETITION} "
                            "(larger ones are not exact in JSON readers)")
        if self.split is not None and self.split not in SPLITS:
            raise DataError(f"split: found {self.split!r}, expected one of {', '.join(SPLITS)}")
        if not isinstance(self.notes, str):
            raise DataError(f"notes: found {self.notes!r}, expected a string")
        if self.excitation is not None and not isinstance(self.excitation, Excitation):
            raise DataError(f"excitation: found {type(self.excitation).__name__}, "
                            "expected Excitation")
