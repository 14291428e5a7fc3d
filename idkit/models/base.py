"""Common interface of isolator models.

An isolator model maps a deflection history (m, positive = tension) to a force
(N). Parameters are declared once (:class:`idkit.params.ParamSpec`) and
exposed by name through :meth:`IsolatorModel.params`; fitters build models with
:meth:`IsolatorModel.from_params`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from idkit.checks import Reals, Samples
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


@contextmanager
def taking_params(model: str, params: Mapping[str, float], expected: str | None = None) -> Iterator[dict]:
    """A copy of ``params`` for :meth:`IsolatorModel.from_params` to take values from with
    ``dict.pop``: a name missing there is a :class:`ParameterError` naming ``model`` and the
    name; with ``expected`` (the names the model takes, for the message), so is a name left over."""
    left = dict(params)
    try:
        yield left
    except KeyError as missing:
        raise ParameterError(f"{model}: parameter {missing.args[0]!r} missing") from None
    if expected is not None and left:
        raise ParameterError(f"{model}: unknown parameters {sorted(left)}, expected {expected}")


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


#: A deflection history in m: a non-empty 1-D array of finite values.
DEFLECTION = Samples(unit="m")
#: Sample times in s of a deflection history (None where the model needs none).
TIME = Reals(unit="s", increasing=True, optional=True, meaning="sample times")
#: Frequencies in Hz, any shape; ``2 pi f`` must be a finite float64.
FREQUENCY = Reals(unit="Hz", ge=-MAX_FREQUENCY, le=MAX_FREQUENCY, min_size=0)


def _as_time(time: np.ndarray, n_samples: int) -> np.ndarray:
    """``time`` (declared :data:`TIME`), one per deflection sample."""
    if time.shape != (n_samples,):
        raise ParameterError(f"time: found shape {time.shape}, expected ({n_samples},) in s")
    return time


def _velocity(deflection: np.ndarray, time: np.ndarray) -> np.ndarray:
    if deflection.size < 2:
        return np.zeros_like(deflection)
    return np.gradient(deflection, time)
