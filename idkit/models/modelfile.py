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
from idkit.checks import Choice, Field, Instance, Real, Text, check_fields
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


_NUMBER = Real(meaning="a JSON number")
_ENTRY = Instance((dict,), what="an object with a 'kind'")
_OBJECT = Instance((dict,), what="an object")
#: The keys of an isolator entry besides ``kind``.
_ISOLATOR_FIELDS = (Field("params", Instance((dict,), what="an object name -> value"), required=True),
                    Field("units", Instance((dict,), what="an object parameter -> unit string"), required=True))
#: The keys of each system kind besides ``kind``.
_SYSTEM_FIELDS = {
    "sdof": (Field("mass", Real(unit="kg"), required=True), Field("isolator", _ENTRY, required=True)),
    "hybrid": (Field("mass", Real(unit="kg"), required=True),
               Field("intermediate_mass", Real(unit="kg"), required=True),
               Field("upper", _ENTRY, required=True), Field("lower", _ENTRY, required=True)),
    "coulomb_spring": (Field("mass", Real(unit="kg"), required=True),
                       Field("stiffness", Real(unit="N/m"), required=True),
                       Field("friction_force", Real(unit="N"), required=True), Field("damping", Real(unit="N s/m")),
                       Field("contact_stiffness_ratio", Real())),
}
_KIND = Choice(tuple(sorted([*_ISOLATORS, *_SYSTEM_FIELDS])))
#: The keys of the document besides ``format`` (checked first: another format is named as such).
_TOP = (Field("format_version", Choice((FORMAT_VERSION,)), required=True), Field("idkit_version", Text()),
        Field("model", _ENTRY, required=True), Field("provenance", _OBJECT))


def model_to_dict(model) -> dict:
    """The ``model`` entry of a model file for an isolator or a system."""
    return model.to_dict()


def _check_units(units: dict, model, where: str) -> None:
    """Exactly one unit per declared parameter, each the declared SI unit (never converted)."""
    declared = {spec.name: spec.unit for spec in model.param_specs()}
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
        Choice((declared[name],)).check(unit, f"{where}.units.{name}", ModelFileError)


def _isolator_from_dict(entry: dict, kind: str, where: str):
    fields = check_fields(entry, _ISOLATOR_FIELDS, f"{where} (kind {kind!r})", known=("kind",), error=ModelFileError)
    params, units = fields["params"], fields["units"]
    for name, value in params.items():
        _NUMBER.check(value, f"{where}.params.{name}", ModelFileError)
    if kind == "generalized_maxwell" and units.get("k0") == "Pa":
        # a Prony series of a material: the units say so (N/m = a part, Pa = a modulus)
        model = GeneralizedMaxwell.from_params(params, quantity="modulus")
    else:
        model = _ISOLATORS[kind].from_params(params)
    _check_units(units, model, where)
    return model


def model_from_dict(entry: dict, *, where: str = "model"):
    """Build an isolator or system from a ``model`` entry (see module docstring).

    Every key is checked: an isolator entry has exactly ``kind``, ``params`` and ``units``
    (a unit for every parameter, as declared); a system entry the keys of its kind. Numbers
    must be JSON numbers (not ``true``/``false``, not strings).
    """
    kind = _KIND.check(_ENTRY.check(entry, where, ModelFileError).get("kind"), f"{where}.kind", ModelFileError)
    try:
        if kind in _ISOLATORS:
            return _isolator_from_dict(entry, kind, where)
        check_fields(entry, _SYSTEM_FIELDS[kind], f"{where} (kind {kind!r})", known=("kind",), error=ModelFileError)
        if kind == "sdof":
            return SDOFSystem(entry["mass"], model_from_dict(entry["isolator"], where=f"{where}.isolator"))
        if kind == "hybrid":
            return HybridSystem(
                entry["mass"], model_from_dict(entry["upper"], where=f"{where}.upper"),
                entry["intermediate_mass"], model_from_dict(entry["lower"], where=f"{where}.lower"),
            )
        return CoulombSpringSystem(**{key: value for key, value in entry.items() if key != "kind"})
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
    check_fields(document, _TOP, label, known=("format",), error=ModelFileError)
    return document
