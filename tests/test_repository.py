"""Repository-level checks: README commands, CI script, import layering and the "never" rules."""

import ast
import functools
import re
import tomllib
from importlib import metadata
from pathlib import Path

import pytest
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[1]

# allowed idkit sub-packages each layer may import (one direction of flow); bottom to top:
# io, signal, models | observe, simulate (signal: the resonance search) | synth, responses | fit | validate | studies (compute only) |
# plot (draws results, types from below) | report (renders and writes) | cli (parses and calls)
LAYERS = {
    "io": {"io"},
    "signal": {"signal"},
    "models": {"models"},
    "simulate": {"models", "signal", "simulate"},
    "observe": {"io", "signal", "observe"},
    "synth": {"models", "simulate", "io", "signal", "synth"},
    "responses": {"models", "simulate", "signal", "responses"},
    "fit": {"models", "simulate", "io", "signal", "observe", "responses", "fit"},
    "validate": {"models", "simulate", "io", "signal", "observe", "responses", "validate"},
    "studies": {"models", "simulate", "io", "signal", "observe", "responses", "fit", "validate", "studies"},
    "plot": {"models", "simulate", "io", "signal", "observe", "responses", "fit", "validate", "studies", "plot"},
    "report": {"models", "simulate", "io", "signal", "observe", "responses", "synth", "fit", "validate", "studies",
               "plot", "report"},
    # catalogue: identify parts (fit, validate) and fit scaling laws; design: simulate candidates from a catalogue
    "catalogue": {"models", "simulate", "io", "signal", "observe", "responses", "fit", "validate", "studies",
                  "catalogue"},
    "design": {"models", "simulate", "io", "signal", "responses", "catalogue", "plot", "design"},
}
CORE = {"errors", "checks", "limits", "params", "atomic", "inputfiles", "gravity", "forked", "exit_status", "_numba_cache",
        "exports"}


def readme_commands():
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```bash\n(python3 -m venv[^\n]*)\n```", text)


def test_readme_has_exactly_two_setup_commands_and_ci_runs_the_test_one():
    commands = readme_commands()
    assert len(commands) == 2
    assert "idkit report" in commands[0] and "pytest" in commands[1]
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    assert commands[1] in ci_lines


def test_readme_setup_commands_install_the_pinned_constraints():
    commands = readme_commands()
    assert all(".venv/bin/pip install -c constraints/ci.txt " in command for command in commands)
    pins = (ROOT / "constraints" / "ci.txt").read_text().splitlines()
    requirements = [line for line in pins if line.strip() and not line.startswith("#")]
    assert requirements and all(re.fullmatch(r"[A-Za-z0-9_.\-]+(\[[\w,\-]+\])?==\S+", line) for line in requirements)
    names = {re.split(r"[\[=]", line)[0].lower().replace("_", "-") for line in requirements}
    assert not names & {"idkit", "idkit-isolators"}  # idkit itself is never pinned
    dependencies = pyproject()["project"]["dependencies"]
    assert {re.split(r"[<>=\[ ]", dep)[0].lower() for dep in dependencies} <= names


def pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_floors_constraints_pin_every_lower_bound():
    """constraints/floors.txt installs each dependency at exactly the floor pyproject declares."""
    floors = {}
    for line in (ROOT / "constraints" / "floors.txt").read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            name, version = line.split("==")
            floors[name.strip().lower()] = version.strip()
    project = pyproject()["project"]
    for dep in project["dependencies"] + project["optional-dependencies"]["test"]:
        match = re.fullmatch(r"([A-Za-z0-9_.\-]+)(\[[\w,]+\])?>=([\w.]+)", dep)
        assert match, f"{dep!r} should read name>=floor"
        pinned = floors.get(match[1].lower())
        assert pinned and Version(pinned) == Version(match[3]), f"{dep}: floors.txt pins {pinned}"


