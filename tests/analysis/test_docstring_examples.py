"""The Examples sections of the analysis modules are executed and must hold."""

import doctest
import importlib

import pytest

MODULES = ["cycles", "harmonics", "frf", "drop", "srs", "psd"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(f"idkit.analysis.{name}")
    failures, attempted = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
    assert attempted > 0, f"idkit.analysis.{name} has no examples"
    assert failures == 0


def test_public_api_is_reexported():
    import idkit.analysis as analysis

    for name in analysis.__all__:
        assert hasattr(analysis, name), name
