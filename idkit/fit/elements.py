"""Identification of the physical elements of docs/elements.md from force records of any deflection history.

* :func:`fit_clearance_jenkin` - a Jenkin element acting through a clearance
  (:class:`~idkit.models.ClearanceIwanModel` of order 1): ``gap``, ``k_1``, ``fc_1`` and a
  parallel spring ``g1``;
* :func:`fit_pinched_boucwen` - the pinched Bouc-Wen model
  (:class:`~idkit.models.PinchedBoucWenModel`): ``k1``, ``alpha``, the saturated force
  ``saturated_force``, ``beta_share``, ``n``, ``pinch``, ``pinch_width``, ``pinch_shift`` (the
  model's ``beta`` and ``gamma`` computed from them);
* :func:`fit_rate_dependent_jenkin` - a Jenkin element whose slip force rises with speed
  (:class:`~idkit.models.RateDependentIwanModel` of order 1): ``k_1``, ``fc_1``,
  ``slip_rate_gain``, ``slip_speed`` and ``g1``.

Each takes ``histories``: a sequence of records with attributes ``name`` (str), ``time`` (s),
``deflection`` (m) and ``force`` (N), the deflection any history (sinusoids, random, earthquake
records). The model is evaluated along each record from the unloaded state at its first sample
(rate-independent elements from the deflection alone, the rate-dependent one with the rate
``dx/dt`` of each sample step); a record that begins loaded and ends where it began (a periodic
test cut at any phase) is evaluated from its cycled state instead (``initial_state``). The
objective is the sum over records of the squared force
error, each record divided by its RMS force and the square root of its length (every record
weighs alike, whatever its length and force level); it is minimised by scipy's bounded
trust-region least squares from a few starts (or from ``start=``, a previous result of the same
family: warm starting, e.g. the folds of a cross-validation); records longer than
:data:`SEARCH_SAMPLES` are thinned for the starts' search and the best start is polished on the
full records.

Standard errors come from the Jacobian of the residuals at the optimum with one noise variance
per record (:func:`idkit.fit._params.jacobian_statistics`), mapped to the model's parameters
by the chain rule. Verdict (``success``, ``reasons``), the rule every idkit fitter follows
(:func:`idkit.fit.result.determinacy_reasons`): not a success when the least squares did not
converge, when a parameter ends on a search bound, or when a varied parameter is not determined
by the data (no standard error, a positive parameter whose 95 % interval reaches zero, or
parameters determined only in combination; ``undetermined`` names them), or when the records'
mean error is more than 2 points above their noise floor read off the residual (the model-form
rule of :mod:`idkit.fit.model_form`: the element misses the records). A parallel
stiffness (``g1``, ``k1``) found at zero is not a failure: it is fixed at 0 (the element alone
explains the data) and said so in ``notes``.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from idkit.checks import Choice, Flag, Seed, Whole, accepts
from idkit.errors import FitError, IdkitError
from idkit.fit._params import jacobian_statistics, to_lmfit
from idkit.fit.model_form import (FLOOR_MARGIN, MODEL_FORM_PREFIX, REPEAT_TOLERANCE, ModelFormReason, misses_the_floor,
                                  residual_floor)
from idkit.fit.result import _interval_reaches_zero, determinacy_reasons, undetermined_groups
from idkit.models import ClearanceIwanModel, IwanModel, PinchedBoucWenModel, RateDependentIwanModel
from idkit.models.base import IsolatorModel
from idkit.observe.quasi_static import UNLOADED_FRACTION
from idkit.signal.cycles import noise_level

__all__ = ["ElementFitResult", "ElementHistory", "fit_clearance_jenkin", "fit_jenkin", "fit_pinched_boucwen",
           "fit_rate_dependent_jenkin", "ELEMENT_FITTERS", "SEARCH_SAMPLES", "PINCHED_PARAMETERS"]

#: Residual value of a record sample where the model cannot be evaluated (parameters outside the
#: model's domain, a non-finite force): large against the normalised residuals (order 1).
_PENALTY_RESIDUAL = 1e3
#: A parameter within this share of its search interval from a bound is "on its bound".
_BOUND_MARGIN = 1e-4
#: Samples per record the starts search on (longer records are thinned for the search, then the
#: best start is polished on the full records): the search costs the same for any record length,
#: the polish a few iterations of the full records (figures in docs/elements.md).
SEARCH_SAMPLES = 1000


@dataclass(frozen=True)
class ElementHistory:
    """One force record: ``name``, sample ``time`` (s), ``deflection`` (m, tension positive), ``force`` (N)."""

    name: str
    time: np.ndarray
    deflection: np.ndarray
    force: np.ndarray


@dataclass(frozen=True)
class ElementFitResult:
    """Result of an element fit.

    Attributes
    ----------
    family : str
        ``"clearance_jenkin"``, ``"pinched_boucwen"`` or ``"rate_dependent_jenkin"``.
    model : IsolatorModel
        The fitted model (``model.force(deflection, time=time)`` in N; a model-file kind).
    params : dict of str to float
        Every model parameter (SI units, as the model declares them).
    stderr : dict of str to float
        Standard error of every varied parameter (NaN where the data do not give one).
    varied : list of str
        The parameters the fit varied (``n_params`` of them); the others were held.
    undetermined : list of str
        Varied parameters the data do not determine (docs in the module).
    reasons : list of str
        Why the fit is not a success (empty when it is).
    notes : list of str
        What the fitter decided on its own (a parallel stiffness fixed at 0).
    errors : dict of str to float
        Normalised RMS force error of each record, ``rms(F_model - F) / rms(F)``.
    evaluations : int
        Residual evaluations of the least squares, all starts.
    elapsed_s : float
        Wall time of the fit in s.
    start_states : dict of str to str
        ``"unloaded"`` or ``"cycled"``: the state each record was evaluated from.
    """

    family: str
    model: IsolatorModel
    params: dict
    stderr: dict
    varied: list
    undetermined: list
    reasons: list
    notes: list
    errors: dict
    evaluations: int
    elapsed_s: float
    internal: np.ndarray = field(repr=False)
    start_states: dict = field(default_factory=dict)
    #: unit of every parameter in :attr:`params`
    units: dict = field(default_factory=dict)
    #: model parameters computed from the varied ones (the pinched Bouc-Wen's ``beta``, ``gamma``)
    computed: tuple = ()

    @property
    def success(self) -> bool:
        """True when :attr:`reasons` is empty."""
        return not self.reasons

    @property
    def n_params(self) -> int:
        """Number of varied parameters."""
        return len(self.varied)

    @property
    def error(self) -> float:
        """Mean of the records' normalised RMS force errors."""
        return float(np.mean(list(self.errors.values())))

    def report(self) -> str:
        """Text for people: verdict, parameters with standard errors, errors per record."""
        lines = [f"{self.family} fit: {'success' if self.success else 'NOT a success'} "
                 f"({self.n_params} parameters, {self.evaluations} evaluations, {self.elapsed_s:.2f} s)"]
        for name, value in self.params.items():
            error = self.stderr.get(name)
            shown = f" +- {error:.3g}" if error is not None and math.isfinite(error) else ""
            state = "" if name in self.varied else "  (from the fitted)" if name in self.computed else "  (held)"
            lines.append(f"  {name:<15} {value:12.6g}{shown} {self.units.get(name, '')}{state}")
        lines += [f"  error {name}: {100 * value:.2f} %" for name, value in self.errors.items()]
        lines += [f"  note: {note}" for note in self.notes]
        lines += [f"  reason: {reason}" for reason in self.reasons]
        return "\n".join(lines)