def test_distribution_name_licence_and_typing_marker():
    """Installed as idkit-isolators (PyPI's "idkit" is another project), imported as idkit."""
    import idkit

    project = pyproject()["project"]
    assert project["name"] == idkit.DISTRIBUTION_NAME
    assert metadata.version(idkit.DISTRIBUTION_NAME) == idkit.__version__ == project["version"]
    assert project["license"] == "BSD-3-Clause" and "BSD 3-Clause" in (ROOT / "LICENSE").read_text()
    assert (ROOT / "idkit" / "py.typed").exists()
    assert f"## [{project['version']}]" in (ROOT / "CHANGELOG.md").read_text()
    texts = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    for path in texts:  # pip commands name the distribution, never the unrelated "idkit"
        for command in re.findall(r"pip install[^\n`&]*", path.read_text()):
            assert not re.search(r"(?<![\w/.-])[\"']?idkit(\[|[\"']|\s|$)", command), f"{path.name}: {command}"


@functools.lru_cache(maxsize=None)
def parsed(source: str) -> ast.Module:
    """The syntax tree of ``source``, parsed once per run: several checks below walk every idkit
    module (none changes a tree)."""
    return ast.parse(source)


@pytest.mark.parametrize("layer", sorted(LAYERS))
def test_imports_flow_one_way(layer):
    offenders = []
    folder = ROOT / "idkit" / layer
    if not folder.exists():
        pytest.skip(f"layer {layer} has no code yet")
    for path in folder.rglob("*.py"):
        tree = parsed(path.read_text())
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


def imported_modules(path: Path, *, skip_type_checking: bool = False) -> list[tuple[int, str]]:
    """(line, module) of every absolute import in ``path``; optionally leaving out ``if TYPE_CHECKING:`` blocks."""
    tree = parsed(path.read_text())
    skipped = set()
    if skip_type_checking:
        for node in ast.walk(tree):
            if isinstance(node, ast.If) and ast.unparse(node.test) in ("TYPE_CHECKING", "typing.TYPE_CHECKING"):
                skipped |= {id(child) for statement in node.body for child in ast.walk(statement)}
    found = []
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.append((node.lineno, node.module))
        elif isinstance(node, ast.Import):
            found.extend((node.lineno, alias.name) for alias in node.names)
    return found


def offenders(folder: str, forbidden: tuple[str, ...], *, skip_type_checking: bool = False) -> list[str]:
    """Imports under ``idkit/<folder>`` of a module in ``forbidden`` (or inside one)."""
    found = []
    for path in sorted((ROOT / "idkit" / folder).rglob("*.py")):
        for line, module in imported_modules(path, skip_type_checking=skip_type_checking):
            if any(module == name or module.startswith(name + ".") for name in forbidden):
                found.append(f"{path.relative_to(ROOT)}:{line} imports {module}")
    return found


def test_imported_modules_sees_type_checking_blocks(tmp_path):
    source = tmp_path / "module.py"
    source.write_text("from typing import TYPE_CHECKING\nimport idkit.models\nif TYPE_CHECKING:\n"
                      "    from idkit.fit import LoopSet\n")
    assert [name for _, name in imported_modules(source)] == ["typing", "idkit.models", "idkit.fit"]
    assert [name for _, name in imported_modules(source, skip_type_checking=True)] == ["typing", "idkit.models"]


def test_cli_only_parses_and_calls():
    """The CLI never draws (matplotlib), never processes signals or measurements, never simulates."""
    assert offenders("cli", ("matplotlib", "idkit.signal", "idkit.observe", "idkit.simulate")) == []


def test_plot_never_runs_a_fitter():
    """plot imports idkit.fit for type hints only (``if TYPE_CHECKING:``): it draws what the caller computed."""
    assert offenders("plot", ("idkit.fit",), skip_type_checking=True) == []


def test_studies_compute_and_never_draw():
    assert offenders("studies", ("idkit.plot", "idkit.report", "matplotlib")) == []


