"""Measurement-level fitting: measurement sets in, identified model with provenance out.

The array-level fitters (:func:`~idkit.fit.fit_iwan`, :func:`~idkit.fit.fit_maxwell`,
:func:`~idkit.fit.fit_boucwen`) take loops and transmissibilities; the fits here pick the right
measurements of a :class:`~idkit.io.MeasurementSet` (kind, isolator, split), turn them into
those inputs through :mod:`idkit.observe` and keep where they came from:

* :func:`fit_iwan_measurements`, :func:`fit_boucwen_measurements` - loop fits on
  :func:`~idkit.observe.quasi_static.loop_sets` (small and large loop sets,
  :class:`~idkit.observe.quasi_static.LoopData`); the Iwan fit also chooses its order
  (:mod:`idkit.fit.orders`) and family (:mod:`idkit.fit.family`) and identifies the viscous
  damping from stepped-sine data (:func:`~idkit.fit.fit_viscous_damping`);
* :func:`fit_maxwell_measurements` - the Maxwell fit on the elastomer's observables, selected once
  (:func:`~idkit.fit.elastomer_data.elastomer_data`).

Each returns a :class:`~idkit.fit.measurement_fit.MeasurementFit`, restricted to ``split="fit"``
by default, whose ``checks`` hold the measurement-level problems: the data set's reach
(:mod:`idkit.fit.data_set_checks`), the loops' noise floor (:mod:`idkit.fit.model_form`) and the
H1 resolution (:mod:`idkit.fit.frf_resolution`).
"""

from __future__ import annotations

import dataclasses

import pandas as pd

from idkit.checks import Choice, Either, accepts
from idkit.errors import DataError, FitError
from idkit.fit.boucwen import fit_boucwen
from idkit.fit.compare import iwan_order_fits, iwan_order_row, maxwell_order_table
from idkit.fit.damping import fit_viscous_damping
from idkit.fit.data_set_checks import (
    damping_settled,
    data_valid_range,
    survives_the_largest_drops,
    survives_the_largest_sweep_level,
    valid_over_the_data,
)
from idkit.fit.elastomer_data import elastomer_data
from idkit.fit.family import IWAN_FAMILIES, choose_iwan_family
from idkit.fit.frf_resolution import resolution_checks
from idkit.fit.iwan import IWAN_ORDER, fit_iwan
from idkit.fit.iwan_start import smallest_branch_secant
from idkit.fit.maxwell import ORDER, fit_maxwell
from idkit.fit.measurement_fit import MeasurementFit
from idkit.fit.model_form import record_floor_reasons
from idkit.io.selection import ONLY_ISOLATOR, resolve_isolator, select_measurements
from idkit.models.laws import lowest_spring_stiffness
from idkit.observe.quasi_static import LOOP_POINTS_PER_SET, loop_sets
from idkit.observe.white_noise import FRF_RESOLUTION_HZ

__all__ = ["fit_iwan_measurements", "fit_boucwen_measurements", "fit_maxwell_measurements", "VALID_RANGE_FIT"]

#: ``fit`` column of an Iwan order-table row that is the valid-range refit of the chosen order
#: (the other rows: ``"loops"``, the loops' own fits the order rule compares).
VALID_RANGE_FIT = "valid-range refit"



