"""Identification of isolator models from measurements (SPEC 4, thesis chapter 7).

- :func:`fit_iwan` - three-stage Nelder-Mead fit of the modified Iwan model to
  quasi-static loops (objective 7.1); :func:`prepare_loops`, :func:`iwan_start`,
  :func:`iwan_set_errors` are its building blocks.
- :func:`fit_maxwell` - bounded SQP fit of the generalized Maxwell model to the
  transmissibilities of several top masses (objective 7.5) with an optional
  global cross-check; :func:`fit_voigt`, :func:`maxwell_order_table`,
  :func:`fit_complex_stiffness` (DMA / complex stiffness data),
  :func:`estimate_k0` (quasi-static slope around the origin).

Every fit returns a typed result (:mod:`idkit.fit.result`) with lmfit
``Parameters`` and a ``report()``. Fitters work on arrays; loading files is
:mod:`idkit.io`'s job.
"""

from idkit.fit.iwan import LoopSet, fit_iwan, iwan_set_errors, iwan_start, prepare_loops
from idkit.fit.maxwell import (
    K0Estimate,
    TransmissibilitySet,
    estimate_k0,
    fit_complex_stiffness,
    fit_maxwell,
    fit_voigt,
    maxwell_objective,
    maxwell_order_table,
)
from idkit.fit.result import (
    CrossCheck,
    IwanFitResult,
    IwanFitSettings,
    IwanStart,
    MaxwellFitResult,
    MaxwellFitSettings,
    StageResult,
)

__all__ = [
    "LoopSet", "prepare_loops", "iwan_start", "iwan_set_errors", "fit_iwan",
    "IwanFitResult", "IwanFitSettings", "IwanStart", "StageResult",
    "TransmissibilitySet", "K0Estimate", "estimate_k0", "maxwell_objective", "fit_maxwell", "fit_voigt",
    "fit_complex_stiffness", "maxwell_order_table",
    "MaxwellFitResult", "MaxwellFitSettings", "CrossCheck",
]
