"""Synthetic catalogue parts: wire-rope and elastomer families over their dimensions.

A maker's catalogue holds several sizes of one design. This generator writes such a family
as one measurement-set folder per part (the io format of ``docs/data-format.md``) plus a
``part.json`` naming the part, its family and its dimensions (the manifest's keys are fixed
by :mod:`idkit.io.manifest`, so the part's description sits beside it), so that
``idkit catalogue build`` and the scaling laws can be tested against known laws.

The truths are held out from the bundled data's: their slip forces are spread over
nine elements in three clusters (neither truth "a"'s two humps nor truth "b"'s 24 elements) and their
elastomer compounds are generalized Maxwell materials of their own.

**Wire rope** (dimensions ``cable_diameter_m``, ``loops``, ``height_m``, ``width_m``): every
stiffness of the reference rope (``g1``, ``g2``, ``g3``, the Jenkin ``k_i``) is multiplied by

    S_k = (d / d_ref)^3.0 (n / n_ref)^1.0 (H / H_ref)^-2.0 x exp(scatter)

and every slip force ``fc_i`` by

    S_f = (d / d_ref)^2.0 (n / n_ref)^1.0 (H / H_ref)^-1.0 x exp(scatter)

(:data:`WIRE_ROPE_EXPONENTS`; a helical rope bends like a beam of ``n`` parallel loops, so
its stiffness grows with the cable's bending stiffness ``d^4`` less the strands' slip, and
falls with the loop height; the strand friction grows with the contact area ``d^2``). The
width does not enter (a documented choice: it is carried as a dimension, and the scaling
laws must find its exponent near 0). Part-to-part scatter: independent normal ``log``
factors of standard deviation :data:`WIRE_ROPE_SCATTER` on ``S_k`` and ``S_f``.

**Elastomer** (``area_m2``, ``thickness_m``, ``shape_factor``, ``compound``): a bonded block in
compression, whose stiffness is the compound's modulus model (Pa) through
:meth:`idkit.models.GeneralizedMaxwell.to_stiffness` (``k = E (1 + 2 S^2) A / h``) times a
part-to-part factor ``exp(scatter)`` (standard deviation :data:`ELASTOMER_SCATTER`); the
shape factor of a round block is ``S = D / (4 h)``.

Per part: quasi-static loops (wire rope: small and large programs; elastomer: one program),
and for elastomers white-noise runs at two top masses (0.6 and 1.2 kg: every part of the default grid keeps its resonance half-power width above 1.5 Hz, resolved by the fit's 0.5 Hz H1 lines); repetitions 1 (fit) and 2 (held out,
``split = "validation"``). Records are short so that a catalogue of a few parts is
generated in seconds.
"""

from __future__ import annotations

import json
import math
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from idkit import __version__
from idkit.atomic import atomic_output_folder, write_bytes_atomic
from idkit.errors import ParameterError
from idkit.io import write_measurement_set
from idkit.models import GeneralizedMaxwell
from idkit.synth.experiments import Planned, realize
from idkit.synth.truth import ModulatedWireRopeTruth, SingleBodyElastomerTruth

__all__ = [
    "COMPOUNDS",
    "ELASTOMER_DIMENSIONS",
    "ELASTOMER_SCATTER",
    "PART_FILE",
    "WIRE_ROPE_DIMENSIONS",
    "WIRE_ROPE_EXPONENTS",
    "WIRE_ROPE_REFERENCE",
    "WIRE_ROPE_SCATTER",
    "CataloguePart",
    "elastomer_family",
    "elastomer_shape_factor",
    "generate_catalogue",
    "wire_rope_family",
]

#: Name of the part description written beside each part's ``manifest.json``.
PART_FILE = "part.json"
#: Dimensions of a wire-rope part (SI; ``loops`` a count).
WIRE_ROPE_DIMENSIONS = ("cable_diameter_m", "loops", "height_m", "width_m")
#: Dimensions of an elastomer part (SI; ``compound`` a name of :data:`COMPOUNDS`).
ELASTOMER_DIMENSIONS = ("area_m2", "thickness_m", "shape_factor", "compound")
#: The reference rope the laws scale from.
WIRE_ROPE_REFERENCE = {"cable_diameter_m": 8e-3, "loops": 8, "height_m": 0.06, "width_m": 0.075}
#: Generator exponents: quantity -> dimension -> exponent (module docstring).
WIRE_ROPE_EXPONENTS = {
    "stiffness": {"cable_diameter_m": 3.0, "loops": 1.0, "height_m": -2.0, "width_m": 0.0},
    "slip_force": {"cable_diameter_m": 2.0, "loops": 1.0, "height_m": -1.0, "width_m": 0.0},
}
#: Standard deviation of the log part-to-part factors of a rope's stiffness and slip force.
WIRE_ROPE_SCATTER = 0.04
#: Standard deviation of the log part-to-part factor of an elastomer's modulus.
ELASTOMER_SCATTER = 0.04