@dataclass(frozen=True)
class _Family:
    """How one family maps an internal vector to a model, and where it searches."""

    name: str
    internal_names: tuple
    lower: np.ndarray
    upper: np.ndarray
    build: Callable  # internal vector -> model (may raise IdkitError)
    #: the model parameters the internal vector sets, one per internal coordinate (the map between
    #: them need not be diagonal: the pinched Bouc-Wen's beta and gamma come from alpha, z_u, share, n)
    varied: tuple
    needs_time: bool
    #: internal index of a parallel stiffness that is fixed at 0 when the fit puts it there
    parallel_index: int | None = None
    #: derived parameters reported and judged beside the model's own: name -> (unit, lower bound,
    #: meaning, value of a model); ``varied`` may name them (the pinched Bouc-Wen's ``z_u``)
    derived: dict = field(default_factory=dict)
    #: model parameters that are functions of the varied ones (reported, not judged)
    computed: tuple = ()

    def parameters(self, model) -> dict:
        """The model's parameters and the family's derived ones, by name (SI units)."""
        return {**model.params(), **{name: float(spec[3](model)) for name, spec in self.derived.items()}}

    def units(self, model) -> dict:
        return {**{spec.name: spec.unit for spec in model.param_specs()},
                **{name: spec[0] for name, spec in self.derived.items()}}


