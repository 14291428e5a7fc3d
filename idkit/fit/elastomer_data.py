"""The elastomer's observables for a Maxwell fit, selected once from a measurement set.

:func:`elastomer_data` picks the white-noise runs and quasi-static records of one isolator and
split (:func:`idkit.io.selection.select_measurements`), turns them into one H1 per run
(:func:`~idkit.observe.white_noise.transmissibility_sets`) and a static stiffness k0 read off the
loops (:func:`idkit.fit.static_stiffness.k0_with_relaxation` or the secant of
:func:`~idkit.observe.k0.k0_from_records`), with the tangent stiffness under each top
mass's preload; :func:`idkit.fit.fit_maxwell_measurements` fits them.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from idkit.checks import Choice, accepts
from idkit.errors import FitError
from idkit.fit.static_stiffness import K0_METHODS, k0_with_relaxation
from idkit.gravity import STANDARD_GRAVITY
from idkit.io import QuasiStaticMeasurement
from idkit.io.selection import ONLY_ISOLATOR, DataProvenance, resolve_isolator, select_measurements
from idkit.observe.k0 import K0FromLoops, k0_from_records, static_operating_point
from idkit.observe.white_noise import FRF_RESOLUTION_HZ, TransmissibilitySet, transmissibility_sets

__all__ = ["ElastomerData", "elastomer_data"]


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
        Top mass (kg) -> :class:`~idkit.observe.k0.StaticOperatingPoint` under its
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


@accepts(k0_method=Choice(K0_METHODS), error=FitError)  # k0_window, resolution_hz: the observers'; k0: fit_maxwell
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
        (:func:`~idkit.observe.k0.k0_from_records`, window ``k0_window``).
    k0_window : float, default 1e-3
        Half-width (m) of the deflection window of the k0 estimate.
    k0_method : {"relaxation", "secant"}, default "relaxation"
        ``"relaxation"``: the loops' time history fitted with the relaxation of elements that
        have not relaxed at the zero crossings (:func:`idkit.fit.static_stiffness.k0_with_relaxation`);
        ``"secant"``: the slope of the loops around zero
        (:func:`~idkit.observe.k0.k0_from_records`), biased high by such elements.
    isolator : str or None, default: the only isolator with white-noise records
        As :func:`~idkit.fit.fit_iwan_measurements`, among the isolators with white-noise runs.
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
