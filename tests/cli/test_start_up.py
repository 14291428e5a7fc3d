"""The ``idkit`` command starts without the numerical stacks: building the parser, ``--version``
and every ``--help`` import no pandas, scipy, numba or matplotlib (each command imports what it
runs, when it runs). Checked in a fresh interpreter, since the test process has them loaded."""

import json
import subprocess
import sys

#: Imported by no parser path (numpy is: the option types are the specs of idkit.checks).
HEAVY = ("pandas", "scipy", "numba", "matplotlib")

_PROBE = f"""
import argparse, contextlib, io, json, sys
from idkit.cli.main import build_parser, main

def commands(parser, path=()):
    subparsers = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    yield path
    for name, command in (subparsers[0].choices.items() if subparsers else ()):
        yield from commands(command, (*path, name))

answers = {{}}
for argv in (["--version"], *[[*path, "--help"] for path in commands(build_parser())]):
    with contextlib.redirect_stdout(io.StringIO()) as shown:
        try:
            main(argv)
        except SystemExit as stop:
            answers[" ".join(argv)] = (stop.code, bool(shown.getvalue().strip()))
print(json.dumps({{"answers": answers, "heavy": sorted(m for m in {HEAVY!r} if m in sys.modules)}}))
"""


def test_version_and_every_help_import_no_heavy_stack():
    completed = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True, check=True)
    found = json.loads(completed.stdout)
    answers = found["answers"]
    # the probe reached what it claims: the version, the top help and each command's help, all answered
    assert {"--version", "--help", "report --help", "data generate --help", "fit iwan --help"} <= set(answers)
    assert len(answers) > 20 and all(answer == [0, True] for answer in answers.values()), answers
    assert found["heavy"] == []
