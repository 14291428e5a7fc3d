"""Parameter sets drawn from an identified part's covariance.

A draw is taken in log space for the positive parameters (stiffnesses, slip forces, rates:
a draw never leaves the model's bounds) and linearly for the signed ones (``g2``, ``g3``),
with the covariance mapped by the Jacobian of the log (``C_log = C / (p p^T)``, first
order). A covariance that round-off left slightly indefinite is projected on the nearest
positive semi-definite one (negative eigenvalues set to 0). Extra common log factors
(``law_log_sd``: ``"stiffness"`` on ``g1``, ``g2``, ``g3``, ``k0`` and every ``k_i``,
``"slip_force"`` on every ``fc_i``) carry the uncertainty of a size predicted from the scaling
laws.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["SIGNED_PARAMETERS", "draw_models"]

#: Parameters drawn linearly (they may change sign).
SIGNED_PARAMETERS = ("g2", "g3")


def _psd_factor(covariance: np.ndarray) -> np.ndarray:
    """``L`` with ``L L^T`` the nearest positive semi-definite matrix (eigenvalues clipped at 0)."""
    values, vectors = np.linalg.eigh(0.5 * (covariance + covariance.T))
    return vectors * np.sqrt(np.clip(values, 0.0, None))


def draw_models(model, names, covariance, n_draws: int, rng: np.random.Generator, *, law_log_sd=None) -> list:
    """``n_draws`` models like ``model`` with parameters drawn from ``covariance`` (module docstring).

    Parameters
    ----------
    model : IsolatorModel
    names : sequence of str
        Parameters ``covariance`` covers (others stay at their values).
    covariance : ndarray, shape (len(names), len(names))
        SI units squared.
    n_draws : int
    rng : numpy.random.Generator
    law_log_sd : dict, optional
        Common log factors' standard deviations (module docstring).
    """
    params = model.params()
    names = list(names)
    keep = [i for i, name in enumerate(names) if name in params]
    names = [names[i] for i in keep]
    covariance = np.asarray(covariance, dtype=float)[np.ix_(keep, keep)] if keep else np.zeros((0, 0))
    values = np.array([params[name] for name in names])
    logged = np.array([name not in SIGNED_PARAMETERS and params[name] > 0 for name in names], dtype=bool)
    jacobian = np.where(logged, 1.0 / np.where(values != 0, values, 1.0), 1.0)
    factor = _psd_factor(covariance * np.outer(jacobian, jacobian)) if names else np.zeros((0, 0))
    law_log_sd = law_log_sd or {}
    models = []
    for _ in range(int(n_draws)):
        drawn = dict(params)
        if names:
            step = factor @ rng.standard_normal(len(names))
            for name, value, delta, is_log in zip(names, values, step, logged):
                drawn[name] = value * math.exp(delta) if is_log else value + delta
        stiffness = math.exp(law_log_sd.get("stiffness", 0.0) * rng.standard_normal())
        force = math.exp(law_log_sd.get("slip_force", 0.0) * rng.standard_normal())
        for name in drawn:
            if name.startswith("fc_"):
                drawn[name] *= force
            elif name in ("g1", "g2", "g3", "k0") or name.startswith("k_"):
                drawn[name] *= stiffness
        models.append(type(model).from_params(drawn))
    return models