def _checked_histories(histories) -> list[ElementHistory]:
    """The records as float arrays, each checked once here (the public boundary)."""
    if isinstance(histories, (str, bytes)) or not isinstance(histories, Sequence) or len(histories) == 0:
        raise FitError(f"histories: found {type(histories).__name__}, expected a non-empty sequence of records "
                       "with name, time [s], deflection [m] and force [N]")
    checked, names = [], set()
    for index, record in enumerate(histories):
        missing = [key for key in ("name", "time", "deflection", "force") if not hasattr(record, key)]
        if missing:
            raise FitError(f"histories[{index}]: found {type(record).__name__} without {', '.join(missing)}, expected "
                           "attributes name, time [s], deflection [m], force [N]")
        name = str(record.name)
        if name in names:
            raise FitError(f"histories[{index}]: record name {name!r} given twice, expected distinct names")
        names.add(name)
        arrays = {}
        for key, unit in (("time", "s"), ("deflection", "m"), ("force", "N")):
            values = np.asarray(getattr(record, key), dtype=float)
            if values.ndim != 1 or values.size < 8:
                raise FitError(f"histories[{index}] ({name!r}) {key}: found shape {values.shape}, expected a 1-D array "
                               f"of at least 8 samples in {unit}")
            if not np.all(np.isfinite(values)):
                bad = int(np.flatnonzero(~np.isfinite(values))[0])
                raise FitError(f"histories[{index}] ({name!r}) {key}: found {values[bad]} at sample {bad}, expected "
                               f"finite values in {unit}")
            arrays[key] = values
        sizes = {key: values.size for key, values in arrays.items()}
        if len(set(sizes.values())) != 1:
            raise FitError(f"histories[{index}] ({name!r}): found lengths {sizes}, expected equal lengths")
        if np.any(np.diff(arrays["time"]) <= 0.0):
            bad = int(np.flatnonzero(np.diff(arrays["time"]) <= 0.0)[0]) + 1
            raise FitError(f"histories[{index}] ({name!r}) time: not increasing at sample {bad}, expected strictly "
                           "increasing times in s")
        if not np.any(arrays["force"] != 0.0) or np.ptp(arrays["deflection"]) == 0.0:
            raise FitError(f"histories[{index}] ({name!r}): found a constant deflection or a zero force, expected a "
                           "record that moves and carries force")
        checked.append(ElementHistory(name, arrays["time"], arrays["deflection"], arrays["force"]))
    return checked


START_STATES = ("auto", "unloaded", "cycled")


def _start_states(records: list[ElementHistory], initial_state: str) -> list[bool]:
    """Per record: start from the cycled state (True) or unloaded (False). ``"auto"``: unloaded when
    the record begins within :data:`~idkit.observe.quasi_static.UNLOADED_FRACTION` of its peaks in
    deflection and force (the loop fits' rule; the force's threshold plus three standard deviations
    of the record's noise, :func:`idkit.signal.cycles.noise_level`), else cycled when it is closed (it ends within
    2 % of its range of where it began, so running it twice continues it), else unloaded."""
    flags = []
    for record in records:
        x, f = record.deflection, record.force
        closed = abs(x[-1] - x[0]) <= REPEAT_TOLERANCE * np.ptp(x)
        if initial_state == "cycled" and not closed:
            raise FitError(f"initial_state 'cycled': record {record.name!r} ends {abs(x[-1] - x[0]):.3g} m from where "
                           f"it began, expected a closed record (within {100 * REPEAT_TOLERANCE:g} % of its range)")
        # the loop fits' rule, the force's threshold widened by three standard deviations of the
        # record's own noise (a zeroed sensor reads its noise at rest)
        unloaded = (abs(x[0]) <= UNLOADED_FRACTION * np.max(np.abs(x))
                    and abs(f[0]) <= UNLOADED_FRACTION * np.max(np.abs(f)) + 3.0 * noise_level(f))
        flags.append(initial_state == "cycled" or (initial_state == "auto" and not unloaded and closed))
    return flags


def _predict(model, family: _Family, record: ElementHistory, cycled: bool) -> np.ndarray:
    """The model's force (N) along a record, from the unloaded state at its first sample, or cycled:
    the record run twice (its second pass starts where the first ended), the second pass kept."""
    if not cycled:
        return model.force(record.deflection, time=record.time if family.needs_time else None)
    x = np.concatenate([record.deflection, record.deflection[1:]])
    t = np.concatenate([record.time, record.time[1:] - record.time[0] + record.time[-1]])
    return model.force(x, time=t if family.needs_time else None)[record.deflection.size - 1:]


