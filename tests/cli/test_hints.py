"""Library suggestions spelled as ``idkit`` options; the set's only isolator as the default."""

from __future__ import annotations

import ast
import pickle
from pathlib import Path

import numpy as np
import pytest

import idkit
from idkit.cli.hints import OPTION_SPELLINGS, cli_message, spell_option
from idkit.errors import DataError, FitError, Message, Suggestion
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, write_measurement_set
from idkit.io.selection import ONLY_ISOLATOR, resolve_isolator
from tests.cli.hostile import check, run_main

PACKAGE = Path(idkit.__file__).resolve().parent


def _suggested_keywords():
    """Every ``Suggestion("keyword", ...)`` written in idkit's source, with where."""
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        if "Suggestion(" not in text:  # parse only the modules that build one
            continue
        for node in ast.walk(ast.parse(text)):
            if (isinstance(node, ast.Call) and getattr(node.func, "id", None) == "Suggestion" and node.args
                    and isinstance(node.args[0], ast.Constant)):
                yield node.args[0].value, f"{path.relative_to(PACKAGE)}:{node.lineno}"


def test_every_suggestion_idkit_raises_has_a_command_line_spelling():
    found = list(_suggested_keywords())
    assert len(found) >= 6  # k0_method twice, valid_range, offset, force_offset, isolator, split
    missing = [where for keyword, where in found if keyword not in OPTION_SPELLINGS]
    assert not missing, f"suggestions without an option spelling in idkit.cli.hints: {missing}"


def test_a_message_reads_as_python_and_renders_as_options_after_pickling():
    error = FitError(Message("k0 with relaxation: found k0 = 0 N/m (use ", Suggestion("k0_method", "secant"),
                             "; or ", Suggestion("split", None), ")"))
    assert str(error) == "k0 with relaxation: found k0 = 0 N/m (use k0_method='secant'; or split=None)"
    again = pickle.loads(pickle.dumps(error))  # errors cross process boundaries
    assert cli_message(again) == "k0 with relaxation: found k0 = 0 N/m (use --k0-method secant; or --split all)"
    assert cli_message(FitError("plain text")) == "plain text"
    assert spell_option(Suggestion("valid_range", None)) == "--no-valid-range"
    assert spell_option(Suggestion("unknown_keyword", 3)) == "unknown_keyword=3"  # no option: as Python


def _loops(isolator, amplitudes=(2e-3, 1e-3), name="qs"):
    x = np.concatenate([a * np.sin(np.linspace(0, 2 * np.pi, 200)) for a in amplitudes])
    return QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=2e4 * x,
                                  info=MeasurementInfo(id=f"{name}_{isolator}", isolator=isolator, split="fit"))


def test_the_only_isolator_is_the_default_and_several_are_listed():
    one = [_loops("rope_8mm")]
    assert resolve_isolator(one, ONLY_ISOLATOR, kind="quasi_static") == "rope_8mm"
    assert resolve_isolator(one, "other", kind="quasi_static") == "other"  # a given name is kept
    assert resolve_isolator(one, None, kind="quasi_static") is None
    assert resolve_isolator(one, ONLY_ISOLATOR, kind="white_noise") is None  # nothing of that kind
    with pytest.raises(DataError) as raised:
        resolve_isolator(one + [_loops("damper")], ONLY_ISOLATOR, kind="quasi_static")
    assert "quasi_static records of 2 isolators (damper, rope_8mm)" in str(raised.value)
    assert "isolator='damper'" in str(raised.value)
    assert "--isolator damper" in cli_message(raised.value)


def test_fit_iwan_uses_the_sets_only_isolator_and_names_its_options(tmp_path):
    """A set of one isolator not called wire_rope needs no --isolator: the selection is made with
    its name (shown here by asking for a split the set lacks, which stops before any fit)."""
    folder = tmp_path / "damper"
    write_measurement_set(folder, [_loops("damper", name="a"), _loops("damper", name="b")], name="one damper")
    output = tmp_path / "m.json"
    outcome = run_main(["fit", "iwan", folder, "--split", "validation", "-o", output], inputs=[folder],
                       must_not_exist=[output])
    check(outcome, "error", ["found none with kind='quasi_static', --isolator damper, --split validation",
                             "available (kind, isolator, split): {('quasi_static', 'damper', 'fit'): 2}"])
    two = tmp_path / "two"
    write_measurement_set(two, [_loops("damper"), _loops("rope")], name="two isolators")
    outcome = run_main(["fit", "iwan", two, "-o", output], inputs=[two], must_not_exist=[output])
    check(outcome, "error", ["2 isolators (damper, rope)", "choose it with --isolator damper"])
    assert "isolator='" not in outcome.stderr  # spelled as an option, never as Python


def test_a_shock_record_without_pre_trigger_samples_suggests_the_option(tmp_path):
    path = tmp_path / "early.csv"
    time = np.arange(400) / 10_000.0
    accel = np.where(time < 0.002, np.sin(np.pi * time / 0.002), 0.0)  # the pulse starts at sample 1
    path.write_text("time [s],shot_1 [g]\n" + "".join(f"{float(t)!r},{float(a)!r}\n" for t, a in zip(time, accel)))
    outcome = run_main(["shock", path], inputs=[path])
    check(outcome, "error", ["early.csv", "use --offset none to keep the record as recorded"])
    assert "offset='none'" not in outcome.stderr