# reference rope: nine Jenkin elements in three clusters of slip displacement (about 60 um,
# 0.4 mm and 2 mm, each spread +-20 %), 10 N of slip force per cluster; a mild spring nonlinearity
_REFERENCE_DELTA = np.concatenate([centre * np.array([0.8, 1.0, 1.2]) for centre in (60e-6, 0.4e-3, 2e-3)])
_REFERENCE_FC = np.full(9, 10.0 / 3.0)
_REFERENCE_ROPE = {"g1": 2.2e4, "g2": 1.5e5, "g3": -2.0e5, "c_visc": 8.0}

#: Compounds: generalized Maxwell moduli (Pa, rates 1/s) of two rubbers; the static modulus
#: of the soft one gives 1.1e4 N/m for a 40 mm round block 20 mm thick (a soft,
#: cellular compound, so that a few kilograms per mount sit near 5-10 Hz).
COMPOUNDS = {
    "NR45": GeneralizedMaxwell(k0=0.12e6, k=[0.016e6, 0.025e6, 0.022e6, 0.014e6], rate=[5.0, 40.0, 300.0, 2500.0],
                               quantity="modulus"),
    "NR60": GeneralizedMaxwell(k0=0.23e6, k=[0.040e6, 0.063e6, 0.052e6, 0.032e6], rate=[4.0, 30.0, 250.0, 2000.0],
                               quantity="modulus"),
}
_RUBBER_DENSITY = 1100.0  # kg/m^3: a third of the block moves with the top mass
_PLATE_MASS_PER_AREA = 32.0  # kg/m^2: the bonded top plate (4 mm steel) moves with the top mass


def elastomer_shape_factor(area_m2: float, thickness_m: float) -> float:
    """Shape factor ``S = D / (4 h)`` of a round block of loaded area ``area_m2`` (m^2) and
    thickness ``thickness_m`` (m): one loaded face over the free (bulging) surface."""
    return math.sqrt(4.0 * area_m2 / math.pi) / (4.0 * thickness_m)


@dataclass(frozen=True)
class CataloguePart:
    """One synthetic part: its name, family, dimensions and generating truth.

    Attributes
    ----------
    part : str
        Part name (folder name).
    family : {"wire_rope", "elastomer"}
    dimensions : dict
        SI dimensions (:data:`WIRE_ROPE_DIMENSIONS` or :data:`ELASTOMER_DIMENSIONS`).
    truth : ModulatedWireRopeTruth or SingleBodyElastomerTruth
        The generating isolator.
    factors : dict
        The scaling factors applied (law and scatter), for the truth file.
    """

    part: str
    family: str
    dimensions: dict
    truth: object
    factors: dict = field(default_factory=dict)

    def description(self) -> dict:
        """The ``part.json`` document (no truth: what a maker would publish)."""
        return {"format": "idkit-part", "version": 1, "part": self.part, "family": self.family,
                "dimensions": dict(self.dimensions)}


def _law(exponents: dict, dimensions: dict, reference: dict) -> float:
    return float(np.prod([(dimensions[name] / reference[name]) ** power for name, power in exponents.items()]))


