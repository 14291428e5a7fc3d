"""Identification of isolator models from measurements (SPEC 4, thesis chapter 7).

- :func:`fit_iwan` - three-stage Nelder-Mead fit of the modified Iwan model to
  quasi-static loops (objective 7.1, :mod:`idkit.fit.loop_objective`); :func:`iwan_start`
  (:mod:`idkit.fit.iwan_start`) and :func:`iwan_set_errors` are its building blocks, the
  loops come from :mod:`idkit.observe.quasi_static` (:func:`prepare_loops`, :func:`loop_sets`).
- :func:`fit_maxwell` - bounded SQP fit of the generalized Maxwell model to the
  transmissibilities of several top masses (objective 7.5) with an optional
  global cross-check; :func:`fit_voigt`, :func:`fit_complex_stiffness` (DMA / complex
  stiffness data), :func:`maxwell_objective` (:mod:`idkit.fit.frf_objective`); the FRFs and
  k0 come from :mod:`idkit.observe` (:func:`transmissibility_sets`, :func:`estimate_k0`).
- :mod:`idkit.fit.dma` - material data: :func:`fit_prony` (Prony series pruned to the fewest
  terms within a stated factor of the best), :func:`fit_dma_table` (isotherms -> shift
  factors estimated and checked -> master curve -> modulus model).
- :mod:`idkit.fit.compare` - :func:`compare_loop_models`, :func:`iwan_order_table`,
  :func:`maxwell_order_table`; the order rule they apply is :mod:`idkit.fit.orders`
  (:data:`ORDER_RULE_FACTOR`), the Iwan family rule :mod:`idkit.fit.family`.
- :func:`fit_boucwen` - staged (elastic, loop shape), scaled, globally searched
  fit of the modified Bouc-Wen model to the same loops; :func:`compare_loop_models`
  tabulates Iwan against Bouc-Wen set by set.
- :func:`fit_boucwen_output` - the force-driven Bouc-Wen oscillator fitted to a
  time record by output (simulation) error, with standard errors.
- :mod:`idkit.fit.measurement_level` - the same fits on measurement sets
  (:func:`fit_iwan_measurements`, :func:`fit_maxwell_measurements` on one
  :class:`ElastomerData` (:mod:`idkit.fit.elastomer_data`), :func:`fit_boucwen_measurements`),
  returning a :class:`MeasurementFit` (:mod:`idkit.fit.measurement_fit`) with provenance and
  model file; their checks of the model against the data set: :mod:`idkit.fit.data_set_checks`,
  :mod:`idkit.fit.model_form` (noise floor), :mod:`idkit.fit.frf_resolution`.
- :mod:`idkit.fit._optim` - the optimiser plumbing every fitter shares (Nelder-Mead with
  restarts, SQP, global searches, the status a result's ``success`` reads).
- :mod:`idkit.fit.bootstrap` - parameter spread by refitting per repetition or
  on seeded resamples.

Every fit returns a typed result (:mod:`idkit.fit.result`, :mod:`idkit.fit.maxwell_result`) as lmfit users expect it
(``params``, ``success``, ``message``, ``nfev``, ``chisqr``, ``aic``, ``fit_report()``)
and a ``report()``. Fitters work on observables; loading files is :mod:`idkit.io`'s job,
turning measurements into observables :mod:`idkit.observe`'s. The observables' names stay
importable from here for existing callers.
"""

from idkit.fit.bootstrap import (
    BootstrapResult,
    bootstrap_fit,
    bootstrap_loops,
    bootstrap_measurements,
    bootstrap_transmissibility,
)
from idkit.fit.boucwen import fit_boucwen
from idkit.fit.boucwen_output import (
    OUTPUT_PARAMETERS,
    BoucWenOutputFit,
    boucwen_output_start,
    fit_boucwen_output,
)
from idkit.fit.compare import LoopModelComparison, compare_loop_models, iwan_order_table, maxwell_order_table
from idkit.fit.damping import ViscousDamping, fit_viscous_damping
from idkit.fit.frf_objective import maxwell_objective
from idkit.fit.iwan import fit_iwan
from idkit.fit.iwan_start import iwan_start
from idkit.fit.landscape import ErrorLandscape, maxwell_error_landscape
from idkit.fit.loop_objective import boucwen_set_errors, boucwen_set_forces, iwan_set_errors, iwan_set_forces
from idkit.fit.maxwell_table import fit_complex_stiffness
from idkit.fit.maxwell import LOSS_RULE_FACTOR, fit_maxwell, fit_voigt
from idkit.fit.orders import ORDER_RULE_FACTOR
from idkit.fit.dma import DmaFit, PronyFit, fit_dma_table, fit_prony
from idkit.fit.elastomer_data import ElastomerData, elastomer_data
from idkit.fit.measurement_fit import MeasurementFit
from idkit.fit.measurement_level import fit_boucwen_measurements, fit_iwan_measurements, fit_maxwell_measurements
from idkit.fit.maxwell_result import CrossCheck, MaxwellFitResult, MaxwellFitSettings
from idkit.fit.result import BoucWenFitResult, BoucWenFitSettings, IwanFitResult, IwanFitSettings, IwanStart, StageResult
from idkit.io.selection import DataProvenance
# observables, defined in idkit.observe; importable from here as before
from idkit.observe.k0 import K0Estimate, K0FromLoops, estimate_k0, k0_from_measurements
from idkit.observe.quasi_static import SMALL_THRESHOLD, LoopData, LoopSet, loop_sets, prepare_loops
from idkit.observe.white_noise import TransmissibilitySet, transmissibility_sets

__all__ = [
    "LoopSet", "prepare_loops", "iwan_start", "iwan_set_errors", "iwan_set_forces", "fit_iwan", "iwan_order_table", "ORDER_RULE_FACTOR",
    "IwanFitResult", "IwanFitSettings", "IwanStart", "StageResult",
    "TransmissibilitySet", "K0Estimate", "estimate_k0", "maxwell_objective", "fit_maxwell", "fit_voigt",
    "fit_complex_stiffness", "maxwell_order_table", "LOSS_RULE_FACTOR", "fit_prony", "PronyFit", "fit_dma_table", "DmaFit",
    "MaxwellFitResult", "MaxwellFitSettings", "CrossCheck",
    "fit_boucwen",
    "fit_viscous_damping", "ViscousDamping", "boucwen_set_errors", "boucwen_set_forces", "BoucWenFitResult", "BoucWenFitSettings",
    "SMALL_THRESHOLD", "DataProvenance", "LoopData", "K0FromLoops", "MeasurementFit", "loop_sets",
    "transmissibility_sets", "k0_from_measurements", "fit_iwan_measurements", "fit_boucwen_measurements",
    "fit_maxwell_measurements", "ElastomerData", "elastomer_data",
    "BootstrapResult", "bootstrap_fit", "bootstrap_loops", "bootstrap_transmissibility", "bootstrap_measurements",
    "LoopModelComparison", "compare_loop_models", "ErrorLandscape", "maxwell_error_landscape",
    "fit_boucwen_output", "boucwen_output_start", "BoucWenOutputFit", "OUTPUT_PARAMETERS",
]
