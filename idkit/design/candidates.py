"""Design candidates: catalogue parts (measured or predicted) times mount counts, single or hybrid.

A candidate carries a payload of mass ``M`` on ``N`` identical mounts. The payload is rigid and
moves vertically, so the ``N`` mounts in parallel are exactly one mount carrying ``M / N``
(every mount sees the same deflection): the system simulated is

* single: ``SDOFSystem(M / N, part)``;
* hybrid (thesis 5.1, the transport study's r_k): ``HybridSystem(M / N, elastomer,
  f_in M / N, wire rope)``: payload - elastomer - intermediate mass - wire rope - floor, the
  intermediate mass a fraction ``f_in`` (1 % in the study) of the payload per mount.

Uncertainty: each part carries the covariance of its fitted parameters, drawn by
:func:`idkit.catalogue.uncertainty.draw_models`; a part predicted from the scaling laws adds
the laws' prediction uncertainty as common log factors on its stiffnesses and its slip forces.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field

import numpy as np

from idkit.catalogue.scaling import fit_scaling_law, geometry_factor
from idkit.checks import Flag, Real, accepts
from idkit.catalogue.uncertainty import draw_models as draw_catalogue_models
from idkit.errors import ParameterError
from idkit.models import GeneralizedMaxwell, HybridSystem, SDOFSystem
from idkit.models.modelfile import model_from_dict, model_to_dict

__all__ = ["Candidate", "DesignPart", "candidate_rng", "draw_models", "make_candidates", "parts_from_catalogue", "predicted_part"]

_FORCE_PREFIX = "fc_"


@dataclass(frozen=True)
class DesignPart:
    """A part a design may use.

    Attributes
    ----------
    name : str
    family : {"wire_rope", "elastomer"}
    model : IwanModel or GeneralizedMaxwell
    covariance_names : tuple of str; covariance : ndarray
        Parameter covariance (SI), possibly empty.
    law_log_sd : dict
        Predicted parts: ``{"stiffness": sd, "slip_force": sd}`` of the laws' prediction (log).
    predicted : bool
        True for a size predicted from the scaling laws, never measured.
    dimensions : dict
    """

    name: str
    family: str
    model: object
    covariance_names: tuple = ()
    covariance: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    law_log_sd: dict = field(default_factory=dict)
    predicted: bool = False
    dimensions: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """Picklable, JSON-ready description (the model as a model-file dict)."""
        return {"name": self.name, "family": self.family, "model": model_to_dict(self.model),
                "covariance_names": list(self.covariance_names), "covariance": np.asarray(self.covariance).tolist(),
                "law_log_sd": dict(self.law_log_sd), "predicted": self.predicted, "dimensions": dict(self.dimensions)}

    @classmethod
    def from_dict(cls, entry: dict) -> DesignPart:
        """Inverse of :meth:`to_dict`."""
        names = tuple(entry["covariance_names"])
        return cls(entry["name"], entry["family"], model_from_dict(entry["model"]), names,
                   np.asarray(entry["covariance"], dtype=float).reshape(len(names), len(names)),
                   dict(entry["law_log_sd"]), bool(entry["predicted"]), dict(entry["dimensions"]))


@dataclass(frozen=True)
class Candidate:
    """One design: ``count`` mounts of ``parts`` (one part, or elastomer then wire rope) under ``payload_mass_kg``."""

    name: str
    parts: tuple
    count: int
    payload_mass_kg: float
    intermediate_fraction: float = 0.01

    @property
    def kind(self) -> str:
        """``"single"`` or ``"hybrid"``."""
        return "single" if len(self.parts) == 1 else "hybrid"

    def system(self, models=None):
        """The system per mount (module docstring), with ``models`` replacing the parts' own."""
        models = models or [part.model for part in self.parts]
        mass = self.payload_mass_kg / self.count
        if self.kind == "single":
            return SDOFSystem(mass, models[0])
        return HybridSystem(mass, models[0], self.intermediate_fraction * mass, models[1])

    def to_dict(self) -> dict:
        return {"name": self.name, "parts": [part.to_dict() for part in self.parts], "count": self.count,
                "payload_mass_kg": self.payload_mass_kg, "intermediate_fraction": self.intermediate_fraction}

    @classmethod
    def from_dict(cls, entry: dict) -> Candidate:
        return cls(entry["name"], tuple(DesignPart.from_dict(p) for p in entry["parts"]), int(entry["count"]),
                   float(entry["payload_mass_kg"]), float(entry["intermediate_fraction"]))