# small_threshold, backend: declared by loop_sets and fit_iwan
@accepts(order=Either((IWAN_ORDER, Choice(("auto",)))), family=Choice(IWAN_FAMILIES), error=FitError)
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
        :func:`idkit.fit.family.choose_iwan_family`): the plain model unless its loop error is more than
        :data:`~idkit.fit.model_form.FLOOR_MARGIN` above the records' noise floor or it leaves a combination of
        parameters undetermined, and the modulated model (orders by continuation,
        :func:`idkit.fit.iwan_modulated.fit_modulated_orders`) succeeds with a mean error lower
        by the order rule's factor or determines what the plain one left undetermined.
    **options
        Passed to :func:`idkit.fit.fit_iwan`. ``valid_range`` defaults to ``"data"``:
        :func:`~idkit.fit.data_set_checks.data_valid_range` of the isolator's records (loops, sweeps and drops, every
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
    # they are smooth functions of the data, while the barrier's penalty is not smooth and a
    # barrier fit from the loops' start estimate can land in different minima
    free_options = {key: value for key, value in options.items() if key != "valid_range"}
    if order == "auto":
        order_table, order_fits = iwan_order_fits(list(data.small), list(data.large), backend=backend, seed=seed,
                                                  **free_options)
        order = int(order_table.loc[order_table["recommended"], "order"].iloc[0])
        result = order_fits[order]  # the table's own fit of that order (same sets and options)
    else:
        result = fit_iwan(list(data.small), list(data.large), order=order, backend=backend, seed=seed,
                          **free_options)
    if options.get("valid_range") is not None and "start" not in options:
        low, high = (float(v) for v in options["valid_range"])
        free = result.model
        if lowest_spring_stiffness(free.g1, free.g2, free.g3, low, high) >= 0.0:
            # the loops' own optimum keeps the spring stiff over the whole range: the barrier
            # is inactive there, so it is the constrained optimum too; refitting from it would
            # only restart the stages, which can wander into other minima
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
                          options={**_loop_options(data, small_threshold, points_per_set, order=order,
                                                   family=result.settings.family, family_rule=family, backend=backend,
                                                   damping_level=damping_level, remove_offsets=remove_offsets),
                                   **options},
                          damping=damping, damping_note=damping_note, order_table=order_table,
                          family_fits=family_fits,
                          checks=valid_over_the_data(result.model, measurements, isolator)
                          + damping_settled(damping)
                          + survives_the_largest_drops(damping.model(result.model) if damping else result.model,
                                                       measurements, isolator)
                          + survives_the_largest_sweep_level(damping.model(result.model) if damping
                                                             else result.model, measurements, isolator)
                          + _above_the_noise_floor(result, measurements, isolator, split))


def _loop_options(data, small_threshold, points_per_set, **settings) -> dict:
    """The options a loop fit records in its provenance: the split of the loops, ``settings``, and
    what the data showed (one amplitude, offsets removed)."""
    return {"small_threshold": data.threshold, "small_threshold_given": small_threshold is not None,
            "points_per_set": points_per_set, **settings, "single_amplitude": data.single_amplitude,
            "offset_corrections": [c.to_dict() for c in data.offset_corrections]}


def _above_the_noise_floor(result, measurements, isolator, split) -> tuple[str, ...]:
    """:func:`~idkit.fit.model_form.record_floor_reasons` of a loop fit on the quasi-static records
    of its selection (none when the selection holds none)."""
    try:
        records, _ = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    except DataError:
        return ()
    return record_floor_reasons(result, records)


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
                          options={**_loop_options(data, small_threshold, points_per_set, backend=backend,
                                                   remove_offsets=remove_offsets), **options},
                          checks=_above_the_noise_floor(result, measurements, isolator, split))


@accepts(order=Either((ORDER, Choice(("auto",)))), error=FitError)
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
        :class:`~idkit.observe.k0.K0FromLoops` (None when ``k0`` was given).
    """
    isolator = resolve_isolator(measurements, isolator, kind="white_noise")
    data = elastomer_data(measurements, k0=k0, k0_window=k0_window, isolator=isolator, split=split, band=band,
                          resolution_hz=resolution_hz, k0_method=k0_method)
    order_table = None
    if order == "auto":
        order_table = maxwell_order_table(list(data.frfs), k0=data.k0, band=band, backend=backend, seed=seed,
                                          **options)
        order = int(order_table.loc[order_table["recommended"], "order"].iloc[0])
    result = fit_maxwell(list(data.frfs), k0=data.k0, k0_stderr=data.k0_stderr, order=order, band=band,
                         backend=backend, cross_check=cross_check, seed=seed, **options)
    return MeasurementFit(kind="maxwell", result=result, data=data, provenance=data.provenance, k0=data.k0_estimate,
                          checks=resolution_checks(data.frfs, result.model),
                          options={"order": int(order), "order_rule": order_table is not None, "k0_window": k0_window,
                                   "k0_method": k0_method if k0 is None else "given",
                                   "resolution_hz": resolution_hz, "band": list(band), "backend": backend,
                                   "cross_check": cross_check, **options},
                          repetitions=data.repetitions, order_table=order_table)
