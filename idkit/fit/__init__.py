"""Identification of isolator models from measurements (SPEC 4, thesis chapter 7).

- :func:`fit_iwan` - three-stage Nelder-Mead fit of the modified Iwan model to
  quasi-static loops (objective 7.1); :func:`prepare_loops`, :func:`iwan_start`,
  :func:`iwan_set_errors` are its building blocks.
- :func:`fit_maxwell` - bounded SQP fit of the generalized Maxwell model to the
  transmissibilities of several top masses (objective 7.5) with an optional
  global cross-check; :func:`fit_voigt`, :func:`maxwell_order_table`,
  :func:`fit_complex_stiffness` (DMA / complex stiffness data),
  :func:`estimate_k0` (quasi-static slope around the origin).
- :func:`fit_boucwen` - staged (elastic, loop shape), scaled, globally searched
  fit of the modified Bouc-Wen model to the same loops; :func:`compare_loop_models`
  tabulates Iwan against Bouc-Wen set by set.
- :func:`fit_boucwen_output` - the force-driven Bouc-Wen oscillator fitted to a
  time record by output (simulation) error, with standard errors.
- :mod:`idkit.fit.measurements` - the same fits on measurement sets
  (:func:`fit_iwan_measurements`, :func:`fit_maxwell_measurements`,
  :func:`fit_boucwen_measurements`) with provenance and model files.
- :mod:`idkit.fit.bootstrap` - parameter spread by refitting per repetition or
  on seeded resamples.

Every fit returns a typed result (:mod:`idkit.fit.result`) with lmfit
``Parameters`` and a ``report()``. Fitters work on arrays; loading files is
:mod:`idkit.io`'s job.
"""

from idkit.fit.bootstrap import (
    BootstrapResult,
    bootstrap_fit,
    bootstrap_loops,
    bootstrap_measurements,
    bootstrap_transmissibility,
)
from idkit.fit.boucwen import boucwen_set_errors, boucwen_set_forces, fit_boucwen
from idkit.fit.boucwen_output import (
    OUTPUT_PARAMETERS,
    BoucWenOutputFit,
    boucwen_output_start,
    fit_boucwen_output,
)
from idkit.fit.compare import LoopModelComparison, compare_loop_models
from idkit.fit.damping import ViscousDamping, fit_viscous_damping
from idkit.fit.iwan import (
    LoopSet,
    fit_iwan,
    iwan_order_table,
    iwan_set_errors,
    iwan_set_forces,
    iwan_start,
    prepare_loops,
)
from idkit.fit.landscape import ErrorLandscape, maxwell_error_landscape
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
from idkit.fit.measurements import (
    SMALL_THRESHOLD,
    DataProvenance,
    K0FromLoops,
    LoopData,
    MeasurementFit,
    fit_boucwen_measurements,
    fit_iwan_measurements,
    fit_maxwell_measurements,
    k0_from_measurements,
    loop_sets,
    transmissibility_sets,
)
from idkit.fit.result import (
    BoucWenFitResult,
    BoucWenFitSettings,
    CrossCheck,
    IwanFitResult,
    IwanFitSettings,
    IwanStart,
    MaxwellFitResult,
    MaxwellFitSettings,
    StageResult,
)

__all__ = [
    "LoopSet", "prepare_loops", "iwan_start", "iwan_set_errors", "iwan_set_forces", "fit_iwan", "iwan_order_table",
    "IwanFitResult", "IwanFitSettings", "IwanStart", "StageResult",
    "TransmissibilitySet", "K0Estimate", "estimate_k0", "maxwell_objective", "fit_maxwell", "fit_voigt",
    "fit_complex_stiffness", "maxwell_order_table",
    "MaxwellFitResult", "MaxwellFitSettings", "CrossCheck",
    "fit_boucwen",
    "fit_viscous_damping", "ViscousDamping", "boucwen_set_errors", "boucwen_set_forces", "BoucWenFitResult", "BoucWenFitSettings",
    "SMALL_THRESHOLD", "DataProvenance", "LoopData", "K0FromLoops", "MeasurementFit", "loop_sets",
    "transmissibility_sets", "k0_from_measurements", "fit_iwan_measurements", "fit_boucwen_measurements",
    "fit_maxwell_measurements",
    "BootstrapResult", "bootstrap_fit", "bootstrap_loops", "bootstrap_transmissibility", "bootstrap_measurements",
    "LoopModelComparison", "compare_loop_models", "ErrorLandscape", "maxwell_error_landscape",
    "fit_boucwen_output", "boucwen_output_start", "BoucWenOutputFit", "OUTPUT_PARAMETERS",
]
