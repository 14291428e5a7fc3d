"""Parameter spread by refitting: per repetition, or on seeded resamples of the data sets.

Two schemes (Efron & Tibshirani, *An Introduction to the Bootstrap*, ch. 6):

``"repetition"``
    One refit per repetition of the experiment (every set labelled with that
    repetition number). With the study's 2-3 repetitions this shows the
    repeatability of the identified parameters rather than a full distribution.
``"resample"``
    ``n_resamples`` refits, each on sets drawn with replacement (small and large
    loop sets separately; for transmissibilities, every top mass keeps its count),
    from ``numpy.random.default_rng(seed)``.

Every refit uses the same seeded optimiser settings, so a bootstrap is
reproducible bit for bit for a given ``seed``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.checks import Choice, Whole, accepts
from idkit.errors import FitError

__all__ = ["BootstrapResult", "bootstrap_loops", "bootstrap_transmissibility", "bootstrap_fit",
           "bootstrap_measurements"]

_METHODS = ("repetition", "resample")


@dataclass(frozen=True)
class BootstrapResult:
    """Parameters of every refit and their spread.

    Attributes
    ----------
    method : {"repetition", "resample"}
    seed : int
    names : tuple of str
        Parameter names (the model's declared names).
    units : tuple of str
    samples : ndarray, shape (n_fits, n_params)
        Parameter values of each refit (SI units).
    labels : tuple of str
        What each refit used (``"repetition 2"``, ``"resample 7"``).
    errors : ndarray, shape (n_fits,)
        Mean fit error (fraction) of each refit.
    elapsed_s : float
    """

    method: str
    seed: int
    names: tuple[str, ...]
    units: tuple[str, ...]
    samples: np.ndarray
    labels: tuple[str, ...]
    errors: np.ndarray
    elapsed_s: float

    def summary(self) -> pd.DataFrame:
        """Per parameter: unit, mean, std (ddof 1), 5 % and 95 % quantiles, relative std."""
        samples = self.samples
        std = samples.std(axis=0, ddof=1) if samples.shape[0] > 1 else np.full(samples.shape[1], np.nan)
        mean = samples.mean(axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            relative = np.where(mean != 0, std / np.abs(mean), np.nan)
        return pd.DataFrame({"parameter": list(self.names), "unit": list(self.units), "mean": mean, "std": std,
                             "p05": np.quantile(samples, 0.05, axis=0), "p95": np.quantile(samples, 0.95, axis=0),
                             "relative_std": relative})

    def report(self) -> str:
        """The summary as text with the method, seed and refit count."""
        head = (f"[[Bootstrap: {self.method}, {self.samples.shape[0]} refits, seed {self.seed}, "
                f"{self.elapsed_s:.2f} s; refit errors {100 * self.errors.min():.3f}-{100 * self.errors.max():.3f} %]]")
        return head + "\n" + self.summary().to_string(index=False, float_format=lambda v: f"{v:.5g}")


@accepts(method=Choice(_METHODS), n_resamples=Whole(ge=2), error=FitError)
def bootstrap_fit(fit: Callable[[list[np.ndarray]], object], partitions: Sequence[Sequence], *,
                  method: str = "repetition", n_resamples: int = 20, seed: int = 0,
                  error: Callable[[object], float]) -> BootstrapResult:
    """Generic driver: refit on subsets of several partitions of data sets.

    Parameters
    ----------
    fit : callable
        ``fit(list_of_index_arrays) -> result`` with ``result.model.params()`` and
        ``result.model.param_specs()``; one index array per partition.
    partitions : sequence of sequences
        For each partition (e.g. small sets, large sets), the repetition label of each set.
    method : {"repetition", "resample"}
    n_resamples : int
        Refits of the ``"resample"`` scheme.
    seed : int
    error : callable
        ``error(result)`` -> mean fit error (fraction).
    """
    partitions = [list(p) for p in partitions]
    plans: list[tuple[str, list[np.ndarray]]] = []
    if method == "repetition":
        labels = sorted({label for p in partitions for label in p}, key=str)
        for label in labels:
            chosen = [np.flatnonzero(np.array([item == label for item in p])) for p in partitions]
            if any(c.size == 0 for c in chosen):
                continue
            plans.append((f"repetition {label}", chosen))
        if len(plans) < 2:
            raise FitError(f"bootstrap: found {len(plans)} repetition(s) present in every group "
                           f"(labels {labels}), expected at least 2; use method='resample'")
    else:
        rng = np.random.default_rng(int(seed))
        for index in range(int(n_resamples)):
            plans.append((f"resample {index + 1}",
                          [np.sort(rng.integers(0, len(p), size=len(p))) for p in partitions]))
    t0 = time.perf_counter()
    samples, errors, names, units = [], [], None, None
    for _, chosen in plans:
        result = fit(chosen)
        params = result.model.params()
        if names is None:
            names = tuple(params)
            specs = {spec.name: spec.unit for spec in result.model.param_specs()}
            units = tuple(specs.get(name, "") for name in names)
        samples.append([params[name] for name in names])
        errors.append(error(result))
    return BootstrapResult(method=method, seed=int(seed), names=names, units=units,
                           samples=np.asarray(samples, dtype=float), labels=tuple(label for label, _ in plans),
                           errors=np.asarray(errors, dtype=float), elapsed_s=time.perf_counter() - t0)


def bootstrap_loops(fitter: Callable, small: Sequence, large: Sequence, *, small_groups: Sequence | None = None,
                    large_groups: Sequence | None = None, method: str = "repetition", n_resamples: int = 20,
                    seed: int = 0, **fit_options) -> BootstrapResult:
    """Bootstrap of a loop fit (:func:`idkit.fit.fit_iwan` or :func:`idkit.fit.fit_boucwen`).

    Parameters
    ----------
    fitter : callable
        ``fitter(small, large, seed=seed, **fit_options)``.
    small, large : sequence of LoopSet (or pairs)
    small_groups, large_groups : sequence, optional
        Repetition label of each set; default ``1, 2, ...`` (each set its own repetition).
    method, n_resamples, seed : see :func:`bootstrap_fit`

    Examples
    --------
    >>> from idkit.fit import fit_iwan                     # doctest: +SKIP
    >>> spread = bootstrap_loops(fit_iwan, small, large, method="resample", n_resamples=20)  # doctest: +SKIP
    >>> spread.summary()                                   # doctest: +SKIP
    """
    small, large = list(small), list(large)
    small_groups = list(range(1, len(small) + 1)) if small_groups is None else list(small_groups)
    large_groups = list(range(1, len(large) + 1)) if large_groups is None else list(large_groups)
    if len(small_groups) != len(small) or len(large_groups) != len(large):
        raise FitError(f"groups: found {len(small_groups)} small and {len(large_groups)} large labels for "
                       f"{len(small)} small and {len(large)} large sets, expected one label per set")

    def fit(chosen):
        return fitter([small[i] for i in chosen[0]], [large[i] for i in chosen[1]], seed=seed, **fit_options)

    return bootstrap_fit(fit, [small_groups, large_groups], method=method, n_resamples=n_resamples, seed=seed,
                         error=lambda r: 0.5 * (r.error_small + r.error_large))


def bootstrap_transmissibility(frfs: Sequence, *, k0: float, groups: Sequence | None = None,
                               method: str = "repetition", n_resamples: int = 20, seed: int = 0,
                               fitter: Callable | None = None, **fit_options) -> BootstrapResult:
    """Bootstrap of :func:`idkit.fit.fit_maxwell` over transmissibility sets.

    ``groups`` labels each set with its repetition (default: each set its own).
    ``"resample"`` draws sets with replacement among those of the same top mass,
    so every mass keeps its weight.
    """
    from idkit.fit.frf_objective import as_transmissibility_sets
    from idkit.fit.maxwell import fit_maxwell

    fitter = fit_maxwell if fitter is None else fitter
    sets = as_transmissibility_sets(frfs)
    groups = list(range(1, len(sets) + 1)) if groups is None else list(groups)
    if len(groups) != len(sets):
        raise FitError(f"groups: found {len(groups)} labels for {len(sets)} sets, expected one per set")
    masses = sorted({s.mass for s in sets})
    by_mass = [[i for i, s in enumerate(sets) if s.mass == m] for m in masses]
    if method == "repetition":
        def fit(chosen):
            return fitter([sets[i] for i in chosen[0]], k0=k0, seed=seed, **fit_options)

        return bootstrap_fit(fit, [groups], method=method, n_resamples=n_resamples, seed=seed,
                             error=lambda r: r.error)

    def fit(chosen):  # one partition per mass: resample within each mass
        picked = [by_mass[j][i] for j, indices in enumerate(chosen) for i in indices]
        return fitter([sets[i] for i in picked], k0=k0, seed=seed, **fit_options)

    return bootstrap_fit(fit, [[groups[i] for i in members] for members in by_mass], method=method,
                         n_resamples=n_resamples, seed=seed, error=lambda r: r.error)


def bootstrap_measurements(fit, *, method: str = "repetition", n_resamples: int = 20,
                           seed: int | None = None) -> BootstrapResult:
    """Bootstrap a :class:`~idkit.fit.MeasurementFit` with its own data and settings.

    Loop fits are refitted per repetition (``info.repetition`` of the records) or on
    resampled sets, with the fit's order, backend, start state and (Iwan) valid range, each
    Iwan refit started at the full data's optimum (a slip-modulated fit, ``settings.family ==
    "modulated"``: its modulation stage from the full data's modulated model); Maxwell fits likewise over the
    transmissibility sets, with ``k0`` held at the value of the original fit. ``seed`` defaults to the fit's seed.
    """
    from idkit.fit.boucwen import fit_boucwen
    from idkit.fit.iwan import fit_iwan
    from idkit.fit.maxwell import fit_maxwell

    settings = fit.result.settings
    seed = settings.seed if seed is None else int(seed)
    if fit.kind in ("iwan", "boucwen"):
        data = fit.data
        if fit.kind == "iwan" and getattr(settings, "family", "plain") == "modulated":
            from idkit.fit.iwan_modulated import fit_iwan_modulated

            start = fit.result.model

            def fitter(small, large, seed, **options):  # the modulation stage from the full data's optimum
                return fit_iwan_modulated(small, large, plain=start, **options).to_iwan_result(settings)

            options = {"initial_state": settings.initial_state, "valid_range": settings.valid_range}
        elif fit.kind == "iwan":
            fitter = fit_iwan
            # every refit starts at the full data's optimum (the usual bootstrap start): from the
            # loops' own start estimate a refit can land in another minimum of near-equal error,
            # which would count the optimiser's choice as spread
            options = {"start": fit.result.model, "backend": settings.backend,
                       "initial_state": settings.initial_state, "valid_range": settings.valid_range}
        else:
            fitter = fit_boucwen
            options = {"backend": settings.backend, "global_search": settings.global_search,
                       "global_max_evals": settings.global_max_evals, "initial_state": settings.initial_state}
        return bootstrap_loops(fitter, data.small, data.large, small_groups=data.small_repetitions,
                               large_groups=data.large_repetitions, method=method, n_resamples=n_resamples,
                               seed=seed, **options)
    if fit.kind == "maxwell":
        k0 = fit.model.k0
        options = {"order": settings.order, "band": settings.band, "backend": settings.backend,
                   "monotone_loss": settings.monotone_loss}
        return bootstrap_transmissibility(fit.data, k0=k0, groups=fit.repetitions or None, method=method,
                                          n_resamples=n_resamples, seed=seed, fitter=fit_maxwell, **options)
    raise FitError(f"fit.kind: found {fit.kind!r}, expected 'iwan', 'boucwen' or 'maxwell'")
