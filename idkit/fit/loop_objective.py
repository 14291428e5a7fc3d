"""The compiled loop objective (7.1) of the Iwan and Bouc-Wen fits.

Each data set is a path starting at a reversal (:class:`~idkit.observe.quasi_static.LoopSet`)
scored by the relative RMS force error (7.1)::

    e = sqrt(sum (F_model - F_meas)^2 / sum F_meas^2)

All sets of a stage are concatenated into flat arrays (:class:`PackedLoops`) and one
compiled (numba) call runs the model over all of them without per-point Python work or
allocations: :class:`IwanLoops` with the stop operator of :func:`idkit.models.laws.jenkin_step`
and the spring :func:`~idkit.models.laws.polynomial_spring_force`, :class:`BoucWenLoops`
with the ``z`` equation of :func:`idkit.models.laws.boucwen_z_step`.

**Initial state.** A set starts at a reversal, where the hysteretic state depends on the
earlier history. ``"virgin"``: the state is taken unloaded at zero deflection and loaded
to the first point of the set, exact when the record itself starts unloaded. ``"cycled"``:
then run once over the whole set and back to its first point, the state of steady
cycling. ``"auto"`` chooses per set: "virgin" when the record starts unloaded
(:attr:`LoopSet.starts_unloaded`), else "cycled".
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.checks import Choice, accepts
from idkit.errors import FitError
from idkit.models import BoucWenModel, IwanModel, ModulatedIwanModel
from idkit.models.laws import (boucwen_z_step, jenkin_step, polynomial_spring_force, scaled_jenkin_step,
                               slip_scale)
from idkit.observe.quasi_static import LoopSet

__all__ = ["START_STATES", "INITIAL_STATE", "set_start_state", "PackedLoops", "IwanLoops", "BoucWenLoops",
           "iwan_set_errors", "iwan_set_forces", "boucwen_set_errors", "boucwen_set_forces", "cycled_flags",
           "modulated_forces", "modulated_errors", "modulated_set_errors", "modulated_set_forces",
           "law_set_forces", "law_set_errors"]

START_STATES = ("auto", "cycled", "virgin")
_H_LAMBDA = 1.0  # RK4 sub-step times the stiffness of the z equation (see _max_substep)
_MAX_SUBSTEPS = 16  # per sample; only parameter sets far from any fit (tiny z_max) need more
_MAX_JUMP_SUBSTEPS = 4096  # loading 0 -> x[0] and the return x[-1] -> x[0] span a whole loop


#: The declared ``initial_state`` of every loop function (:mod:`idkit.checks`).
INITIAL_STATE = Choice(START_STATES)


def set_start_state(loop_set: LoopSet, initial_state: str) -> str:
    """``"virgin"`` or ``"cycled"`` for one set; ``"auto"`` reads it off the record's start."""
    if initial_state == "auto":
        return "virgin" if loop_set.starts_unloaded else "cycled"
    return initial_state


class PackedLoops:
    """Sets concatenated into flat arrays for a compiled objective.

    Parameters
    ----------
    sets : sequence of LoopSet
    initial_state : {"auto", "cycled", "virgin"}

    Attributes
    ----------
    names, start_states : tuple of str
    cycled : ndarray of bool
        Start state of each set.
    x, f : ndarray
        Concatenated deflection (m) and force (N).
    offsets : ndarray of int64
        Set ``s`` is ``x[offsets[s]:offsets[s + 1]]``.
    norm, norm2 : ndarray
        ``|F_meas|`` and its square per set.
    sources : ndarray
        Concatenated :attr:`LoopSet.source_index` (NaN where a set has none): the raw samples
        the points interpolate, for the standard errors.
    """

    def __init__(self, sets: Sequence[LoopSet], initial_state: str):
        self.names = tuple(s.name for s in sets)
        self.start_states = tuple(set_start_state(s, initial_state) for s in sets)
        self.cycled = np.array([state == "cycled" for state in self.start_states], dtype=np.bool_)
        self.x = np.ascontiguousarray(np.concatenate([s.deflection for s in sets]))
        self.f = np.ascontiguousarray(np.concatenate([s.force for s in sets]))
        self.offsets = np.concatenate([[0], np.cumsum([s.deflection.size for s in sets])]).astype(np.int64)
        self.norm = np.array([math.sqrt(float(np.sum(s.force**2))) for s in sets])
        # the raw-sample index of every point (NaN: a measured sample of its own), for the statistics
        self.sources = np.concatenate([np.full(s.deflection.size, np.nan) if getattr(s, "source_index", None) is None
                                       else np.asarray(s.source_index, dtype=float) for s in sets])
        self.norm2 = self.norm**2
        self.errors = np.empty(len(sets))

    def split(self, values: np.ndarray) -> list[np.ndarray]:
        """A concatenated per-point array cut back into one copy per set."""
        return [values[a:b].copy() for a, b in zip(self.offsets[:-1], self.offsets[1:])]

    def normalised(self, forces: np.ndarray) -> np.ndarray:
        """Per-set normalised residuals ``(F_model - F_meas) / |F_meas|_set``."""
        return (forces - self.f) / np.repeat(self.norm, np.diff(self.offsets))


