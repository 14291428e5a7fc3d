"""Every notebook runs top to bottom on the bundled data (nbclient), asserts what it shows and shows its figures.

The notebooks are split over this file and ``test_notebooks_second.py`` so that pytest-xdist, which
hands out whole files, runs the two halves on two workers."""

import json
from pathlib import Path

import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))

_EXECUTED = {}  # path -> executed notebook: one kernel run serves every test of a notebook
#: The notebooks this file runs (about half the kernel time); the others run in test_notebooks_second.py.
FIRST_HALF = ("catalogue_and_design", "hybrid", "transport_study")
HERE = [path for path in NOTEBOOKS if path.stem in FIRST_HALF]

# Appended (in memory) to the wire-rope notebook and run in its kernel after its own cells: the
# report's pipeline applied to the notebook's data. The fit is the one costly step, so it is not
# repeated: the options the notebook's fit recorded must be the report's, and the fit is
# deterministic; the validations are repeated through the report's own function.
REPORT_CHECK_MARK = "report check: "
REPORT_CHECK = """
import json as _json
from idkit.studies import pipeline as _pipeline

_report_options = _pipeline.wire_rope_fit_options(wire_rope, seed=SEED)
_recorded = {**iwan.options, "seed": iwan.result.settings.seed}
_isolators = {m.info.isolator for m in wire_rope.measurements}  # the default: the set's only isolator
_recorded.setdefault("isolator", _isolators.pop() if len(_isolators) == 1 else None)
_report_sweeps, _report_drops = _pipeline.validate_wire_rope(
    wire_rope.select(kind="stepped_sine", split="validation"), wire_rope.select(kind="drop", split="validation"),
    iwan.model, loop_amplitude_range=iwan.loop_amplitude_range)
print(%r + _json.dumps({
    "options": {name: [_recorded.get(name), value] for name, value in _report_options.items()},
    "rules": [iwan.options["family_rule"], iwan.order_table is not None],
    "notebook": [sweeps.verdict, drops.verdict, sweeps.summary, drops.summary],
    "report": [_report_sweeps.verdict, _report_drops.verdict, _report_sweeps.summary, _report_drops.summary],
}, default=float))
""" % REPORT_CHECK_MARK
REPORT_CHECKS = {"wire_rope": REPORT_CHECK}


def executed(path):
    """The notebook at ``path`` after running it in a fresh python3 kernel (cached per session)."""
    if path not in _EXECUTED:
        nbclient = pytest.importorskip("nbclient", reason="nbclient is a test dependency (pip install -e '.[test]')")
        notebook = nbformat.read(path, as_version=4)
        if path.stem in REPORT_CHECKS:
            notebook.cells.append(nbformat.v4.new_code_cell(REPORT_CHECKS[path.stem]))
        # the kernel inherits os.environ, MPLBACKEND=Agg from conftest included: the notebooks'
        # own `%matplotlib inline` must win over it, as it does over any user setting
        client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                         resources={"metadata": {"path": str(path.parent)}})
        client.execute()
        _EXECUTED[path] = notebook
    return _EXECUTED[path]


def code_outputs(notebook):
    """(cell index, output) of every output of every code cell."""
    return [(index, output) for index, cell in enumerate(notebook.cells) if cell.cell_type == "code"
            for output in cell.get("outputs", [])]


def test_there_are_five_notebooks():
    assert [p.stem for p in NOTEBOOKS] == ["catalogue_and_design", "elastomer", "hybrid", "transport_study", "wire_rope"]


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebooks_are_committed_without_outputs(path):
    # the test runs them, git keeps them small
    notebook = nbformat.read(path, as_version=4)
    assert [index for index, cell in enumerate(notebook.cells)
            if cell.cell_type == "code" and (cell.get("outputs") or cell.get("execution_count") is not None)] == []


def check_executes(path):
    errors = [output for _, output in code_outputs(executed(path)) if output.get("output_type") == "error"]
    assert errors == []


def check_figures_inline(path):
    outputs = code_outputs(executed(path))
    images = [index for index, output in outputs if "image/png" in output.get("data", {})]
    assert images, f"{path.name}: no figure displayed (image/png) in any cell"
    # each figure once: a cell ending in a pyplot figure would be drawn twice (its value and the inline flush)
    assert sorted(set(images)) == images
    # a figure printed as "<Figure size ... with 2 Axes>" instead of drawn means a non-inline backend
    bare = [index for index, output in outputs if "image/png" not in output.get("data", {})
            and output.get("data", {}).get("text/plain", "").startswith("<Figure")]
    assert bare == []


@pytest.mark.parametrize("path", HERE, ids=lambda p: p.stem)
def test_notebook_executes(path):
    check_executes(path)


@pytest.mark.parametrize("path", HERE, ids=lambda p: p.stem)
def test_notebook_shows_its_figures_inline(path):
    check_figures_inline(path)


def check_wire_rope_numbers_are_the_reports():
    """The wire-rope notebook fits with the report's options and rules (order and family
    "auto", valid range of the set, seed) and validates as the report does: its verdicts and
    every summary number (sweeps: log-magnitude, resonance, phase errors; drops: median and
    largest peak errors under the rig drop model) equal the report's pipeline on the same
    fit, exactly (the same deterministic computation)."""
    notebook = executed(NOTEBOOKS[[p.stem for p in NOTEBOOKS].index("wire_rope")])
    printed = [text for _, output in code_outputs(notebook) for text in output.get("text", "").splitlines()
               if text.startswith(REPORT_CHECK_MARK)]
    assert len(printed) == 1, "the report check appended to the notebook printed nothing"
    check = json.loads(printed[0][len(REPORT_CHECK_MARK):])
    differing = {name: pair for name, pair in check["options"].items() if pair[0] != pair[1]}
    assert differing == {}, "fit options of the notebook [0] and the report [1]"
    assert check["rules"] == ["auto", True]  # family rule and order rule, as the report
    assert json.dumps(check["notebook"], sort_keys=True) == json.dumps(check["report"], sort_keys=True)
    assert check["notebook"][3]["drop_model"] == "rig"
