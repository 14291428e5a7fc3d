"""Every numeric command-line option whose type is an idkit.checks spec, fed the values its spec
must refuse, as one table: argparse stops with exit status 2 and a message naming the option, the
text found and what is expected (the library's own template). A new option declared with
``opt.real``/``opt.integer`` is covered by declaring it."""

from __future__ import annotations

import argparse
import math

import pytest

from idkit.checks import Spec
from idkit.cli.main import build_parser

PARSER = build_parser()
#: argparse's exit status for a refused option (every command's usage error)
USAGE_ERROR = 2


def _spec_options(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """``(command path, action, spec)`` of every option typed by a spec's ``parse``."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _spec_options(sub, path + (name,))
        elif action.option_strings and isinstance(getattr(action.type, "__self__", None), Spec):
            yield path, action, action.type.__self__


def _texts(spec: Spec) -> list[str]:
    """The spec's bad values as command-line text (text that reads as a valid number is not bad there)."""
    texts = ["abc"]
    for value in spec.bad_values():
        if isinstance(value, float) and not value.is_integer() or isinstance(value, int) and not isinstance(value, bool):
            texts.append(repr(value) if not (isinstance(value, float) and math.isinf(value)) else str(value))
    return list(dict.fromkeys(texts))


OPTIONS = list(_spec_options(PARSER))
CASES = [pytest.param(path, action, spec, id=f"{' '.join(path)} {action.option_strings[-1]}")
         for path, action, spec in OPTIONS]


def test_the_numeric_options_are_typed_by_specs():
    assert len(OPTIONS) > 40


@pytest.mark.parametrize(("path", "action", "spec"), CASES)
def test_every_spec_option_refuses_its_bad_values_naming_itself(path, action, spec, capsys):
    count = action.nargs if isinstance(action.nargs, int) else 1
    for text in _texts(spec):
        with pytest.raises(SystemExit) as stopped:
            PARSER.parse_args([*path, action.option_strings[-1], *[text] * count])
        assert stopped.value.code == USAGE_ERROR, text
        message = capsys.readouterr().err.strip().splitlines()[-1]
        assert f"argument {'/'.join(action.option_strings)}: found {text!r}, expected " in message, message
