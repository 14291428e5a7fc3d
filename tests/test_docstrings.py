"""Every docstring example in the package runs and holds (examples that need files say +SKIP).

One walk over all modules, like ``pytest --doctest-modules``, so a new module's examples are
executed without anyone adding it to a list.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import idkit

MODULES = sorted(
    info.name for info in pkgutil.walk_packages(idkit.__path__, prefix="idkit.")
    if not info.name.endswith("__main__")
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_hold(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
                             verbose=False, report=True)
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples fail"

