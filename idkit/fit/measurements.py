"""Measurement-level fitting: measurement sets in, identified model with provenance out.

The array-level fitters (:func:`~idkit.fit.fit_iwan`, :func:`~idkit.fit.fit_maxwell`,
:func:`~idkit.fit.fit_boucwen`) take loops and transmissibilities; this module picks
the right measurements of a :class:`~idkit.io.MeasurementSet` (kind, isolator, split),
turns them into those inputs and keeps where they came from:

* the observables come from :mod:`idkit.observe`: :func:`~idkit.observe.quasi_static.loop_sets`
  (small and large loop sets, :class:`~idkit.observe.quasi_static.LoopData`),
  :func:`~idkit.observe.white_noise.transmissibility_sets` (one H1 per white-noise run) and
  :func:`~idkit.observe.quasi_static.k0_from_measurements` (the elastomer's static stiffness);
  the selection and its provenance from :func:`idkit.io.selection.select_measurements`.
* :func:`elastomer_data` - the elastomer's observables selected once into one
  :class:`ElastomerData` (FRFs, k0 with its loops, provenance, repetitions), handed to
  :func:`~idkit.fit.fit_maxwell` by :func:`fit_maxwell_measurements`.
* :func:`fit_iwan_measurements`, :func:`fit_maxwell_measurements`,
  :func:`fit_boucwen_measurements` - the fits, restricted to ``split="fit"`` by default,
  returning a :class:`MeasurementFit` that can write the model file with provenance
  (data files and their SHA-256, idkit version, algorithm settings, seed).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.errors import DataError, FitError, Message, Suggestion
from idkit.fit.boucwen import fit_boucwen
from idkit.fit.compare import iwan_order_fits, iwan_order_row
from idkit.fit.damping import ViscousDamping, fit_viscous_damping
from idkit.fit.iwan import fit_iwan
from idkit.fit.iwan_start import smallest_branch_secant
from idkit.fit.static_stiffness import K0_METHODS, k0_with_relaxation
from idkit.fit.maxwell import fit_maxwell
from idkit.fit.model_form import FLOOR_MARGIN, MODEL_FORM_PREFIX
from idkit.io import QuasiStaticMeasurement
from idkit.io.selection import ONLY_ISOLATOR, DataProvenance, resolve_isolator, select_measurements
from idkit.models import save_model
from idkit.models.laws import lowest_spring_stiffness, sdof_transmissibility
from idkit.models.maxwell import preloaded
from idkit.observe.quasi_static import (
    LOOP_POINTS_PER_SET,
    K0FromLoops,
    LoopData,
    k0_from_records,
    loop_sets,
    static_operating_point,
)
from idkit.gravity import STANDARD_GRAVITY
from idkit.observe.white_noise import FRF_RESOLUTION_HZ, TransmissibilitySet, transmissibility_sets
from idkit.signal.cycles import noise_level
from idkit.signal.frf import HANN_ENBW_BINS, half_power_damping, window_peak_bias

__all__ = [
    "ElastomerData",
    "MeasurementFit",
    "elastomer_data",
    "fit_iwan_measurements",
    "fit_boucwen_measurements",
    "fit_maxwell_measurements",
]


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
        from idkit.fit.bootstrap import bootstrap_measurements

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


# --------------------------------------------------------------------------- the fits


def fit_iwan_measurements(
    measurements,
    *,
    order: int | str = "auto",
    small_threshold: float | None = None,
    isolator=ONLY_ISOLATOR,
    split: str | None = "fit",
    points_per_set: int | None = LOOP_POINTS_PER_SET,
    backend: str = "nlopt",
    seed: int = 0,
    damping_level="largest",
    remove_offsets: bool = False,
    family: str = "auto",
    **options,
) -> MeasurementFit:
    """Three-stage Iwan fit (:func:`idkit.fit.fit_iwan`) on the quasi-static records of a set.

    Records are split into small and large sets by :func:`loop_sets`
    (``small_threshold`` default: the data's own, :func:`~idkit.observe.quasi_static.split_threshold`); ``options`` go to :func:`~idkit.fit.fit_iwan`.
    When the same selection holds stepped-sine points of the isolator, the viscous
    damping is identified from the resonance of the level ``damping_level``
    (:func:`idkit.fit.fit_viscous_damping`; ``None`` keeps ``c_visc = 0``) and
    carried by ``fit.model`` and the model file.

    ``order="auto"`` fits orders 1-6 (:func:`idkit.fit.iwan_order_table`) and keeps the
    one the documented order rule recommends; the table is in ``fit.order_table`` and
    the model file's provenance.

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
        Selected by :func:`idkit.io.selection.select_measurements`.
    order : int or "auto", default "auto"
        Number of Jenkin elements, or ``"auto"`` for the order rule (docs/fitting.md).
    small_threshold : float or None
        Amplitude (m) at or below which a record is a small-loop set; default (None) the geometric
        mean of the smallest and largest record amplitude (:func:`~idkit.observe.quasi_static.split_threshold`).
    isolator : str or None, default: the only isolator with loop records
        The isolator whose records are fitted (None: every record). By default the only one
        with quasi-static records (:func:`idkit.io.selection.resolve_isolator`); with several,
        a :class:`~idkit.errors.DataError` lists them.
    split : {"fit", "validation", "all", None}, default "fit"
    points_per_set : int or None, default :data:`~idkit.observe.quasi_static.LOOP_POINTS_PER_SET`
        Resampled points per record (:func:`~idkit.observe.quasi_static.prepare_loops`).
    backend : {"nlopt", "scipy"}
    seed : int, default 0
    damping_level : float, "largest" or None, default "largest"
        Stepped-sine level whose resonance gives ``c_visc`` (None: keep ``c_visc = 0``).
    remove_offsets : bool, default False
        Remove each record's loop-centre drift and force offset before fitting
        (:func:`idkit.observe.quasi_static.remove_loop_offsets`); what was subtracted goes
        to ``options["offset_corrections"]`` and the model file's provenance.
    family : {"auto", "plain", "modulated"}, default "auto"
        Model family. ``"plain"``: the three-stage fit's :class:`~idkit.models.IwanModel`.
        ``"modulated"``: the slip-modulation stage (:func:`idkit.fit.fit_iwan_modulated`) on top
        of it, a :class:`~idkit.models.ModulatedIwanModel`. ``"auto"`` (the family rule,
        :func:`choose_iwan_family`): the plain model unless its loop error is more than
        :data:`FLOOR_MARGIN` above the records' noise floor or it leaves a combination of
        parameters undetermined, and the modulated model (orders by continuation,
        :func:`idkit.fit.iwan_modulated.fit_modulated_orders`) succeeds with a mean error lower
        by the order rule's factor or determines what the plain one left undetermined.
    **options
        Passed to :func:`idkit.fit.fit_iwan`. ``valid_range`` defaults to ``"data"``:
        :func:`data_valid_range` of the isolator's records (loops, sweeps and drops, every
        split), so that the spring stays stiff wherever the data set will be simulated; pass
        ``valid_range=None`` for the loops' own optimum without the barrier, or ``(x_min, x_max)``.

    Returns
    -------
    MeasurementFit
        ``kind="iwan"``; ``data`` the :class:`~idkit.observe.quasi_static.LoopData`;
        ``checks`` the measurement-level problems (the spring turns negative-stiff inside the
        data set's deflections, the model cannot simulate its highest drop).

    Raises
    ------
    FitError
        Bad records or options, only small or only large sets.
    DataError
        No quasi-static record matches the selection.

    Examples
    --------
    >>> from idkit.io import load_measurement_set          # doctest: +SKIP
    >>> fit = fit_iwan_measurements(load_measurement_set("data/wire_rope"))  # doctest: +SKIP
    >>> fit.save("wire_rope.json")                         # doctest: +SKIP
    """
    if family not in IWAN_FAMILIES:
        raise FitError(f"family: found {family!r}, expected one of {IWAN_FAMILIES}")
    valid_range = options.pop("valid_range", "data")
    if isinstance(valid_range, str) and valid_range != "data":
        raise FitError(f"valid_range: found {valid_range!r}, expected 'data', None or (x_min, x_max) in m")
    isolator = resolve_isolator(measurements, isolator, kind="quasi_static")
    # the loops first: a selection that matches no record is named with what the set holds
    # (the valid range's own error only said no record of the isolator had a deflection)
    data = loop_sets(measurements, small_threshold=small_threshold, isolator=isolator, split=split,
                     points_per_set=points_per_set, remove_offsets=remove_offsets)
    if isinstance(valid_range, str):
        valid_range = data_valid_range(measurements, isolator=isolator)
    if valid_range is not None:
        options["valid_range"] = tuple(float(v) for v in valid_range)
    order_table = None
    # the loops' own fits (no valid-range barrier) choose the order and start the final fit:
    # they are the same to the last digits on every numpy CPU path, while the barrier's
    # penalty is not smooth and a barrier fit from the loops' start estimate lands in
    # different minima (the bundled rope at order 3: 4.907 or 5.007 %, which flipped the
    # order rule between 3 and 4 with the CPU)
    free_options = {key: value for key, value in options.items() if key != "valid_range"}
    if order == "auto":
        order_table, order_fits = iwan_order_fits(list(data.small), list(data.large), backend=backend, seed=seed,
                                                  **free_options)
        order = int(order_table.loc[order_table["recommended"], "order"].iloc[0])
        result = order_fits[order]  # the table's own fit of that order (same sets and options)
    elif isinstance(order, str):
        raise FitError(f"order: found {order!r}, expected an integer >= 1 or 'auto'")
    else:
        result = fit_iwan(list(data.small), list(data.large), order=order, backend=backend, seed=seed,
                          **free_options)
    if options.get("valid_range") is not None and "start" not in options:
        low, high = (float(v) for v in options["valid_range"])
        free = result.model
        if lowest_spring_stiffness(free.g1, free.g2, free.g3, low, high) >= 0.0:
            # the loops' own optimum keeps the spring stiff over the whole range: the barrier
            # is inactive there, so it is the constrained optimum too. Refitting from it only
            # wanders: the stages restart and land in other minima with the numpy CPU path
            # (truth "b" rope: 1.485 or 2.117 % small-loop error from a 1.476 % start)
            result = dataclasses.replace(result, settings=dataclasses.replace(result.settings,
                                                                              valid_range=(low, high)))
        else:
            result = fit_iwan(list(data.small), list(data.large), backend=backend, seed=seed, start=result.model,
                              **options)
            if order_table is not None:
                # the table shows the fit the model is (and the report's loop errors quote): the
                # chosen order's valid-range refit, beside the loops' own fits the rule compared
                refit = pd.DataFrame([iwan_order_row(result, order_table["smallest_loop_secant [N/m]"].iloc[0])])
                order_table = pd.concat([order_table.assign(recommended=False),
                                         refit.assign(fit=VALID_RANGE_FIT, recommended=True)], ignore_index=True)
    family_fits = {"plain": result}
    if family != "plain":
        plain_fits = {order: result} if order_table is None else {
            o: (result if o == order else fit) for o, fit in order_fits.items()}
        plain_result = result
        result, family_rows, modulated_result = choose_iwan_family(
            list(data.small), list(data.large), plain_fits, plain_order=order, family=family,
            valid_range=options.get("valid_range"),
            initial_state=options.get("initial_state", "auto"),
            floor_check=lambda fit: _above_the_noise_floor(fit, measurements, isolator, split))
        if family_rows is not None:
            secant = (order_table["smallest_loop_secant [N/m]"].iloc[0] if order_table is not None else
                      smallest_branch_secant(list(data.small) + list(data.large)))
            family_rows["smallest_loop_secant [N/m]"] = secant
            base = order_table if order_table is not None else pd.DataFrame(
                [iwan_order_row(plain_fits[order], secant)])
            order_table = pd.concat([base.assign(recommended=False), family_rows], ignore_index=True)
            chosen = (order_table["family"] == result.settings.family) & (order_table["order"] == result.model.order)
            if result.settings.family == "plain" and (order_table["fit"] == VALID_RANGE_FIT).any():
                chosen &= order_table["fit"] == VALID_RANGE_FIT  # the refit, not the loops' own fit of that order
            order_table["recommended"] = chosen
        order = result.model.order
        family_fits = {"plain": plain_result, **({"modulated": modulated_result} if modulated_result else {})}
    damping, damping_note = None, ""
    if damping_level is not None:
        try:
            sweeps, _ = select_measurements(measurements, kind="stepped_sine", isolator=isolator, split=split)
        except DataError:
            sweeps = []
        if sweeps:
            try:
                damping = fit_viscous_damping(result.model, sweeps, level=damping_level)
            except FitError as problem:  # e.g. no resonance inside the sweep: keep c_visc = 0 and say why
                damping_note = f"c_visc = 0: not identified from the stepped-sine data ({problem})"
    return MeasurementFit(kind="iwan", result=result, data=data, provenance=data.provenance,
                          options={"small_threshold": data.threshold, "small_threshold_given": small_threshold is not None,
                                   "points_per_set": points_per_set,
                                   "order": order, "family": result.settings.family,
                                   "family_rule": family, "backend": backend, "damping_level": damping_level,
                                   "remove_offsets": remove_offsets, "single_amplitude": data.single_amplitude,
                                   "offset_corrections": [c.to_dict() for c in data.offset_corrections], **options},
                          damping=damping, damping_note=damping_note, order_table=order_table,
                          family_fits=family_fits,
                          checks=_valid_over_the_data(result.model, measurements, isolator)
                          + _damping_settled(damping)
                          + _survives_the_largest_drops(damping.model(result.model) if damping else result.model,
                                                        measurements, isolator)
                          + _survives_the_largest_sweep_level(damping.model(result.model) if damping
                                                              else result.model, measurements, isolator)
                          + _above_the_noise_floor(result, measurements, isolator, split))


def _damping_settled(damping: ViscousDamping | None) -> tuple[str, ...]:
    """A viscous damping matched to a simulated peak that never reached steady state is not an
    identification: its runs were cut at the period limit, so the peak compared was a transient's."""
    if damping is None or not damping.unsettled_points:
        return ()
    return (f"c_visc = {damping.c_visc:.4g} N s/m: {damping.unsettled_points} of {damping.points} simulated "
            f"stepped-sine points of level {damping.level:g} did not reach steady state with it, so the resonance "
            "peak it was matched on is a transient's; the viscous damping is not identified by these sweeps",)


#: ``fit`` column of an Iwan order-table row that is the valid-range refit of the chosen order
#: (the other rows: ``"loops"``, the loops' own fits the order rule compares).
VALID_RANGE_FIT = "valid-range refit"

#: The default valid range of an Iwan fit reaches this far beyond the data set's deflections.
VALID_RANGE_MARGIN = 1.25


def _deflection_extent(measurements, isolator: str | None) -> tuple[float, float] | None:
    """Lowest and highest finite deflection (m) of every record of ``isolator`` (None: every
    record), or None when no record has one."""
    records = getattr(measurements, "measurements", measurements)
    seen = [np.asarray(m.deflection, dtype=float) for m in records
            if getattr(m, "deflection", None) is not None
            and (isolator is None or getattr(getattr(m, "info", None), "isolator", None) == isolator)]
    seen = [d[np.isfinite(d)] for d in seen]
    seen = [d for d in seen if d.size]
    if not seen:
        return None
    return min(float(d.min()) for d in seen), max(float(d.max()) for d in seen)


def data_valid_range(measurements, *, isolator: str | None = None,
                     margin: float = VALID_RANGE_MARGIN) -> tuple[float, float]:
    """``margin`` times the lowest and highest deflection (m) of every record of the isolator.

    Loops, sweeps and drops of every split count: drops compress far beyond the quasi-static
    loops, and an identified spring must stay valid wherever the data set will be simulated.
    The range always straddles zero (a side the data do not reach is ``-1e-3`` times the
    other side's reach). NaN deflections are ignored.

    Raises
    ------
    DataError
        No record of the isolator has a finite deflection.
    """
    extent = _deflection_extent(measurements, isolator)
    if extent is None:
        raise DataError(Message(f"valid range: found no record of isolator {isolator!r} with a finite deflection, "
                                "expected at least one (pass ", Suggestion("valid_range", None), " or ",
                                Suggestion("valid_range", "(x_min, x_max)", placeholder=True), ")"))
    low = margin * min(0.0, extent[0])
    high = margin * max(0.0, extent[1])
    if low == 0.0:
        low = -1e-3 * high
    if high == 0.0:
        high = -1e-3 * low
    return low, high


#: Model families of :func:`fit_iwan_measurements` (``family=``).
IWAN_FAMILIES = ("auto", "plain", "modulated")


def choose_iwan_family(small, large, plain_fits: dict, *, plain_order: int | None = None, family: str = "auto",
                       valid_range=None, initial_state: str = "auto", floor_check=lambda fit: ()):
    """The family rule: plain or slip-modulated Iwan model (docs/fitting.md, "Model family").

    Parameters
    ----------
    small, large : sequence of LoopSet
        The loop sets the plain fits saw.
    plain_fits : dict
        Order -> plain :class:`~idkit.fit.IwanFitResult` (``order="auto"``: every order of the
        table; a given order: that order alone).
    plain_order : int, optional
        The order the plain order rule chose (default: the lowest in ``plain_fits``).
    family : {"auto", "modulated"}
    valid_range : (float, float), optional
        Passed to the modulation stage (its valid-range barrier).
    initial_state : {"auto", "cycled", "virgin"}
    floor_check : callable
        ``floor_check(fit) -> tuple of str``: why a fit's loop errors are more than
        :data:`FLOOR_MARGIN` above the records' noise floor (empty when they are not).

    Returns
    -------
    (IwanFitResult, pandas.DataFrame or None, IwanFitResult or None)
        The chosen fit (``settings.family`` says which), one order-table row per modulated fit
        (``family="modulated"``) and the modulated fit of the modulated order rule (both None
        when the modulation stage did not run).

    Notes
    -----
    With ``"auto"`` a plain fit that passes ``floor_check`` and whose parameters the data
    determine (no group in :attr:`~idkit.fit.IwanFitResult.undetermined`) is kept as it is: the
    plain model explains the loops down to the noise margin and the modulation could only fit
    noise. Else the modulation stage (:func:`idkit.fit.fit_iwan_modulated`, three parameters
    more) runs from the lowest plain fit given and adds elements by continuation in the order
    (:func:`idkit.fit.iwan_modulated.fit_modulated_orders`: each order starts from the one below
    with an element split in two), and the modulated order is the lowest successful one that
    passes ``floor_check`` with every parameter determined
    (elements are added until the model explains the loops to within the margin, and no
    further: the higher orders are not fitted, so the table's modulated rows stop there); when
    none does, the order rule of the table (:data:`~idkit.fit.compare.ORDER_RULE_FACTOR`: the
    lowest successful order within 1.1 x the best mean of small and large error). ``"auto"``
    keeps the modulated fit when it succeeds and either its mean error is below the plain
    fit's divided by that factor (the modulation parameters must earn their place as an
    element's two do), or the plain fit leaves a combination of parameters undetermined while
    the modulated one, within the floor margin, determines every parameter (a plain fit that
    trades g1 against an element slipping only at the tips of the largest loops moves by tens
    of percent when the data move by one ulp); ``"modulated"`` keeps it in any case, its
    reasons saying what is wrong.
    """
    from idkit.fit.iwan_modulated import fit_modulated_orders

    orders = sorted(plain_fits)
    plain = plain_fits[orders[0] if plain_order is None else plain_order]
    plain_undetermined = bool(plain.undetermined)
    misses_the_loops = bool(floor_check(plain)) or any(reason.startswith(MODEL_FORM_PREFIX) for reason in plain.reasons)
    if family == "auto" and not misses_the_loops and not plain_undetermined:
        return plain, None, None

    judged: dict = {}  # order -> (IwanFitResult, accepted), each link judged once

    def accept(modulated) -> bool:  # a determined, successful fit within the floor margin
        order = modulated.model.order
        if order not in judged:
            settings = plain_fits.get(order, plain).settings
            fit = modulated.to_iwan_result(settings if modulated.plain is None else None)
            judged[order] = (fit, fit.success and not floor_check(fit) and not fit.undetermined)
        return judged[order][1]

    # upwards by continuation in the order (fit_modulated_orders), from the lowest plain fit,
    # stopping at the first determined order that reaches the floor margin
    chain = fit_modulated_orders(list(small), list(large), plain_fits[orders[0]], max_order=orders[-1],
                                 points_per_set=None, valid_range=valid_range, initial_state=initial_state,
                                 accept=accept)
    within = [order for order, modulated in chain.items() if accept(modulated)][:1]  # judges the last link too
    fits = {order: judged[order][0] for order in chain}
    rows = pd.DataFrame([iwan_order_row(fit, math.nan) for fit in fits.values()])
    chosen = fits[within[0] if within else _order_rule(rows)]
    mean = 0.5 * (chosen.error_small + chosen.error_large)
    plain_mean = 0.5 * (plain.error_small + plain.error_large)
    from idkit.fit.compare import ORDER_RULE_FACTOR

    determines_more = plain_undetermined and bool(within)
    if family == "modulated" or (chosen.success and (mean * ORDER_RULE_FACTOR <= plain_mean or determines_more)):
        return chosen, rows, chosen
    return plain, rows, chosen


def _order_rule(table: pd.DataFrame) -> int:
    from idkit.fit.compare import _rule

    return _rule(table, 0.5 * (table["error_small_percent"] + table["error_large_percent"]))


def _survives_the_largest_drops(model, measurements, isolator) -> tuple[str, ...]:
    """A reason if the model cannot simulate the data set's most severe drop.

    For every top mass among the isolator's drop records, the highest drop is simulated
    as the drop validation does (conditioned free fall at ``sqrt(2 g h)``, 0.3 s at 20 us);
    a run the simulator flags (negative spring stiffness, Newton failure, non-finite state)
    means the model cannot predict a test the data set holds.
    """
    from idkit.models import SDOFSystem
    from idkit.simulate import free_fall

    records = getattr(measurements, "measurements", measurements)
    highest: dict[float, float] = {}
    for m in records:
        info = getattr(m, "info", None)
        if (getattr(m, "kind", None) != "drop" or info is None or info.drop_height_m is None
                or info.top_mass_kg is None or (isolator is not None and info.isolator != isolator)):
            continue
        highest[info.top_mass_kg] = max(highest.get(info.top_mass_kg, 0.0), float(info.drop_height_m))
    reasons = []
    for mass, height in sorted(highest.items()):
        run = free_fall(SDOFSystem(mass, model), drop_height=[height], duration=0.3, time_step=2e-5)
        if run.reasons[0] != "ok":
            reasons.append(f"the model cannot simulate the data set's highest drop ({height:g} m on {mass:g} kg): "
                           f"{run.reasons[0]}")
    return tuple(reasons)




def loop_noise_floor(records) -> dict:
    """Relative force noise of each quasi-static record: ``noise_level(force) / rms(force)``.

    :func:`idkit.signal.cycles.noise_level` (second differences, median-based) is the white
    sensor noise on the force; a model that were exactly right would score about this under
    the objective (7.1). Offsets and drift between repetitions are not in it, so it is a lower
    bound of the floor (the generating law of the bundled rope scores 0.2-0.7 % where this
    reads 0.04-0.1 %), and :data:`FLOOR_MARGIN` is measured from it.
    """
    floors = {}
    for index, record in enumerate(records, start=1):
        force = np.asarray(record.force, dtype=float)
        rms = float(np.sqrt(np.mean(force**2)))
        floors[record.id or f"record{index}"] = noise_level(force) / rms if rms > 0 else math.nan
    return floors


def _above_the_noise_floor(result, measurements, isolator, split) -> tuple[str, ...]:
    """A reason per loop group whose mean error exceeds its noise floor by more than
    :data:`FLOOR_MARGIN`; the group's floor is the largest over its records (repetitions). A
    group the fit's own check (:mod:`idkit.fit.model_form`, the floor read off its residual)
    named already is not named again."""
    try:
        records, _ = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    except DataError:
        return ()
    floors = loop_noise_floor(records)
    family = getattr(getattr(result, "settings", None), "family", None)
    remedy = {"plain": "a higher order, --order-table, or the slip-modulated Iwan: --family, docs/fitting.md",
              "modulated": "a higher order: --order auto, --order-table, docs/fitting.md"}.get(
        family, "another model form, docs/fitting.md")
    reasons = []
    named = tuple(getattr(result, "reasons", ()) or ())
    for group, names, errors in (("small", result.small_names, result.small_errors),
                                 ("large", result.large_names, result.large_errors)):
        known = [floors[name] for name in names if name in floors and math.isfinite(floors[name])]
        if not known or any(reason.startswith(f"{MODEL_FORM_PREFIX} {group} loops") for reason in named):
            continue  # the fit's own model-form check named this group already
        floor, error = max(known), float(np.mean(errors))
        if error - floor > FLOOR_MARGIN:
            reasons.append(f"{group}-loop error {100 * error:.3g} % is {100 * (error - floor):.3g} points above the "
                           f"noise floor {100 * floor:.2g} % of its {len(known)} record(s) (limit "
                           f"{100 * FLOOR_MARGIN:g} points): the model form misses the loops ({remedy}), or the "
                           "records carry a force offset the floor does not count (--remove-offsets)")
    return tuple(reasons)


#: Periods of the short simulation at the data set's largest sweep level (enough for the
#: transient's largest excursion; steady state is the validation's business).
SWEEP_CHECK_PERIODS = 16


def _survives_the_largest_sweep_level(model, measurements, isolator) -> tuple[str, ...]:
    """A reason if the model cannot simulate the data set's largest stepped-sine level.

    Every stepped-sine record of the isolator at the largest nominal level (either split) is
    simulated from rest for :data:`SWEEP_CHECK_PERIODS` periods of a pure sine with the
    record's measured first-harmonic base amplitude, as the sweep validation drives it; a run
    the simulator flags (negative spring stiffness, Newton failure, non-finite state) means
    the model cannot predict a test the data set holds. Not settling is not a reason here.
    """
    from idkit.models import SDOFSystem
    from idkit.observe.stepped_sine import hosidf_from_stepped_sine
    from idkit.simulate import harmonic_response

    records = [m for m in getattr(measurements, "measurements", measurements)
               if getattr(m, "kind", None) == "stepped_sine" and m.info.top_mass_kg is not None
               and m.info.excitation is not None and m.info.excitation.amplitude is not None
               and (isolator is None or m.info.isolator == isolator)]
    if not records:
        return ()
    level = max(m.info.excitation.amplitude for m in records)
    reasons = []
    for mass in sorted({m.info.top_mass_kg for m in records}):
        points = [hosidf_from_stepped_sine(m) for m in records
                  if m.info.excitation.amplitude == level and m.info.top_mass_kg == mass]
        freq = np.array([p.freq for p in points])
        amplitude = np.array([p.result.input_amplitude for p in points]) / (2 * np.pi * freq)
        run = harmonic_response(SDOFSystem(mass, model), freq, amplitude, min_periods=SWEEP_CHECK_PERIODS,
                                max_periods=SWEEP_CHECK_PERIODS, workers=1)
        flagged = [(f, a, reason) for f, a, flag, reason in zip(freq, amplitude, run.flags, run.reasons) if flag]
        if flagged:
            f, a, reason = flagged[0]
            reasons.append(f"the model cannot simulate the data set's largest sweep level ({level:g} on {mass:g} kg): "
                           f"{len(flagged)} of {freq.size} points flagged, first at {f:g} Hz, base amplitude "
                           f"{1e3 * a:.3g} mm: {reason}")
    return tuple(reasons)


def _valid_over_the_data(model, measurements, isolator) -> tuple[str, ...]:
    """A reason if the model's spring turns negative-stiff inside the deflections of the whole set.

    Every record of the isolator counts (loops, sweeps and drops, either split): a model
    that cannot be simulated over its own data's range is not a successful identification.
    """
    extent = _deflection_extent(measurements, isolator)
    if extent is None:
        return ()
    low, high = extent
    lower, upper = model.valid_deflection_range()
    if lower <= low and high <= upper:
        return ()
    return (f"the fitted spring turns negative-stiff at {1e3 * lower:.4g} / {1e3 * upper:.4g} mm, inside the "
            f"deflections of the data set ({1e3 * low:.4g} to {1e3 * high:.4g} mm, every record of the isolator): "
            "the model cannot be simulated over its own data (fit with valid_range, idkit fit iwan --valid-range)",)


def fit_boucwen_measurements(
    measurements,
    *,
    small_threshold: float | None = None,
    isolator=ONLY_ISOLATOR,
    split: str | None = "fit",
    points_per_set: int | None = LOOP_POINTS_PER_SET,
    backend: str = "nlopt",
    seed: int = 0,
    remove_offsets: bool = False,
    **options,
) -> MeasurementFit:
    """Bouc-Wen fit (:func:`idkit.fit.fit_boucwen`) on the same loop sets as :func:`fit_iwan_measurements`.

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
    small_threshold, isolator, split, points_per_set, backend, seed, remove_offsets :
        As :func:`fit_iwan_measurements`.
    **options
        Passed to :func:`idkit.fit.fit_boucwen`.

    Returns
    -------
    MeasurementFit
        ``kind="boucwen"``; ``data`` the :class:`~idkit.observe.quasi_static.LoopData`.

    Raises
    ------
    FitError
        Bad records or options, only small or only large sets.
    DataError
        No quasi-static record matches the selection.
    """
    isolator = resolve_isolator(measurements, isolator, kind="quasi_static")
    data = loop_sets(measurements, small_threshold=small_threshold, isolator=isolator, split=split,
                     points_per_set=points_per_set, remove_offsets=remove_offsets)
    result = fit_boucwen(list(data.small), list(data.large), backend=backend, seed=seed, **options)
    return MeasurementFit(kind="boucwen", result=result, data=data, provenance=data.provenance,
                          options={"small_threshold": data.threshold, "small_threshold_given": small_threshold is not None,
                                   "points_per_set": points_per_set,
                                   "backend": backend, "remove_offsets": remove_offsets,
                                   "single_amplitude": data.single_amplitude,
                                   "offset_corrections": [c.to_dict() for c in data.offset_corrections], **options},
                          checks=_above_the_noise_floor(result, measurements, isolator, split))


@dataclass(frozen=True)
class ElastomerData:
    """The elastomer's observables for a Maxwell fit, selected once from a measurement set.

    Iterating over it (and ``len``) gives the transmissibility sets, as a plain tuple of
    :class:`~idkit.observe.white_noise.TransmissibilitySet` would.

    Attributes
    ----------
    frfs : tuple of TransmissibilitySet
        One H1 per white-noise run (:func:`~idkit.observe.white_noise.transmissibility_sets`).
    k0 : float
        Static stiffness used, N/m.
    k0_stderr : float or None
        Its standard uncertainty (N/m) when estimated from the loops, None when given.
    k0_estimate : K0FromLoops or None
        The estimate from the quasi-static loops (None when ``k0`` was given).
    loops : tuple of QuasiStaticMeasurement
        The quasi-static records of the estimate (empty when ``k0`` was given).
    provenance : DataProvenance
        Every record used: the loops (when they gave k0) then the white-noise runs.
    repetitions : tuple of int
        Repetition number of each FRF (``info.repetition``, else its 1-based position).
    operating_points : dict
        Top mass (kg) -> :class:`~idkit.observe.quasi_static.StaticOperatingPoint` under its
        weight on the loops (None where the loops do not reach it; empty when ``k0`` was
        given). Each FRF carries that point's tangent stiffness as ``static_stiffness``.
    """

    frfs: tuple[TransmissibilitySet, ...]
    k0: float
    k0_stderr: float | None
    k0_estimate: K0FromLoops | None
    loops: tuple[QuasiStaticMeasurement, ...]
    provenance: DataProvenance
    repetitions: tuple[int, ...]
    operating_points: dict = field(default_factory=dict)

    def static_stiffness(self, top_mass_kg: float) -> float | None:
        """Tangent static stiffness (N/m) under ``top_mass_kg`` on the loops, None when unknown."""
        point = self.operating_points.get(top_mass_kg)
        if point is None and self.loops and top_mass_kg not in self.operating_points:
            point = static_operating_point(self.loops, top_mass_kg * STANDARD_GRAVITY, window=self.k0_window)
        return None if point is None else point.stiffness

    @property
    def k0_window(self) -> float:
        return self.k0_estimate.window if self.k0_estimate is not None else 1e-3

    def __iter__(self):
        return iter(self.frfs)

    def __len__(self) -> int:
        return len(self.frfs)


def elastomer_data(
    measurements,
    *,
    k0: float | None = None,
    k0_window: float = 1e-3,
    isolator=ONLY_ISOLATOR,
    split: str | None = "fit",
    band=(1.0, 100.0),
    resolution_hz: float = FRF_RESOLUTION_HZ,
    k0_method: str = "relaxation",
) -> ElastomerData:
    """Select the elastomer's records once and turn them into the Maxwell fit's observables.

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
        Selected by :func:`idkit.io.selection.select_measurements`.
    k0 : float, optional
        Static stiffness in N/m; default from the quasi-static loops
        (:func:`~idkit.observe.quasi_static.k0_from_records`, window ``k0_window``).
    k0_window : float, default 1e-3
        Half-width (m) of the deflection window of the k0 estimate.
    k0_method : {"relaxation", "secant"}, default "relaxation"
        ``"relaxation"``: the loops' time history fitted with the relaxation of elements that
        have not relaxed at the zero crossings (:func:`idkit.fit.static_stiffness.k0_with_relaxation`);
        ``"secant"``: the slope of the loops around zero
        (:func:`~idkit.observe.quasi_static.k0_from_records`), biased high by such elements.
    isolator : str or None, default: the only isolator with white-noise records
        As :func:`fit_iwan_measurements`, among the isolators with white-noise runs.
    split : {"fit", "validation", "all", None}, default "fit"
    band : (float, float), default (1, 100)
        Band of the H1 estimates, Hz.
    resolution_hz : float, default 0.5
        Frequency step of the H1 estimates (:func:`~idkit.observe.white_noise.frf_from_white_noise`).

    Returns
    -------
    ElastomerData

    Raises
    ------
    DataError
        No white-noise run (or, without ``k0``, no quasi-static record) matches.
    FitError
        A run without a top mass, an unusable FRF, a k0 estimate that fails.
    """
    isolator = resolve_isolator(measurements, isolator, kind="white_noise")
    frfs, provenance = transmissibility_sets(measurements, isolator=isolator, split=split, band=band,
                                             resolution_hz=resolution_hz)
    records, _ = select_measurements(measurements, kind="white_noise", isolator=isolator, split=split)
    repetitions = tuple(r.info.repetition if r.info.repetition is not None else i
                        for i, r in enumerate(records, start=1))
    loops, estimate, stderr = (), None, None
    if k0 is None:
        loops, loops_provenance = select_measurements(measurements, kind="quasi_static", isolator=isolator,
                                                      split=split)
        if k0_method not in K0_METHODS:
            raise FitError(f"k0_method: found {k0_method!r}, expected one of {K0_METHODS}")
        estimate = (k0_with_relaxation(loops, window=k0_window) if k0_method == "relaxation"
                    else k0_from_records(loops, window=k0_window))
        k0, stderr = estimate.k0, estimate.stderr
        provenance = loops_provenance.merged(provenance, kind="quasi_static (k0) + white_noise")
    # each top mass's weight preloads the isolator: small-amplitude motion about that preload
    # sees the loops' tangent stiffness there (a softening elastomer: lower than k0)
    points = {mass: static_operating_point(loops, mass * STANDARD_GRAVITY, window=k0_window)
              for mass in sorted({item.mass for item in frfs})} if loops else {}
    frfs = [dataclasses.replace(item, static_stiffness=None if points.get(item.mass) is None
                                else points[item.mass].stiffness) for item in frfs]
    return ElastomerData(frfs=tuple(frfs), k0=float(k0), k0_stderr=stderr, k0_estimate=estimate, loops=tuple(loops),
                         provenance=provenance, repetitions=repetitions, operating_points=points)


#: Largest peak loss of a measured resonance through the H1 estimator's Hann window
#: (:func:`idkit.signal.frf.window_peak_bias`) for a Maxwell fit to be trusted near resonance.
#: 10 %: the damping read from such a peak is then about 10 % high, a quarter of the FRF
#: validation's 3 dB damping limit.
WINDOW_BIAS_LIMIT = 0.10


def _resolution_checks(frfs, model=None) -> tuple[str, ...]:
    """A check when an H1 cannot resolve its resonance: the window's bandwidth against the
    resonance's half-power width (the fit compares exact model curves with biased peaks).

    The width is the narrower of the one read off the measured H1 and, given ``model`` (the fitted
    isolator), the one of its exact transmissibility about the set's preload on a grid 20 times
    finer than the H1's, when its resonance lies inside the set's band: the window widens the
    measured peak (the bias read off it is low), and a peak whose half-power point lies outside the
    band gives no measured width at all (the generated set B2's 6.4 kg run: 1 Hz lines, peak at
    1.6 Hz, the lower half-power point below 1 Hz; skipped before).
    """
    worst = None
    for item in frfs:
        step = float(np.median(np.diff(item.freq)))
        widths = []
        resonance, zeta = half_power_damping(item.freq, np.abs(item.transmissibility))
        if math.isfinite(zeta) and zeta > 0:
            widths.append((2.0 * zeta * resonance, "read off the H1"))
        if model is not None:
            local = preloaded(model, item.static_stiffness)
            low, high = float(np.min(item.freq)), float(np.max(item.freq))
            grid = np.arange(low / 4.0, high, step / 20.0)
            curve = np.abs(sdof_transmissibility(local.complex_stiffness(grid), item.mass + local.m_eff,
                                                 2 * np.pi * grid))
            resonance, zeta = half_power_damping(grid, curve)
            if low <= resonance <= high and math.isfinite(zeta) and zeta > 0:
                widths.append((2.0 * zeta * resonance, "of the fitted model's exact curve"))
        if not widths:
            continue
        width, source = min(widths)
        bias = window_peak_bias(step, width)
        if worst is None or bias > worst[0]:
            worst = (bias, item.name, step, width, source)
    if worst is None or worst[0] <= WINDOW_BIAS_LIMIT:
        return ()
    bias, name, step, width, source = worst
    loss = (f"loses about {100 * bias:.0f} % of the peak" if bias < 1.0
            else "cannot hold the peak (first-order loss above 100 %)")
    return (f"the H1 of {name} cannot resolve its resonance: a {step:g} Hz step (window bandwidth "
            f"{HANN_ENBW_BINS * step:g} Hz) against a half-power width of {width:.3g} Hz ({source}) {loss} "
            f"(limit {100 * WINDOW_BIAS_LIMIT:g} %), so the damping near resonance is biased; longer white-noise "
            "records (a finer resolution_hz) resolve it",)


def fit_maxwell_measurements(
    measurements,
    *,
    order: int | str = "auto",
    k0: float | None = None,
    k0_window: float = 1e-3,
    isolator=ONLY_ISOLATOR,
    split: str | None = "fit",
    band=(1.0, 100.0),
    resolution_hz: float = FRF_RESOLUTION_HZ,
    backend: str = "nlopt",
    cross_check: bool = False,
    seed: int = 0,
    k0_method: str = "relaxation",
    **options,
) -> MeasurementFit:
    """Generalized Maxwell fit: k0 from the quasi-static loops, the rest from all white-noise FRFs.

    The records are selected once into an :class:`ElastomerData` (:func:`elastomer_data`)
    handed to :func:`idkit.fit.fit_maxwell`; the uncertainty of a k0 read off the loops is
    the fixed ``k0`` parameter's stderr (``fit_maxwell(k0_stderr=...)``).

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
    order : int or "auto", default "auto"
        Number of Maxwell elements, or ``"auto"``: orders 1-4 are fitted
        (:func:`idkit.fit.maxwell_order_table`, same band, backend and seed) and the one
        its order rule recommends is kept; the table is in ``fit.order_table``.
    k0 : float, optional
        Static stiffness in N/m; default from the loops (window ``k0_window``, m).
    k0_window : float, default 1e-3
    k0_method : {"relaxation", "secant"}, default "relaxation"
        How k0 is read off the loops (:func:`elastomer_data`).
    isolator, split : as :func:`elastomer_data` (default the only isolator with white-noise runs, ``"fit"``)
    band : (float, float), default (1, 100) Hz
    resolution_hz : float, default 0.5
        Frequency step of the H1 estimates, Hz.
    backend, cross_check, seed, options
        Passed to :func:`idkit.fit.fit_maxwell`.

    Returns
    -------
    MeasurementFit
        ``kind="maxwell"``; ``data`` is the :class:`ElastomerData`, ``k0`` its
        :class:`~idkit.observe.quasi_static.K0FromLoops` (None when ``k0`` was given).
    """
    isolator = resolve_isolator(measurements, isolator, kind="white_noise")
    data = elastomer_data(measurements, k0=k0, k0_window=k0_window, isolator=isolator, split=split, band=band,
                          resolution_hz=resolution_hz, k0_method=k0_method)
    order_table = None
    if order == "auto":
        from idkit.fit.compare import maxwell_order_table

        order_table = maxwell_order_table(list(data.frfs), k0=data.k0, band=band, backend=backend, seed=seed,
                                          **options)
        order = int(order_table.loc[order_table["recommended"], "order"].iloc[0])
    elif isinstance(order, str) or not (isinstance(order, (int, np.integer)) and order >= 1):
        raise FitError(f"order: found {order!r}, expected an integer >= 1 or 'auto'")
    result = fit_maxwell(list(data.frfs), k0=data.k0, k0_stderr=data.k0_stderr, order=int(order), band=band,
                         backend=backend, cross_check=cross_check, seed=seed, **options)
    return MeasurementFit(kind="maxwell", result=result, data=data, provenance=data.provenance, k0=data.k0_estimate,
                          checks=_resolution_checks(data.frfs, result.model),
                          options={"order": int(order), "order_rule": order_table is not None, "k0_window": k0_window,
                                   "k0_method": k0_method if k0 is None else "given",
                                   "resolution_hz": resolution_hz, "band": list(band), "backend": backend,
                                   "cross_check": cross_check, **options},
                          repetitions=data.repetitions, order_table=order_table)
