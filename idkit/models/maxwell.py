"""Linear viscoelastic models of an elastomer isolator (SPEC 1.4, thesis ch. 4).

Generalized Maxwell: spring ``k0`` in parallel with ``n`` Maxwell elements, each a
spring ``k_i`` in series with a dashpot ``d_i``. Each element is described by its
stiffness and its relaxation **rate** ``rate_i = k_i / d_i`` in 1/s (the quantity
Table 7.3 prints under "tau"; see SPEC 1.4). Time constants ``tau_i = 1 / rate_i``
in s and dashpot coefficients ``d_i`` in N s/m are derived properties.

The same law describes a part (``quantity="stiffness"``: N/m, what a system simulates) or a
material (``quantity="modulus"``: Pa, what a DMA measures: a Prony series). A modulus model
cannot be simulated or put in a system; :meth:`GeneralizedMaxwell.to_stiffness` turns it
into the stiffness of a part of given geometry (module docstring of that method: the rule).
"""

from __future__ import annotations

import math

import numpy as np

from idkit.checks import Choice, Real, accepts
from idkit.errors import ParameterError
from idkit.models.laws import kernel_array, maxwell_states
from idkit.models.base import M_EFF_SPEC, IsolatorArrays, IsolatorModel, taking_params
from idkit.models.base import DEFLECTION, FREQUENCY, TIME, _as_time, _velocity
from idkit.params import ParamSpec, check_array

__all__ = ["GeneralizedMaxwell", "VoigtModel"]

K0_SPEC = ParamSpec("k0", "N/m", 0.0, math.inf, "static (parallel) stiffness")
QUANTITIES = {"stiffness": "N/m", "modulus": "Pa"}
DEFORMATIONS = ("tension", "compression", "shear")


def _check_quantity(quantity: object, model: str) -> str:
    if quantity not in QUANTITIES:
        raise ParameterError(f"{model}: quantity: found {quantity!r}, expected 'stiffness' (N/m, a part) or "
                             "'modulus' (Pa, a material)")
    return str(quantity)


class _Viscoelastic:
    """What every linear viscoelastic model derives from its complex stiffness ``k*(f)``."""

    def loss_factor(self, freq) -> np.ndarray:
        """Loss factor ``Im k* / Re k*`` at ``freq`` in Hz (eq. 4.4)."""
        stiffness = self.complex_stiffness(freq)
        return stiffness.imag / stiffness.real

    def damping_ratio(self, freq) -> np.ndarray:
        """Equivalent damping ratio ``eta / 2`` at ``freq`` in Hz (eq. 4.5)."""
        return 0.5 * self.loss_factor(freq)


