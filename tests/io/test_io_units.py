"""Unit table: conversions to SI, context-dependent symbols, errors."""

from __future__ import annotations

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.io.units import (
    QUANTITIES,
    SI_UNITS,
    STANDARD_GRAVITY_M_PER_S2,
    accepted_units,
    convert_from_si,
    convert_to_si,
    lookup_unit,
)


@pytest.mark.parametrize(("unit", "quantity", "value", "si"), [
    ("mm", "length", 1500.0, 1.5),
    ("um", "length", 250.0, 2.5e-4),
    ("cm", "length", 3.0, 0.03),
    ("in", "length", 1.0, 0.0254),
    ("daN", "force", 1.5, 15.0),
    ("kN", "force", 2.0, 2000.0),
    ("lbf", "force", 1.0, 4.4482216152605),
    # a kip is 1000 lbf and a klbf the same unit; kgf is the kilogram's weight under standard gravity
    ("kip", "force", 2.0, 8896.443230521),
    ("klbf", "force", 1.0, 4448.2216152605),
    ("kgf", "force", 10.0, 98.0665),
    ("MN", "force", 1.5, 1.5e6),
    ("ft", "length", 1.0, 0.3048),
    ("mil", "length", 10.0, 2.54e-4),
    ("\u00b5m", "length", 250.0, 2.5e-4),
    ("ft/s", "velocity", 2.0, 0.6096),
    ("in/s^2", "acceleration", 1.0, 0.0254),
    ("lbf/in", "stiffness", 1.0, 4.4482216152605 / 0.0254),
    ("psi", "modulus", 1.0, 6894.757293168361),
    ("g", "acceleration", 2.0, 2 * 9.80665),
    ("1000g", "acceleration", 1.0, 9806.65),
    ("mm/s", "velocity", 10.0, 0.01),
    ("in/s", "velocity", 1.0, 0.0254),
    ("ms", "time", 5.0, 0.005),
    ("kHz", "frequency", 1.2, 1200.0),
    ("N/mm", "stiffness", 21.0, 21e3),
    ("MPa", "modulus", 8.0, 8e6),
    ("GPa", "modulus", 2.0, 2e9),
    ("g", "mass", 140.0, 0.14),
    ("mV", "voltage", 250.0, 0.25),
    ("C", "temperature", -5.0, 268.15),
])
def test_conversion_to_si(unit, quantity, value, si):
    scale = lookup_unit(unit, quantity, where="test")
    assert scale.quantity == quantity
    assert convert_to_si(np.array([value]), scale)[0] == pytest.approx(si, rel=1e-15)


def test_g_means_gravity_in_acceleration_and_gram_in_mass():
    assert lookup_unit("g", "acceleration", where="t").factor == STANDARD_GRAVITY_M_PER_S2
    assert lookup_unit("g", "mass", where="t").factor == 1e-3


def test_decimal_submultiples_divide_exactly():
    # 0.3 mm -> m must equal 0.3 / 1000 (correctly rounded), not 0.3 * 1e-3
    scale = lookup_unit("mm", "length", where="t")
    assert convert_to_si(np.array([0.3]), scale)[0] == 0.3 / 1000


def test_si_units_are_identity_and_round_trip():
    rng = np.random.default_rng(1)
    values = rng.normal(size=100)
    for quantity in QUANTITIES:
        scale = lookup_unit(SI_UNITS[quantity], quantity, where="t")
        assert np.array_equal(convert_to_si(values, scale), values)
        assert np.array_equal(convert_from_si(values, scale), values)


def test_kilogram_is_not_an_acceleration_unit():
    with pytest.raises(DataError, match="unknown unit 'kg'.*1000g"):
        lookup_unit("kg", "acceleration", where="file 'a.csv', column 'a_top_1 [kg]'")


@pytest.mark.parametrize("unit", [None, "", "  "])
def test_missing_unit_is_an_error(unit):
    with pytest.raises(DataError, match="unit missing"):
        lookup_unit(unit, "force", where="file 'a.csv', column 'force'")


def test_unknown_unit_message_names_location_and_accepted_units():
    with pytest.raises(DataError) as info:
        lookup_unit("tonf", "force", where="file 'a.csv', column 'force [tonf]'")
    message = str(info.value)
    for fragment in ("a.csv", "force [tonf]", "'tonf'", ", ".join(accepted_units("force"))):
        assert fragment in message


def test_units_are_case_sensitive():
    with pytest.raises(DataError):
        lookup_unit("MM", "length", where="t")
    with pytest.raises(DataError):
        lookup_unit("G", "acceleration", where="t")


def test_unknown_quantity_lists_known_ones():
    with pytest.raises(KeyError, match="known"):
        accepted_units("luminosity")


@pytest.mark.parametrize(("unit", "quantity", "hint"), [
    ("KN", "force", " (did you mean 'kN'?)"),
    ("hz", "frequency", " (did you mean 'Hz'?)"),
    ("mm/sec", "velocity", " (did you mean 'mm/s'?)"),
    ("lb", "force", " (did you mean 'lbf'?)"),
    ("mN", "force", ""),     # a millinewton is not a meganewton: no case-only hint across m/M
    ("mpa", "modulus", ""),
    ("tonf", "force", ""),
])
def test_unknown_unit_names_the_close_accepted_one_never_taking_it(unit, quantity, hint):
    with pytest.raises(DataError) as info:
        lookup_unit(unit, quantity, where="file 'a.csv', column 'x'")
    assert f"unknown unit {unit!r} for quantity {quantity}{hint}; accepted" in str(info.value)
