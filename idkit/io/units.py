"""Unit table: declared units of measurement columns converted to SI.

Every column of a measurement file declares its unit in its header
(``force [daN]``). The unit is interpreted *in the context of the column's
physical quantity*, which is fixed by the column name (``force`` is a force,
``a_top_1`` an acceleration). This resolves symbols that mean different
things in different quantities: ``g`` is the standard gravity
(9.80665 m/s^2) in an acceleration column and would be the gram in a mass
column. idkit never guesses: a missing or unknown unit raises
:class:`~idkit.errors.DataError` naming the file, the column, the unit found
and the units accepted for that quantity.

Conversions multiply by an exact integer numerator and divide by an exact
integer denominator where the factor is a power of ten below one (``mm`` ->
``m`` divides by 1000), so a value converted to SI is the correctly rounded
result of the exact conversion. Temperatures are the only affine conversion
(``C`` -> ``K`` adds 273.15). Imperial units use the exact international definitions
(1 in = 0.0254 m, 1 lbf = 4.4482216152605 N, 1 kip = 1 klbf = 1000 lbf); their factors
to SI, and those of the units derived from them (``psi``, ``lbf/in``), are the float64
nearest the exact product, so these conversions are within one rounding of exact.

The AFRL drop-tower data are in units of 1000 g (written ``kg_n`` in their
source). ``kg`` would read as kilogram, so idkit spells this unit ``1000g``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.errors import DataError
from idkit.gravity import STANDARD_GRAVITY

__all__ = [
    "QUANTITIES",
    "SI_UNITS",
    "UnitScale",
    "accepted_units",
    "convert_to_si",
    "convert_from_si",
    "lookup_unit",
]

#: Standard gravity in m/s^2 (CGPM 1901), used for ``g``, ``1000g`` and ``kgf``.
STANDARD_GRAVITY_M_PER_S2 = STANDARD_GRAVITY  # one value of g (idkit.gravity)
#: The international inch and foot (1959 agreement), exact in m.
INCH_M = 0.0254
FOOT_M = 0.3048
#: The pound-force: 0.45359237 kg (the international avoirdupois pound, exact) x 9.80665 m/s^2,
#: 4.4482216152605 N exactly; a kip (klbf) is 1000 lbf.
POUND_FORCE_N = 4.4482216152605


@dataclass(frozen=True)
class UnitScale:
    """Conversion of one declared unit to SI: ``si = value * numerator / denominator + offset``.

    Parameters
    ----------
    symbol : str
        The unit as written in a column header, e.g. ``"mm"``.
    quantity : str
        Physical quantity the symbol belongs to, e.g. ``"length"``.
    numerator, denominator : float
        The scale factor split so that decimal sub-multiples divide by an
        exact power of ten (better rounding than multiplying by ``1e-3``).
    offset : float
        Added after scaling, in SI units (only temperatures: 273.15 K).
    """

    symbol: str
    quantity: str
    numerator: float = 1.0
    denominator: float = 1.0
    offset: float = 0.0

    @property
    def factor(self) -> float:
        """Scale factor to SI (dimensionless ratio ``numerator / denominator``)."""
        return self.numerator / self.denominator


def _table() -> dict[str, dict[str, UnitScale]]:
    g0 = STANDARD_GRAVITY_M_PER_S2
    spec: dict[str, list[tuple[str, float, float]]] = {
        # quantity: [(symbol, numerator, denominator)]
        "time": [("s", 1, 1), ("ms", 1, 1e3), ("us", 1, 1e6), ("min", 60, 1)],
        "length": [("m", 1, 1), ("cm", 1, 1e2), ("mm", 1, 1e3), ("um", 1, 1e6),
                   ("\u00b5m", 1, 1e6), ("in", INCH_M, 1), ("ft", FOOT_M, 1), ("mil", INCH_M, 1e3)],
        "velocity": [("m/s", 1, 1), ("cm/s", 1, 1e2), ("mm/s", 1, 1e3), ("in/s", INCH_M, 1),
                     ("ft/s", FOOT_M, 1)],
        "acceleration": [("m/s^2", 1, 1), ("mm/s^2", 1, 1e3), ("g", g0, 1),
                         ("1000g", g0 * 1000, 1), ("in/s^2", INCH_M, 1), ("ft/s^2", FOOT_M, 1)],
        "force": [("N", 1, 1), ("daN", 10, 1), ("kN", 1e3, 1), ("MN", 1e6, 1),
                  ("lbf", POUND_FORCE_N, 1), ("kip", POUND_FORCE_N * 1000, 1),
                  ("klbf", POUND_FORCE_N * 1000, 1), ("kgf", g0, 1)],
        "frequency": [("Hz", 1, 1), ("kHz", 1e3, 1)],
        "stiffness": [("N/m", 1, 1), ("N/mm", 1e3, 1), ("kN/m", 1e3, 1),
                      ("kN/mm", 1e6, 1), ("lbf/in", POUND_FORCE_N / INCH_M, 1),
                      ("kip/in", POUND_FORCE_N * 1000 / INCH_M, 1)],
        "modulus": [("Pa", 1, 1), ("kPa", 1e3, 1), ("MPa", 1e6, 1), ("GPa", 1e9, 1),
                    ("psi", POUND_FORCE_N / INCH_M**2, 1), ("ksi", POUND_FORCE_N * 1000 / INCH_M**2, 1)],
        "mass": [("kg", 1, 1), ("g", 1, 1e3)],
        "voltage": [("V", 1, 1), ("mV", 1, 1e3)],
        "dimensionless": [("-", 1, 1), ("1", 1, 1)],
    }
    table = {
        quantity: {sym: UnitScale(sym, quantity, float(num), float(den))
                   for sym, num, den in rows}
        for quantity, rows in spec.items()
    }
    table["temperature"] = {
        "K": UnitScale("K", "temperature"),
        "C": UnitScale("C", "temperature", offset=273.15),
        "degC": UnitScale("degC", "temperature", offset=273.15),
        "\u00b0C": UnitScale("\u00b0C", "temperature", offset=273.15),
    }
    return table


_UNITS = _table()

#: Physical quantities idkit knows, each with its accepted unit symbols.
QUANTITIES: tuple[str, ...] = tuple(_UNITS)

#: The SI unit symbol idkit uses for each quantity (in written files and DataFrames).
SI_UNITS: dict[str, str] = {
    "time": "s", "length": "m", "velocity": "m/s", "acceleration": "m/s^2",
    "force": "N", "frequency": "Hz", "stiffness": "N/m", "modulus": "Pa",
    "mass": "kg", "voltage": "V", "dimensionless": "-", "temperature": "K",
}


def accepted_units(quantity: str) -> tuple[str, ...]:
    """Unit symbols accepted for a physical quantity.

    Parameters
    ----------
    quantity : str
        One of :data:`QUANTITIES`, e.g. ``"force"``.

    Returns
    -------
    tuple of str
        The symbols, SI first, e.g. ``("N", "daN", "kN", "MN", "lbf", "kip", "klbf", "kgf")``.

    Examples
    --------
    >>> accepted_units("length")
    ('m', 'cm', 'mm', 'um', '\u00b5m', 'in', 'ft', 'mil')
    """
    try:
        return tuple(_UNITS[quantity])
    except KeyError:
        raise KeyError(f"unknown quantity {quantity!r}; known: {', '.join(QUANTITIES)}") from None


def lookup_unit(unit: str | None, quantities: tuple[str, ...] | str, *, where: str) -> UnitScale:
    """Find the scale of a declared unit among the units of the given quantities.

    Parameters
    ----------
    unit : str or None
        The unit as declared, e.g. ``"daN"``; ``None`` or ``""`` means missing.
    quantities : str or tuple of str
        The physical quantity (or the admissible quantities, in order) of the
        column, e.g. ``"force"`` or ``("stiffness", "modulus")``.
    where : str
        Location for error messages, e.g. ``"file 'a.csv', column 'force'"``.

    Returns
    -------
    UnitScale
        The conversion to SI; its ``quantity`` says which quantity matched.

    Raises
    ------
    DataError
        If the unit is missing or not accepted for these quantities.
    """
    if isinstance(quantities, str):
        quantities = (quantities,)
    accepted = [sym for q in quantities for sym in _UNITS[q]]
    if unit is None or not unit.strip():
        raise DataError(
            f"{where}: unit missing; expected a header like 'name [unit]' with one of "
            f"{', '.join(accepted)} ({' or '.join(quantities)})"
        )
    for quantity in quantities:
        scale = _UNITS[quantity].get(unit.strip())
        if scale is not None:
            return scale
    raise DataError(
        f"{where}: unknown unit {unit!r} for quantity {' or '.join(quantities)}{_closest_unit(unit, accepted)}; "
        f"accepted: {', '.join(accepted)}"
    )


def _closest_unit(unit: str, accepted) -> str:
    """`` (did you mean 'kN'?)`` for a unit that differs from an accepted one by case (units are
    case-sensitive) or by a slip of spelling; ``""`` when none is close. A milli- and a mega-
    unit differ by case only (``mN``, ``MN``: nine decades apart): never suggested for each other."""
    import difflib

    unit = unit.strip()
    same_letters = [symbol for symbol in accepted if symbol.lower() == unit.lower()
                    and {symbol[0], unit[0]} != {"m", "M"}]
    close = same_letters or difflib.get_close_matches(unit, accepted, n=1, cutoff=0.75)
    return f" (did you mean {close[0]!r}?)" if close else ""


def convert_to_si(values: np.ndarray, scale: UnitScale) -> np.ndarray:
    """Convert values in a declared unit to SI (a new float64 array).

    Parameters
    ----------
    values : numpy.ndarray
        Values in the unit ``scale.symbol``.
    scale : UnitScale
        From :func:`lookup_unit`.

    Returns
    -------
    numpy.ndarray
        Values in the SI unit of ``scale.quantity`` (:data:`SI_UNITS`).

    Examples
    --------
    >>> import numpy as np
    >>> scale = lookup_unit("mm", "length", where="example")
    >>> convert_to_si(np.array([1500.0]), scale)
    array([1.5])
    """
    out = np.array(values, dtype=np.float64, copy=True)
    if scale.numerator != 1.0:
        out *= scale.numerator
    if scale.denominator != 1.0:
        out /= scale.denominator
    if scale.offset != 0.0:
        out += scale.offset
    return out


def convert_from_si(values: np.ndarray, scale: UnitScale) -> np.ndarray:
    """Convert SI values to the unit ``scale.symbol`` (inverse of :func:`convert_to_si`).

    Not bit-exact in general for non-SI units: a value converted there and
    back can differ in the last bit.

    Parameters
    ----------
    values : numpy.ndarray
        Values in the SI unit of ``scale.quantity``.
    scale : UnitScale
        Target unit.

    Returns
    -------
    numpy.ndarray
        Values in ``scale.symbol``.
    """
    out = np.array(values, dtype=np.float64, copy=True)
    if scale.offset != 0.0:
        out -= scale.offset
    if scale.denominator != 1.0:
        out *= scale.denominator
    if scale.numerator != 1.0:
        out /= scale.numerator
    return out