def _residual_function(family: _Family, records: list[ElementHistory], cycled: list[bool]):
    """``residuals(u)``: per sample ``(F_model - F) / (rms(F) sqrt(n))`` of every record, stacked."""
    weights = [1.0 / (math.sqrt(float(np.mean(r.force**2))) * math.sqrt(r.force.size)) for r in records]
    total = sum(r.force.size for r in records)

    def residuals(u) -> np.ndarray:
        try:  # parameters outside the model's domain, or a history it cannot follow (a diverging z)
            model = family.build(np.asarray(u, dtype=float))
            parts = [(_predict(model, family, record, state) - record.force) * weight
                     for record, weight, state in zip(records, weights, cycled)]
        except IdkitError:
            return np.full(total, _PENALTY_RESIDUAL)
        stacked = np.concatenate(parts)
        return np.where(np.isfinite(stacked), stacked, _PENALTY_RESIDUAL)

    return residuals


def _errors(model, family: _Family, records, cycled) -> dict:
    values = {}
    for record, state in zip(records, cycled):
        predicted = _predict(model, family, record, state)
        values[record.name] = float(np.sqrt(np.mean((predicted - record.force) ** 2) / np.mean(record.force**2)))
    return values


def _reversals(deflection: np.ndarray) -> np.ndarray:
    """Sample indices of the record's ends and of every reversal of the deflection."""
    step = np.sign(np.diff(deflection))
    moving = np.flatnonzero(step != 0.0)
    turns = moving[1:][step[moving[1:]] != step[moving[:-1]]]
    return np.unique(np.concatenate([[0], turns, [deflection.size - 1]]))


def _model_form_reasons(model, family: _Family, records, cycled, errors: dict) -> list[str]:
    """The shared model-form rule (:mod:`idkit.fit.model_form`): not a success when the records'
    mean error is more than :data:`~idkit.fit.model_form.FLOOR_MARGIN` above their mean noise
    floor read off the residual (repeated branches, else second differences between reversals)."""
    floors = []
    for record, state in zip(records, cycled):
        predicted = _predict(model, family, record, state)
        floor = residual_floor(record.force, predicted, _reversals(record.deflection), record.deflection)
        if math.isfinite(floor):
            floors.append(floor)
    if not floors:
        return []
    error, floor = float(np.mean(list(errors.values()))), float(np.mean(floors))
    if not misses_the_floor(error, floor):
        return []
    return [ModelFormReason(f"{MODEL_FORM_PREFIX} records: their mean error {100 * error:.3g} % is {100 * (error - floor):.3g} "
            f"points above the noise floor {100 * floor:.2g} % read off the residual (limit {100 * FLOOR_MARGIN:g} "
            "points): the residual is systematic, not noise (another element, docs/elements.md)", "records")]