def wire_rope_family(cable_diameters_m: Sequence[float] = (6e-3, 8e-3, 10e-3, 12e-3),
                     loops: Sequence[int] = (6, 8, 10), heights_m: Sequence[float] = (0.05, 0.06, 0.075),
                     *, count: int | None = None, seed: int = 2026, scatter: float = WIRE_ROPE_SCATTER,
                     prefix: str = "WR") -> list[CataloguePart]:
    """Wire-rope parts over a grid of dimensions (module docstring for the laws).

    Parameters
    ----------
    cable_diameters_m, loops, heights_m : sequences
        Grid values: cable diameter (m), number of loops, loop height (m). The width is
        ``1.25 x height`` (not in the laws).
    count : int, optional
        Keep this many parts spread over the grid (every grid point when None).
    seed : int
        Seed of the part-to-part scatter (each part seeded by its name).
    scatter : float
        Standard deviation of the log factors (0: the laws exactly).
    prefix : str
        Part names read ``{prefix}-{d mm}-{loops}-{H mm}``.

    Returns
    -------
    list of CataloguePart
    """
    grid = [(d, n, h) for d in cable_diameters_m for n in loops for h in heights_m]
    if count is not None:
        if not (isinstance(count, int) and 1 <= count <= len(grid)):
            raise ParameterError(f"count: found {count!r}, expected a whole number in [1, {len(grid)}]")
        grid = [grid[i] for i in np.unique(np.round(np.linspace(0, len(grid) - 1, count)).astype(int))]
    parts = []
    for d, n, h in grid:
        name = f"{prefix}-{d * 1e3:g}-{n:d}-{h * 1e3:g}"
        dimensions = {"cable_diameter_m": float(d), "loops": int(n), "height_m": float(h), "width_m": 1.25 * float(h)}
        rng = np.random.default_rng([int(seed), zlib.crc32(name.encode())])
        noise_k, noise_f = (scatter * rng.standard_normal(2)) if scatter > 0 else (0.0, 0.0)
        s_k = _law(WIRE_ROPE_EXPONENTS["stiffness"], dimensions, WIRE_ROPE_REFERENCE) * math.exp(noise_k)
        s_f = _law(WIRE_ROPE_EXPONENTS["slip_force"], dimensions, WIRE_ROPE_REFERENCE) * math.exp(noise_f)
        fc = _REFERENCE_FC * s_f
        k = fc / (_REFERENCE_DELTA * s_f / s_k)
        truth = ModulatedWireRopeTruth(
            g1=_REFERENCE_ROPE["g1"] * s_k, g2=_REFERENCE_ROPE["g2"] * s_k, g3=_REFERENCE_ROPE["g3"] * s_k,
            c_visc=_REFERENCE_ROPE["c_visc"], beta=0.0, y_ref=0.006,
            fc=[float(v) for v in np.round(fc, 5)], k=[float(v) for v in np.round(k, 2)], mass_kg=0.2)
        parts.append(CataloguePart(name, "wire_rope", dimensions, truth,
                                   {"stiffness_factor": s_k, "slip_force_factor": s_f,
                                    "log_scatter": [float(noise_k), float(noise_f)]}))
    return parts


def elastomer_family(diameters_m: Sequence[float] = (0.03, 0.04, 0.05), thicknesses_m: Sequence[float] = (0.01, 0.015, 0.02),
                     compounds: Sequence[str] = ("NR45", "NR60"), *, count: int | None = None, seed: int = 2026,
                     scatter: float = ELASTOMER_SCATTER, prefix: str = "EL") -> list[CataloguePart]:
    """Elastomer parts (round bonded blocks in compression) over diameters, thicknesses and compounds.

    The stiffness is the compound's modulus through ``to_stiffness(area, thickness,
    "compression", shape_factor)`` times ``exp(scatter)``; ``m_eff`` is a third of the
    block's mass (density 1100 kg/m^3) plus its bonded top plate (4 mm of steel, 32 kg/m^2).
    """
    unknown = sorted(set(compounds) - set(COMPOUNDS))
    if unknown:
        raise ParameterError(f"compounds: unknown {unknown}, expected names from {sorted(COMPOUNDS)}")
    grid = [(c, d, t) for c in compounds for d in diameters_m for t in thicknesses_m]
    if count is not None:
        if not (isinstance(count, int) and 1 <= count <= len(grid)):
            raise ParameterError(f"count: found {count!r}, expected a whole number in [1, {len(grid)}]")
        grid = [grid[i] for i in np.unique(np.round(np.linspace(0, len(grid) - 1, count)).astype(int))]
    parts = []
    for compound, diameter, thickness in grid:
        name = f"{prefix}-{compound}-{diameter * 1e3:g}-{thickness * 1e3:g}"
        area = math.pi * diameter**2 / 4.0
        shape = elastomer_shape_factor(area, thickness)
        rng = np.random.default_rng([int(seed), zlib.crc32(name.encode())])
        noise = float(scatter * rng.standard_normal()) if scatter > 0 else 0.0
        stiffness = COMPOUNDS[compound].to_stiffness(area_m2=area, thickness_m=thickness, deformation="compression",
                                                      shape_factor=shape).scaled(math.exp(noise))
        moving = _PLATE_MASS_PER_AREA * area + _RUBBER_DENSITY * area * thickness / 3.0
        truth = SingleBodyElastomerTruth(k0=stiffness.k0, k=[float(v) for v in stiffness.k],
                                         rate=[float(v) for v in stiffness.rate], alpha=0.03, y_soft=0.012,
                                         moving_mass_kg=moving, mass_kg=3.0 * moving)
        parts.append(CataloguePart(name, "elastomer",
                                   {"area_m2": area, "thickness_m": float(thickness), "shape_factor": shape,
                                    "compound": compound}, truth,
                                   {"geometry_factor_m": area / thickness * (1.0 + 2.0 * shape**2),
                                    "log_scatter": noise}))
    return parts