def parts_from_catalogue(catalogue) -> list[DesignPart]:
    """The usable parts of a catalogue (:meth:`idkit.catalogue.Catalogue.usable`) as design parts."""
    parts = []
    for record in catalogue.usable():
        names = tuple(record["covariance"]["names"])
        matrix = np.asarray(record["covariance"]["matrix"], dtype=float).reshape(len(names), len(names))
        parts.append(DesignPart(record["part"], record["family"], catalogue.model(record["part"]), names, matrix,
                                dimensions=dict(record["dimensions"])))
    return parts


def _nearest(records, dimensions, keys):
    def distance(record):
        return sum(math.log(float(record["dimensions"][k]) / float(dimensions[k])) ** 2 for k in keys)
    return min(records, key=distance)


def predicted_part(catalogue, family: str, dimensions: dict, *, name: str | None = None) -> DesignPart:
    """A part of ``dimensions`` never measured, predicted from the family's scaling laws.

    The nearest measured part (log distance in the dimensions; elastomer: same compound)
    is scaled: wire rope stiffnesses (``g1``, ``g2``, ``g3``, ``k_i``) by the ratio of the
    stuck-stiffness law's predictions, slip forces by the total-slip-force law's; an
    elastomer's modulus model (the part divided by its geometry factor, a material in Pa)
    goes through :meth:`~idkit.models.GeneralizedMaxwell.to_stiffness` for the new block and
    is scaled to the ``k0`` law's prediction. The reference part's covariance is kept in
    relative terms; the laws' prediction standard deviations enter as ``law_log_sd``.
    """
    records = [r for r in catalogue.usable() if r["family"] == family]
    if family == "wire_rope":
        stiffness_law = fit_scaling_law(records, "stuck_stiffness")
        force_law = fit_scaling_law(records, "total_slip_force")
        reference = _nearest(records, dimensions, stiffness_law.dimensions)
        k_new, f_new = stiffness_law.predict(dimensions), force_law.predict(dimensions)
        k_ref, f_ref = (stiffness_law.predict(reference["dimensions"]).value,
                        force_law.predict(reference["dimensions"]).value)
        # the reference part's own deviation from the law is kept (the laws scale it)
        k_ratio, f_ratio = k_new.value / k_ref, f_new.value / f_ref
        model = catalogue.model(reference["part"])
        params = {key: value * (f_ratio if key.startswith(_FORCE_PREFIX) else k_ratio if key != "c_visc" else 1.0)
                  for key, value in model.params().items()}
        predicted = type(model).from_params(params)
        law_sd = {"stiffness": k_new.log_sd, "slip_force": f_new.log_sd}
        scale = {key: (f_ratio if key.startswith(_FORCE_PREFIX) else k_ratio) for key in params}
    elif family == "elastomer":
        law = fit_scaling_law(records, "k0")
        same = [r for r in records if r["dimensions"]["compound"] == dimensions.get("compound")]
        if not same:
            raise ParameterError(f"dimensions.compound: found {dimensions.get('compound')!r}, expected a compound "
                                 f"of the catalogue: {sorted({r['dimensions']['compound'] for r in records})}")
        reference = _nearest(same, dimensions, ("area_m2", "thickness_m"))
        model = catalogue.model(reference["part"])
        geometry = geometry_factor(reference["dimensions"])
        material = GeneralizedMaxwell(k0=model.k0 / geometry, k=np.asarray(model.k) / geometry, rate=model.rate,
                                      quantity="modulus")
        block = material.to_stiffness(area_m2=float(dimensions["area_m2"]), thickness_m=float(dimensions["thickness_m"]),
                                      deformation="compression", shape_factor=float(dimensions["shape_factor"]))
        prediction = law.predict(dimensions)
        ratio = prediction.value / law.predict(reference["dimensions"]).value * model.k0 / block.k0
        volume = dimensions["area_m2"] * dimensions["thickness_m"] / (
            reference["dimensions"]["area_m2"] * reference["dimensions"]["thickness_m"])
        predicted = GeneralizedMaxwell(k0=block.k0 * ratio, k=np.asarray(block.k) * ratio, rate=block.rate,
                                       m_eff=model.m_eff * volume)
        law_sd = {"stiffness": prediction.log_sd}
        scale = {key: (1.0 if key.startswith("rate_") else predicted.params()[key] / value if value else 1.0)
                 for key, value in model.params().items()}
    else:
        raise ParameterError(f"family: found {family!r}, expected 'wire_rope' or 'elastomer'")
    names = tuple(reference["covariance"]["names"])
    matrix = np.asarray(reference["covariance"]["matrix"], dtype=float).reshape(len(names), len(names))
    factors = np.array([scale.get(n, 1.0) for n in names])
    label = name or f"{family} predicted " + ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                                                      for k, v in dimensions.items())
    return DesignPart(label, family, predicted, names, matrix * np.outer(factors, factors), law_sd, True,
                      dict(dimensions))


