"""idkit.exports: a package's public names imported from their modules on first use, and the
packages that declare theirs so (idkit.io, idkit.synth) keep their public lists."""

import ast
import importlib
import inspect
import pkgutil
import sys
import types

import pytest

import idkit.io
import idkit.synth
from idkit.exports import lazy_exports

#: The public lists as they were when the packages imported every module eagerly.
PUBLIC = {
    idkit.io: {
        "SAMPLE_RATE_TOLERANCE", "AccelerationRecord", "ComplexStiffnessTable", "DropMeasurement", "Excitation",
        "Manifest", "ManifestEntry", "MatColumn", "Measurement", "MeasurementInfo", "MeasurementSet",
        "QuasiStaticMeasurement", "ShiftFactorTable", "Source", "SteppedSineMeasurement", "WhiteNoiseMeasurement",
        "accepted_units", "build_measurement", "file_sha256", "load_measurement_set", "read_complex_stiffness",
        "read_csv_measurement", "read_manifest", "read_mat", "read_shock_csv", "read_shift_factors",
        "write_complex_stiffness", "write_csv_measurement", "write_measurement_set"},
    idkit.synth: {
        "DEFAULT_SEED", "FILE_UNITS", "SET_NAMES", "TRUTH_NAMES", "ElastomerTruth", "GenerationSummary",
        "ModulatedWireRopeTruth", "Planned", "SingleBodyElastomerTruth", "WireRopeTruth", "default_elastomer",
        "default_wire_rope", "generate", "generate_measurement", "plan", "truth_models"},
}


@pytest.fixture
def package(tmp_path, monkeypatch):
    """A package ``lazypkg`` with a submodule ``heavy`` holding ``VALUE``, exported lazily."""
    root = tmp_path / "lazypkg"
    root.mkdir()
    (root / "__init__.py").write_text("from idkit.exports import lazy_exports\n"
                                      "__all__, __getattr__, __dir__ = lazy_exports(__name__, {'heavy': ('VALUE',)})\n")
    (root / "heavy.py").write_text("VALUE = object()\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    yield importlib.import_module("lazypkg")
    for name in ("lazypkg", "lazypkg.heavy"):
        sys.modules.pop(name, None)


def test_a_name_imports_its_module_on_first_use_only(package):
    assert package.__all__ == ["VALUE"] and "VALUE" in dir(package)
    assert "lazypkg.heavy" not in sys.modules
    from lazypkg import VALUE

    assert "lazypkg.heavy" in sys.modules and VALUE is sys.modules["lazypkg.heavy"].VALUE
    assert vars(package)["VALUE"] is VALUE  # kept: later look-ups do not go through __getattr__


def test_an_unknown_name_is_an_attribute_error(package):
    with pytest.raises(AttributeError, match="^module 'lazypkg' has no attribute 'VALU'$"):
        package.VALU
    with pytest.raises(ImportError):
        from lazypkg import VALU  # noqa: F401


def test_a_public_name_that_is_also_a_submodule_name_is_refused():
    with pytest.raises(ValueError, match=r"^lazypkg: public names \['heavy'\] are also submodule names"):
        lazy_exports("lazypkg", {"heavy": ("heavy", "VALUE")})


@pytest.mark.parametrize("package", list(PUBLIC), ids=lambda package: package.__name__)
def test_the_lazy_packages_keep_their_public_names_after_every_submodule_is_imported(package):
    """Importing a submodule binds its name in the package: no public name is a submodule's name,
    so each still gives the object its home module defines (``idkit.synth.generate`` is the
    function whichever of ``idkit.synth.sets`` and the name was imported first)."""
    assert set(package.__all__) == PUBLIC[package] and PUBLIC[package] <= set(dir(package))
    submodules = {info.name for info in pkgutil.iter_modules(package.__path__)} - {"__main__"}
    assert not submodules & PUBLIC[package]
    for name in sorted(submodules):
        importlib.import_module(f"{package.__name__}.{name}")
    for name in package.__all__:
        value = getattr(package, name)
        assert not isinstance(value, types.ModuleType), name
        home = getattr(value, "__module__", None)
        if home is not None and home.startswith(package.__name__ + "."):  # classes and functions: defined there
            assert getattr(sys.modules[home], name) is value, name
    assert callable(idkit.synth.generate) and idkit.synth.generate.__module__ == "idkit.synth.sets"


@pytest.mark.parametrize("package", list(PUBLIC), ids=lambda package: package.__name__)
def test_the_type_checking_imports_state_the_same_names_and_homes(package):
    """What type checkers and editors read (``if TYPE_CHECKING:`` imports) is what runs."""
    tree = ast.parse(inspect.getsource(package))
    blocks = [node for node in tree.body if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING"]
    imports = [(node.module, alias.name) for block in blocks for node in block.body
               if isinstance(node, ast.ImportFrom) for alias in node.names]
    assert sorted(name for _, name in imports) == package.__all__
    for module, name in imports:
        assert getattr(package, name) is getattr(importlib.import_module(module), name), name
