"""The result of a measurement-level fit: the array-level result with its data and provenance.

:class:`MeasurementFit` is what :func:`idkit.fit.fit_iwan_measurements`,
:func:`idkit.fit.fit_boucwen_measurements` and :func:`idkit.fit.fit_maxwell_measurements`
return: the fitter's typed result, the observables it saw, where they came from, the
measurement-level checks, and the model file with its provenance (data files and their
SHA-256, idkit version, algorithm settings, seed).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.errors import FitError
from idkit.fit.bootstrap import bootstrap_measurements
from idkit.fit.damping import ViscousDamping
from idkit.io.selection import DataProvenance
from idkit.models import save_model
from idkit.observe.k0 import K0FromLoops
from idkit.observe.quasi_static import LoopData

__all__ = ["MeasurementFit"]




@dataclass(frozen=True)
class MeasurementFit:
    """A fit to measurements: the array-level result plus its data and provenance.

    Attributes
    ----------
    kind : {"iwan", "boucwen", "maxwell"}
    result : IwanFitResult, BoucWenFitResult or MaxwellFitResult
    data : LoopData or ElastomerData
        The observables the fit saw: loop sets (Iwan, Bouc-Wen) or the elastomer's FRFs and k0
        (Maxwell; iterating over it gives the transmissibility sets).
    provenance : DataProvenance
    k0 : K0FromLoops or None
        Maxwell fits: the static stiffness used.
    options : dict
        Options of the measurement-level call (recorded in the provenance).
    repetitions : tuple
        Maxwell fits: repetition number of each transmissibility set (for the bootstrap).
    damping : ViscousDamping or None
        Iwan fits: the viscous damping identified from stepped-sine data
        (:func:`idkit.fit.fit_viscous_damping`); the model carries it.
    damping_note : str
        Why the stepped-sine data present did not give a viscous damping.
    order_table : pandas.DataFrame or None
        Iwan fits with ``order="auto"``: the order table the order was chosen from.
    checks : tuple of str
        Problems found at the measurement level (e.g. the model is invalid inside the
        deflections the data set reaches); they make :attr:`success` false.
    spread : BootstrapResult or None
        Parameters refitted on each repetition of the experiment alone
        (:meth:`with_repetition_spread`): the spread across repetitions, beside the
        standard errors of ``result.params`` (the spread within one data set).
    spread_note : str
        Why :attr:`spread` is None after :meth:`with_repetition_spread` (e.g. one repetition).
    family_fits : dict
        Iwan fits: ``"plain"`` -> the plain fit and, when the modulation stage ran (family
        rule), ``"modulated"`` -> the modulated fit of the modulated order rule, whichever of
        the two ``result`` is (both without the viscous damping; :meth:`with_damping` adds it).
    """

    kind: str
    result: object
    data: object
    provenance: DataProvenance
    k0: K0FromLoops | None = None
    options: dict = field(default_factory=dict)
    repetitions: tuple = ()
    damping: ViscousDamping | None = None
    damping_note: str = ""
    checks: tuple[str, ...] = ()
    order_table: pd.DataFrame | None = field(default=None, repr=False)
    spread: object | None = None
    spread_note: str = ""
    family_fits: dict = field(default_factory=dict, repr=False)

    def with_damping(self, model):
        """``model`` with this fit's identified viscous damping (unchanged without one)."""
        return self.damping.model(model) if self.damping is not None else model

    def with_repetition_spread(self, *, method: str = "repetition", n_resamples: int = 20,
                               seed: int | None = None) -> "MeasurementFit":
        """This fit with :attr:`spread` from :func:`idkit.fit.bootstrap_measurements`.

        One refit per repetition (``info.repetition`` of the records; ``method="resample"``
        for resampled sets) with the fit's own settings. When the data hold fewer than two
        repetitions the spread stays None and :attr:`spread_note` says so.
        """
        try:
            spread = bootstrap_measurements(self, method=method, n_resamples=n_resamples, seed=seed)
        except FitError as problem:
            return dataclasses.replace(self, spread=None, spread_note=f"no spread across repetitions: {problem}")
        return dataclasses.replace(self, spread=spread, spread_note="")

    def parameters_table(self) -> pd.DataFrame:
        """One row per parameter: value, stderr (residual Jacobian) and spread across repetitions.

        Columns ``parameter``, ``unit``, ``value``, ``stderr``, ``stderr_note`` (why there is
        none: fixed, or the reason from ``result.stderr_notes``), ``repetition_std`` (std,
        ddof 1, of the refits of :attr:`spread`), ``repetition_values`` (each refit's value),
        ``repetitions`` (refit count) and ``fitted``.
        """
        notes = tuple(getattr(self.result, "stderr_notes", ()) or ())
        spread = {}
        if self.spread is not None:
            summary = self.spread.summary().set_index("parameter")
            for index, name in enumerate(self.spread.names):
                spread[name] = (float(summary.loc[name, "std"]), tuple(float(v) for v in self.spread.samples[:, index]))
        rows = []
        for name, parameter in self.result.parameters.items():
            unit = (parameter.user_data or {}).get("unit", "") if isinstance(parameter.user_data, dict) else ""
            if parameter.stderr is not None:
                note = ""
            elif not parameter.vary:
                note = "fixed in the fit"
            else:
                named = [n for n in notes if n.startswith(f"{name}:") or f"{name} (" in n or n.startswith("every")]
                note = "; ".join(named) or "not estimated"
            std, values = spread.get(name, (float("nan"), ()))
            value = parameter.value
            if name == "c_visc" and self.damping is not None:  # identified apart from the loop fit
                value, note = self.damping.c_visc, "from the stepped-sine resonance, not the loops"
                std, values = float("nan"), ()
            rows.append({"parameter": name, "unit": unit, "value": value, "stderr": parameter.stderr,
                         "stderr_note": note, "repetition_std": std,
                         "repetition_values": ", ".join(f"{v:.5g}" for v in values),
                         "repetitions": len(values), "fitted": parameter.vary})
        return pd.DataFrame(rows)

    @property
    def reasons(self) -> tuple[str, ...]:
        """Why the fit is not a success: the fitter's reasons and the measurement-level checks."""
        return tuple(getattr(self.result, "reasons", ())) + tuple(self.checks)

    @property
    def success(self) -> bool:
        """The fitter succeeded and no measurement-level check failed."""
        return bool(self.result.success) and not self.checks

    @property
    def model(self):
        """The identified model (Iwan: with the identified viscous damping, if any)."""
        if self.damping is not None:
            return self.damping.model(self.result.model)
        return self.result.model

    @property
    def loop_amplitude_range(self) -> tuple[float, float] | None:
        """Smallest and largest loop amplitude (m) the model was identified on
        (:meth:`idkit.observe.quasi_static.LoopData.amplitude_range`), or None for a fit not
        made on loops; outside it the model is extrapolated."""
        if not isinstance(self.data, LoopData):
            return None
        smallest, largest = self.data.amplitude_range()
        return (smallest, largest) if np.isfinite(smallest) else None

    def report(self) -> str:
        """The fit's report preceded by the data it used."""
        p = self.provenance
        lines = [f"[[Data]] {p.folder or 'in-memory measurements'}: {len(p.ids)} measurements "
                 f"({', '.join(f'{k}={v}' for k, v in p.selection.items())})"]
        if isinstance(self.data, LoopData) and self.data.single_amplitude:
            names = ", ".join(s.name for s in self.data.small)
            lines.append(f"    one-amplitude test ({names}): every stage fits the same loops, so the small- and "
                         "large-loop errors are one number")
        elif isinstance(self.data, LoopData):
            small = ", ".join(s.name for s in self.data.small)
            large = ", ".join(s.name for s in self.data.large)
            lines.append(f"    small loops (amplitude <= {1e3 * self.data.threshold:g} mm): {small}")
            lines.append(f"    large loops: {large}")
        if self.loop_amplitude_range is not None:
            smallest, largest = self.loop_amplitude_range
            lines.append(f"    loop amplitudes {1e3 * smallest:.3g} to {1e3 * largest:.3g} mm (half the travel "
                         "between reversals): the model is extrapolated outside this range")
        if isinstance(self.data, LoopData) and self.data.offset_corrections:
            lines.append("    offsets removed before fitting: " + ", ".join(
                f"{c.measurement_id} (force {c.force_offset:+.4g} N"
                + (f", centre drift {1e3 * float(np.ptp(c.center_knots)):.3g} mm" if c.center_knots.size else "")
                + ")" for c in self.data.offset_corrections))
        if self.k0 is not None:
            k = self.k0
            how = (f"relaxation of the loops fitted, secant slope {k.secant_k0:.5g} N/m; " if k.method == "relaxation"
                   else "secant slope; ")
            lines.append(f"    k0 = {k.k0:.5g} +- {k.stderr:.2g} N/m from the quasi-static loops ({how}|deflection| <= "
                         f"{1e3 * k.window:g} mm; per record "
                         + ", ".join(f"{name}: {value:.5g}" for name, value in k.per_record.items()) + ")")
            if k.fallback:
                lines.append(f"    k0: {k.fallback}")
        if self.damping is not None:
            d = self.damping
            lines.append(f"    c_visc = {d.c_visc:.4g} N s/m (damping ratio {d.damping_ratio:.3g}) from the resonance "
                         f"peak of the stepped-sine level {d.level:g} ({d.points} points, {d.peak_frequency_hz:.3g} Hz, "
                         f"|H1| {d.peak_measured:.4g}); peak-matching value per level: "
                         + ", ".join(f"{level:g}: {value:.3g}" for level, value in d.per_level.items()))
        elif self.kind == "iwan":
            lines.append("    " + (self.damping_note or "c_visc = 0: no stepped-sine data to identify viscous "
                                   "damping") + "; steady-state responses of a lightly hysteretic rope may not settle")
        lines.extend(f"    not a success: {check}" for check in self.checks)
        if self.spread is not None:
            lines.append(f"    spread across repetitions: {self.spread.method}, {self.spread.samples.shape[0]} refits ("
                         + ", ".join(self.spread.labels) + ")")
        elif self.spread_note:
            lines.append(f"    {self.spread_note}")
        if self.damping is not None:  # the loop fit holds c_visc at 0; the model carries the resonance's
            loop_report = self.result.report({"c_visc": f"the loop fit's; the model's {self.damping.c_visc:.4g} N s/m "
                                                        "is from the stepped-sine resonance, above"})
        else:
            loop_report = self.result.report()
        return "\n".join(lines) + "\n" + loop_report

    def provenance_dict(self) -> dict:
        """Provenance record for the model file (JSON-ready)."""
        from idkit import __version__

        settings = _jsonable(dataclasses.asdict(self.result.settings))
        record = {
            "fitter": f"idkit.fit.fit_{self.kind}_measurements",
            "idkit_version": __version__,
            "data": self.provenance.to_dict(),
            "settings": settings,
            "options": _jsonable(self.options),
            "seed": settings.get("seed"),
        }
        if self.order_table is not None:
            record["order_table"] = _jsonable(self.order_table.to_dict(orient="records"))
        if self.damping is not None:
            record["viscous_damping"] = _jsonable(dataclasses.asdict(self.damping))
        elif self.damping_note:
            record["viscous_damping"] = self.damping_note
        if getattr(self.result, "start_states", None):
            record["start_states"] = dict(self.result.start_states)
        record["success"] = self.success
        record["reasons"] = list(self.reasons)
        record["determined_only_in_combination"] = [list(found) for found in getattr(self.result, "undetermined", ())]
        if self.loop_amplitude_range is not None:
            record["loop_amplitude_range_m"] = list(self.loop_amplitude_range)
        if self.kind in ("iwan", "boucwen"):
            record["errors_percent"] = {
                "small": {n: 100 * float(e) for n, e in zip(self.result.small_names, self.result.small_errors)},
                "large": {n: 100 * float(e) for n, e in zip(self.result.large_names, self.result.large_errors)},
            }
        else:
            record["errors_percent"] = {n: 100 * float(e) for n, e in zip(self.result.set_names,
                                                                          self.result.set_errors)}
            record["error_percent"] = 100 * float(self.result.error)
        if self.k0 is not None:
            record["k0"] = {"value_N_per_m": self.k0.k0, "stderr_N_per_m": self.k0.stderr,
                            "window_m": self.k0.window, "per_record_N_per_m": _jsonable(dict(self.k0.per_record)),
                            "method": self.k0.method, "secant_N_per_m": self.k0.secant_k0,
                            "relaxation_N_per_m_by_rate_per_s": _jsonable(self.k0.relaxation),
                            "fallback": self.k0.fallback}
        points = getattr(self.data, "operating_points", None)
        if points:  # each top mass was fitted about its preload: k0 -> this tangent stiffness
            record["operating_points"] = {f"{mass:g} kg": None if point is None else
                                          {"static_deflection_m": point.deflection,
                                           "tangent_stiffness_N_per_m": point.stiffness}
                                          for mass, point in points.items()}
        return record

    def save(self, path, *, overwrite: bool = False) -> Path:
        """Write the model file (:func:`idkit.models.save_model`) with :meth:`provenance_dict`."""
        return save_model(self.model, path, provenance=self.provenance_dict(), overwrite=overwrite)


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        number = float(value)
        return number if math.isfinite(number) else str(number)
    if isinstance(value, (np.integer, np.bool_)):
        return value.item()
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    return value