class GeneralizedMaxwell(_Viscoelastic, IsolatorModel):
    """Generalized Maxwell model of order ``n``.

    Parameters
    ----------
    k0 : float
        Static stiffness in N/m (>= 0).
    k : array_like, shape (n,)
        Maxwell element stiffnesses in N/m (> 0).
    rate : array_like, shape (n,)
        Relaxation rates ``k_i / d_i`` in 1/s (> 0).
    m_eff : float, optional
        Isolator mass in kg that moves with the mass above it (identified with
        the model, Table 7.3). Systems add it to that mass. Default 0.
    quantity : {"stiffness", "modulus"}
        ``"stiffness"`` (default): ``k0`` and ``k`` in N/m, a part. ``"modulus"``: in Pa,
        a material's Prony series (E' + i E'' or G' + i G''); no ``m_eff``, not simulable.

    Examples
    --------
    >>> elastomer = GeneralizedMaxwell(k0=1.40e4, k=[3.49e3, 1.07e4], rate=[46.6, 841.0])
    >>> round(float(elastomer.loss_factor(20.0)), 3)
    0.156
    >>> material = GeneralizedMaxwell(k0=2.0e6, k=[1.0e6], rate=[100.0], quantity="modulus")
    >>> material.unit, material.to_stiffness(area_m2=1e-3, thickness_m=0.01).k0
    ('Pa', 200000.0)
    """

    kind = "generalized_maxwell"

    def __init__(self, *, k0, k, rate, m_eff=0.0, quantity="stiffness"):
        name = type(self).__name__
        self._quantity = _check_quantity(quantity, name)
        unit = QUANTITIES[self._quantity]
        self._k0 = ParamSpec("k0", unit, 0.0, math.inf, K0_SPEC.meaning).check(k0, model=name)
        self._k = check_array(k, name="k", unit=unit, lower=0.0, meaning=f"Maxwell element {self._quantity}",
                              positive=True, model=name, min_length=1)
        self._rate = check_array(rate, name="rate", unit="1/s", lower=0.0,
                                 meaning="relaxation rate k_i/d_i", positive=True, model=name,
                                 length=self._k.size)
        self._m_eff = M_EFF_SPEC.check(m_eff, model=name)
        if self._quantity == "modulus" and self._m_eff != 0.0:
            raise ParameterError(f"{name}: m_eff: found {self._m_eff!r} kg on a modulus model, expected 0 (a "
                                 "material has no moving mass; give it to the stiffness model of the part)")

    @classmethod
    def from_dampers(cls, *, k0, k, damping, m_eff=0.0) -> GeneralizedMaxwell:
        """Build from dashpot coefficients ``d_i`` in N s/m (Table B.1 style)."""
        k_array = np.asarray(k, dtype=float)
        d_array = check_array(damping, name="damping", unit="N s/m", lower=0.0, meaning="dashpot coefficient",
                              positive=True, model=cls.__name__, length=np.size(k_array))
        return cls(k0=k0, k=k_array, rate=k_array / d_array, m_eff=m_eff)

    @classmethod
    def from_time_constants(cls, *, k0, k, tau, m_eff=0.0) -> GeneralizedMaxwell:
        """Build from relaxation time constants ``tau_i = d_i / k_i`` in s."""
        tau_array = check_array(tau, name="tau", unit="s", lower=0.0, meaning="relaxation time constant",
                                positive=True, model=cls.__name__)
        return cls(k0=k0, k=k, rate=1.0 / tau_array, m_eff=m_eff)

    @classmethod
    def maxwell(cls, *, k, damping) -> GeneralizedMaxwell:
        """Single Maxwell element (spring ``k`` N/m in series with dashpot ``damping`` N s/m)."""
        return cls.from_dampers(k0=0.0, k=[k], damping=[damping])

    k0 = property(lambda self: self._k0, doc="Static stiffness, N/m (static modulus, Pa, for a modulus model).")
    k = property(lambda self: self._k, doc="Maxwell element stiffnesses, N/m (moduli, Pa, for a modulus model).")
    rate = property(lambda self: self._rate, doc="Relaxation rates k_i/d_i, 1/s.")
    quantity = property(lambda self: self._quantity, doc="'stiffness' (N/m, a part) or 'modulus' (Pa, a material).")

    @property
    def unit(self) -> str:
        """Unit of ``k0``, ``k`` and the complex value: ``"N/m"`` or ``"Pa"``."""
        return QUANTITIES[self._quantity]

    @accepts(area_m2=Real(unit="m^2", gt=0), thickness_m=Real(unit="m", gt=0), deformation=Choice(DEFORMATIONS),
             shape_factor=Real(gt=0, optional=True), compression_coefficient=Real(gt=0))
    def to_stiffness(self, *, area_m2: float, thickness_m: float, deformation: str = "tension",
                     shape_factor: float | None = None, compression_coefficient: float = 1.0,
                     m_eff: float = 0.0) -> GeneralizedMaxwell:
        """Stiffness model (N/m) of a block of this material: ``k = M_a A / h``.

        Rule (linear viscoelasticity, the same factor on every term because the geometry
        does not depend on frequency):

        * ``"tension"`` or ``"shear"``: ``k* = M* A / h`` with ``M*`` the measured modulus
          (Young's modulus for a tensile DMA, shear modulus for a shear DMA), ``A`` the
          loaded area and ``h`` the thickness (length along the load). Valid for a block
          free to deform laterally (tension) or in simple shear.
        * ``"compression"`` of a block bonded to rigid plates: the apparent modulus
          ``E_a = E (1 + 2 kappa S**2)`` (Gent and Lindley, Proc. IMechE 173 (1959) 111;
          Gent, *Engineering with Rubber*, ch. 9) with ``S`` the shape factor (one loaded
          area over the area free to bulge) and ``kappa`` the ``compression_coefficient``
          (1 for a soft rubber, down to about 0.5 for hard ones). Valid for S below about
          10, where bulk compressibility is negligible. ``shape_factor`` is required.

        Parameters
        ----------
        area_m2 : float
            Loaded area in m^2 (> 0).
        thickness_m : float
            Thickness in m (> 0).
        deformation : {"tension", "compression", "shear"}
            Load case (see the rule above).
        shape_factor : float, optional
            Shape factor S (-, > 0); compression only.
        compression_coefficient : float
            kappa (-, > 0); compression only.
        m_eff : float
            Moving mass of the part in kg, if known.

        Returns
        -------
        GeneralizedMaxwell
            ``quantity="stiffness"``, same rates.

        Raises
        ------
        ParameterError
            If this model is already a stiffness, or a geometry value is not positive.
        """
        name = f"{type(self).__name__}.to_stiffness"
        if self._quantity != "modulus":
            raise ParameterError(f"{name}: the model is already a stiffness (N/m); expected a modulus model (Pa)")
        factor = area_m2 / thickness_m
        if deformation == "compression":
            if shape_factor is None:
                raise ParameterError(f"{name}: shape_factor: found None for 'compression', expected a positive "
                                     "number (compression of a bonded block needs the shape factor)")
            factor *= 1.0 + 2.0 * compression_coefficient * shape_factor ** 2
        elif shape_factor is not None:
            raise ParameterError(f"{name}: shape_factor: found {shape_factor!r} for {deformation!r}, expected "
                                 "None (the shape factor only enters bonded compression)")
        return GeneralizedMaxwell(k0=self._k0 * factor, k=self._k * factor, rate=self._rate, m_eff=m_eff)

    def _refuse_modulus(self, what: str) -> None:
        if self._quantity == "modulus":
            raise ParameterError(f"{type(self).__name__}.{what}: the model is a modulus (Pa, a material), "
                                 "expected a stiffness (N/m, a part); convert it with "
                                 "to_stiffness(area_m2=..., thickness_m=...)")

    @property
    def m_eff(self) -> float:
        return self._m_eff

    @property
    def tau(self) -> np.ndarray:
        """Relaxation time constants ``1 / rate_i`` in s."""
        return 1.0 / self._rate

    @property
    def damping(self) -> np.ndarray:
        """Dashpot coefficients ``d_i = k_i / rate_i`` in N s/m."""
        return self._k / self._rate

    @property
    def order(self) -> int:
        """Number of Maxwell elements."""
        return int(self._k.size)

    @property
    def instantaneous_stiffness(self) -> float:
        """High-frequency limit ``k0 + sum k_i`` in N/m."""
        return self._k0 + float(self._k.sum())

    @accepts(static_stiffness=Real(gt=0, optional=True, meaning="N/m, or Pa for a modulus"))
    def preloaded(self, static_stiffness: float | None) -> GeneralizedMaxwell:
        """The model linearised about a static preload: ``k0`` replaced by the static tangent
        stiffness there (N/m; :func:`idkit.observe.k0.static_operating_point`), the
        elements unchanged. ``None`` returns the model itself."""
        if static_stiffness is None:
            return self
        return GeneralizedMaxwell(k0=float(static_stiffness), k=self._k, rate=self._rate, m_eff=self._m_eff,
                                  quantity=self._quantity)

    @accepts(factor=Real(gt=0))
    def scaled(self, factor: float) -> GeneralizedMaxwell:
        """Model with every stiffness multiplied by ``factor`` (rates unchanged)."""
        return GeneralizedMaxwell(k0=self._k0 * factor, k=self._k * factor, rate=self._rate, m_eff=self._m_eff,
                                  quantity=self._quantity)

    def param_specs(self) -> tuple[ParamSpec, ...]:
        n, unit, what = self.order, self.unit, self._quantity
        specs = (
            ParamSpec("k0", unit, 0.0, math.inf, f"static (parallel) {what}"),
            *(ParamSpec(f"k_{i}", unit, 0.0, math.inf, f"Maxwell element {what}", True) for i in range(1, n + 1)),
            *(ParamSpec(f"rate_{i}", "1/s", 0.0, math.inf, "relaxation rate k_i/d_i", True) for i in range(1, n + 1)),
        )
        return specs if self._quantity == "modulus" else (*specs, M_EFF_SPEC)

    def params(self) -> dict[str, float]:
        values = {"k0": self._k0}
        values.update({f"k_{i}": float(v) for i, v in enumerate(self._k, start=1)})
        values.update({f"rate_{i}": float(v) for i, v in enumerate(self._rate, start=1)})
        if self._quantity == "stiffness":
            values["m_eff"] = self._m_eff
        return values

    def with_vector(self, vector) -> GeneralizedMaxwell:
        """A model of the same structure and quantity with parameters taken from ``vector``."""
        model = super().with_vector(vector)
        if self._quantity == "stiffness":
            return model
        return GeneralizedMaxwell(k0=model.k0, k=model.k, rate=model.rate, quantity=self._quantity)

    def __eq__(self, other) -> bool:
        return super().__eq__(other) and self._quantity == other._quantity

    def __hash__(self) -> int:
        return hash((super().__hash__(), self._quantity))

    def to_dict(self) -> dict:
        """Model-file entry; the units (N/m or Pa) say whether it is a stiffness or a modulus."""
        return super().to_dict()

    @classmethod
    def from_params(cls, params: dict[str, float], *, quantity: str = "stiffness") -> GeneralizedMaxwell:
        with taking_params("GeneralizedMaxwell", params, "k0, k_i, rate_i, m_eff") as left:
            order = sum(1 for name in left if name.startswith("k_"))
            model = cls(
                k0=left.pop("k0"),
                k=[left.pop(f"k_{i}") for i in range(1, order + 1)],
                rate=[left.pop(f"rate_{i}") for i in range(1, order + 1)],
                m_eff=left.pop("m_eff", 0.0),
                quantity=quantity,
            )
        return model

    @accepts(freq=FREQUENCY)
    def complex_stiffness(self, freq) -> np.ndarray:
        """Complex stiffness ``k0 + sum k_i s / (s + rate_i)``, ``s = 2 pi i freq`` (eq. 4.3), N/m.

        For a modulus model the same law gives the complex modulus in Pa (also
        :meth:`complex_modulus`).
        """
        s = 2j * np.pi * freq
        return self._k0 + np.sum(self._k * s[..., None] / (s[..., None] + self._rate), axis=-1)

    small_amplitude_stiffness = complex_stiffness

    def complex_modulus(self, freq) -> np.ndarray:
        """Complex modulus ``E0 + sum E_i s / (s + rate_i)`` in Pa (modulus models only)."""
        if self._quantity != "modulus":
            raise ParameterError(f"{type(self).__name__}.complex_modulus: the model is a stiffness (N/m); "
                                 "expected a modulus model (Pa); use complex_stiffness")
        return self.complex_stiffness(freq)

    @accepts(deflection=DEFLECTION, time=TIME)
    def element_states(self, deflection, time, initial_states=None) -> np.ndarray:
        """Maxwell spring elongations ``u_i`` in m along the history, shape (n_samples, n)."""
        x = deflection
        t = _as_time(time, x.size)
        start = np.zeros(self.order) if initial_states is None else np.asarray(initial_states, float)
        return maxwell_states(kernel_array(x), kernel_array(t), kernel_array(self._rate), kernel_array(start))

    @accepts(deflection=DEFLECTION)
    def force(self, deflection, time=None, initial_states=None) -> np.ndarray:
        """Isolator force in N along a deflection history (m) sampled at ``time`` (s).

        Exact for deflection piecewise linear in time; the elements start
        relaxed unless ``initial_states`` (m) are given. ``time`` is required:
        the model is rate dependent.
        """
        self._refuse_modulus("force")
        if time is None:
            raise ParameterError("GeneralizedMaxwell.force: found time=None, expected sample times in s")
        x = deflection
        return self._k0 * x + self.element_states(x, time, initial_states) @ self._k

    def kernel_arrays(self) -> IsolatorArrays:
        self._refuse_modulus("kernel_arrays")
        return IsolatorArrays(
            poly=np.array([self._k0, 0.0, 0.0]),
            c_visc=0.0,
            jenkin_stiffness=np.zeros(0),
            jenkin_friction=np.zeros(0),
            maxwell_stiffness=np.array(self._k),
            maxwell_rate=np.array(self._rate),
            boucwen=np.zeros(10),
        )


