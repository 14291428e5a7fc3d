"""The idkit model file: a JSON document holding one isolator model or system.

Schema (``format_version`` 1)::

    {
      "format": "idkit-model",
      "format_version": 1,
      "idkit_version": "0.1.0",
      "model": {"kind": "iwan", "params": {"g1": 3000.0, ...}, "units": {"g1": "N/m", ...}},
      "provenance": {...}          # optional, free-form (fitters: data hashes, settings, seed)
    }

``model.kind`` is one of ``iwan``, ``iwan_modulated``, ``iwan_clearance``, ``iwan_rate``, ``bouc_wen``,
``bouc_wen_pinched``, ``generalized_maxwell``, ``voigt``
(isolators, with ``params`` by declared name in SI units) or ``sdof``
(``mass``, ``isolator``), ``hybrid`` (``mass``, ``intermediate_mass``, ``upper``,
``lower``), ``coulomb_spring``. ``units`` is required in every isolator entry, with
exactly one unit per parameter, each equal to the declaration (an error, never converted).
A ``generalized_maxwell`` entry whose ``k0`` unit is ``Pa`` is a material's modulus (Prony
series, no ``m_eff``); with ``N/m`` it is a part's stiffness.
Reading is strict (:mod:`idkit.inputfiles`): duplicate keys, NaN/Infinity, unknown keys
(top level and inside ``model``) and booleans or strings as numbers are refused.
See ``docs/model-file.md``.
"""

from __future__ import annotations

import json
from pathlib import Path

from idkit.atomic import write_bytes_atomic
from idkit.errors import ModelFileError, ParameterError
from idkit.inputfiles import load_json, read_input_bytes
from idkit.models.boucwen import BoucWenModel
from idkit.models.iwan import IwanModel
from idkit.models.iwan_modulated import ModulatedIwanModel
from idkit.models.boucwen_pinched import PinchedBoucWenModel
from idkit.models.clearance import ClearanceIwanModel
from idkit.models.rate_dependent import RateDependentIwanModel
from idkit.models.maxwell import GeneralizedMaxwell, VoigtModel
from idkit.models.systems import CoulombSpringSystem, HybridSystem, SDOFSystem

__all__ = ["save_model", "load_model", "model_to_dict", "model_from_dict", "FORMAT", "FORMAT_VERSION"]

FORMAT = "idkit-model"
FORMAT_VERSION = 1
_ISOLATORS = {cls.kind: cls for cls in (IwanModel, ModulatedIwanModel, ClearanceIwanModel, RateDependentIwanModel,
                                        BoucWenModel, PinchedBoucWenModel, GeneralizedMaxwell, VoigtModel)}


_ISOLATOR_KEYS = ("kind", "params", "units")
_SYSTEM_KEYS = {
    "sdof": (("kind", "mass", "isolator"), ()),
    "hybrid": (("kind", "mass", "intermediate_mass", "upper", "lower"), ()),
    "coulomb_spring": (("kind", "mass", "stiffness", "friction_force"),
                       ("damping", "contact_stiffness_ratio")),
}
_SYSTEM_NUMBERS = ("mass", "intermediate_mass", "stiffness", "friction_force", "damping",
                   "contact_stiffness_ratio")
_TOP_KEYS = ("format", "format_version", "idkit_version", "model", "provenance")


def model_to_dict(model) -> dict:
    """The ``model`` entry of a model file for an isolator or a system."""
    return model.to_dict()


def _check_keys(entry: dict, required, optional, where: str, kind: str) -> None:
    allowed = (*required, *optional)
    unknown = [key for key in entry if key not in allowed]
    if unknown:
        raise ModelFileError(f"{where}: unknown key(s) {', '.join(map(repr, unknown))} for kind "
                             f"{kind!r}; expected keys {', '.join(allowed)}")
    missing = [key for key in required if key not in entry]
    if missing:
        raise ModelFileError(f"{where}: key {missing[0]!r} missing for kind {kind!r}; expected "
                             f"keys {', '.join(allowed)}")