def _fit(family: _Family, records: list[ElementHistory], starts: list[np.ndarray], max_nfev: int,
         initial_state: str, statistics: bool) -> ElementFitResult:
    """Least squares from each start, then the statistics and the verdict at the best."""
    begin = _time.perf_counter()
    cycled = _start_states(records, initial_state)
    residuals = _residual_function(family, records, cycled)
    # the starts search on records thinned to at most SEARCH_SAMPLES samples each (every k-th
    # sample: the deflection path stays the same to within a thinned step), then the best is
    # polished on the full records, which alone give the result and its statistics
    stride = max(1, max(math.ceil(r.force.size / SEARCH_SAMPLES) for r in records))
    thinned = records if stride == 1 else [
        ElementHistory(r.name, r.time[::stride], r.deflection[::stride], r.force[::stride]) for r in records]
    search = residuals if stride == 1 else _residual_function(family, thinned, cycled)
    best, evaluations = None, 0
    for u0 in starts:
        u0 = np.clip(np.asarray(u0, dtype=float), family.lower + 1e-9, family.upper - 1e-9)
        solution = scipy.optimize.least_squares(search, u0, bounds=(family.lower, family.upper), method="trf",
                                                x_scale="jac", max_nfev=max_nfev, xtol=1e-10, ftol=1e-10)
        evaluations += int(solution.nfev)
        if best is None or solution.cost < best.cost:
            best = solution
    if stride > 1 and statistics:  # from near the optimum: a few iterations, to the statistics' precision
        best = scipy.optimize.least_squares(residuals, best.x, bounds=(family.lower, family.upper), method="trf",
                                            x_scale="jac", max_nfev=max_nfev, xtol=1e-8, ftol=1e-8)
        evaluations += int(best.nfev)
    u = best.x.copy()
    span = family.upper - family.lower
    at_bound = (u - family.lower < _BOUND_MARGIN * span) | (family.upper - u < _BOUND_MARGIN * span)
    free = np.ones(u.size, dtype=bool)
    notes = []
    reasons = []
    index = family.parallel_index
    if index is not None and at_bound[index] and u[index] - family.lower[index] < _BOUND_MARGIN * span[index]:
        u[index] = family.lower[index]  # exactly 0: the element alone explains the data
        free[index] = False
        at_bound[index] = False
        notes.append(f"{family.varied[index]} = 0: the parallel spring is not needed (fitted at its bound 0), held "
                     "there")
    model = family.build(u)
    physical = family.parameters(model)
    if best.status <= 0:
        reasons.append(f"least squares stopped without converging: {best.message}")
    for index in np.flatnonzero(at_bound & free):
        name = family.varied[index]
        reasons.append(f"parameter {name} = {physical[name]:.6g} is on its search bound (internal "
                       f"{family.internal_names[index]} = {u[index]:.6g} in [{family.lower[index]:.6g}, "
                       f"{family.upper[index]:.6g}])")
        free[index] = False
    free_names = [family.internal_names[i] for i in np.flatnonzero(free)]
    varied = [family.varied[i] for i in np.flatnonzero(free)]

    def free_residuals(v):
        full = u.copy()
        full[free] = v
        return residuals(full)

    sizes = [r.force.size for r in records]
    stats = None
    if statistics:
        stats = jacobian_statistics(free_residuals, u[free], free_names, step=1e-6, group_sizes=sizes,
                                    method="Jacobian of the per-sample force residuals at the least-squares optimum")
    else:
        notes.append("statistics=False: no standard errors, determinacy not judged; parameters from the records "
                     f"thinned to every {stride}. sample" if stride > 1 else
                     "statistics=False: no standard errors, determinacy not judged")
    # chain rule to the model's parameters: d physical / d internal by central differences of the map
    stderr, correl = {}, {}
    if stats is not None and stats.covar is not None and np.all(np.isfinite(stats.covar)):
        step = 1e-7
        columns = []
        for i in np.flatnonzero(free):
            up, down = u.copy(), u.copy()
            up[i] += step
            down[i] -= step
            p_up, p_down = family.parameters(family.build(up)), family.parameters(family.build(down))
            columns.append([(p_up[name] - p_down[name]) / (2.0 * step) for name in varied])
        mapping = np.array(columns).T  # (varied, free)
        covariance = mapping @ stats.covar @ mapping.T
        sigma = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
        for a, name in enumerate(varied):
            stderr[name] = float(sigma[a])
            correl[name] = {other: float(covariance[a, b] / (sigma[a] * sigma[b])) if sigma[a] * sigma[b] > 0 else 0.0
                            for b, other in enumerate(varied) if b != a}
    specs = {spec.name: (spec.unit, spec.lower, spec.upper) for spec in model.param_specs()}
    specs.update({name: (unit, lower, math.inf) for name, (unit, lower, _, _) in family.derived.items()})
    parameters = to_lmfit(varied, [physical[name] for name in varied], units=[specs[n][0] for n in varied],
                          lower=[specs[n][1] for n in varied], upper=[specs[n][2] for n in varied],
                          vary=[True] * len(varied), stderr=[stderr.get(n) for n in varied])
    for name in varied:
        parameters[name].correl = correl.get(name)
    determinacy = determinacy_reasons(parameters, stats) if statistics else ()
    reasons.extend(determinacy)
    errors = _errors(model, family, records, cycled)
    reasons.extend(_model_form_reasons(model, family, records, cycled, errors))
    undetermined = [] if not statistics else _undetermined(parameters, stats)
    return ElementFitResult(
        family=family.name, model=model, params=physical,
        stderr={name: stderr.get(name, math.nan) for name in varied}, varied=varied, undetermined=undetermined,
        reasons=list(dict.fromkeys(reasons)), notes=notes, errors=errors,
        evaluations=evaluations, elapsed_s=_time.perf_counter() - begin, internal=u,
        start_states={record.name: "cycled" if state else "unloaded" for record, state in zip(records, cycled)},
        units=family.units(model), computed=family.computed)


def _undetermined(parameters, stats) -> list[str]:
    """The varied parameters :func:`~idkit.fit.result.determinacy_reasons` finds undetermined, by
    name: every one without statistics or a finite standard error, a positive one whose 95 %
    interval reaches zero, and each member of a group determined only in combination."""
    names = list(parameters)
    if stats is None:
        return names
    found = {name for name in names if parameters[name].stderr is None
             or not math.isfinite(float(parameters[name].stderr)) or _interval_reaches_zero(parameters[name])}
    found.update(name for group in undetermined_groups(parameters) for name in group)
    return [name for name in names if name in found]


