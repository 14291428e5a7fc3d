"""Typed validation results: a metrics table, scalar metrics, thresholds, pass/fail."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np
import pandas as pd

from idkit.checks import Reals
from idkit.errors import ValidationError
from idkit.validate.records import RECORD_METRIC

__all__ = ["ValidationResult", "check_thresholds", "Verdict", "VERDICTS"]


class Verdict(StrEnum):
    """A judgement idkit prints: a validation's (PASS, INCONCLUSIVE, FAIL, from best to worst trust
    in the model) or a fit's that is not a success (FLAGGED). A ``str``, so it prints and compares
    as its word; decisions test it against the members, never against text."""

    PASS = "PASS"
    INCONCLUSIVE = "INCONCLUSIVE"
    FAIL = "FAIL"
    FLAGGED = "FLAGGED"

    @classmethod
    def of_fit(cls, success: bool) -> Verdict:
        """PASS for a fit that is a success, else FLAGGED."""
        return cls.PASS if success else cls.FLAGGED


#: The three validation verdicts, from best to worst trust in the model.
VERDICTS = (Verdict.PASS, Verdict.INCONCLUSIVE, Verdict.FAIL)


def check_thresholds(defaults: dict[str, float], thresholds: dict[str, float] | None) -> dict[str, float]:
    """Merge user thresholds into the defaults; unknown names are an error."""
    merged = dict(defaults)
    for name, value in (thresholds or {}).items():
        if name not in defaults:
            raise ValidationError(f"thresholds: found unknown name {name!r}, expected some of {sorted(defaults)}")
        if not (np.isfinite(value) and value >= 0):
            raise ValidationError(f"thresholds[{name!r}]: found {value!r}, expected a finite number >= 0")
        merged[name] = float(value)
    return merged


#: The contract of ``identified_range``: the smallest and largest loop amplitude (m) an isolator
#: model was identified on.
IDENTIFIED_RANGE = Reals(unit="m", gt=0, min_size=2, max_size=2, optional=True,
                         meaning="smallest and largest identified amplitude")


def checked_identified_range(identified_range, isolator) -> tuple[float, float] | None:
    """``identified_range`` (declared :data:`IDENTIFIED_RANGE` by the validations) as two floats
    ``smallest <= largest``, or None; only for one isolator."""
    if identified_range is None:
        return None
    if isolator is None:
        raise ValidationError("identified_range: given without isolator=; expected it only for one isolator "
                              "(the deflection of a hybrid or a whole system is not one isolator's)")
    smallest, largest = (float(value) for value in identified_range)
    if not smallest <= largest:
        raise ValidationError(f"identified_range: found ({smallest!r}, {largest!r}), expected smallest <= largest (m)")
    return smallest, largest


@dataclass(frozen=True)
class ValidationResult:
    """Outcome of validating a model against held-out measurements.

    Attributes
    ----------
    name : str
        What was validated (e.g. ``"harmonic sweep, wire rope"``).
    metrics : pandas.DataFrame
        One row per measurement point (units in the column names).
    summary : dict
        Scalar metrics; every key of ``thresholds`` is one of them.
    thresholds : dict
        Upper limits of the summary metrics (documented defaults, user-settable).
    details : dict
        Further tables (e.g. resonance per amplitude), by name.
    inconclusive : tuple of str
        Why the metrics cannot carry a PASS even where they are within their limits
        (e.g. a simulated point that never reached steady state); empty when
        the validation is complete.
    cannot_see : tuple of str
        Deliberately wrong components that pass this validation too
        (:func:`idkit.validate.blind_spots.blind_spots`): the verdict does not vouch for them.
    notes : tuple of str
        Findings that explain the verdict without changing it (e.g. amplitude levels that lie
        outside the range the model was identified on, where the model is extrapolated).
    record_failures : tuple of str
        The held-out records beyond their own per-record limit (:mod:`idkit.validate.records`),
        one line each naming the record, its error and the limit; their number is the summary
        metric ``records_beyond_limit`` (limit 0), and when it is beyond its limit :attr:`why`
        lists these lines. The ``metrics`` table carries each record's per-record errors, limits
        and ``record verdict``.
    """

    name: str
    metrics: pd.DataFrame
    summary: dict
    thresholds: dict
    details: dict = field(default_factory=dict)
    inconclusive: tuple[str, ...] = ()
    cannot_see: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()
    record_failures: tuple[str, ...] = ()

    @property
    def checks(self) -> dict[str, bool]:
        """Each thresholded metric: True if within its limit (NaN fails)."""
        return {key: bool(np.isfinite(self.summary[key]) and self.summary[key] <= limit)
                for key, limit in self.thresholds.items()}

    @property
    def unmeasured(self) -> tuple[str, ...]:
        """Thresholded metrics that could not be computed (NaN): nothing to judge them by."""
        return tuple(key for key in self.thresholds if np.isnan(self.summary[key]))

    @property
    def verdict(self) -> Verdict:
        """FAIL if a metric exceeds its limit (an infinite error does); else INCONCLUSIVE if a
        metric could not be computed or :attr:`inconclusive` names a reason; else PASS."""
        if any(not ok and key not in self.unmeasured for key, ok in self.checks.items()):
            return Verdict.FAIL
        return Verdict.INCONCLUSIVE if self.inconclusive or self.unmeasured else Verdict.PASS

    @property
    def why(self) -> tuple[str, ...]:
        """What keeps the verdict from PASS, one line each: every metric beyond its limit
        (``"name value > limit"``; for ``records_beyond_limit`` followed by each record beyond its
        own limit, :attr:`record_failures`), every reason it is inconclusive, every metric that
        could not be computed; empty for a PASS."""
        beyond = []
        for key, limit in self.thresholds.items():
            if not self.checks[key] and key not in self.unmeasured:
                beyond.append(f"{key} {self.summary[key]:.4g} > {limit:g}")
                if key == RECORD_METRIC:
                    beyond.extend(self.record_failures)
        return tuple(beyond) + tuple(self.inconclusive) + tuple(f"{key} could not be computed"
                                                                for key in self.unmeasured)

    @property
    def passed(self) -> bool:
        """True only for the verdict PASS."""
        return self.verdict is Verdict.PASS

    def report(self) -> str:
        """Readable summary: the verdict, why it is inconclusive if it is, each metric against its limit."""
        lines = [f"{self.name}: {self.verdict} ({len(self.metrics)} points)"]
        lines.extend(f"  inconclusive: {reason}" for reason in self.inconclusive)
        lines.extend(f"  inconclusive: {key} could not be computed" for key in self.unmeasured)
        if self.cannot_see:
            lines.append("  cannot see (these wrong components pass too): " + "; ".join(self.cannot_see))
        lines.extend(f"  note: {note}" for note in self.notes)
        lines.extend(f"  record beyond its limit: {line}" for line in self.record_failures)
        for key, value in self.summary.items():
            if key in self.thresholds:
                verdict = "ok" if self.checks[key] else "n/a" if key in self.unmeasured else "FAIL"
                lines.append(f"  {key:40s} {value:10.4g}  (limit {self.thresholds[key]:g}) {verdict}")
            else:
                lines.append(f"  {key:40s} {value:10.4g}" if isinstance(value, (int, float)) else f"  {key}: {value}")
        return "\n".join(lines)
