"""Common interface of isolator models.

An isolator model maps a deflection history (m, positive = tension) to a force
(N). Parameters are declared once (:class:`idkit.params.ParamSpec`) and
exposed by name through :meth:`IsolatorModel.params`; fitters build models with
:meth:`IsolatorModel.from_params`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from idkit.errors import ParameterError
from idkit.params import ParamSpec

__all__ = ["IsolatorModel", "IsolatorArrays"]

M_EFF_SPEC = ParamSpec(
    "m_eff", "kg", 0.0, np.inf, "isolator mass moving with the mass above it", positive=False
)
C_VISC_SPEC = ParamSpec(
    "c_visc", "N s/m", 0.0, np.inf, "small parallel viscous damping", positive=False
)


@dataclass(frozen=True)
class IsolatorArrays:
    """Flat numeric description of an isolator for the compiled simulator.

    The force of any supported isolator is
    ``P(x) + sum Jenkin + sum k_i u_i + c_visc * xdot + BoucWen(x, z)`` where every
    part may be empty. ``boucwen`` is ``[active, k1, k2, k3, alpha, beta, gamma, n, b, c]``.
    ``slip_modulation`` is ``[a, y_ref, b]``: the Jenkin slip forces are scaled by
    ``1 - a t + b t^2``, ``t = tanh(x / y_ref)`` (:mod:`idkit.models.iwan_modulated`; ``a = b =
    0``: constant). ``clearance`` (m) puts every Jenkin element behind a clearance of that
    half-width; ``jenkin_friction`` then holds the widened limits ``fc_i + k_i gap`` of the
    elements' virtual forces (:mod:`idkit.models.clearance`). ``slip_rate`` is ``[r, v_ref]``:
    the slip forces are ``fc_i (1 + r tanh(|v| / v_ref))`` at the deflection rate ``v``
    (:mod:`idkit.models.rate_dependent`; ``r = 0``: constant). ``pinching`` is ``[pinch,
    width, shift]`` (-, N, N) of the Bouc-Wen ``z`` law (:mod:`idkit.models.boucwen_pinched`;
    ``pinch = 0``: none).
    """

    poly: np.ndarray  # (3,) g1 [N/m], g2 [N/m^2], g3 [N/m^3]
    c_visc: float  # N s/m
    jenkin_stiffness: np.ndarray  # (n_j,) N/m
    jenkin_friction: np.ndarray  # (n_j,) N
    maxwell_stiffness: np.ndarray  # (n_m,) N/m
    maxwell_rate: np.ndarray  # (n_m,) 1/s
    boucwen: np.ndarray  # (10,)
    slip_modulation: np.ndarray = field(default_factory=lambda: np.zeros(3))  # (3,) a [-], y_ref [m], b [-]
    clearance: float = 0.0  # m, half-width of the clearance before every Jenkin element
    slip_rate: np.ndarray = field(default_factory=lambda: np.zeros(2))  # (2,) r [-], v_ref [m/s]
    pinching: np.ndarray = field(default_factory=lambda: np.zeros(3))  # (3,) pinch [-], width [N], shift [N]


class IsolatorModel(ABC):
    """Abstract isolator: parameters by name, quasi-static force, model-file dict."""

    kind: ClassVar[str]

    @abstractmethod
    def param_specs(self) -> tuple[ParamSpec, ...]:
        """Declarations of this model's parameters, in vector order."""

    @abstractmethod
    def params(self) -> dict[str, float]:
        """Parameter values by declared name (SI units), in vector order."""

    @classmethod
    @abstractmethod
    def from_params(cls, params: dict[str, float]) -> IsolatorModel:
        """Build the model from a name -> value mapping (as written by :meth:`params`)."""

    @abstractmethod
    def force(self, deflection, time=None) -> np.ndarray:
        """Quasi-static isolator force in N along a deflection history in m."""

    @abstractmethod
    def small_amplitude_stiffness(self, freq) -> np.ndarray:
        """Complex stiffness in N/m at ``freq`` (Hz) for vanishing amplitude."""

    @abstractmethod
    def kernel_arrays(self) -> IsolatorArrays:
        """The flat description used by :mod:`idkit.simulate`."""

    @property
    def m_eff(self) -> float:  # overridden by models that carry it
        """Isolator mass in kg moving with the mass above it (0 unless identified)."""
        return 0.0

    def to_vector(self) -> np.ndarray:
        """Parameter values as an array in the order of :meth:`param_specs`."""
        return np.array(list(self.params().values()), dtype=float)

    def with_vector(self, vector) -> IsolatorModel:
        """A model of the same structure with parameters taken from ``vector``."""
        names = [spec.name for spec in self.param_specs()]
        vector = np.asarray(vector, dtype=float)
        if vector.shape != (len(names),):
            raise ParameterError(
                f"{type(self).__name__}: found a parameter vector of shape {vector.shape}, "
                f"expected ({len(names)},) for {names}"
            )
        return type(self).from_params(dict(zip(names, vector.tolist())))

    def to_dict(self) -> dict:
        """Model-file representation: kind, parameter values and their units."""
        return {
            "kind": self.kind,
            "params": self.params(),
            "units": {spec.name: spec.unit for spec in self.param_specs()},
        }

    def __eq__(self, other) -> bool:
        return type(self) is type(other) and self.params() == other.params()

    def __hash__(self) -> int:
        return hash((self.kind, tuple(self.params().items())))

    def __repr__(self) -> str:
        units = {spec.name: spec.unit for spec in self.param_specs()}
        body = ", ".join(f"{name}={value:.4g} {units[name]}" for name, value in self.params().items())
        return f"{type(self).__name__}({body})"


