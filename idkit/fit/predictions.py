"""What an identified model predicts for the data it was fitted to, ready to be drawn.

The figures of :mod:`idkit.plot` never run a fitter or a model; they draw the arrays
computed here: the model force along every prepared loop set (with the start state the
fit used) and, for a Maxwell fit, the one-element error landscape. ``idkit fit --plots``,
the notebooks and the report compute these once and hand them to the plots.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from idkit.errors import FitError
from idkit.fit.loop_objective import boucwen_set_forces, iwan_set_forces
from idkit.fit.landscape import ErrorLandscape, maxwell_error_landscape
from idkit.models import BoucWenModel, IwanModel
from idkit.observe.quasi_static import LoopSet

__all__ = ["FitPrediction", "LoopFitPrediction", "LoopPrediction", "predict_fit", "predict_loops"]


@dataclass(frozen=True)
class LoopPrediction:
    """Measured and model force along one prepared loop set.

    Attributes
    ----------
    name : str
        The set's name (its record id).
    deflection : ndarray
        Deflection path in m (positive = tension).
    measured_force, model_force : ndarray
        Forces in N along ``deflection``.
    """

    name: str
    deflection: np.ndarray
    measured_force: np.ndarray
    model_force: np.ndarray


@dataclass(frozen=True)
class LoopFitPrediction:
    """Loop predictions of one loop model on the small- and the large-amplitude sets."""

    small: tuple[LoopPrediction, ...]
    large: tuple[LoopPrediction, ...]


def _set_forces(model, sets: Sequence[LoopSet], initial_state: str) -> list[np.ndarray]:
    if isinstance(model, IwanModel):
        return iwan_set_forces(model, sets, initial_state=initial_state)
    if isinstance(model, BoucWenModel):
        return boucwen_set_forces(model, sets, initial_state=initial_state)
    raise FitError(f"model: found {type(model).__name__}, expected IwanModel or BoucWenModel")


def predict_loops(model: IwanModel | BoucWenModel, small: Sequence[LoopSet], large: Sequence[LoopSet], *,
                  initial_state: str = "auto") -> LoopFitPrediction:
    """Model force along every small and large loop set (the compiled path the fit scores).

    Parameters
    ----------
    model : IwanModel or BoucWenModel
    small, large : sequence of LoopSet
        Prepared sets, e.g. ``fit.data.small`` and ``fit.data.large``.
    initial_state : {"auto", "cycled", "virgin"}
        Element state at each set's first point (as in :func:`idkit.fit.fit_iwan`).

    Returns
    -------
    LoopFitPrediction

    Examples
    --------
    >>> import numpy as np
    >>> from idkit.fit import prepare_loops
    >>> from idkit.models import IwanModel
    >>> model = IwanModel(g1=3e3, k=[3e3], fc=[8.0])
    >>> x = 4e-3 * np.sin(np.linspace(0, 4 * np.pi, 801))
    >>> loops = [prepare_loops(x, model.force(x))]
    >>> prediction = predict_loops(model, loops, loops)
    >>> bool(np.allclose(prediction.small[0].model_force, prediction.small[0].measured_force, atol=1e-9))
    True
    """
    predictions = []
    for sets in (list(small), list(large)):
        forces = _set_forces(model, sets, initial_state) if sets else []
        predictions.append(tuple(
            LoopPrediction(loop_set.name, np.asarray(loop_set.deflection), np.asarray(loop_set.force), force)
            for loop_set, force in zip(sets, forces)))
    return LoopFitPrediction(*predictions)


@dataclass(frozen=True)
class FitPrediction:
    """Everything the figures of one :class:`~idkit.fit.MeasurementFit` draw.

    Attributes
    ----------
    kind : {"iwan", "boucwen", "maxwell"}
    model : IsolatorModel
        The identified model.
    loops : LoopFitPrediction or None
        Loop fits: measured and model force per set.
    frfs : tuple of TransmissibilitySet
        Maxwell fits: the measured transmissibilities.
    band : (float, float) or None
        Maxwell fits: the fitted band, Hz.
    landscape : ErrorLandscape or None
        Maxwell fits: the one-element error over (k_1, rate_1).
    """

    kind: str
    model: object
    loops: LoopFitPrediction | None = None
    frfs: tuple = ()
    band: tuple[float, float] | None = None
    landscape: ErrorLandscape | None = None


def predict_fit(fit, *, landscape: bool = True) -> FitPrediction:
    """The arrays behind the figures of a :class:`~idkit.fit.MeasurementFit`.

    Loop fits: :func:`predict_loops` on ``fit.data``. Maxwell fits: the measured
    transmissibilities and, with ``landscape``, :func:`idkit.fit.maxwell_error_landscape`
    at the fit's k0, band and seed (an order-1 fit and a 41 x 41 grid).
    """
    if fit.kind in ("iwan", "boucwen"):
        return FitPrediction(fit.kind, fit.model, loops=predict_loops(fit.model, fit.data.small, fit.data.large))
    if fit.kind != "maxwell":
        raise FitError(f"fit.kind: found {fit.kind!r}, expected 'iwan', 'boucwen' or 'maxwell'")
    band = tuple(fit.result.settings.band)
    grid = (maxwell_error_landscape(fit.data, k0=fit.model.k0, band=band, seed=fit.result.settings.seed)
            if landscape else None)
    return FitPrediction("maxwell", fit.model, frfs=tuple(fit.data), band=band, landscape=grid)
