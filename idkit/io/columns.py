"""Column schema: the columns of each kind of measurement and their quantities.

A column header is ``name [unit]``. The name fixes the physical quantity
(:data:`COLUMN_QUANTITIES`), the unit is looked up within that quantity
(:mod:`idkit.io.units`). :data:`KIND_SCHEMAS` lists, per kind of measurement
(SPEC section 3), the required and optional columns.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass

from idkit.checks import Choice
from idkit.errors import DataError

__all__ = [
    "COLUMN_QUANTITIES",
    "KINDS",
    "KIND_SCHEMAS",
    "KindSchema",
    "COLUMN_SYNONYMS",
    "closest_column_names",
    "did_you_mean",
    "parse_header_cell",
]

#: Kinds of measurements (SPEC section 3).
KINDS: tuple[str, ...] = ("quasi_static", "white_noise", "stepped_sine", "drop")

#: The contract of a ``kind`` argument or manifest key.
KIND = Choice(KINDS)

#: Physical quantity (or admissible quantities) of every known column name.
COLUMN_QUANTITIES: dict[str, tuple[str, ...]] = {
    "time": ("time",),
    "deflection": ("length",),
    "force": ("force",),
    "v_rel": ("velocity",),
    "v_base": ("velocity",),
    "v_top": ("velocity",),
    "x_base": ("length",),
    "u_in": ("voltage",),
    "a_base": ("acceleration",),
    "a_top": ("acceleration",),
    "a_top_1": ("acceleration",),
    "a_top_2": ("acceleration",),
    # complex stiffness / DMA tables
    "frequency": ("frequency",),
    "storage": ("stiffness", "modulus"),
    "loss": ("stiffness", "modulus"),
    "temperature": ("temperature",),
    "log_aT": ("dimensionless",),
}


@dataclass(frozen=True)
class KindSchema:
    """Columns of one kind of measurement file.

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.
    required : tuple of str
        Columns that must be present.
    optional : tuple of str
        Columns that may be present.
    alternatives : tuple of tuple of str
        Groups of columns of which at least one group must be complete
        (white noise: velocities or accelerations); a group given in part is
        an error.
    """

    kind: str
    required: tuple[str, ...]
    optional: tuple[str, ...] = ()
    alternatives: tuple[tuple[str, ...], ...] = ()

    @property
    def allowed(self) -> tuple[str, ...]:
        """Every column name this kind accepts."""
        names = list(self.required) + list(self.optional)
        for group in self.alternatives:
            names.extend(group)
        return tuple(dict.fromkeys(names))

    def describe(self) -> str:
        """Human-readable list of the expected columns (for error messages)."""
        text = "required " + ", ".join(self.required)
        if self.alternatives:
            text += "; and all of " + " or all of ".join(
                "(" + ", ".join(group) + ")" for group in self.alternatives
            )
        if self.optional:
            text += "; optional " + ", ".join(self.optional)
        return text


KIND_SCHEMAS: dict[str, KindSchema] = {
    "quasi_static": KindSchema("quasi_static", ("time", "deflection", "force"), ("v_rel",)),
    "white_noise": KindSchema(
        "white_noise", ("time",), (), (("v_base", "v_top"), ("a_base", "a_top"))
    ),
    "stepped_sine": KindSchema(
        "stepped_sine", ("time", "v_base", "v_top"), ("x_base", "u_in")
    ),
    "drop": KindSchema("drop", ("time", "deflection", "a_top_1", "a_top_2"), ("v_rel",)),
}

COMPLEX_STIFFNESS_SCHEMA = KindSchema(
    "complex_stiffness", ("frequency", "storage", "loss"), ("temperature", "log_aT")
)

#: Common lab names of idkit's columns (lower case). They only feed the "did you mean" hint of an
#: unknown column: a file is never read under a name it does not carry, since ``displacement``
#: may be the base's displacement rather than the isolator's deflection.
COLUMN_SYNONYMS: dict[str, tuple[str, ...]] = {
    "displacement": ("deflection", "x_base"), "disp": ("deflection", "x_base"), "stroke": ("deflection",),
    "extension": ("deflection",), "elongation": ("deflection",), "position": ("deflection", "x_base"),
    "compression": ("deflection",), "travel": ("deflection",), "x": ("deflection",), "x_rel": ("deflection",),
    "load": ("force",), "f": ("force", "frequency"), "reaction": ("force",), "force_n": ("force",),
    "t": ("time",), "seconds": ("time",), "timestamp": ("time",),
    "velocity": ("v_rel", "v_base", "v_top"), "vel": ("v_rel", "v_base", "v_top"),
    "acceleration": ("a_top", "a_base", "a_top_1"), "accel": ("a_top", "a_base", "a_top_1"),
    "acc": ("a_top", "a_base", "a_top_1"), "voltage": ("u_in",),
    "freq": ("frequency",), "e_stor": ("storage",), "e_storage": ("storage",), "storage_modulus": ("storage",),
    "e_loss": ("loss",), "loss_modulus": ("loss",), "temp": ("temperature",), "t_c": ("temperature",),
}


def closest_column_names(name: str, allowed, *, n: int = 2) -> tuple[str, ...]:
    """The known column names closest to an unknown ``name``: synonyms first, then spelling.

    Parameters
    ----------
    name : str
        The column name found in a file, e.g. ``"displacement"``.
    allowed : iterable of str
        The names this kind of file accepts.
    n : int
        At most this many names.

    Returns
    -------
    tuple of str
        Names of ``allowed``, best first (empty when nothing is close): the
        :data:`COLUMN_SYNONYMS` of ``name`` (case-insensitive), then :func:`difflib.get_close_matches`.

    Examples
    --------
    >>> closest_column_names("displacement", ("time", "deflection", "force"))
    ('deflection',)
    >>> closest_column_names("forse", ("time", "deflection", "force"))
    ('force',)
    """
    allowed = tuple(allowed)
    lowered = {candidate.lower(): candidate for candidate in allowed}
    found = [candidate for candidate in COLUMN_SYNONYMS.get(name.lower(), ()) if candidate in allowed]
    if name.lower() in lowered:
        found.insert(0, lowered[name.lower()])
    found += [lowered[close] for close in difflib.get_close_matches(name.lower(), list(lowered), n=n)]
    return tuple(dict.fromkeys(found))[:n]


def did_you_mean(name: str, allowed) -> str:
    """`` (did you mean 'deflection'?)`` for an unknown column ``name``, or ``""`` when nothing is close."""
    close = closest_column_names(name, allowed)
    return f" (did you mean {' or '.join(repr(c) for c in close)}?)" if close else ""


_HEADER_RE = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\[([^\[\]]*)\])?\s*$")


def parse_header_cell(cell: str, *, where: str) -> tuple[str, str | None]:
    """Split a header cell ``name [unit]`` into name and unit.

    Parameters
    ----------
    cell : str
        The header cell, e.g. ``"force [daN]"``.
    where : str
        Location for error messages (file and column number).

    Returns
    -------
    name : str
        Column name, e.g. ``"force"``.
    unit : str or None
        Unit symbol stripped of spaces, or ``None`` if there are no brackets
        or they are empty (the caller reports the missing unit, knowing
        whether the name is known).

    Raises
    ------
    DataError
        If the cell is not of the form ``name`` or ``name [unit]``.
    """
    match = _HEADER_RE.match(cell)
    if match is None:
        raise DataError(
            f"{where}: header cell {cell!r} is not of the form 'name [unit]' "
            "(name: letters, digits, underscore)"
        )
    name, unit = match.group(1), match.group(2)
    unit = unit.strip() if unit is not None else None
    return name, (unit or None)
