"""The docstring examples of idkit.io run (those not marked +SKIP, which need files)."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = ["idkit.io.units", "idkit.io.info", "idkit.io.measurements", "idkit.io.csv_measurement",
           "idkit.io.matfile", "idkit.io.manifest", "idkit.io.complex_stiffness"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
