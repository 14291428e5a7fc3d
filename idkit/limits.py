"""Size, memory and precision limits, each stated once with its reason.

Every public function and command option that could ask for more than a 24 GiB machine holds,
or for a precision float64 cannot give, is refused against one of these limits before any
work starts; the refusal names the argument and the limit (:mod:`idkit.checks`).
"""

from __future__ import annotations

import math
import sys

__all__ = ["MAX_STEPS", "MAX_SAMPLES", "MAX_GRID_POINTS", "MAX_DROP_SAMPLES", "MIN_TOLERANCE",
           "MIN_TIME_STEP", "MAX_WORKERS", "MAX_SEED", "SMALLEST_NORMAL", "MAX_FORCE_SCALE", "MAX_IMPACT_SPEED"]

#: Most integration steps of one simulated run (a time response, one harmonic point, one drop):
#: each step stores a few float64 per degree of freedom, so 10^8 steps already fill gigabytes.
MAX_STEPS = 10**8

#: Most samples one array of a signal computation holds at once (a synthesized floor record of
#: all realizations, an SRS residual window): 10^8 float64 are 800 MB.
MAX_SAMPLES = 10**8

#: Most points of one harmonic grid (``simulate harmonic --max-points``): each point holds its
#: harmonic coefficients, state and table row, at least 350 bytes at 3 harmonics, so 10^8 points
#: need over 35 GB, beyond the 24 GiB machines idkit runs on.
MAX_GRID_POINTS = 10**8

#: Most stored samples of one batch of drops (``simulate drop --max-samples``): each is at least 7
#: float64 records per degree of freedom (56 bytes), so 10^9 samples need 56 GB.
MAX_DROP_SAMPLES = 10**9

#: Smallest relative tolerance of a steady state or closed orbit: the round-off of a state
#: integrated over a period is about 1e-14 of its scale, so a smaller tolerance is never met.
MIN_TOLERANCE = 1e-12

#: Smallest time step, s: a shorter one resolves nothing an isolator does, and the step count of
#: a run of seconds would pass :data:`MAX_STEPS`.
MIN_TIME_STEP = 1e-9

#: Most worker threads of a grid or sweep (far above any machine's cores).
MAX_WORKERS = 256

#: Largest random seed: the range every generator idkit uses (numpy, nlopt) accepts.
MAX_SEED = 2**32 - 1

#: Smallest normal float64: a nonzero number below it is subnormal, with fewer significant bits,
#: and a response divided by it overflows. (Python's float is float64: ``sys.float_info`` states
#: its extremes, as ``numpy.finfo(numpy.float64)`` does, without importing numpy.)
SMALLEST_NORMAL = sys.float_info.min

#: Largest force scale (N) the implicit step handles: its Newton iteration squares the force
#: residual, which overflows float64 above the square root of its largest value.
MAX_FORCE_SCALE = math.sqrt(sys.float_info.max)

#: Largest impact speed (m/s) of a drop: its square, and so the drop height ``v0^2 / (2 g)``,
#: overflows float64 above the square root of its largest value.
MAX_IMPACT_SPEED = math.sqrt(sys.float_info.max)
