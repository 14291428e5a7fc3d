"""The steps specialised per system structure against the generic step, on the same inputs.

The specialised steps (:mod:`idkit.simulate._structured`) perform the generic step's
floating-point operations in the same order on the parts the structure has (the generic step
adds exact zeros for the absent ones), so the records agree to round-off. Tolerance: 1e-10
relative to the record's largest magnitude, four orders above what a reordering of a few
operations by the compiler could produce (1e-14 per step, amplified by the Newton tolerance
1e-13 over 1e4 steps of a stable system). Flags must be identical. The generic path is obtained
by emptying ``_kernel.SPECIALISED`` (every structure then runs the generic driver).
"""

from __future__ import annotations

import functools

import numba
import numpy as np
import pytest

from idkit.models import BoucWenModel, ModulatedIwanModel, library
from idkit.models.systems import HybridSystem, SDOFSystem
from idkit.simulate import _generic_step, _kernel, free_fall, harmonic_response, simulate
from idkit.simulate._arrays import system_arrays
from idkit.simulate._structured import (
    GENERIC,
    HYBRID,
    HYBRID_MODULATED,
    SDOF_IWAN,
    SDOF_IWAN_MODULATED,
    SDOF_MAXWELL,
    step_hybrid,
    step_sdof,
    structure_of,
)

RTOL = 1e-10

SYSTEMS = {
    "sdof_iwan": (lambda: library.get("system_a1_asymmetric"), SDOF_IWAN),
    "sdof_maxwell": (lambda: library.get("system_b1_medium"), SDOF_MAXWELL),
    "hybrid": (lambda: library.get("hybrid_asymmetric"), HYBRID),
    "sdof_boucwen": (lambda: SDOFSystem(1.0, BoucWenModel(k1=3e3, k2=2e5, k3=-1e6, alpha=2.5e4, beta=1.2e4,
                                                          gamma=3e3, n=1.3, b=np.e, c=20.0)), GENERIC),
    "sdof_modulated_iwan": (lambda: SDOFSystem(1.0, _modulated_rope()), SDOF_IWAN_MODULATED),
    "hybrid_modulated_iwan": (lambda: HybridSystem(1.0, library.get("table_7_3_elastomer"), 0.2,
                                                   _modulated_rope()), HYBRID_MODULATED),
    # the symmetric term alone (a = 0) is a modulation too: not the plain step
    "sdof_symmetric_modulation": (lambda: SDOFSystem(1.0, _modulated_rope(a=0.0, b=0.5)), SDOF_IWAN_MODULATED),
    "sdof_modulated_maxwell_part": (lambda: SDOFSystem(1.0, _modulated_with_maxwell()), GENERIC),
}


def _modulated_rope(a=0.35, b=0.25):
    return ModulatedIwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3],
                              slip_modulation=a, slip_growth=b, slip_length=6e-3)


def _modulated_with_maxwell():
    """A modulated rope with a Maxwell element in the same isolator: no specialised step has both."""
    from idkit.models.base import IsolatorArrays

    rope = _modulated_rope()

    class _Mixed(type(rope)):
        def kernel_arrays(self) -> IsolatorArrays:
            arrays = super().kernel_arrays()
            return IsolatorArrays(**{**arrays.__dict__, "maxwell_stiffness": np.array([2e3]),
                                     "maxwell_rate": np.array([50.0])})

    return _Mixed(**{name: getattr(rope, name) for name in ("g1", "g2", "g3", "k", "fc", "slip_modulation",
                                                            "slip_length")})


def both_paths(monkeypatch, run):
    """``run()`` with the specialised kernels, then with the generic kernel only."""
    specialised = run()
    with monkeypatch.context() as patch:
        patch.setattr(_kernel, "SPECIALISED", frozenset())
        generic = run()
    return specialised, generic


def assert_same_records(specialised, generic, names):
    for name in names:
        a = np.asarray(getattr(specialised, name))
        b = np.asarray(getattr(generic, name))
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        finite = ~np.isnan(b)
        scale = np.max(np.abs(b[finite])) if finite.any() else 1.0
        np.testing.assert_allclose(a[finite], b[finite], rtol=0, atol=RTOL * scale, err_msg=name)
    np.testing.assert_array_equal(specialised.flags, generic.flags)