@accepts(payload_mass_kg=Real(unit="kg", gt=0), hybrids=Flag(), singles=Flag(),
         intermediate_fraction=Real(gt=0, lt=1, meaning="of the payload per mount"))
def make_candidates(parts, payload_mass_kg: float, *, counts=(4,), hybrids: bool = True, singles: bool = True,
                    intermediate_fraction: float = 0.01) -> list[Candidate]:
    """Every single part and every (elastomer, wire rope) pair, at every mount count.

    Parameters
    ----------
    parts : sequence of DesignPart
    payload_mass_kg : float
        Total payload (kg), shared equally by the mounts.
    counts : sequence of int
        Mount counts to try.
    hybrids, singles : bool
        Which kinds to generate.
    intermediate_fraction : float
        Hybrid intermediate mass per mount as a fraction of the payload per mount.
    """
    for count in counts:
        if isinstance(count, bool) or not (isinstance(count, (int, np.integer)) and count >= 1):
            raise ParameterError(f"counts: found {count!r}, expected whole numbers >= 1")
    candidates = []
    ropes = [p for p in parts if p.family == "wire_rope"]
    bodies = [p for p in parts if p.family == "elastomer"]
    for count in counts:
        if singles:
            candidates += [Candidate(f"{count} x {p.name}", (p,), int(count), float(payload_mass_kg),
                                     intermediate_fraction) for p in parts]
        if hybrids:
            candidates += [Candidate(f"{count} x ({body.name} on {rope.name})", (body, rope), int(count),
                                     float(payload_mass_kg), intermediate_fraction)
                           for body in bodies for rope in ropes]
    return candidates


def draw_models(part: DesignPart, n_draws: int, rng: np.random.Generator) -> list:
    """``n_draws`` models of ``part`` drawn from its covariance and, for a predicted part, its laws'
    uncertainty (:func:`idkit.catalogue.uncertainty.draw_models`)."""
    return draw_catalogue_models(part.model, part.covariance_names, part.covariance, n_draws, rng,
                                 law_log_sd=part.law_log_sd)


def candidate_rng(candidate: Candidate, seed: int) -> np.random.Generator:
    """The candidate's own random stream: the same draws whatever executor or order runs it."""
    return np.random.default_rng([int(seed), zlib.crc32(candidate.name.encode())])