#: Largest |frequency| in Hz a model takes: its angular frequency ``2 pi f`` is a finite float64.
MAX_FREQUENCY = float(np.finfo(np.float64).max) / (2.0 * np.pi)


def _as_frequency(freq, name: str = "freq") -> np.ndarray:
    """``freq`` as a float array of finite frequencies in Hz, else a :class:`ParameterError` naming ``name``.

    NaN and infinite frequencies made numpy warn inside the complex stiffness (``complex_stiffness(nan)``:
    RuntimeWarning "invalid value") and gave NaN; text, booleans and complex numbers are not frequencies.
    """
    raw = np.asarray(freq) if not isinstance(freq, (str, bytes)) else np.asarray([freq])
    if raw.dtype.kind not in "iuf":
        if raw.dtype.kind == "O":
            try:
                raw = np.asarray(freq, dtype=float)
            except (TypeError, ValueError):
                pass
        if raw.dtype.kind not in "iuf":
            raise ParameterError(f"{name}: found {freq!r}, expected real frequencies in Hz")
    values = raw.astype(float, copy=False)
    bad = ~(np.abs(values) <= MAX_FREQUENCY)
    if bad.any():
        first = float(values[bad].flat[0])
        raise ParameterError(f"{name}: found {first!r}, expected finite frequencies in Hz, |f| <= {MAX_FREQUENCY:.4g} "
                             "(2 pi f a finite float64)")
    return values


def _as_deflection(deflection, name: str = "deflection") -> np.ndarray:
    array = np.asarray(deflection, dtype=float)
    if array.ndim != 1 or array.size == 0:
        raise ParameterError(f"{name}: found shape {array.shape}, expected a non-empty 1-D array in m")
    if not np.all(np.isfinite(array)):
        index = int(np.flatnonzero(~np.isfinite(array))[0])
        raise ParameterError(f"{name}: found {array[index]} at index {index}, expected finite values in m")
    return array


def _as_time(time, n_samples: int) -> np.ndarray:
    array = np.asarray(time, dtype=float)
    if array.shape != (n_samples,):
        raise ParameterError(f"time: found shape {array.shape}, expected ({n_samples},) in s")
    steps = np.diff(array)
    if not np.all(np.isfinite(array)) or np.any(steps <= 0):
        index = int(np.flatnonzero(~(steps > 0))[0]) + 1 if np.any(steps <= 0) else 0
        raise ParameterError(
            f"time: found non-increasing or non-finite value at index {index}, "
            "expected strictly increasing finite times in s"
        )
    return array


def _velocity(deflection: np.ndarray, time: np.ndarray) -> np.ndarray:
    if deflection.size < 2:
        return np.zeros_like(deflection)
    return np.gradient(deflection, time)