def _scales(records):
    """Deflection amplitude (m), force amplitude (N), secant stiffness (N/m), largest speed (m/s)."""
    amplitude = max(0.5 * float(np.ptp(r.deflection)) for r in records)
    force = max(0.5 * float(np.ptp(r.force)) for r in records)
    speed = max(float(np.max(np.abs(np.diff(r.deflection) / np.diff(r.time)))) for r in records)
    return amplitude, force, force / amplitude, speed


#: The options every element fitter declares (:func:`fit_clearance_jenkin`).
_FIT_OPTIONS = dict(seed=Seed(), max_nfev=Whole(ge=1, meaning="residual evaluations per start"),
                    initial_state=Choice(START_STATES), statistics=Flag(),
                    max_starts=Whole(ge=1, optional=True, meaning="None: every start"), error=FitError)


def _warm(start, family_name: str, family: _Family):
    if start is None:
        return None
    if not isinstance(start, ElementFitResult) or start.family != family_name:
        raise FitError(f"start: found {type(start).__name__}"
                       f"{'' if not isinstance(start, ElementFitResult) else ' of family ' + repr(start.family)}, "
                       f"expected a {family_name!r} ElementFitResult")
    return np.clip(start.internal, family.lower, family.upper)


@accepts(**_FIT_OPTIONS)
def fit_clearance_jenkin(histories, *, start: ElementFitResult | None = None, seed: int = 0,
                         max_nfev: int = 400, initial_state: str = "auto",
        statistics: bool = True, max_starts: int | None = None) -> ElementFitResult:
    """Fit a Jenkin element acting through a clearance, with a parallel spring, to force records.

    ``F = g1 x + dead_zone(V, k gap)``, ``V`` the virtual force of a Jenkin element of stiffness
    ``k`` and slip force ``fc + k gap`` (:class:`~idkit.models.ClearanceIwanModel`, order 1).

    Parameters
    ----------
    histories : sequence
        Records with ``name``, ``time`` (s), ``deflection`` (m), ``force`` (N) (module docstring).
    start : ElementFitResult, optional
        A previous clearance-Jenkin result: the only start (warm start).
    seed : int
        Seeds the jitter of the starts (the search is otherwise deterministic).
    max_nfev : int
        Residual evaluations per start.
    initial_state : {"auto", "unloaded", "cycled"}
        State each record is evaluated from: unloaded at its first sample, or cycled (a closed
        record run twice, the second pass kept: the steady cycle of a periodic test cut at any
        phase). ``"auto"``: unloaded when the record begins near zero deflection and force, else
        cycled when it is closed, else unloaded (module docstring).
    statistics : bool
        False: no standard errors and no determinacy verdict (``stderr`` NaN, ``undetermined``
        empty), and long records are not polished at full length after the thinned search:
        for the folds of a cross-validation, warm started from the full fit (a fold of ten
        20,000-sample pinched Bouc-Wen records then costs a few evaluations of thinned records).
    max_starts : int, optional
        Only the first ``max_starts`` starts (default every one): with a small ``max_nfev`` and
        ``statistics=False`` a cheap first stage (``fit auto``'s screen of a family).

    Returns
    -------
    ElementFitResult
        ``model`` a :class:`~idkit.models.ClearanceIwanModel`; varied ``gap`` (m), ``k_1`` (N/m),
        ``fc_1`` (N), ``g1`` (N/m).
    """
    records = _checked_histories(histories)
    amplitude, force, secant, _ = _scales(records)
    x_small = min(0.5 * float(np.ptp(r.deflection)) for r in records)

    def build(u):
        return ClearanceIwanModel(gap=u[0] * amplitude, k=[math.exp(u[1])], fc=[math.exp(u[2])], g1=u[3] * secant)

    k0 = math.log(secant)
    family = _Family("clearance_jenkin", ("gap", "log_k_1", "log_fc_1", "g1"),
                     lower=np.array([0.0, k0 - math.log(10.0), math.log(force) - math.log(1e3), 0.0]),
                     upper=np.array([1.0, k0 + math.log(1e5), math.log(force) + math.log(10.0), 10.0]),
                     build=build, varied=("gap", "k_1", "fc_1", "g1"), needs_time=False, parallel_index=3)
    warm = _warm(start, "clearance_jenkin", family)
    if warm is not None:
        starts = [warm]
    else:
        rng = np.random.default_rng(seed)
        starts = [np.array([gap * x_small / amplitude, k0 + math.log(ratio), math.log(0.8 * force), 0.02])
                  * (1.0 + 0.01 * rng.standard_normal(4))
                  for gap in (0.1, 0.4) for ratio in (10.0, 100.0)]
    return _fit(family, records, starts[:max_starts], max_nfev, initial_state, statistics)