class VoigtModel(_Viscoelastic, IsolatorModel):
    """Voigt (Kelvin-Voigt, viscous) model: spring ``k`` N/m parallel to dashpot ``damping`` N s/m."""

    kind = "voigt"
    _SPECS = (
        ParamSpec("k", "N/m", 0.0, math.inf, "spring stiffness"),
        ParamSpec("damping", "N s/m", 0.0, math.inf, "dashpot coefficient"),
        M_EFF_SPEC,
    )

    def __init__(self, *, k, damping, m_eff=0.0):
        name = type(self).__name__
        self._k = self._SPECS[0].check(k, model=name)
        self._damping = self._SPECS[1].check(damping, model=name)
        self._m_eff = M_EFF_SPEC.check(m_eff, model=name)

    k = property(lambda self: self._k, doc="Stiffness, N/m.")
    damping = property(lambda self: self._damping, doc="Dashpot coefficient, N s/m.")

    @property
    def m_eff(self) -> float:
        return self._m_eff

    def param_specs(self) -> tuple[ParamSpec, ...]:
        return self._SPECS

    def params(self) -> dict[str, float]:
        return {"k": self._k, "damping": self._damping, "m_eff": self._m_eff}

    @classmethod
    def from_params(cls, params: dict[str, float]) -> VoigtModel:
        with taking_params("VoigtModel", params, "k, damping, m_eff") as left:
            model = cls(k=left.pop("k"), damping=left.pop("damping"), m_eff=left.pop("m_eff", 0.0))
        return model

    @accepts(freq=FREQUENCY)
    def complex_stiffness(self, freq) -> np.ndarray:
        """``k + i omega d`` in N/m at ``freq`` in Hz."""
        return self._k + 2j * np.pi * freq * self._damping

    small_amplitude_stiffness = complex_stiffness

    @accepts(deflection=DEFLECTION, time=TIME)
    def force(self, deflection, time=None) -> np.ndarray:
        """Force ``k x + d xdot`` in N; ``time`` (s) is required for the viscous part."""
        x = deflection
        if time is None:
            raise ParameterError("VoigtModel.force: found time=None, expected sample times in s")
        return self._k * x + self._damping * _velocity(x, _as_time(time, x.size))

    def kernel_arrays(self) -> IsolatorArrays:
        return IsolatorArrays(
            poly=np.array([self._k, 0.0, 0.0]),
            c_visc=self._damping,
            jenkin_stiffness=np.zeros(0),
            jenkin_friction=np.zeros(0),
            maxwell_stiffness=np.zeros(0),
            maxwell_rate=np.zeros(0),
            boucwen=np.zeros(10),
        )


def preloaded(model, static_stiffness: float | None):
    """``model`` about a static preload (:meth:`GeneralizedMaxwell.preloaded`); any other
    model, and ``static_stiffness=None``, unchanged (a Voigt model's static stiffness is a
    fitted parameter of its own)."""
    if static_stiffness is None or not isinstance(model, GeneralizedMaxwell):
        return model
    return model.preloaded(static_stiffness)