@pytest.mark.parametrize("name", list(SYSTEMS))
def test_structure_is_recognised(name):
    build, expected = SYSTEMS[name]
    assert structure_of(system_arrays(build())) == expected


@pytest.mark.parametrize("name", list(SYSTEMS))
def test_random_base_and_drop_agree(monkeypatch, name):
    """Random base acceleration (random vibration) and a conditioned drop with gravity."""
    system = SYSTEMS[name][0]()
    rng = np.random.default_rng(7)
    time = np.arange(4001) * 2e-4
    accel = rng.normal(0.0, 20.0, size=(3, time.size))
    names = ("displacement", "velocity", "acceleration", "isolator_force")
    assert_same_records(*both_paths(monkeypatch, lambda: simulate(system, time, base_acceleration=accel,
                                                                    workers=1)), names)
    assert_same_records(*both_paths(monkeypatch, lambda: free_fall(
        system, impact_velocity=[-0.5, -2.0], duration=0.2, time_step=1e-4, gravity=True, workers=1)), names)


@pytest.mark.parametrize("name", list(SYSTEMS))
def test_harmonic_map_agrees(monkeypatch, name):
    """Steady-state map points, including one far outside the valid range of the wire rope."""
    system = SYSTEMS[name][0]()
    freq = np.array([3.0, 8.0, 20.0])
    amplitude = np.array([2e-4, 1e-3, 5e-2])
    specialised, generic = both_paths(monkeypatch, lambda: harmonic_response(
        system, freq, amplitude, max_periods=40, workers=1))
    assert_same_records(specialised, generic, ("coefficients", "deflection_coefficients", "half_range",
                                               "peak_acceleration", "change"))
    np.testing.assert_array_equal(specialised.periods, generic.periods)
    np.testing.assert_array_equal(specialised.converged, generic.converged)


def test_kernels_are_compiled_once_per_structure():
    assert _kernel.time_kernel(SDOF_IWAN) is _kernel.time_kernel(SDOF_IWAN)
    assert _kernel.harmonic_kernel(HYBRID) is _kernel.harmonic_kernel(HYBRID)
    assert _kernel.time_kernel(GENERIC) is _kernel.run_time_batch
    # a structure outside SPECIALISED runs the generic driver
    assert _kernel.time_kernel(99) is _kernel.run_time_batch


def test_each_structures_driver_has_its_own_name_and_cache_files():
    """numba names a compiled closure by its qualified name and a per-process counter and keeps
    one cache index per qualified name: two structures' drivers compiled in two processes came
    out under one name (seen: SDOF Iwan and slip-modulated SDOF Iwan both
    'run_time_batchB2v1') and shared one index, where concurrent saves could cross their entries
    (idkit._numba_cache). Each structure's driver has its own name and index file."""
    structures = sorted(_kernel.SPECIALISED | {GENERIC})
    for kernel in (_kernel.time_kernel, _kernel.harmonic_kernel):
        drivers = [kernel(structure) for structure in structures]
        names = {driver.py_func.__qualname__ for driver in drivers}
        indexes = {driver._cache._cache_file._index_path for driver in drivers}
        assert len(names) == len(indexes) == len(structures)


#: The step each specialised driver calls (its kind of Iwan or Maxwell part), as the drivers' dispatch.
_STEPS = {SDOF_IWAN: (1, 1), SDOF_MAXWELL: (1, 2), HYBRID: (2, 1), SDOF_IWAN_MODULATED: (1, 3),
          HYBRID_MODULATED: (2, 3)}