@accepts(**_FIT_OPTIONS)
def fit_rate_dependent_jenkin(histories, *, start: ElementFitResult | None = None, seed: int = 0,
                              max_nfev: int = 400, initial_state: str = "auto",
        statistics: bool = True, max_starts: int | None = None) -> ElementFitResult:
    """Fit a Jenkin element with slip force ``fc (1 + r tanh(|v| / v_ref))`` and a parallel spring.

    :class:`~idkit.models.RateDependentIwanModel` of order 1; the records' sample times give
    the deflection rate. Arguments as :func:`fit_clearance_jenkin`; varied ``k_1`` (N/m),
    ``fc_1`` (N, at rest), ``slip_rate_gain`` (-), ``slip_speed`` (m/s), ``g1`` (N/m). The
    records must span sliding speeds around ``v_ref`` (loops at several frequencies), else
    ``slip_speed`` is reported undetermined.
    """
    records = _checked_histories(histories)
    amplitude, force, secant, speed = _scales(records)

    def build(u):
        return RateDependentIwanModel(k=[math.exp(u[0])], fc=[math.exp(u[1])], slip_rate_gain=u[2],
                                      slip_speed=math.exp(u[3]), g1=u[4] * secant)

    k0 = math.log(secant)
    family = _Family("rate_dependent_jenkin", ("log_k_1", "log_fc_1", "slip_rate_gain", "log_slip_speed", "g1"),
                     lower=np.array([k0 - math.log(10.0), math.log(force) - math.log(1e3), -0.9,
                                     math.log(speed / 1e3), 0.0]),
                     upper=np.array([k0 + math.log(1e5), math.log(force) + math.log(10.0), 20.0,
                                     math.log(speed * 1e2), 10.0]),
                     build=build, varied=("k_1", "fc_1", "slip_rate_gain", "slip_speed", "g1"), needs_time=True,
                     parallel_index=4)
    warm = _warm(start, "rate_dependent_jenkin", family)
    if warm is not None:
        starts = [warm]
    else:
        rng = np.random.default_rng(seed)
        starts = [np.array([k0 + math.log(20.0), math.log(0.7 * force), gain, math.log(share * speed), 0.02])
                  + 0.01 * rng.standard_normal(5)
                  for gain in (0.2, 1.0) for share in (0.1, 0.5)]
    return _fit(family, records, starts[:max_starts], max_nfev, initial_state, statistics)


@accepts(**_FIT_OPTIONS)
def fit_jenkin(histories, *, start: ElementFitResult | None = None, seed: int = 0, max_nfev: int = 400,
               initial_state: str = "auto", statistics: bool = True,
               max_starts: int | None = None) -> ElementFitResult:
    """Fit a plain Jenkin element (spring ``k_1`` in series with a slider ``fc_1``) with a parallel
    spring ``g1``: the Iwan model of order 1 (:class:`~idkit.models.IwanModel`), on force records of
    any deflection history, e.g. the simple baseline a model must out-predict
    (:func:`idkit.fit.baselines.fit_baselines`). Arguments as :func:`fit_clearance_jenkin`; varied
    ``k_1`` (N/m), ``fc_1`` (N), ``g1`` (N/m)."""
    records = _checked_histories(histories)
    _, force, secant, _ = _scales(records)

    def build(u):
        return IwanModel(g1=u[2] * secant, k=[math.exp(u[0])], fc=[math.exp(u[1])])

    k0 = math.log(secant)
    family = _Family("jenkin", ("log_k_1", "log_fc_1", "g1"),
                     lower=np.array([k0 - math.log(10.0), math.log(force) - math.log(1e3), 0.0]),
                     upper=np.array([k0 + math.log(1e5), math.log(force) + math.log(10.0), 10.0]),
                     build=build, varied=("k_1", "fc_1", "g1"), needs_time=False, parallel_index=2)
    warm = _warm(start, "jenkin", family)
    if warm is not None:
        starts = [warm]
    else:
        rng = np.random.default_rng(seed)
        starts = [np.array([k0 + math.log(ratio), math.log(share * force), 0.1]) + 0.01 * rng.standard_normal(3)
                  for ratio in (3.0, 30.0) for share in (0.3, 0.8)]
    return _fit(family, records, starts[:max_starts], max_nfev, initial_state, statistics)


