"""Suggestions of library errors spelled as ``idkit`` options.

An idkit error that suggests another argument value carries it as a
:class:`idkit.errors.Suggestion` inside a :class:`idkit.errors.Message`; Python callers
read ``k0_method='secant'``. The command line prints the same message with each
suggestion spelled as the option that sets it (``--k0-method secant``), from the one
table :data:`OPTION_SPELLINGS`. A keyword the table lacks keeps its Python spelling
(tests/cli/test_hints.py checks that every suggestion idkit raises is in the table).
"""

from __future__ import annotations

from idkit.errors import Message, Suggestion

__all__ = ["OPTION_SPELLINGS", "spell_option", "cli_message"]


#: keyword of the Python API -> its spelling as an ``idkit`` option, given the suggested value.
OPTION_SPELLINGS = {
    "k0_method": lambda value: f"--k0-method {value}",
    "isolator": lambda value: "every isolator (no --isolator)" if value is None else f"--isolator {value}",
    "split": lambda value: f"--split {'all' if value is None else value}",
    "valid_range": lambda value: "--no-valid-range" if value is None else "--valid-range X_MIN X_MAX",
    "force_offset": lambda value: "no --remove-offsets" if not value else "--remove-offsets",
    "offset": lambda value: f"--offset {value}",
}


def spell_option(suggestion: Suggestion) -> str:
    """``suggestion`` as an ``idkit`` option (its Python spelling when no option sets it).

    Examples
    --------
    >>> spell_option(Suggestion("k0_method", "secant"))
    '--k0-method secant'
    >>> spell_option(Suggestion("split", None))
    '--split all'
    """
    spelling = OPTION_SPELLINGS.get(suggestion.keyword)
    return str(suggestion) if spelling is None else spelling(suggestion.value)


def cli_message(problem: BaseException) -> str:
    """The text ``idkit`` prints for ``problem``: its message with suggestions as options."""
    if len(problem.args) == 1 and isinstance(problem.args[0], Message):
        return problem.args[0].render(spell_option)
    return str(problem)
