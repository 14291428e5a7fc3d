"""Time simulation of isolator systems (SPEC 1.5, 5).

The fast path (:func:`simulate`, :func:`free_fall`, :func:`harmonic_response`)
runs batches through one compiled kernel: average-acceleration Newmark with the
exact Jenkin stop operator and exact exponential Maxwell update. Independent
reference paths for cross-checks live in :mod:`idkit.simulate.reference`. The drop rig
(:func:`drop_rig`): the whole stack released from rest, bottom mass on a unilateral floor.
"""

from idkit.simulate._arrays import STANDARD_GRAVITY
from idkit.simulate.base_motion import BaseMotion
from idkit.simulate.drop_rig import (
    DEFAULT_CONTACT,
    ContactModel,
    DropRigResponse,
    contact_from_velocity_step,
    drop_rig,
)
from idkit.simulate.force_driven import ForceDrivenResponse, ForceInput, benchmark_truth, simulate_force_driven
from idkit.simulate.moreau import MoreauResponse, moreau_coulomb_spring
from idkit.simulate.reference import ReferenceHarmonic, ReferenceResponse, harmonic_reference, solve_ivp_reference
from idkit.simulate.harmonic import (
    HarmonicResponse,
    default_steps_per_period,
    harmonic_response,
    small_amplitude_resonance,
)
from idkit.simulate.time_response import (
    IntegratorState,
    TimeResponse,
    TimeState,
    free_fall,
    initial_states,
    relaxation_deflection,
    simulate,
    static_deflection,
)

__all__ = [
    "BaseMotion", "IntegratorState", "TimeResponse", "TimeState", "simulate", "free_fall", "static_deflection", "initial_states", "relaxation_deflection",
    "HarmonicResponse", "harmonic_response", "default_steps_per_period", "small_amplitude_resonance",
    "STANDARD_GRAVITY", "solve_ivp_reference", "harmonic_reference", "ReferenceResponse", "ReferenceHarmonic",
    "moreau_coulomb_spring", "MoreauResponse", "drop_rig", "DropRigResponse", "ContactModel", "DEFAULT_CONTACT",
    "contact_from_velocity_step",
    "ForceInput", "ForceDrivenResponse", "simulate_force_driven", "benchmark_truth",
]