#: The pinched Bouc-Wen fit's parameters, one per internal coordinate (:func:`fit_pinched_boucwen`).
PINCHED_PARAMETERS = ("k1", "alpha", "saturated_force", "beta_share", "n", "pinch", "pinch_width", "pinch_shift")


@accepts(**_FIT_OPTIONS)
def fit_pinched_boucwen(histories, *, start: ElementFitResult | None = None, seed: int = 0,
                        max_nfev: int = 400, initial_state: str = "auto",
        statistics: bool = True, max_starts: int | None = None) -> ElementFitResult:
    """Fit the pinched Bouc-Wen model (``k2 = k3 = 0``, ``b = 1``, ``c = 0``, no viscous part).

    Fitted, reported and judged in the loop's own coordinates (:data:`PINCHED_PARAMETERS`):
    ``k1`` (N/m), ``alpha`` (N/m, the slope of ``z`` at ``z = 0`` before pinching), the saturated
    hysteretic force ``saturated_force`` ``z_u = (alpha / (beta + gamma))^(1/n)`` (N), the share
    ``beta_share = beta / (beta + gamma)`` (the slope just after a reversal from saturation is
    ``2 beta_share alpha``), the exponent ``n`` (the sharpness of the knee) and ``pinch``,
    ``pinch_width``, ``pinch_shift``. The model's ``beta = beta_share alpha / z_u^n`` and
    ``gamma`` are computed from them and reported without a verdict of their own: their unit
    N^(1-n)/m carries ``n``, so a change of ``n`` by ``dn`` rescales both by ``z_u^-dn`` (a
    factor 1.6 for ``dn = 0.1`` at ``z_u = 100 N``) while the loop hardly moves; in the
    ``(beta, gamma, n)`` coordinates the data then determine ``beta`` and ``n`` only in
    combination, in these they determine each one (docs/fitting.md, "Pinched Bouc-Wen").
    Arguments as :func:`fit_clearance_jenkin`.
    """
    records = _checked_histories(histories)
    amplitude, force, secant, _ = _scales(records)

    def build(u):
        alpha, z_u, share, n = math.exp(u[1]), math.exp(u[2]), u[3], math.exp(u[4])
        total = alpha / z_u**n
        return PinchedBoucWenModel(k1=u[0] * secant, k2=0.0, k3=0.0, alpha=alpha, beta=share * total,
                                   gamma=(1.0 - share) * total, n=n, pinch=u[5], pinch_width=math.exp(u[6]),
                                   pinch_shift=u[7])

    a0 = math.log(secant)
    family = _Family("pinched_boucwen",
                     ("k1", "log_alpha", "log_z_u", "beta_share", "log_n", "pinch", "log_pinch_width", "pinch_shift"),
                     lower=np.array([0.0, a0 - math.log(10.0), math.log(force / 1e3), -3.0, math.log(0.3), 0.0,
                                     math.log(0.02), -0.9]),
                     upper=np.array([10.0, a0 + math.log(1e4), math.log(force * 10.0), 4.0, math.log(6.0), 0.98,
                                     math.log(3.0), 0.9]),
                     build=build, varied=PINCHED_PARAMETERS, needs_time=False, parallel_index=0,
                     derived={"saturated_force": ("N", 0.0, "saturated hysteretic force z_u",
                                                  lambda model: model.saturated_force),
                              "beta_share": ("-", -math.inf, "beta / (beta + gamma)",
                                             lambda model: model.beta / (model.beta + model.gamma))},
                     computed=("beta", "gamma"))
    warm = _warm(start, "pinched_boucwen", family)
    if warm is not None:
        starts = [warm]
    else:
        rng = np.random.default_rng(seed)
        starts = [np.array([0.1, a0 + math.log(ratio), math.log(0.7 * force), 0.5, 0.0, pinch, math.log(0.3), 0.0])
                  + 0.01 * rng.standard_normal(8)
                  for ratio in (5.0, 30.0) for pinch in (0.4, 0.8)]
    return _fit(family, records, starts[:max_starts], max_nfev, initial_state, statistics)


#: The families of this module by name, for the model-choice registry (``idkit fit auto``).
ELEMENT_FITTERS = {"clearance_jenkin": fit_clearance_jenkin, "pinched_boucwen": fit_pinched_boucwen,
                   "rate_dependent_jenkin": fit_rate_dependent_jenkin}
