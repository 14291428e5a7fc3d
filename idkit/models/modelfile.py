"""The idkit model file: a JSON document holding one isolator model or system.

Schema (``format_version`` 1)::

    {
      "format": "idkit-model",
      "format_version": 1,
      "idkit_version": "0.1.0",
      "model": {"kind": "iwan", "params": {"g1": 3000.0, ...}, "units": {"g1": "N/m", ...}},
      "provenance": {...}          # optional, free-form (fitters: data hashes, settings, seed)
    }

``model.kind`` is one of ``iwan``, ``bouc_wen``, ``generalized_maxwell``, ``voigt``
(isolators, with ``params`` by declared name in SI units) or ``sdof``
(``mass``, ``isolator``), ``hybrid`` (``mass``, ``intermediate_mass``, ``upper``,
``lower``), ``coulomb_spring``. ``units`` is informative and checked on load:
a unit different from the declaration is an error, never converted.
See ``docs/model-file.md``.
"""

from __future__ import annotations

import json
from pathlib import Path

from idkit.atomic import write_bytes_atomic
from idkit.errors import ModelFileError, ParameterError
from idkit.models.boucwen import BoucWenModel
from idkit.models.iwan import IwanModel
from idkit.models.maxwell import GeneralizedMaxwell, VoigtModel
from idkit.models.systems import CoulombSpringSystem, HybridSystem, SDOFSystem

__all__ = ["save_model", "load_model", "model_to_dict", "model_from_dict", "FORMAT", "FORMAT_VERSION"]

FORMAT = "idkit-model"
FORMAT_VERSION = 1
_ISOLATORS = {cls.kind: cls for cls in (IwanModel, BoucWenModel, GeneralizedMaxwell, VoigtModel)}


def model_to_dict(model) -> dict:
    """The ``model`` entry of a model file for an isolator or a system."""
    return model.to_dict()


def model_from_dict(entry: dict, *, where: str = "model"):
    """Build an isolator or system from a ``model`` entry (see module docstring)."""
    if not isinstance(entry, dict) or "kind" not in entry:
        raise ModelFileError(f"{where}: found {type(entry).__name__}, expected an object with a 'kind'")
    kind = entry["kind"]
    try:
        if kind in _ISOLATORS:
            cls = _ISOLATORS[kind]
            params = entry.get("params")
            if not isinstance(params, dict):
                raise ModelFileError(f"{where}.params: found {params!r}, expected an object name -> value")
            model = cls.from_params(params)
            declared = {spec.name: spec.unit for spec in model.param_specs()}
            for name, unit in entry.get("units", {}).items():
                if declared.get(name) != unit:
                    raise ModelFileError(
                        f"{where}.units.{name}: found {unit!r}, expected {declared.get(name)!r} (SI, not converted)"
                    )
            return model
        if kind == "sdof":
            return SDOFSystem(entry["mass"], model_from_dict(entry["isolator"], where=f"{where}.isolator"))
        if kind == "hybrid":
            return HybridSystem(
                entry["mass"], model_from_dict(entry["upper"], where=f"{where}.upper"),
                entry["intermediate_mass"], model_from_dict(entry["lower"], where=f"{where}.lower"),
            )
        if kind == "coulomb_spring":
            fields = {key: value for key, value in entry.items() if key != "kind"}
            return CoulombSpringSystem(**fields)
    except KeyError as missing:
        raise ModelFileError(f"{where}: key {missing.args[0]!r} missing for kind {kind!r}") from None
    except TypeError as problem:
        raise ModelFileError(f"{where}: {problem}") from None
    except ParameterError as problem:
        raise ModelFileError(f"{where}: {problem}") from None
    known = sorted([*_ISOLATORS, "sdof", "hybrid", "coulomb_spring"])
    raise ModelFileError(f"{where}.kind: found {kind!r}, expected one of {known}")


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
    return model_from_dict(load_model_document(path)["model"], where=f"{path}: model")


def load_model_document(path) -> dict:
    """Read and check the whole model-file document (format, version, model, provenance)."""
    path = Path(path)
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as problem:
        raise ModelFileError(f"{path}: not valid JSON ({problem})") from None
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        found = document.get("format") if isinstance(document, dict) else type(document).__name__
        raise ModelFileError(f"{path}: found format {found!r}, expected {FORMAT!r}")
    if document.get("format_version") != FORMAT_VERSION:
        raise ModelFileError(
            f"{path}: found format_version {document.get('format_version')!r}, expected {FORMAT_VERSION}"
        )
    if "model" not in document:
        raise ModelFileError(f"{path}: key 'model' missing")
    return document