# --------------------------------------------------------------------------- Iwan


@numba.njit(cache=True)
def _start_state(state, stiffness, friction, x, a, b, cycled):
    """Element forces at the first point of set ``x[a:b]``; returns their sum (N).

    Unloaded at x = 0 and loaded to the first point; if ``cycled``, the set is run
    once and closed back to its first point (module docstring).
    """
    for j in range(state.shape[0]):
        state[j] = 0.0
    jenkin_step(state, stiffness, friction, x[a])
    if cycled:
        for i in range(a + 1, b):
            jenkin_step(state, stiffness, friction, x[i] - x[i - 1])
        jenkin_step(state, stiffness, friction, x[a] - x[b - 1])
    jenkin = 0.0
    for j in range(state.shape[0]):
        jenkin += state[j]
    return jenkin


@numba.njit(cache=True)
def _iwan_set_forces(x, offsets, g1, g2, g3, stiffness, friction, cycled, out):
    """Model force of every set of a concatenated path (``offsets`` delimit the sets;
    ``cycled[s]`` selects the start state of set ``s``)."""
    state = np.empty(stiffness.shape[0])
    for s in range(offsets.shape[0] - 1):
        a = offsets[s]
        b = offsets[s + 1]
        jenkin = _start_state(state, stiffness, friction, x, a, b, cycled[s])
        for i in range(a, b):
            if i > a:
                jenkin = jenkin_step(state, stiffness, friction, x[i] - x[i - 1])
            out[i] = polynomial_spring_force(x[i], g1, g2, g3) + jenkin


@numba.njit(cache=True)
def _iwan_set_errors(x, f, offsets, norm2, g1, g2, g3, stiffness, friction, cycled, out):
    """Relative RMS error (7.1) of every set, written to ``out``; no allocation per point."""
    state = np.empty(stiffness.shape[0])
    for s in range(offsets.shape[0] - 1):
        a = offsets[s]
        b = offsets[s + 1]
        jenkin = _start_state(state, stiffness, friction, x, a, b, cycled[s])
        acc = 0.0
        for i in range(a, b):
            if i > a:
                jenkin = jenkin_step(state, stiffness, friction, x[i] - x[i - 1])
            diff = polynomial_spring_force(x[i], g1, g2, g3) + jenkin - f[i]
            acc += diff * diff
        out[s] = math.sqrt(acc / norm2[s])


class IwanLoops(PackedLoops):
    """Packed sets with the Iwan force law (parameters ``g1, g2, g3, k, fc`` in SI units)."""

    def evaluate(self, g1, g2, g3, stiffness, friction) -> None:
        """Write the per-set errors (7.1) into :attr:`errors` (no copy: the fast path of a stage)."""
        _iwan_set_errors(self.x, self.f, self.offsets, self.norm2, g1, g2, g3, stiffness, friction,
                         self.cycled, self.errors)

    def set_errors(self, g1, g2, g3, stiffness, friction) -> np.ndarray:
        """Per-set errors (7.1), fractions."""
        self.evaluate(g1, g2, g3, stiffness, friction)
        return self.errors.copy()

    def forces(self, g1, g2, g3, stiffness, friction) -> np.ndarray:
        """Model force (N) at every concatenated point."""
        out = np.empty_like(self.x)
        _iwan_set_forces(self.x, self.offsets, g1, g2, g3, stiffness, friction, self.cycled, out)
        return out

    def residuals(self, g1, g2, g3, stiffness, friction) -> np.ndarray:
        """Per-set normalised residuals ``(F_model - F_meas) / |F_meas|_set``."""
        return self.normalised(self.forces(g1, g2, g3, stiffness, friction))