def _protocol(part: CataloguePart, quick: bool) -> list[Planned]:
    """The measurements of one part: repetition 1 fits, repetition 2 is held out."""
    items = []
    reps = (1, 2)
    split = {1: "fit", 2: "validation"}
    if part.family == "wire_rope":
        programs = {"small": ([0.05, 0.3, 1.5, 4.0] if quick else [0.05, 0.1, 0.3, 0.8, 1.5, 2.5, 4.0], 0.6e-3),
                    "large": ([2.0, 6.0, 12.0] if quick else [1.0, 2.0, 4.0, 7.0, 10.0, 12.0], 2.0e-3)}
        for group, (amplitudes_mm, speed) in programs.items():
            for rep in reps:
                items.append(Planned(f"qs_wr_{group}_{rep}", "quasi_static", "wire_rope",
                                     {"amplitudes_m": [a * 1e-3 for a in amplitudes_mm], "cycles": 2,
                                      "speed_m_per_s": speed, "group": group, "repetition": rep}, split[rep]))
        return items
    for rep in reps:
        items.append(Planned(f"qs_el_loops_{rep}", "quasi_static", "elastomer",
                             {"amplitudes_m": [a * 1e-3 for a in ([1.0, 4.0] if quick else [1.0, 2.0, 4.0, 6.0])],
                              "cycles": 2, "speed_m_per_s": 1.5e-3, "group": "loops", "repetition": rep}, split[rep]))
    for mass in (0.6, 1.2):
        for rep in reps:
            items.append(Planned(f"wn_el_{mass:.2f}kg_{rep}", "white_noise", "elastomer",
                                 {"top_mass_kg": mass, "duration_s": 8.0 if quick else 16.0, "band_hz": [1.0, 500.0],
                                  "accel_rms": 3.0, "repetition": rep}, split[rep]))
    return items


def generate_catalogue(folder, parts: Sequence[CataloguePart], *, seed: int = 2026, quick: bool = True,
                       force: bool = False) -> list[Path]:
    """Write one measurement-set folder per part, with its ``part.json``, under ``folder``.

    The generating truths go to ``folder/_truth/<part>.json`` (outside every part folder:
    a catalogue build reads only what a maker would publish).

    Parameters
    ----------
    folder : str or pathlib.Path
        Output folder (created if missing).
    parts : sequence of CataloguePart
        From :func:`wire_rope_family` / :func:`elastomer_family`.
    seed : int
        Seed of the sensor noise and hand-driven paths (each part seeded by its name).
    quick : bool, default True
        Short records (tests, docs): a few seconds of generation per part.
    force : bool
        Replace existing part folders.

    Returns
    -------
    list of pathlib.Path
        The part folders, in the order of ``parts``.
    """
    folder = Path(folder)
    names = [part.part for part in parts]
    if len(set(names)) != len(names):
        raise ParameterError(f"parts: found repeated part names {sorted({n for n in names if names.count(n) > 1})}")
    existing = [str(folder / name) for name in names if (folder / name).exists()]
    if existing and not force:
        raise FileExistsError(f"refusing to overwrite {', '.join(existing)} (force=True replaces them)")
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "_truth").mkdir(exist_ok=True)
    written = []
    for part in parts:
        part_seed = [int(seed), zlib.crc32(part.part.encode())]
        measurements, records = [], {}
        for item in _protocol(part, quick):
            rope = part.truth if part.family == "wire_rope" else None
            body = part.truth if part.family == "elastomer" else None
            measurement, record = realize(item, seed=int(np.random.SeedSequence(part_seed).generate_state(1)[0]),
                                          quick=quick, wire_rope=rope, elastomer=body)
            measurements.append(measurement)
            records[item.id] = record
        with atomic_output_folder(folder / part.part, force=True) as staging:
            write_measurement_set(staging, measurements, gzip=True,
                                  name=f"synthetic catalogue part {part.part} ({part.family.replace('_', ' ')})",
                                  notes="SYNTHETIC data made by idkit.synth.catalogue; repetition 2 is the "
                                        "validation split; the part's dimensions are in part.json")
            write_bytes_atomic(staging / PART_FILE, (json.dumps(part.description(), indent=1) + "\n").encode())
        truth = {"synthetic": True, "generator": "idkit.synth.catalogue", "idkit_version": __version__,
                 "seed": int(seed), "quick": bool(quick), **part.description(), "factors": part.factors,
                 "model": part.truth.to_dict(), "measurements": records}
        write_bytes_atomic(folder / "_truth" / f"{part.part}.json",
                           (json.dumps(truth, indent=1, default=float) + "\n").encode(), overwrite=True)
        written.append(folder / part.part)
    return written
