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
(:func:`idkit.synth.truth.truth_models`; not bundled). The sets are written by
:mod:`idkit.synth.sets`; their names, the truths' names and the default seed live in the light
:mod:`idkit.synth.names`, which the command's parser reads.
"""

from typing import TYPE_CHECKING

from idkit.exports import lazy_exports

if TYPE_CHECKING:  # for type checkers and editors: the names below (tests/test_exports.py keeps them equal)
    from idkit.synth.experiments import Planned, plan
    from idkit.synth.names import DEFAULT_SEED, SET_NAMES, TRUTH_NAMES
    from idkit.synth.sets import FILE_UNITS, GenerationSummary, generate, generate_measurement
    from idkit.synth.truth import (ElastomerTruth, ModulatedWireRopeTruth, SingleBodyElastomerTruth, WireRopeTruth,
                                   default_elastomer, default_wire_rope, truth_models)

# imported on first use: the parser reads idkit.synth.names without importing the generator
__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    "experiments": ("Planned", "plan"),
    "names": ("DEFAULT_SEED", "SET_NAMES", "TRUTH_NAMES"),
    "sets": ("FILE_UNITS", "GenerationSummary", "generate", "generate_measurement"),
    "truth": ("ElastomerTruth", "ModulatedWireRopeTruth", "SingleBodyElastomerTruth", "WireRopeTruth",
              "default_elastomer", "default_wire_rope", "truth_models"),
})