def test_one_axes_helper_and_no_private_imports_across_plot_modules():
    """Every plot module gets its axes from plot/_figure.py; none builds a Figure or imports another's private."""
    for path in sorted((ROOT / "idkit" / "plot").glob("*.py")):
        if path.name == "_figure.py":
            continue
        text = path.read_text()
        assert "Figure(" not in text and "subplots(" not in text, path.name
        for _, module in imported_modules(path):
            assert not (module.startswith("idkit.plot.") and module.split(".")[-1].startswith("_")
                        and module != "idkit.plot._figure"), f"{path.name} imports {module}"
        tree = parsed(text)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("idkit.plot"):
                private = [a.name for a in node.names if a.name.startswith("_")]
                assert not private, f"{path.name} imports {private} from {node.module}"


def test_computation_modules_never_import_pyplot():
    for layer in ("models", "simulate", "io", "signal", "observe", "responses", "synth", "fit", "validate", "studies"):
        for path in (ROOT / "idkit" / layer).rglob("*.py"):
            assert "matplotlib" not in path.read_text(), path


def backend_switches(source):
    """Lines of ``source`` that choose a matplotlib backend: ``matplotlib.use`` or ``pyplot.switch_backend``,
    under any alias or imported by name, and ``%matplotlib`` magics other than ``inline``."""
    lines = source.splitlines()
    found = [number for number, line in enumerate(lines, 1)
             if line.lstrip().startswith("%matplotlib") and line.split()[1:] != ["inline"]]
    # IPython magics and shell lines are not Python: blank them, keeping the line numbers
    if any(line.lstrip().startswith(("%", "!")) for line in lines):
        source = "\n".join("" if line.lstrip().startswith(("%", "!")) else line for line in lines)
    tree = parsed(source)
    switches = {("matplotlib", "use"), ("matplotlib.pyplot", "switch_backend")}
    modules, functions = {}, set()  # local name -> module; local names of the switch functions
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname:
                    modules[alias.asname] = alias.name
                else:
                    modules[alias.name.split(".")[0]] = alias.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                if (node.module, alias.name) in switches:
                    functions.add(alias.asname or alias.name)
                elif f"{node.module}.{alias.name}" == "matplotlib.pyplot":
                    modules[alias.asname or alias.name] = "matplotlib.pyplot"
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        target = ast.unparse(node.func)
        owner, _, name = target.rpartition(".")
        if target in functions or (modules.get(owner, owner), name) in switches:
            found.append(node.lineno)
    return sorted(found)


def test_backend_switch_guard_sees_aliases_and_magics():
    assert backend_switches("import matplotlib as mpl\nmpl.use('Agg')") == [2]
    assert backend_switches("from matplotlib import use\nuse('Agg')") == [2]
    assert backend_switches("import matplotlib.pyplot as plt\nplt.switch_backend('Agg')") == [2]
    assert backend_switches("%matplotlib agg\nimport matplotlib.pyplot as plt\nplt.plot([1])") == [1]
    assert backend_switches("%matplotlib inline\nimport matplotlib\nprint(matplotlib.get_backend())") == []


def test_library_and_notebooks_never_choose_the_matplotlib_backend():
    """The backend is the user's (inline in Jupyter, MPLBACKEND elsewhere); idkit and its notebooks never force one."""
    import nbformat

    sources = {str(path.relative_to(ROOT)): path.read_text() for path in (ROOT / "idkit").rglob("*.py")}
    notebooks = sorted((ROOT / "notebooks").glob("*.ipynb"))
    assert notebooks
    for path in notebooks:
        for index, cell in enumerate(nbformat.read(path, as_version=4).cells):
            if cell.cell_type == "code":
                sources[f"{path.relative_to(ROOT)} cell {index}"] = cell.source
    offenders = [f"{where} line {line}" for where, source in sources.items() for line in backend_switches(source)]
    assert offenders == []


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
    # The quasi-static fit carries no viscous damping (c_visc = 0), so most sweep points
    # of the lightly damped rope never settle: the verdict must say so rather than PASS.
    from idkit.validate.harmonic import MAX_UNSETTLED_FRACTION

    check = namespace["check"]
    unsettled = check.summary["points_not_converged"] > MAX_UNSETTLED_FRACTION * len(check.metrics)
    assert check.verdict == ("INCONCLUSIVE" if unsettled else "PASS"), check.report()