@functools.lru_cache(maxsize=None)
def _specialised_step_of(structure):
    """The specialised step of ``structure`` compiled as its driver calls it, the kind a literal: a
    constant of the closure (numba types it as a literal and prunes the other kinds' branches), as
    the structure is in the drivers. One compile per structure; a literal made at each call instead
    (``numba.literally``) would type the call again every time."""
    masses, kind = _STEPS[structure]
    if masses == 1:
        @numba.njit
        def step(m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
            return step_sdof(kind, m0, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)
    else:
        @numba.njit
        def step(m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
            return step_hybrid(kind, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)
    return masses, step


def _specialised_step(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
    masses, step = _specialised_step_of(structure)
    assert masses == ndof
    return step(m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)


def _random_step_inputs(arrays, rng):
    """A step from a random state: steps from 1e-5 to 0.05 s, base moves up to 20 mm, element
    forces anywhere within their slip limits, Maxwell elongations up to 5 mm (hard steps: the
    Newton iteration halves its directions and some steps fail, as at the edge of a map)."""
    h = 10.0 ** rng.uniform(-5.0, np.log10(0.05))
    P = _kernel._pack(*arrays.as_tuple()[1:], h)
    ndof = arrays.ndof
    jforce = rng.uniform(-1.0, 1.0, arrays.jk.shape) * arrays.jfc
    mstate = rng.uniform(-5e-3, 5e-3, arrays.mk.shape) * (arrays.mk > 0)
    S = _kernel._pack_states(P, jforce, mstate, np.zeros(ndof))
    state = np.zeros(6)
    state[:ndof] = rng.uniform(-1e-2, 1e-2, ndof)
    state[2:2 + ndof] = rng.uniform(-1.0, 1.0, ndof)
    state[4:4 + ndof] = rng.uniform(-50.0, 50.0, ndof)
    xb_old, xb_new = rng.uniform(-2e-2, 2e-2, 2)
    return (ndof, arrays.masses[0], arrays.masses[1] if ndof == 2 else 1.0, state, h, rng.choice([0.0, 9.81]),
            xb_old, xb_new, rng.uniform(-1.0, 1.0), P, S, _kernel_force_scale(arrays))


def _kernel_force_scale(arrays):
    from idkit.simulate._arrays import force_scale

    return force_scale(arrays, 4e2)


@pytest.mark.parametrize("name", [name for name, (_, structure) in SYSTEMS.items() if structure != GENERIC])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_one_step_equals_the_generic_step(name, seed):
    """One step from 200 random states: the specialised step returns the generic step's flag,
    state and committed internal states bit for bit (the same operations in the same order; the
    specialised step commits the Jenkin forces of its last evaluation instead of evaluating the
    converged point again, which is the same point)."""
    build, structure = SYSTEMS[name]
    arrays = system_arrays(build())
    rng = np.random.default_rng(seed)
    flags = set()
    for _ in range(200):
        ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, scale = _random_step_inputs(arrays, rng)
        state_g, S_g = state.copy(), S.copy()
        flag = _specialised_step(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, scale)
        flag_g = _generic_step._step(ndof, m0, m1, state_g, h, load, xb_old, xb_new, vb_new, P, S_g, scale)
        assert flag == flag_g
        flags.add(int(flag))
        if flag == _kernel.FLAG_OK:
            np.testing.assert_array_equal(state, state_g)
            np.testing.assert_array_equal(S[:, :3], S_g[:, :3])  # row 3: scratch of the last trial
    assert _kernel.FLAG_OK in flags


def test_a_driver_compiles_only_its_own_step():
    """A driver calls _kernel.structure_step with its structure, a constant of its closure: the
    call resolves at compile time to that structure's step alone, so the SDOF driver types the
    SDOF step only (were every structure's step typed, every step would compile with every driver,
    the hybrid's included). A fresh process, so that no step has been typed before, with the
    driver's own on-disk cache off: it is compiled, and so typed, there (a driver loaded from the
    cache types nothing); the steps it calls are then compiled or loaded, and either way counted
    in their signatures. Which functions are typed does not depend on LLVM's optimisation level,
    so the process compiles at level 0 (NUMBA_OPT), a fraction of the driver's optimised compile,
    and saves nothing to the cache (its machine code is not the other processes')."""
    import os
    import subprocess
    import sys

    code = (
        "from numba.core import caching\n"
        "from idkit.models import library\n"
        "from idkit.simulate import simulate, _generic_step, _kernel, _structured\n"
        "import numpy as np\n"
        "caching.Cache.save_overload = lambda self, sig, data: None\n"
        "_kernel.time_kernel(_structured.SDOF_MAXWELL)._cache = caching.NullCache()\n"
        "simulate(library.get('system_b1_low'), np.arange(11) * 1e-3, base_acceleration=np.zeros(11), workers=1)\n"
        "print([str(s[0]) for s in _structured.step_hybrid.signatures], len(_structured.step_sdof.signatures), "
        "len(_generic_step._step.signatures))\n"
    )
    env = dict(os.environ, IDKIT_WORKERS="1", NUMBA_OPT="0")
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert result.stdout.strip().splitlines()[-1] == "[] 1 0"
