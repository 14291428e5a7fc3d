"""Synthetic measurement data: the seeded, deterministic generator of the bundled ``data/``.

The generating "truth" (:mod:`idkit.synth.truth`) is richer than the models idkit fits
(Iwan of order 30 with deflection-dependent slip forces and a bottoming spring; an order-8
generalized Maxwell elastomer with an internal mass and compression softening), and the
experiments (:mod:`idkit.synth.experiments`) reproduce the grid of SPEC section 3 with the
imperfections of real tests: hand-driven quasi-static rate with jerks, a distorted and
non-flat shaker, relaxation during the fall and a bouncing bottom mass in drops, and sensor
noise with ADC-like rounding on every channel. The chain integrator is
:mod:`idkit.synth.chain`.

Command: ``idkit data generate -o data/ --seed 2026 [--force]`` or
``python -m idkit.synth``; ``--truth b`` writes the second, different truth
(:func:`idkit.synth.truth.truth_models`; not bundled).
"""

from idkit.synth.experiments import Planned, plan
from idkit.synth.generate import (
    DEFAULT_SEED,
    FILE_UNITS,
    SET_NAMES,
    GenerationSummary,
    generate,
    generate_measurement,
)
from idkit.synth.truth import (
    TRUTH_NAMES,
    ElastomerTruth,
    ModulatedWireRopeTruth,
    SingleBodyElastomerTruth,
    WireRopeTruth,
    default_elastomer,
    default_wire_rope,
    truth_models,
)

__all__ = [
    "DEFAULT_SEED",
    "FILE_UNITS",
    "SET_NAMES",
    "TRUTH_NAMES",
    "ElastomerTruth",
    "GenerationSummary",
    "ModulatedWireRopeTruth",
    "Planned",
    "SingleBodyElastomerTruth",
    "WireRopeTruth",
    "default_elastomer",
    "default_wire_rope",
    "generate",
    "generate_measurement",
    "plan",
    "truth_models",
]
