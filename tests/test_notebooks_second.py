"""The second half of the notebooks (test_notebooks.py holds the checks and the first half)."""

import pytest

from tests.test_notebooks import (FIRST_HALF, NOTEBOOKS, check_executes, check_figures_inline,
                                  check_wire_rope_numbers_are_the_reports)

HERE = [path for path in NOTEBOOKS if path.stem not in FIRST_HALF]


def test_the_two_files_run_every_notebook_once():
    assert {path.stem for path in HERE} == {"elastomer", "wire_rope"}


@pytest.mark.parametrize("path", HERE, ids=lambda p: p.stem)
def test_notebook_executes(path):
    check_executes(path)


@pytest.mark.parametrize("path", HERE, ids=lambda p: p.stem)
def test_notebook_shows_its_figures_inline(path):
    check_figures_inline(path)


def test_wire_rope_notebook_numbers_are_the_reports():
    check_wire_rope_numbers_are_the_reports()
