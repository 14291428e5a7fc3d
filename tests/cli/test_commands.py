"""The ``idkit`` command: version, entry point, library, simulate, the study parser."""

import subprocess
import sys

import pandas as pd
import pytest

from idkit.cli.main import build_parser, main


def test_cli_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.startswith("idkit ")


def test_module_entry_point():
    completed = subprocess.run([sys.executable, "-m", "idkit", "--version"], capture_output=True, text=True,
                               check=True)
    assert completed.stdout.startswith("idkit ")


def test_cli_library_and_simulate(tmp_path, capsys):
    model_file = tmp_path / "hybrid.json"
    assert main(["library", "hybrid_asymmetric", "-o", str(model_file)]) == 0
    out_csv = tmp_path / "map.csv"
    assert main(["simulate", "harmonic", str(model_file), "--freq", "2", "20", "3", "--freq-spacing", "log",
                 "--amplitude", "1e-4", "1e-3", "--quiet", "-o", str(out_csv)]) == 0
    table = pd.read_csv(out_csv)
    assert len(table) == 6 and table["converged"].all()
    assert list(table["freq [Hz]"][:2]) == pytest.approx([2.0, 2.0])  # frequency-major, the axes as given
    assert main(["simulate", "harmonic", str(model_file), "--freq", "5", "--amplitude", "1e-3", "--quiet",
                 "-o", str(out_csv)]) == 2  # refuses to overwrite
    wire_rope = tmp_path / "wr.json"
    assert main(["library", "table_7_1_wire_rope", "-o", str(wire_rope)]) == 0
    capsys.readouterr()
    assert main(["simulate", "drop", str(wire_rope), "--height", "0.01", "0.05"]) == 2  # needs --mass
    assert "give --mass" in capsys.readouterr().err
    assert main(["simulate", "drop", str(wire_rope), "--mass", "4.33", "--height", "0.01", "0.05",
                 "--duration", "0.2"]) == 0
    printed = capsys.readouterr().out
    assert "rest_shock" in printed and "ok" in printed


def test_simulate_json_table_keeps_every_digit(tmp_path):
    """A JSON table holds the numbers the CSV holds: a 1e-11 m amplitude is not rounded to 0."""
    import json

    model_file = tmp_path / "elastomer.json"
    assert main(["library", "table_7_3_elastomer", "-o", str(model_file)]) == 0
    tables = {}
    for suffix in ("csv", "json"):
        tables[suffix] = tmp_path / f"map.{suffix}"
        assert main(["simulate", "harmonic", str(model_file), "--mass", "4.37", "--freq", "5", "--amplitude",
                     "1e-11", "1.0288907133153256e-05", "--quiet", "-o", str(tables[suffix])]) == 0
    records = json.loads(tables["json"].read_text())
    table = pd.read_csv(tables["csv"])
    assert [row["amplitude [m]"] for row in records] == [1e-11, 1.0288907133153256e-05]
    assert [row["half_range [m]"] for row in records] == list(table["half_range [m]"])


def test_library_output_without_a_name_is_refused(tmp_path, capsys):
    """``idkit library -o FILE`` lists the sets and writes nothing: an error, not exit 0 without the file."""
    model_file = tmp_path / "model.json"
    assert main(["library", "-o", str(model_file)]) == 2
    assert "-o" in capsys.readouterr().err and not model_file.exists()


def test_one_parser_with_every_command_and_study():
    parser = build_parser()
    args = parser.parse_args(["study", "transport", "--quick"])
    assert args.study == "transport" and args.quick and args.output == "idkit-study-transport"
    for name in ("wire-rope", "elastomer", "hybrid"):
        assert parser.parse_args(["study", name]).output == f"idkit-study-{name}"
    with pytest.raises(SystemExit):  # the demo is gone: `idkit study NAME --quick` replaces it
        parser.parse_args(["demo"])


def test_every_command_module_is_registered(capsys):
    """Each ``idkit/cli/<family>.py`` with ``register(commands)`` is listed in ``build_parser``: its commands answer."""
    import argparse
    import importlib
    import pkgutil

    import idkit.cli

    parser = build_parser()
    for info in pkgutil.iter_modules(idkit.cli.__path__):
        module = importlib.import_module(f"idkit.cli.{info.name}")
        if not callable(getattr(module, "register", None)):
            continue
        probe = argparse.ArgumentParser(prog="probe").add_subparsers(dest="command")
        module.register(probe)
        for name in probe.choices:
            with pytest.raises(SystemExit) as stop:
                parser.parse_args([name, "--help"])
            assert stop.value.code == 0, f"idkit {name} ({info.name}.py) is not registered"
    capsys.readouterr()


def test_simulate_drop_from_height_zero_says_nothing_moves(tmp_path, capsys):
    # --height 0 without --gravity wrote NaN peaks under status "ok"; the drop is valid (exit 0)
    # and its status says why its peaks are NaN
    model_file = tmp_path / "system.json"
    assert main(["library", "system_b1_medium", "-o", str(model_file)]) == 0
    out_csv = tmp_path / "drops.csv"
    assert main(["simulate", "drop", str(model_file), "--height", "0", "0.01", "--duration", "0.05",
                 "--time-step", "1e-4", "-o", str(out_csv)]) == 0
    table = pd.read_csv(out_csv)
    assert table["status"][0].startswith("no motion: v0 = 0 without gravity") and table["status"][1] == "ok"
    assert pd.isna(table["rest_shock_level [m/s^2]"][0]) and table["rest_shock_level [m/s^2]"][1] > 0
    assert (table["flag"] == 0).all()
