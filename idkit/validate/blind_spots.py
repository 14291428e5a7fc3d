"""What a validation cannot see: deliberately wrong components that still pass it.

A PASS says the model agrees with the held-out data; it does not say that every
component of the model was tested. On a hybrid (elastomer over wire rope) the series
stiffness is the elastomer's and the wire rope barely moves at small amplitude, so a
rope whose slip forces are off by a factor 3 may pass the hybrid's validation as well
as the fitted one. :func:`blind_spots` re-runs a validation with each component
scaled by a documented factor (:data:`PROBES`) and names those whose wrong version
still passes: the report prints them beside the verdict ("cannot see ...") instead of
letting the PASS vouch for them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from idkit.models import GeneralizedMaxwell, IwanModel
from idkit.validate.result import ValidationResult

__all__ = ["PROBES", "scaled", "blind_spots"]

#: Component changes a validation should detect: (label, parameter group, factor).
PROBES = (
    ("slip forces x0.3", "fc", 0.3),
    ("slip forces x3", "fc", 3.0),
    ("stiffness x0.5", "stiffness", 0.5),
    ("stiffness x2", "stiffness", 2.0),
)


def scaled(model, group: str, factor: float):
    """``model`` with one parameter group scaled: ``"fc"`` (Iwan slip forces) or ``"stiffness"``
    (Iwan ``g1, g2, g3, k_i``; Maxwell ``k0, k_i``). ``None`` if the model has no such group."""
    params = model.params()
    if isinstance(model, IwanModel):
        names = [n for n in params if n.startswith("fc_")] if group == "fc" else \
            [n for n in params if n in ("g1", "g2", "g3") or n.startswith("k_")]
    elif isinstance(model, GeneralizedMaxwell) and group == "stiffness":
        names = [n for n in params if n == "k0" or n.startswith("k_")]
    else:
        return None
    return type(model).from_params({**params, **{n: params[n] * factor for n in names}})


def blind_spots(result: ValidationResult, rerun: Callable[..., ValidationResult], components: dict,
                probes=PROBES) -> ValidationResult:
    """``result`` with :attr:`ValidationResult.cannot_see` naming the probes that still pass.

    Parameters
    ----------
    result : ValidationResult
        The validation of the identified model.
    rerun : callable(**components) -> ValidationResult
        Runs the same validation with the given components (keyword arguments such as
        ``upper=``, ``lower=``, ``isolator=``).
    components : dict
        The identified components by keyword, e.g. ``{"upper": elastomer, "lower": rope}``.
    probes : sequence of (label, group, factor)
        Changes to try on each component (:data:`PROBES`).
    """
    missed = []
    for keyword, model in components.items():
        for label, group, factor in probes:
            wrong = scaled(model, group, factor)
            if wrong is None:
                continue
            if rerun(**{**components, keyword: wrong}).passed:
                missed.append(f"{type(model).__name__} ({keyword}) {label}")
    return dataclasses.replace(result, cannot_see=tuple(missed))