def _check_number(value: object, where: str) -> None:
    """A JSON number: ``true``/``false`` (Python's bool is an int) and strings are refused."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        note = " (JSON true/false is not a number)" if isinstance(value, bool) else ""
        raise ModelFileError(f"{where}: found {value!r} ({type(value).__name__}), expected a "
                             f"number{note}")


def _check_units(entry: dict, model, where: str) -> None:
    units = entry["units"]
    declared = {spec.name: spec.unit for spec in model.param_specs()}
    if not isinstance(units, dict):
        raise ModelFileError(f"{where}.units: found {units!r}, expected an object parameter -> "
                             "unit string")
    unknown = [name for name in units if name not in declared]
    if unknown:
        raise ModelFileError(f"{where}.units: unknown parameter(s) {', '.join(map(repr, unknown))}; "
                             f"expected the units of {', '.join(declared)}")
    missing = [name for name in declared if name not in units]
    if missing:
        raise ModelFileError(f"{where}.units: no unit for {', '.join(map(repr, missing))}; expected "
                             "a unit for every parameter (SI, as declared: "
                             f"{', '.join(f'{k} {v}' for k, v in declared.items())})")
    for name, unit in units.items():
        if unit != declared[name]:
            raise ModelFileError(
                f"{where}.units.{name}: found {unit!r}, expected {declared[name]!r} (SI, not converted)"
            )


def _isolator_from_dict(entry: dict, kind: str, where: str):
    _check_keys(entry, _ISOLATOR_KEYS, (), where, kind)
    params = entry["params"]
    if not isinstance(params, dict):
        raise ModelFileError(f"{where}.params: found {params!r}, expected an object name -> value")
    for name, value in params.items():
        _check_number(value, f"{where}.params.{name}")
    if kind == "generalized_maxwell" and isinstance(entry["units"], dict) and entry["units"].get("k0") == "Pa":
        # a Prony series of a material: the units say so (N/m = a part, Pa = a modulus)
        model = GeneralizedMaxwell.from_params(params, quantity="modulus")
    else:
        model = _ISOLATORS[kind].from_params(params)
    _check_units(entry, model, where)
    return model


def model_from_dict(entry: dict, *, where: str = "model"):
    """Build an isolator or system from a ``model`` entry (see module docstring).

    Every key is checked: an isolator entry has exactly ``kind``, ``params`` and ``units``
    (a unit for every parameter, as declared); a system entry the keys of its kind. Numbers
    must be JSON numbers (not ``true``/``false``, not strings).
    """
    if not isinstance(entry, dict) or "kind" not in entry:
        raise ModelFileError(f"{where}: found {type(entry).__name__}, expected an object with a 'kind'")
    kind = entry["kind"]
    known = sorted([*_ISOLATORS, *_SYSTEM_KEYS])
    if not isinstance(kind, str) or kind not in known:
        raise ModelFileError(f"{where}.kind: found {kind!r}, expected one of {known}")
    try:
        if kind in _ISOLATORS:
            return _isolator_from_dict(entry, kind, where)
        _check_keys(entry, *_SYSTEM_KEYS[kind], where, kind)
        for key in _SYSTEM_NUMBERS:
            if key in entry:
                _check_number(entry[key], f"{where}.{key}")
        if kind == "sdof":
            return SDOFSystem(entry["mass"], model_from_dict(entry["isolator"], where=f"{where}.isolator"))
        if kind == "hybrid":
            return HybridSystem(
                entry["mass"], model_from_dict(entry["upper"], where=f"{where}.upper"),
                entry["intermediate_mass"], model_from_dict(entry["lower"], where=f"{where}.lower"),
            )
        fields = {key: value for key, value in entry.items() if key != "kind"}
        return CoulombSpringSystem(**fields)
    except KeyError as missing:
        raise ModelFileError(f"{where}: key {missing.args[0]!r} missing for kind {kind!r}") from None
    except TypeError as problem:
        raise ModelFileError(f"{where}: {problem}") from None
    except ParameterError as problem:
        raise ModelFileError(f"{where}: {problem}") from None


def save_model(model, path, *, provenance: dict | None = None, overwrite: bool = False) -> Path:
    """Write ``model`` to a JSON model file atomically; returns the path.

    Refuses to replace an existing file unless ``overwrite=True``.
    """
    from idkit import __version__

    path = Path(path)
    document = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "idkit_version": __version__,
        "model": model_to_dict(model),
        "provenance": provenance or {},
    }
    text = json.dumps(document, indent=2, allow_nan=False)
    write_bytes_atomic(path, (text + "\n").encode("utf-8"), overwrite=overwrite)
    return path


def load_model(path):
    """Read a model file; returns the isolator or system. Provenance: :func:`load_model_document`."""
    return model_from_dict(load_model_document(path)["model"], where=f"model file '{path}': model")


def load_model_document(path) -> dict:
    """Read and check the whole model-file document (format, version, model, provenance).

    Raises
    ------
    ModelFileError
        Naming the file: not found, a folder, unreadable, not UTF-8, invalid JSON (also a
        key given twice, NaN/Infinity), unknown top-level keys, another format or version.
    """
    path = Path(path)
    label = f"model file '{path}'"
    raw = read_input_bytes(path, label, ModelFileError)
    document = load_json(raw, label, ModelFileError, expected=f"a JSON object with format {FORMAT!r}")
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        found = document.get("format") if isinstance(document, dict) else f"a JSON {type(document).__name__}"
        raise ModelFileError(f"{label}: found format {found!r}, expected {FORMAT!r}")
    version = document.get("format_version")
    if type(version) is not int or version != FORMAT_VERSION:  # `true == 1` in Python
        raise ModelFileError(f"{label}: found format_version {version!r}, expected {FORMAT_VERSION}")
    unknown = [key for key in document if key not in _TOP_KEYS]
    if unknown:
        raise ModelFileError(f"{label}: unknown top-level key(s) {', '.join(map(repr, unknown))}; "
                             f"expected keys {', '.join(_TOP_KEYS)} (put notes in 'provenance')")
    if "model" not in document:
        raise ModelFileError(f"{label}: key 'model' missing")
    if not isinstance(document.get("idkit_version", ""), str):
        raise ModelFileError(f"{label}: idkit_version: found {document['idkit_version']!r}, "
                             "expected a string")
    if not isinstance(document.get("provenance", {}), dict):
        raise ModelFileError(f"{label}: provenance: found {document['provenance']!r:.60}, "
                             "expected an object")
    return document
