"""A package's public names, imported from their modules on first use (PEP 562).

A package whose ``__init__`` imports every module it re-exports makes each of its modules as
costly to import as the whole package: ``from idkit.io.columns import KINDS`` would run
``idkit/io/__init__.py`` and with it pandas and scipy. Such a package declares instead where
each public name lives::

    __all__, __getattr__, __dir__ = lazy_exports(__name__, {"manifest": ("Manifest", ...), ...})

``idkit.io.Manifest`` and ``from idkit.io import Manifest`` still work; the module holding the
name is imported the first time the name is asked for, and the value is then kept in the
package, so later look-ups cost nothing. The ``idkit`` command's parser imports only such
light modules (the names of the choices it offers, its limits), never the heavy ones.

A public name must not also be a submodule's name: importing that submodule (from anywhere)
sets the package's attribute to the module, which would then hide the name.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping

__all__ = ["lazy_exports"]


def lazy_exports(package: str, homes: Mapping[str, tuple[str, ...]]
                 ) -> tuple[list[str], Callable[[str], object], Callable[[], list[str]]]:
    """``__all__``, ``__getattr__`` and ``__dir__`` of ``package``, whose public names live in
    its submodules as ``homes`` states (submodule name -> the names it defines).

    Examples
    --------
    >>> names, getattr_, _ = lazy_exports("idkit.synth", {"names": ("DEFAULT_SEED", "SET_NAMES")})
    >>> names, getattr_("SET_NAMES")
    (['DEFAULT_SEED', 'SET_NAMES'], ('wire_rope', 'elastomer', 'hybrid'))
    """
    home_of = {name: f"{package}.{module}" for module, names in homes.items() for name in names}
    clashes = sorted(set(home_of) & set(homes))
    if clashes:
        raise ValueError(f"{package}: public names {clashes} are also submodule names; expected distinct "
                         "names (importing the submodule would replace the name by the module)")

    def __getattr__(name: str) -> object:
        if name not in home_of:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(home_of[name]), name)
        setattr(sys.modules[package], name, value)  # found in the package from now on
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(home_of))

    return sorted(home_of), __getattr__, __dir__
