"""Every notebook runs top to bottom on the bundled data (nbclient), asserts what it shows and shows its figures."""

from pathlib import Path

import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))

_EXECUTED = {}  # path -> executed notebook: one kernel run serves every test of a notebook


def executed(path):
    """The notebook at ``path`` after running it in a fresh python3 kernel (cached per session)."""
    if path not in _EXECUTED:
        nbclient = pytest.importorskip("nbclient", reason="nbclient is a test dependency (pip install -e '.[test]')")
        notebook = nbformat.read(path, as_version=4)
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


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_executes(path):
    errors = [output for _, output in code_outputs(executed(path)) if output.get("output_type") == "error"]
    assert errors == []


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_shows_its_figures_inline(path):
    outputs = code_outputs(executed(path))
    images = [index for index, output in outputs if "image/png" in output.get("data", {})]
    assert images, f"{path.name}: no figure displayed (image/png) in any cell"
    # each figure once: a cell ending in a pyplot figure would be drawn twice (its value and the inline flush)
    assert sorted(set(images)) == images
    # a figure printed as "<Figure size ... with 2 Axes>" instead of drawn means a non-inline backend
    bare = [index for index, output in outputs if "image/png" not in output.get("data", {})
            and output.get("data", {}).get("text/plain", "").startswith("<Figure")]
    assert bare == []