def _iwan_args(model: IwanModel):
    return (model.g1, model.g2, model.g3, np.array(model.k, dtype=np.float64), np.array(model.fc, dtype=np.float64))


@accepts(initial_state=INITIAL_STATE, error=FitError)
def iwan_set_errors(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> np.ndarray:
    """Relative RMS error (7.1) of ``model`` on each prepared set (fractions, 0.01 = 1 %).

    Parameters
    ----------
    model : IwanModel
    sets : sequence of LoopSet
        From :func:`~idkit.observe.quasi_static.prepare_loops`.
    initial_state : {"auto", "cycled", "virgin"}
        Element forces at the first point (module docstring).

    Returns
    -------
    ndarray
        One error per set.

    A :class:`~idkit.models.ModulatedIwanModel` is scored with its slip modulation
    (:func:`modulated_set_errors`), never as the plain model.
    """
    if isinstance(model, ModulatedIwanModel):
        return modulated_set_errors(model, sets, initial_state=initial_state)
    if type(model) is not IwanModel:
        return law_set_errors(model, sets, initial_state=initial_state)
    return IwanLoops(list(sets), initial_state).set_errors(*_iwan_args(model))


@accepts(initial_state=INITIAL_STATE, error=FitError)
def iwan_set_forces(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> list[np.ndarray]:
    """Model force (N) along each prepared set, with the initial element state used by the fit.

    Parameters
    ----------
    model : IwanModel
    sets : sequence of LoopSet
    initial_state : {"auto", "cycled", "virgin"}

    Returns
    -------
    list of ndarray
        One force array per set (a modulated model with its slip modulation).
    """
    if isinstance(model, ModulatedIwanModel):
        return modulated_set_forces(model, sets, initial_state=initial_state)
    if type(model) is not IwanModel:
        return law_set_forces(model, sets, initial_state=initial_state)
    packed = IwanLoops(list(sets), initial_state)
    return packed.split(packed.forces(*_iwan_args(model)))


@accepts(initial_state=INITIAL_STATE, error=FitError)
def law_set_forces(model, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> list[np.ndarray]:
    """Force (N) along each prepared set from the model's own force law (``model.force``), for
    models without a packed loop kernel (e.g. the elements of :mod:`idkit.models.clearance`):
    loaded monotonically from the unloaded state to the first point and, for a cycled set, run
    through the set once before the pass that is kept, as the packed kernels do."""
    forces = []
    for loop_set in sets:
        x = np.asarray(loop_set.deflection, dtype=float)
        passes = 2 if set_start_state(loop_set, initial_state) == "cycled" else 1
        path = np.concatenate([[0.0]] + [x] * passes)
        forces.append(np.asarray(model.force(path), dtype=float)[path.size - x.size:])
    return forces


def law_set_errors(model, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> np.ndarray:
    """Error (7.1) as a fraction of ``model`` on each prepared set, from :func:`law_set_forces`."""
    return np.array([np.sqrt(np.sum((f - s.force) ** 2) / np.sum(s.force**2))
                     for f, s in zip(law_set_forces(model, sets, initial_state=initial_state), sets)])


# --------------------------------------------------------------------------- slip-modulated Iwan


@numba.njit(cache=True)
def _modulated_set_forces(x, g1, g2, g3, k, fc, a, b, length, cycled, out):
    """Force (N) of the slip-modulated Iwan model along one set ``x`` (m), from the virgin or the
    cycled start state, written to ``out``."""
    state = np.zeros(k.shape[0])
    scale0 = slip_scale(x[0], a, b, length)
    scaled_jenkin_step(state, k, fc, scale0, x[0])  # monotone loading from the unloaded state
    passes = 2 if cycled else 1
    for p in range(passes):
        if p == 1:  # back from the last point to the first (one linear step), then score
            scaled_jenkin_step(state, k, fc, scale0, x[0] - x[x.shape[0] - 1])
        for s in range(x.shape[0]):
            y = x[s]
            if s > 0:
                scaled_jenkin_step(state, k, fc, slip_scale(y, a, b, length), y - x[s - 1])
            total = polynomial_spring_force(y, g1, g2, g3)
            for i in range(state.shape[0]):
                total += state[i]
            out[s] = total


@accepts(initial_state=INITIAL_STATE, error=FitError)
def cycled_flags(sets: Sequence[LoopSet], initial_state: str) -> list[bool]:
    """Whether each set starts from the cycled state (``initial_state``: :data:`START_STATES`)."""
    return [set_start_state(loop_set, initial_state) == "cycled" for loop_set in sets]


def modulated_forces(model: ModulatedIwanModel, sets: Sequence[LoopSet], cycled: Sequence[bool]) -> list[np.ndarray]:
    """Force (N) of ``model`` along each set, each from the start state ``cycled`` gives."""
    forces = []
    for loop_set, is_cycled in zip(sets, cycled):
        out = np.empty(loop_set.deflection.size)
        _modulated_set_forces(loop_set.deflection, model.g1, model.g2, model.g3, np.ascontiguousarray(model.k, float),
                              np.ascontiguousarray(model.fc, float), model.slip_modulation, model.slip_growth,
                              model.slip_length, bool(is_cycled), out)
        forces.append(out)
    return forces


def modulated_errors(model: ModulatedIwanModel, sets: Sequence[LoopSet], cycled: Sequence[bool]) -> np.ndarray:
    """Error (7.1) as a fraction of ``model`` on each set, each from the start state ``cycled`` gives."""
    return np.array([np.sqrt(np.sum((f - s.force) ** 2) / np.sum(s.force**2))
                     for f, s in zip(modulated_forces(model, sets, cycled), sets)])


def modulated_set_errors(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> np.ndarray:
    """Error (7.1) as a fraction of ``model`` (plain or modulated Iwan) on each prepared set."""
    if not isinstance(model, ModulatedIwanModel):
        model = ModulatedIwanModel.from_iwan(model)
    return modulated_errors(model, sets, cycled_flags(sets, initial_state))


def modulated_set_forces(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> list[np.ndarray]:
    """Force (N) of ``model`` (plain or modulated Iwan) along each prepared set, from the start
    state the fit uses."""
    if not isinstance(model, ModulatedIwanModel):
        model = ModulatedIwanModel.from_iwan(model)
    return modulated_forces(model, sets, cycled_flags(sets, initial_state))


# --------------------------------------------------------------------------- Bouc-Wen


@numba.njit(cache=True)
def _z_step(z, dx, alpha, beta, gamma, n, max_substep, cap):
    """RK4 over ``dx`` in sub-steps no longer than ``max_substep`` (at least one, at most ``cap``)."""
    count = 1
    if max_substep > 0.0:
        needed = int(math.ceil(abs(dx) / max_substep))
        if needed > count:
            count = min(needed, cap)
    z, _ = boucwen_z_step(z, dx, alpha, beta, gamma, n, count)
    return z


@numba.njit(cache=True)
def _bw_forces(x, offsets, k1, k2, k3, alpha, beta, gamma, n, c, cycled, max_substep, out):
    # np.int64(...): a bare module constant would be typed as a literal, one compiled _z_step per value
    for s in range(offsets.shape[0] - 1):
        a = offsets[s]
        b = offsets[s + 1]
        z = _z_step(0.0, x[a], alpha, beta, gamma, n, max_substep, np.int64(_MAX_JUMP_SUBSTEPS))
        if cycled[s]:
            for i in range(a + 1, b):
                z = _z_step(z, x[i] - x[i - 1], alpha, beta, gamma, n, max_substep, np.int64(_MAX_SUBSTEPS))
            z = _z_step(z, x[a] - x[b - 1], alpha, beta, gamma, n, max_substep, np.int64(_MAX_JUMP_SUBSTEPS))
        for i in range(a, b):
            if i > a:
                z = _z_step(z, x[i] - x[i - 1], alpha, beta, gamma, n, max_substep, np.int64(_MAX_SUBSTEPS))
            xi = x[i]
            out[i] = math.exp(c * xi) * (xi * (k1 + k2 * abs(xi) + k3 * xi * xi) + z)


def _max_substep(p: dict) -> float:
    """Sub-step length (m) with ``h lambda <= 1`` for RK4: ``lambda = n (|beta| + |gamma|) z_max^(n-1)``.

    ``lambda`` bounds ``|d(dz/dx)/dz|`` for ``|z| <= z_max``, the stiffness of the z equation;
    a sub-step within ``1 / lambda`` keeps RK4 stable and accurate (relative force error below ~3e-5
    in the transients after a reversal, exact at saturation).
    """
    total = p["beta"] + p["gamma"]
    if not (total > 0 and p["alpha"] > 0):
        return 0.0
    z_max = (p["alpha"] / total) ** (1.0 / p["n"])
    lam = p["n"] * (abs(p["beta"]) + abs(p["gamma"])) * z_max ** (p["n"] - 1.0)
    return _H_LAMBDA / lam if lam > 0 and math.isfinite(lam) else 0.0


@numba.njit(cache=True)
def _bw_errors(x, f, offsets, norm2, k1, k2, k3, alpha, beta, gamma, n, c, cycled, max_substep, scratch, out):
    _bw_forces(x, offsets, k1, k2, k3, alpha, beta, gamma, n, c, cycled, max_substep, scratch)
    for s in range(offsets.shape[0] - 1):
        acc = 0.0
        for i in range(offsets[s], offsets[s + 1]):
            diff = scratch[i] - f[i]
            acc += diff * diff
        out[s] = math.sqrt(acc / norm2[s])


class BoucWenLoops(PackedLoops):
    """Packed sets with the Bouc-Wen force law; parameters as a dict ``k1, k2, k3, alpha,
    beta, gamma, n, c`` (SI units, the asymmetry factor ``exp(c x)``)."""

    def __init__(self, sets: Sequence[LoopSet], initial_state: str):
        super().__init__(sets, initial_state)
        self.scratch = np.empty_like(self.x)

    def set_errors(self, p: dict) -> np.ndarray:
        """Per-set errors (7.1), fractions."""
        _bw_errors(self.x, self.f, self.offsets, self.norm2, p["k1"], p["k2"], p["k3"], p["alpha"], p["beta"],
                   p["gamma"], p["n"], p["c"], self.cycled, _max_substep(p), self.scratch, self.errors)
        return self.errors.copy()

    def forces(self, p: dict) -> np.ndarray:
        """Model force (N) at every concatenated point."""
        out = np.empty_like(self.x)
        _bw_forces(self.x, self.offsets, p["k1"], p["k2"], p["k3"], p["alpha"], p["beta"], p["gamma"], p["n"],
                   p["c"], self.cycled, _max_substep(p), out)
        return out

    def residuals(self, p: dict) -> np.ndarray:
        """Per-set normalised residuals ``(F_model - F_meas) / |F_meas|_set``."""
        return self.normalised(self.forces(p))


def boucwen_values(model: BoucWenModel) -> dict:
    """The loop objective's parameters of a rate-independent Bouc-Wen model (``c`` as ``c ln b``)."""
    if model.c_visc:
        raise FitError("model: found c_visc != 0, expected a rate-independent Bouc-Wen model for loops")
    return {"k1": model.k1, "k2": model.k2, "k3": model.k3, "alpha": model.alpha, "beta": model.beta,
            "gamma": model.gamma, "n": model.n, "c": model.c * math.log(model.b) if model.b > 0 else 0.0}


@accepts(initial_state=INITIAL_STATE, error=FitError)
def boucwen_set_errors(model: BoucWenModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> np.ndarray:
    """Relative RMS error (7.1) of a Bouc-Wen ``model`` on each prepared set (fractions).

    Parameters
    ----------
    model : BoucWenModel
    sets : sequence of LoopSet
        From :func:`~idkit.observe.quasi_static.prepare_loops`.
    initial_state : {"auto", "cycled", "virgin"}
        ``z`` at the first point (module docstring); ``"virgin"``: ``z`` loaded from 0 only.

    Returns
    -------
    ndarray
        One error per set.
    """
    if type(model) is not BoucWenModel:
        return law_set_errors(model, sets, initial_state=initial_state)
    return BoucWenLoops(list(sets), initial_state).set_errors(boucwen_values(model))


@accepts(initial_state=INITIAL_STATE, error=FitError)
def boucwen_set_forces(model: BoucWenModel, sets: Sequence[LoopSet], *,
                       initial_state: str = "auto") -> list[np.ndarray]:
    """Model force (N) along each prepared set, with the initial state used by the fit.

    Returns
    -------
    list of ndarray
        One force array per set.
    """
    if type(model) is not BoucWenModel:
        return law_set_forces(model, sets, initial_state=initial_state)
    packed = BoucWenLoops(list(sets), initial_state)
    return packed.split(packed.forces(boucwen_values(model)))
