"""Responses of models: what a fitted or catalogue isolator does under a given input.

Each function takes a model or system (:mod:`idkit.models`), runs the simulator
(:mod:`idkit.simulate`) or a closed form, and returns a typed result with ``report()`` and
``to_dataframe()``:

- :mod:`~idkit.responses.harmonic_map` - frequency-amplitude maps of steady states, HOSIDF (SPEC 5);
- :mod:`~idkit.responses.periodic` - periodic steady states by shooting, Floquet stability, 1/2 subharmonic;
- :mod:`~idkit.responses.continuation` - branches of periodic states through folds (pseudo-arclength);
- :mod:`~idkit.responses.linear` - complex stiffness, loss factor, transmissibility, damping ratios;
- :mod:`~idkit.responses.shock` - the one drop sweep: conditioned free fall, peaks per phase,
  rest shock level, SRS;
- :mod:`~idkit.responses.random_vibration` - random floor vibration, output PSDs.
"""

from idkit.responses.harmonic_map import (
    harmonic_map,
    HarmonicMap,
)
from idkit.responses.periodic import (
    periodic_response,
    PeriodicResponse,
)
from idkit.responses.continuation import (
    Branch,
    continue_in_amplitude,
    continue_in_frequency,
    SpecialPoint,
)
from idkit.responses.linear import (
    complex_stiffness,
    effective_stiffness,
    linear_frf,
    linear_resonance,
    LinearFrf,
    LinearResonance,
    loss_factor,
    stiffness_response,
    StiffnessResponse,
)
from idkit.responses.shock import (
    default_shock_grid,
    shock_sweep,
    ShockSweep,
)
from idkit.responses.random_vibration import (
    flat_input_psds,
    FLAT_LEVELS,
    is_linear_system,
    linear_output_psd,
    random_response,
    RandomResponse,
)

__all__ = [
    "Branch",
    "continue_in_amplitude",
    "continue_in_frequency",
    "periodic_response",
    "PeriodicResponse",
    "SpecialPoint",
    "complex_stiffness",
    "default_shock_grid",
    "effective_stiffness",
    "flat_input_psds",
    "FLAT_LEVELS",
    "harmonic_map",
    "HarmonicMap",
    "is_linear_system",
    "linear_frf",
    "linear_output_psd",
    "linear_resonance",
    "LinearFrf",
    "LinearResonance",
    "loss_factor",
    "random_response",
    "RandomResponse",
    "shock_sweep",
    "ShockSweep",
    "stiffness_response",
    "StiffnessResponse",
]
