"""The idkit.plot package re-exports the public list of each of its plot modules."""

import idkit.plot
from idkit.plot import basic, branches, fits, responses, validation


def test_package_re_exports_each_module_public_list_once():
    modules = (basic, branches, fits, responses, validation)
    for module in modules:
        for name in module.__all__:
            assert getattr(idkit.plot, name) is getattr(module, name), (module.__name__, name)
    names = [name for module in modules for name in module.__all__]
    # a name in two modules would shadow one of them
    assert sorted(idkit.plot.__all__) == sorted(set(names)) and len(names) == len(set(names))
