"""Compile the simulation kernels a study will run, ahead of it, beside other work.

numba compiles each simulation kernel (a driver per system structure and kind of run, the
drop rig, the period map; :mod:`idkit.simulate._kernel`) the first time a process calls it,
1-5 s each, and saves it in its on-disk cache, from which every later process loads it in
milliseconds. On a first run, ``idkit report`` needs about ten of them after its fits, and
compiled them one after another in the process that validates, while the second core had
little to do.

:func:`compile_kernels` runs each requested kernel once, on a problem of a few steps,
through the public functions the studies call (:func:`idkit.simulate.simulate`,
:func:`idkit.simulate.harmonic_response`, :func:`idkit.simulate.drop_rig`,
:func:`idkit.responses.periodic_response`), so it compiles the very signatures they need.
A kernel depends on the structure of the system (which parts each isolator has, one or two
masses), not on its parameter values: a stand-in system of the same structure compiles the
kernel a fitted system will use. Run in a forked child (:func:`idkit.forked.fork_call`)
while the fits run, it compiles on the core the fits leave free and leaves the kernels in
the cache for the validations. With a warm cache it only loads them.

It is an optimisation only: nothing depends on it. A kernel it did not compile (another
structure, a cache numba cannot write) compiles where it is first used, as before.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from idkit.responses.periodic import periodic_response
from idkit.simulate import drop_rig as run_drop_rig
from idkit.simulate import harmonic_response, simulate
from idkit.simulate._arrays import system_arrays
from idkit.simulate._structured import STRUCTURE_NAMES, structure_of

__all__ = ["compile_kernels"]

#: Excitation of the tiny harmonic problems: a base amplitude small against any isolator's
#: travel and a frequency of the order of the studies' resonances.
_FREQ_HZ = 10.0
_AMPLITUDE_M = 1e-5


def compile_kernels(*, time: Sequence = (), harmonic: Sequence = (), drop_rig: Sequence = (),
                    period_map: Sequence = ()) -> tuple[str, ...]:
    """Compile (or load from numba's cache) the kernels that simulate the given systems.

    Parameters
    ----------
    time, harmonic, drop_rig, period_map : sequences of SDOFSystem or HybridSystem
        Systems whose time-response kernel (:func:`idkit.simulate.simulate`), harmonic-map
        kernel (:func:`idkit.simulate.harmonic_response`), drop-rig kernel
        (:func:`idkit.simulate.drop_rig`) and period map
        (:func:`idkit.responses.periodic_response`) to compile. Systems of one structure share
        a kernel (compiled once); any system of the structure will do.

    Returns
    -------
    tuple of str
        What was run, one entry per kernel: "time: SDOF Iwan", "drop rig", ...

    Examples
    --------
    >>> from idkit.models import library
    >>> compile_kernels(time=[library.get("system_b1_medium")])
    ('time: SDOF Maxwell',)
    """
    done: list[str] = []

    def once(entry: str) -> bool:
        if entry in done:
            return False
        done.append(entry)
        return True

    for system in time:
        if once(f"time: {_structure_name(system)}"):
            simulate(system, np.arange(3) * 1e-4, workers=1)
    for system in harmonic:
        if once(f"harmonic: {_structure_name(system)}"):
            harmonic_response(system, _FREQ_HZ, _AMPLITUDE_M, workers=1)
    for system in drop_rig:
        if once("drop rig"):  # one kernel for every structure
            run_drop_rig(system, bottom_mass=float(np.sum(system.masses)), drop_height=[1e-3], duration=1e-3,
                         workers=1)
    for system in period_map:
        if once("period map"):  # one kernel for every structure
            periodic_response(system, _FREQ_HZ, _AMPLITUDE_M, settle_periods=1, max_iterations=1)
    return tuple(done)


def _structure_name(system) -> str:
    return STRUCTURE_NAMES[structure_of(system_arrays(system))]