def _module_imports() -> dict[str, set[str]]:
    """idkit module -> the idkit modules it imports, at module level or inside functions."""
    package = ROOT / "idkit"
    modules = {}
    for path in package.rglob("*.py"):
        parts = path.relative_to(ROOT).with_suffix("").parts
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph = {}
    for name, path in modules.items():
        targets = set()
        for node in ast.walk(parsed(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").startswith("idkit"):
                targets |= {node.module} | {f"{node.module}.{alias.name}" for alias in node.names}
            elif isinstance(node, ast.Import):
                targets |= {alias.name for alias in node.names}
        graph[name] = {t for t in targets if t in modules and t != name and not name.startswith(t + ".")}
    return graph


def test_no_import_cycle_between_modules_lazy_imports_included():
    """A function-level import hides a cycle from the interpreter, not from the reader: no module
    may reach itself through the imports of others (a package's own ``__init__`` excepted)."""
    graph = _module_imports()
    done, path, cycles = set(), [], []

    def visit(name):
        if name in path:
            cycles.append(path[path.index(name):] + [name])
            return
        if name in done:
            return
        path.append(name)
        for target in sorted(graph[name]):
            visit(target)
        path.pop()
        done.add(name)

    for name in sorted(graph):
        visit(name)
    assert not cycles, cycles[:3]


# Commands with a README row whose code is being added on another branch: each entry fails
# the test below once its command exists (then remove it here), so none stays here unnoticed.
NOT_YET_IN_THE_PARSER: set[tuple[str, ...]] = set()


def parser_commands() -> set[tuple[str, ...]]:
    """Every command of ``idkit --help`` and every sub-command below it, e.g. ("fit", "iwan")."""
    import argparse

    from idkit.cli.main import build_parser

    def choices(parser):
        actions = [action for action in parser._actions if isinstance(action, argparse._SubParsersAction)]
        return actions[0].choices if actions else {}

    found = set()
    for name, command in choices(build_parser()).items():
        below = choices(command)
        found |= {(name, sub) for sub in below} if below else {(name,)}
    return found


def readme_command_rows() -> set[tuple[str, ...]]:
    """The commands of the README's command table: `idkit fit iwan\\|maxwell DATASET` gives
    ("fit", "iwan") and ("fit", "maxwell"); `idkit report [DATA_DIR]` gives ("report",)."""
    text = (ROOT / "README.md").read_text()
    section = text.split("\n## Commands\n", 1)[1].split("\n## ", 1)[0]
    rows = set()
    for cell in re.findall(r"^\| `idkit ([^`]*)`", section, flags=re.M):
        words = cell.replace("\\|", "|").split()
        subs = words[1].split("|") if len(words) > 1 and re.fullmatch(r"[a-z][a-z-]*(\|[a-z][a-z-]*)*", words[1]) else []
        rows |= {(words[0], sub) for sub in subs} if subs else {(words[0],)}
    return rows


def test_readme_command_table_lists_every_command_of_the_parser():
    """The README's command table and `idkit --help` name the same commands and sub-commands."""
    parser, readme = parser_commands(), readme_command_rows()
    assert sorted(parser - readme) == [], "commands of the parser without a README row"
    assert sorted(readme - parser - NOT_YET_IN_THE_PARSER) == [], "README rows naming no command of the parser"
    assert sorted(NOT_YET_IN_THE_PARSER & parser) == [], "now in the parser: remove from NOT_YET_IN_THE_PARSER"
