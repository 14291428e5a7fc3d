"""The report's conclusions in words, read off the computed results (nothing here is fixed text about the data).

:func:`isolator_conclusions` states, per isolator, the identified model with its standard
errors and valid deflection range, and each validation's verdict with its reason: which
thresholded metrics are within their limits (what the model predicts well) and which are
not (where it fails), with the numbers. :func:`transport_conclusions` names the system that
protects the payload best at each floor level (lowest RMS top acceleration) and each drop
height (lowest rest shock), with the margin over the runner-up and the reference, and where a
system's rest-shock curve ends because its model went invalid.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from idkit.plot.studies import curve_ends

__all__ = [
    "drop_model_sentence",
    "fit_sentence",
    "key_metric",
    "parameters_cell",
    "parameters_sentence",
    "rest_shock_ends",
    "transport_conclusions",
    "validation_sentence",
]


def _number(value: float, digits: int = 3) -> str:
    return "n/a" if value is None or not np.isfinite(value) else f"{value:.{digits}g}"


def parameters_sentence(table: pd.DataFrame, *, limit: int | None = None, unfitted: bool = False) -> str:
    """``name = value +- stderr unit`` for the fitted parameters of a ``parameters_table``.

    With ``unfitted``, the model's other parameters follow with their ``stderr_note`` (how
    they were set, e.g. the wire rope's ``c_visc`` from the stepped-sine resonance): the
    identified model is then stated whole, as the model file holds it.

    Examples
    --------
    >>> table = pd.DataFrame({"parameter": ["k", "c"], "unit": ["N/m", "N s/m"], "value": [1200.0, 3.5],
    ...                       "stderr": [15.0, None], "fitted": [True, True]})
    >>> parameters_sentence(table)
    'k = 1.2e+03 +- 15 N/m; c = 3.5 N s/m (no stderr)'
    """
    parts = []
    fitted = table["fitted"].astype(bool) if "fitted" in table else pd.Series(True, index=table.index)
    for _, row in table[fitted].iterrows():
        unit = _unit(row)
        stderr = row.get("stderr")
        if stderr is not None and not (isinstance(stderr, float) and math.isnan(stderr)):
            parts.append(f"{row['parameter']} = {_number(row['value'])} +- {_number(float(stderr), 2)}{unit}")
        else:
            parts.append(f"{row['parameter']} = {_number(row['value'])}{unit} (no stderr)")
    if limit is not None and len(parts) > limit:
        parts = parts[:limit] + [f"{len(parts) - limit} more in the fit section"]
    if unfitted:
        for _, row in table[~fitted].iterrows():
            note = row.get("stderr_note")
            how = note if isinstance(note, str) and note else "not fitted"
            parts.append(f"{row['parameter']} = {_number(row['value'])}{_unit(row)} ({how})")
    return "; ".join(parts)


def _unit(row) -> str:
    unit = row.get("unit")
    return f" {unit}" if isinstance(unit, str) and unit and unit != "-" else ""


def fit_sentence(name: str, fit, *, comparison: bool = False) -> tuple[str, str]:
    """``(verdict, text)``: whether the fit of a :class:`~idkit.fit.measurement_level.MeasurementFit` succeeded, and why not.

    A fit that is not a success is "FLAGGED", as ``idkit report`` prints it: FAIL is a
    validation's verdict (exit status 1), a flagged fit the report predicts with gives exit
    status 4. A ``comparison`` fit (Bouc-Wen) says that it enters neither.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> fit_sentence("Bouc-Wen", SimpleNamespace(success=False, reasons=["loop error 7 %"]), comparison=True)[0]
    'FLAGGED'
    """
    if fit.success:
        return "PASS", f"{name}: the fit succeeded."
    text = f"{name}: the fit is not a success: " + "; ".join(fit.reasons) + "."
    if comparison:
        text += (" A comparison of model forms: the report does not predict with it, and it enters neither the "
                 "verdicts nor the exit status.")
    return "FLAGGED", text


def validation_sentence(key: str, result, *, quick_note: str = "") -> tuple[str, str]:
    """``(verdict, text)`` of a :class:`~idkit.validate.ValidationResult`: the verdict and its reason with numbers.

    FAIL names every metric over its limit (``records_beyond_limit`` with each record beyond its own
    limit, :attr:`~idkit.validate.ValidationResult.record_failures`); INCONCLUSIVE the reasons the metrics cannot
    carry a PASS; PASS every metric with its limit. Metrics within their limits follow as
    what the model predicts well.
    """
    checks, summary, thresholds = result.checks, result.summary, result.thresholds
    unmeasured = set(result.unmeasured)
    good = [f"{metric} {_number(summary[metric])} <= {thresholds[metric]:g}" for metric, ok in checks.items() if ok]
    bad = [f"{metric} {_number(summary[metric])} > {thresholds[metric]:g}"
           + (" (" + "; ".join(result.record_failures) + ")"
              if metric == "records_beyond_limit" and getattr(result, "record_failures", ()) else "")
           for metric, ok in checks.items() if not ok and metric not in unmeasured]
    points = f"{len(result.metrics)} points"
    if result.verdict == "FAIL":
        text = f"{key} ({points}): fails on " + "; ".join(bad)
        if good:
            text += "; within the limits: " + "; ".join(good)
    elif result.verdict == "INCONCLUSIVE":
        reasons = list(result.inconclusive) + [f"{metric} could not be computed" for metric in sorted(unmeasured)]
        text = f"{key} ({points}): inconclusive because " + "; ".join(reasons)
        if good:
            text += "; the metrics that were computed are within their limits: " + "; ".join(good)
    else:
        text = f"{key} ({points}): predicts well: " + "; ".join(good)
    if result.cannot_see:
        text += "; this check cannot tell these wrong components apart: " + "; ".join(result.cannot_see)
    text += (f" ({quick_note})" if quick_note else "") + "."
    for note in result.notes:
        text += f" Note: {note}."
    return result.verdict, text


def drop_model_sentence(comparison, *, used: tuple[str, str | None]) -> str:
    """The rope model and drop model the held-out drops support, with their median peak errors
    (support only by a pair whose verdict is PASS; else the closest pair, named as not passing).

    Parameters
    ----------
    comparison : DropModelComparison
        :func:`idkit.studies.drop_models.wire_rope_drop_models`.
    used : (str, str or None)
        The rope model (a name of ``comparison``) and drop model the report's validations
        use; when the drops support another pair, the sentence gives that pair's errors too,
        so that the support is not read as the validated model's.
    """
    def errors(key) -> tuple[float, float]:
        summary = comparison.results[key].summary
        return (summary.get("median_peak_acceleration_compression_error", np.nan),
                summary.get("median_peak_acceleration_tension_error", np.nan))

    model, drop = comparison.supported()
    compression, tension = errors((model, drop))
    verdict = comparison.results[(model, drop)].verdict
    if verdict == "PASS":
        text = (f"The held-out drops support the {model} model with the {drop} drop model: median peak "
                f"error {compression:.3f} in compression and {tension:.3f} in tension")
    else:  # the best pair did not pass: nothing is supported, say so with the closest pair's errors
        text = (f"The held-out drops support no rope and drop model compared ({len(comparison.results)} pairs, "
                f"none passes); the closest is the {model} model with the {drop} drop model ({verdict}): median "
                f"peak error {compression:.3f} in compression and {tension:.3f} in tension")
    if tuple(used) != (model, drop) and tuple(used) in comparison.results:
        compression, tension = errors(tuple(used))
        text += (f"; the {used[0]} model with the {used[1]} drop model, which the validations above use, "
                 f"{compression:.3f} and {tension:.3f}")
    return text + "."


def _ranking_sentence(values: pd.Series, what: str, unit: str) -> str:
    finite = values[np.isfinite(values.to_numpy(float))].sort_values()
    if finite.empty:
        return f"{what}: no system gives a finite value."
    best, best_value = finite.index[0], float(finite.iloc[0])
    text = f"{what}: {best} protects the payload best ({_number(best_value)} {unit}"
    named = [best]
    if len(finite) > 1:
        second, second_value = finite.index[1], float(finite.iloc[1])
        text += f"; next {second} {_number(second_value)} {unit}, {_number(second_value / best_value)} times as much"
        named.append(second)
    if "reference" in finite.index and "reference" not in named:
        text += f"; the viscous reference {_number(float(finite['reference']))} {unit}"
    missing = [name for name in values.index if name not in finite.index]
    if missing:
        text += "; no value (model invalid) for " + ", ".join(missing)
    return text + ")."


def transport_conclusions(study, heights=(0.02, 0.05, 0.10)) -> list[str]:
    """Which system protects the payload best at each floor level and drop height, in words.

    Parameters
    ----------
    study : TransportStudy
    heights : sequence of float
        Drop heights (m) to state (interpolated in the study's height sweep, within its range).

    Returns
    -------
    list of str
        One sentence per floor level (saying so when the best or next system's random runs
        did not settle, :meth:`~idkit.studies.transport.TransportStudy.unsettled`), one per
        drop height, one per system whose rest-shock curve versus impact speed or drop height
        ends because its model went invalid (:func:`rest_shock_ends`).
    """
    sentences = []
    unsettled = {(system, level): value for system, level, value in study.unsettled()}
    for column in study.rms.columns:
        sentence = _ranking_sentence(study.rms[column], f"floor PSD {column}, RMS top acceleration", "m/s^2")
        ranked = study.rms[column].dropna().sort_values().index[:2]
        doubtful = [f"{name} (settling error {unsettled[(name, column)]:.2g})" for name in ranked
                    if (name, column) in unsettled]
        if doubtful:
            sentence += (" Not settled, so uncertain by about that fraction: " + ", ".join(doubtful) + ".")
        sentences.append(sentence)
    table_heights = study.shock_height.index.to_numpy(float)
    for height in heights:
        if not (table_heights.min() <= height <= table_heights.max()
                or np.isclose(table_heights, height, rtol=1e-9, atol=0.0).any()):
            continue
        # the summary table's values: a level interpolated next to an invalid point is not a value
        values = study.rest_shock_at(height)
        sentences.append(_ranking_sentence(values, f"drop height {100 * height:g} cm, rest shock", "m/s^2"))
    for name, where in rest_shock_ends(study).items():
        sentences.append(f"{name}: the rest-shock curve stops {where}; beyond it the model leaves its valid range "
                         "(the simulator flags the runs), so no level is given.")
    return sentences


def rest_shock_ends(study) -> dict[str, str]:
    """Where each system's rest-shock curves stop, in words: ``{system: "at an impact speed of ... m/s ..."}``.

    Both sweeps count: the speed sweep may end before a curve versus drop height stops
    (the bundled study's speeds reach 1 m/s, its heights 15 cm, about 1.7 m/s). Systems
    whose curves run to the end of both sweeps are left out.

    Examples
    --------
    >>> from idkit.studies.transport import TransportStudy
    >>> study = TransportStudy(tuning=pd.DataFrame(), rms=pd.DataFrame(), psd=(), seed=0, n_realizations=1,
    ...                        flagged_runs=0, shock_velocity=pd.DataFrame({"a": [1.0, 2.0]}, index=[0.5, 1.0]),
    ...                        shock_height=pd.DataFrame({"a": [1.0, np.nan]}, index=[0.05, 0.1]))
    >>> rest_shock_ends(study)
    {'a': 'at a drop height of 5 cm (its curve versus impact speed runs to the end of that sweep, 1 m/s)'}
    """
    speeds, heights = study.shock_velocity, study.shock_height
    by_speed, by_height = curve_ends(speeds), curve_ends(heights)
    ends = {}
    for name in speeds.columns.union(heights.columns, sort=False):
        speed = _sweep_end(speeds, name, by_speed, lambda value: f"an impact speed of {value:.3g} m/s")
        height = _sweep_end(heights, name, by_height, lambda value: f"a drop height of {100 * value:.3g} cm")
        if speed and height:
            ends[name] = f"at {speed} and {height}"
        elif speed:
            ends[name] = (f"at {speed} (its curve versus drop height runs to the end of that sweep, "
                          f"{100 * heights.index.max():.3g} cm)")
        elif height:
            ends[name] = (f"at {height} (its curve versus impact speed runs to the end of that sweep, "
                          f"{speeds.index.max():.3g} m/s)")
    return ends


def _sweep_end(table: pd.DataFrame, name: str, ends: dict, words) -> str:
    """Where ``name``'s curve in ``table`` stops, in ``words``; "" when it runs to the end of the sweep."""
    if name not in table.columns:
        return ""
    if not np.isfinite(table[name].to_numpy(float)).any():
        return f"{words(float(table.index.min()))} already (no valid point)"
    return words(ends[name]) if name in ends else ""


def key_metric(result) -> tuple[str, float, float]:
    """``(metric, value, limit)``: the thresholded metric of a validation nearest to (or furthest beyond) its limit.

    The metric with the largest value over limit (a metric with limit 0 ranks first when it
    is above 0); a metric that could not be computed (NaN) ranks above all when the verdict is
    not PASS, since it is then what the verdict hangs on. Nothing is judged here: the verdict
    stays :attr:`~idkit.validate.ValidationResult.verdict`.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> key_metric(SimpleNamespace(summary={"a": 0.5, "b": 2.0}, thresholds={"a": 1.0, "b": 3.0}, verdict="PASS"))
    ('b', 2.0, 3.0)
    """
    def rank(metric: str) -> float:
        value, limit = float(result.summary[metric]), float(result.thresholds[metric])
        if not np.isfinite(value):
            return math.inf if result.verdict != "PASS" else -math.inf
        if limit == 0:
            return math.inf if value > 0 else 0.0
        return value / limit

    if not result.thresholds:
        return "", math.nan, math.nan
    metric = max(result.thresholds, key=rank)
    return metric, float(result.summary[metric]), float(result.thresholds[metric])


def parameters_cell(table: pd.DataFrame) -> str:
    """A model's parameters for a table cell: ``name = value ± stderr unit``, the unfitted ones marked.

    Examples
    --------
    >>> table = pd.DataFrame({"parameter": ["k", "c"], "unit": ["N/m", "N s/m"], "value": [1200.0, 3.5],
    ...                       "stderr": [15.0, None], "fitted": [True, False]})
    >>> parameters_cell(table)
    'k = 1.2e+03 ± 15 N/m; c = 3.5 N s/m (not fitted)'
    """
    parts = []
    fitted = table["fitted"].astype(bool) if "fitted" in table else pd.Series(True, index=table.index)
    for (_, row), varied in zip(table.iterrows(), fitted):
        stderr = row.get("stderr")
        has_stderr = stderr is not None and not (isinstance(stderr, float) and math.isnan(stderr))
        text = f"{row['parameter']} = {_number(row['value'])}"
        if varied and has_stderr:
            text += f" ± {_number(float(stderr), 2)}"
        text += _unit(row)
        if not varied:
            note = row.get("stderr_note")
            text += f" ({note.split(',')[0]})" if isinstance(note, str) and note else " (not fitted)"
        elif not has_stderr:
            text += " (no stderr)"
        parts.append(text)
    return "; ".join(parts)
