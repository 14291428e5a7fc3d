"""Repository-level checks: README commands, CI script, import layering, CLI."""

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

from idkit.cli.main import main

ROOT = Path(__file__).resolve().parents[1]

# allowed idkit sub-packages each layer may import (one direction of flow)
LAYERS = {
    "models": {"models"},
    "simulate": {"models", "simulate"},
    "io": {"io"},
    "analysis": {"models", "simulate", "io", "analysis"},
    "synth": {"models", "simulate", "io", "analysis", "synth"},
    "fit": {"models", "simulate", "io", "analysis", "fit"},
    "validate": {"models", "simulate", "io", "analysis", "fit", "validate"},
    "plot": {"models", "simulate", "io", "analysis", "fit", "validate", "plot"},
    "report": {"models", "simulate", "io", "analysis", "synth", "fit", "validate", "plot", "report"},
}
CORE = {"errors", "params", "atomic"}


def readme_commands():
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```bash\n(python3 -m venv[^\n]*)\n```", text)


def test_readme_has_exactly_two_setup_commands_and_ci_runs_the_test_one():
    commands = readme_commands()
    assert len(commands) == 2
    assert "idkit report" in commands[0] and "pytest" in commands[1]
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    assert commands[1] in ci_lines


@pytest.mark.parametrize("layer", sorted(LAYERS))
def test_imports_flow_one_way(layer):
    offenders = []
    folder = ROOT / "idkit" / layer
    if not folder.exists():
        pytest.skip(f"layer {layer} has no code yet")
    for path in folder.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module]
            elif isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            for name in names:
                parts = name.split(".")
                if parts[0] == "idkit" and len(parts) > 1:
                    target = parts[1]
                    if target not in CORE and target not in LAYERS[layer]:
                        offenders.append(f"{path.relative_to(ROOT)} imports {name}")
    assert offenders == []


def test_computation_modules_never_import_pyplot():
    for layer in ("models", "simulate", "io", "analysis", "synth", "fit"):
        for path in (ROOT / "idkit" / layer).rglob("*.py"):
            assert "matplotlib" not in path.read_text(), path


def test_cli_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.startswith("idkit ")


def test_cli_library_and_simulate(tmp_path, capsys):
    model_file = tmp_path / "hybrid.json"
    assert main(["library", "hybrid_asymmetric", "-o", str(model_file)]) == 0
    out_csv = tmp_path / "map.csv"
    assert main(["simulate", "harmonic", str(model_file), "--freq", "2", "20", "3", "--freq-spacing", "log",
                 "--amplitude", "1e-4", "1e-3", "--quiet", "-o", str(out_csv)]) == 0
    import pandas as pd

    table = pd.read_csv(out_csv)
    assert len(table) == 6 and table["converged"].all()
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


def test_demo_writes_atomically_and_refuses_overwrite(tmp_path):
    from idkit.report import run_demo

    target = tmp_path / "demo"
    summary = run_demo(target, quick=True)
    assert (target / "summary.json").exists() and (target / "rest_shock.png").exists()
    assert summary["hybrid_map_points_converged"] == summary["hybrid_map_points"]
    with pytest.raises(FileExistsError):
        run_demo(target, quick=True)
    assert [p.name for p in tmp_path.iterdir()] == ["demo"]  # no partial folders left


def test_module_entry_point():
    completed = subprocess.run([sys.executable, "-m", "idkit", "--version"], capture_output=True, text=True,
                               check=True)
    assert completed.stdout.startswith("idkit ")


@pytest.mark.slow
def test_readme_python_example_runs(monkeypatch):
    """The README's Python block runs as written from the repository root."""
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(ROOT)
    namespace = {}
    exec(compile(blocks[0].replace("print(", "str("), "README.md", "exec"), namespace)
    assert namespace["grid"].converged.all()
    assert namespace["check"].passed
