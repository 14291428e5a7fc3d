"""Pseudo-arclength branches: Duffing folds and backbone against harmonic balance, the Table A.1
period-doubling range against the damped Mathieu tongue, agreement with time integration."""

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import IwanModel, SDOFSystem, VoigtModel, library
from idkit.responses.continuation import (
    Branch,
    continue_in_amplitude,
    continue_in_frequency,
)
from idkit.responses.periodic import periodic_response
from idkit.simulate import harmonic_response

MASS = 1.0  # kg
STIFFNESS = (2 * np.pi * 5.0) ** 2 * MASS  # N/m: 5 Hz linear resonance
ZETA = 0.01
DAMPING = 2 * ZETA * np.sqrt(STIFFNESS * MASS)  # N s/m
BASE_AMPLITUDE = 1e-3  # m
# the linear peak deflection A / (2 zeta) = 0.05 m carries a cubic force 0.3 of the linear one
CUBIC = 0.3 * STIFFNESS / (BASE_AMPLITUDE / (2 * ZETA)) ** 2  # N/m^3
STEPS = 256
# The same discrete steady state from both sides: an orbit closed to 1e-9 and a time run settled to 1e-8.
TIME_AGREEMENT = 1e-5


def _duffing():
    """m y'' + c y' + k y + k3 y^3 = m A w^2 sin(w t): a linear spring split between the parallel
    spring and one Jenkin element that never slips (1 MN), so the friction memory is conserved (0)."""
    return SDOFSystem(MASS, IwanModel(g1=0.9 * STIFFNESS, k=[0.1 * STIFFNESS], fc=[1e6], g3=CUBIC, c_visc=DAMPING))


def _hb_omegas(amplitude):
    """First-order harmonic balance ``[(k_e - m w^2)^2 + (c w)^2] Y^2 = (m A w^2)^2``,
    ``k_e = k + 3/4 k3 Y^2``: the two frequencies (rad/s) of deflection amplitude ``Y`` (NaN if none)."""
    effective = STIFFNESS + 0.75 * CUBIC * amplitude**2
    a = MASS**2 * (amplitude**2 - BASE_AMPLITUDE**2)
    b = (DAMPING**2 - 2 * effective * MASS) * amplitude**2
    c = effective**2 * amplitude**2
    root = np.sqrt(np.where(b * b - 4 * a * c >= 0, b * b - 4 * a * c, np.nan))
    return np.sqrt((-b - root) / (2 * a)), np.sqrt((-b + root) / (2 * a))


def _hb_error_bound(amplitude, freq):
    """First-order HB error of a Duffing frequency, ``3/256 (k3 Y^2 / k)^2`` (the Lindstedt series
    of the free oscillation, ``21/256`` against HB's ``18/256`` at second order), plus the Newmark
    period error ``(w_bb h)^2 / 12``; times 1.5 for the forcing and higher orders."""
    nonlinearity = CUBIC * amplitude**2 / STIFFNESS
    backbone = np.sqrt((STIFFNESS + 0.75 * CUBIC * amplitude**2) / MASS)
    return 1.5 * (3 / 256 * nonlinearity**2 + (backbone / (freq * STEPS)) ** 2 / 12)


@pytest.fixture(scope="module")
def duffing_branch() -> Branch:
    return continue_in_frequency(_duffing(), BASE_AMPLITUDE, (4.0, 7.0), steps_per_period=STEPS)


def test_duffing_branch_follows_harmonic_balance(duffing_branch):
    branch = duffing_branch
    assert branch.success and branch.freq[-1] >= 7.0
    deflection = np.abs(branch.deflection_coefficients[:, 2])
    omega = 2 * np.pi * branch.freq
    low, high = _hb_omegas(deflection)
    predicted = np.where(np.abs(low - omega) < np.abs(high - omega), low, high)
    inside = np.isfinite(predicted) & (deflection > 3 * BASE_AMPLITUDE)  # HB's quadratic is singular at Y = A
    assert inside.sum() > 40
    error = np.abs(omega / predicted - 1)[inside]
    assert np.all(error < _hb_error_bound(deflection, branch.freq)[inside])


def test_duffing_folds_match_harmonic_balance(duffing_branch):
    folds = duffing_branch.points("fold")
    assert len(folds) == 2
    # HB folds: the turning points of the upper-frequency root w(Y) (jump down at the top, jump up below)
    grid = np.linspace(5e-3, 0.07, 200001)
    upper = _hb_omegas(grid)[1]
    top = int(np.nanargmax(upper))
    bottom = int(np.nanargmin(upper[:top]))
    expected = {"down": (upper[top] / (2 * np.pi), grid[top]), "up": (upper[bottom] / (2 * np.pi), grid[bottom])}
    found = {"down": max(folds, key=lambda p: p.freq), "up": min(folds, key=lambda p: p.freq)}
    for name in ("down", "up"):
        freq, amplitude = expected[name]
        assert abs(found[name].freq / freq - 1) < _hb_error_bound(amplitude, freq), name
    # between the folds the branch is unstable (a real multiplier above 1), outside it is stable
    table = duffing_branch.to_dataframe()
    assert table["fold"].sum() == 2
    first, second = sorted(point.index for point in folds)
    assert not table["stable"][first + 2:second - 1].any()
    assert table["stable"][:first].all() and table["stable"][second + 2:].all()
    assert (table["max |mu| [-]"][first + 2:second - 1] > 1).all()


def test_duffing_backbone_at_phase_quadrature(duffing_branch):
    """Where the deflection lags the force by 90 degrees, first-order HB puts the response on the
    backbone ``w^2 = (k + 3/4 k3 Y^2) / m``."""
    branch = duffing_branch
    ratio = branch.deflection_coefficients[:, 2] / (-1j)  # relative to the force m A w^2 sin(w t)
    crossings = np.flatnonzero(np.sign(ratio.real[:-1]) != np.sign(ratio.real[1:]))
    assert crossings.size >= 1
    index = crossings[0]
    weight = ratio.real[index] / (ratio.real[index] - ratio.real[index + 1])
    freq = branch.freq[index] + weight * (branch.freq[index + 1] - branch.freq[index])
    deflection = np.abs(branch.deflection_coefficients[[index, index + 1], 2])
    amplitude = deflection[0] + weight * (deflection[1] - deflection[0])
    backbone = np.sqrt((STIFFNESS + 0.75 * CUBIC * amplitude**2) / MASS) / (2 * np.pi)
    assert abs(freq / backbone - 1) < _hb_error_bound(amplitude, freq)
    assert amplitude > 0.05  # near the top of the resonance, strongly non-linear


def test_duffing_stable_branch_is_the_time_integration_limit(duffing_branch):
    """Outside the fold range the periodic solution is unique and a time integration reaches it."""
    branch = duffing_branch
    folds = [point.freq for point in branch.points("fold")]
    outside = np.flatnonzero(branch.stable & ((branch.freq < min(folds) - 0.05) | (branch.freq > max(folds) + 0.05)))
    chosen = outside[np.linspace(0, outside.size - 1, 4).astype(int)]
    settled = harmonic_response(_duffing(), branch.freq[chosen], BASE_AMPLITUDE, steps_per_period=STEPS,
                                tolerance=1e-8, start="linear", max_periods=20000, workers=1)
    assert settled.converged.all()
    assert np.allclose(branch.half_range[chosen, 0], settled.half_range, rtol=TIME_AGREEMENT, atol=0)


def _mathieu_tongue(mass, stiffness, damping, depth):
    """Excitation frequencies (Hz) bounding the first parametric-resonance tongue of
    ``m y'' + c y' + k (1 + depth cos(W t)) y = 0`` by first-order harmonic balance at ``W / 2``:
    ``(1 - r^2)^2 + (2 zeta r)^2 = depth^2 / 4`` with ``r = W / (2 w0)``."""
    omega0 = np.sqrt(stiffness / mass)
    zeta = damping / (2 * np.sqrt(stiffness * mass))
    # quadratic in s = r^2: s^2 + (4 zeta^2 - 2) s + 1 - depth^2/4 = 0
    roots = np.roots([1.0, 4 * zeta**2 - 2, 1 - depth**2 / 4])
    return np.sort(2 * omega0 * np.sqrt(roots.real) / (2 * np.pi))


def test_table_a1_period_doubling_range_is_the_damped_mathieu_tongue():
    """Thesis 3.4.2: the 1/2 subharmonic near 11 Hz at 1e-3 - 1.5e-3 m. The quadratic spring term
    modulates the stuck stiffness at the excitation frequency, depth ``(2 g2 + 6 g3 y_mean) Y / k``
    with Y the first-harmonic deflection: a parametric resonance at twice the stuck resonance.
    The branch's two period-doubling points bound it to the first-order Mathieu estimate,
    whose error is O(depth^2) ~ 2e-4, plus the location by interpolation between branch points
    (steps of at most 0.2 % in frequency): tolerance 1e-3 relative."""
    system = library.get("system_a1_asymmetric")
    wire_rope = system.isolator
    branch = continue_in_frequency(system, 1.2e-3, (10.5, 10.9), max_step=0.002)
    assert branch.success
    doubling = branch.points("period doubling")
    assert len(doubling) == 2
    near = [int(np.argmin(np.abs(branch.freq - point.freq))) for point in doubling]
    deflection = np.abs(branch.deflection_coefficients[near, 2]).mean()
    mean = branch.deflection_coefficients[near, 0].real.mean()
    stiffness = wire_rope.stuck_stiffness + 2 * wire_rope.g2 * mean + 3 * wire_rope.g3 * (mean**2 + deflection**2 / 2)
    depth = (2 * wire_rope.g2 + 6 * wire_rope.g3 * mean) * deflection / stiffness
    expected = _mathieu_tongue(system.mass, stiffness, wire_rope.c_visc, depth)
    found = np.sort([point.freq for point in doubling])
    assert np.all(np.abs(found / expected - 1) < 1e-3), (found, expected)
    inside = (branch.freq > found[0]) & (branch.freq < found[1])
    assert inside.any() and not branch.stable[inside].any()
    assert branch.stable[~inside][[0, -1]].all()
    table = branch.to_dataframe()
    assert table["period_doubling"].sum() == 2
    # a stable 1/2 subharmonic branch lives inside the range
    subharmonic = continue_in_frequency(system, 1.2e-3, (10.5, 10.9), start=10.68, periods=2, max_points=6,
                                        max_step=0.002)
    assert subharmonic.stable.all()
    assert np.all(np.abs(subharmonic.hosidf(0.5)) > 0.3)


def test_linear_amplitude_branch_is_flat_and_the_transmissibility():
    mass, omega0, zeta = 5.0, 2 * np.pi * 5.0, 0.05
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    branch = continue_in_amplitude(system, 20.0, (1e-4, 1e-2))
    assert branch.success and branch.amplitude[-1] >= 1e-2 and branch.stable.all()
    h1 = branch.hosidf(1)
    assert np.allclose(h1, h1[0], rtol=1e-8, atol=0)  # linear: independent of the amplitude
    analytic = system.transmissibility(20.0)
    assert abs(h1[0] / analytic - 1) < 2e-3  # Newmark at 128 steps per period (see test_harmonic_map)


def test_report_table_and_bad_input(duffing_branch):
    text = duffing_branch.report()
    assert "fold" in text and "Branch in freq" in text
    table = duffing_branch.to_dataframe()
    assert list(table.columns[:3]) == ["freq [Hz]", "amplitude [m]", "x1 [m]"]
    assert {"stable", "fold", "period_doubling", "max |mu| [-]"} <= set(table)
    with pytest.raises(SimulationError, match="start"):
        continue_in_frequency(_duffing(), 1e-3, (4.0, 7.0), start=9.0)


def test_a_branch_run_downwards_meets_the_same_solutions():
    """From 4.5 Hz down to 4 Hz: the same (unique, stable) orbits as shooting point by point."""
    downward = continue_in_frequency(_duffing(), BASE_AMPLITUDE, (4.0, 4.5), direction=-1, steps_per_period=STEPS)
    assert downward.success and downward.freq[0] == 4.5 and downward.freq[-1] <= 4.0
    assert np.all(np.diff(downward.freq) < 0)
    inside = downward.freq >= 4.0
    points = periodic_response(_duffing(), downward.freq[inside], BASE_AMPLITUDE, steps_per_period=STEPS)
    # both closed to 1e-9 of the state scale: the same discrete orbits
    assert np.allclose(downward.half_range[inside, 0], points.half_range[:, 0], rtol=1e-6, atol=0)


def test_plot_branch_dashes_unstable_parts(duffing_branch):
    from idkit.plot import plot_branch
    from idkit.responses.harmonic_map import harmonic_map

    hmap = harmonic_map(_duffing(), np.geomspace(4.0, 7.0, 9), [BASE_AMPLITUDE], steps_per_period=STEPS, workers=1)
    ax = plot_branch(duffing_branch, hmap=hmap)
    styles = [line.get_linestyle() for line in ax.get_lines()]
    assert "--" in styles and "-" in styles
    labels = [line.get_label() for line in ax.get_lines()]
    assert "fold" in labels and any(label.startswith("time integration") for label in labels)
    ax.figure.clear()


def test_a_corrector_that_wanders_off_halves_the_step_instead_of_crashing():
    """A Duffing oscillator (8 Hz, 2 %, k3 Y^2 / k up to 0.6) with a negligible Jenkin element
    (1e-3 N/m, 1e-9 N: slipping, except where the deflection turns at t = 0 on the top of the
    resonance). There the friction memory of that element makes the corrector wander to
    36000 Hz, and ``math.exp`` overflowed (OverflowError) instead of a shorter step. The branch
    must pass, with its two folds within the harmonic-balance error of the Duffing folds."""
    mass, stiffness = 2.0, (2 * np.pi * 8.0) ** 2 * 2.0
    damping, amplitude = 2 * 0.02 * np.sqrt(stiffness * mass), 2e-3
    cubic = 0.4 * stiffness / (amplitude / 0.04) ** 2
    system = SDOFSystem(mass, IwanModel(g1=stiffness, k=[1e-3], fc=[1e-9], g3=cubic, c_visc=damping))
    branch = continue_in_frequency(system, amplitude, (6.0, 12.0), steps_per_period=256)
    assert branch.success and branch.freq[-1] >= 12.0, branch.reason
    folds = sorted(point.freq for point in branch.points("fold"))
    # first-order HB turning points of [(k + 3/4 k3 Y^2 - m w^2)^2 + (c w)^2] Y^2 = (m A w^2)^2
    deflection = np.linspace(5e-3, 0.1, 200001)
    effective = stiffness + 0.75 * cubic * deflection**2
    a = mass**2 * (deflection**2 - amplitude**2)
    b = (damping**2 - 2 * effective * mass) * deflection**2
    discriminant = b * b - 4 * a * effective**2 * deflection**2
    upper = np.sqrt((-b + np.sqrt(np.where(discriminant >= 0, discriminant, np.nan))) / (2 * a))
    slope = np.diff(upper)
    turns = np.flatnonzero(slope[:-1] * slope[1:] < 0) + 1  # the jump up (a minimum), the jump down
    assert len(folds) == 2 and turns.size == 2
    for found, turn in zip(folds, turns):
        omega, height = upper[turn], deflection[turn]
        nonlinearity = cubic * height**2 / stiffness
        bound = 1.5 * (3 / 256 * nonlinearity**2 + (omega / (found * 256)) ** 2 / 12)  # as _hb_error_bound
        assert abs(found / (omega / (2 * np.pi)) - 1) < bound, (found, omega / (2 * np.pi), bound)


def test_a_branch_stopped_by_max_points_is_not_a_success():
    """Undamped linear oscillator (5.03 Hz): towards its resonance the periodic response grows
    without bound (8.3 m at 5.03 Hz after 400 points), so the branch never reaches 8 Hz. It said
    success=True and "complete"; the cap must be named with where it stopped."""
    system = SDOFSystem(1.0, VoigtModel(k=1e3, damping=0.0))
    branch = continue_in_frequency(system, 1e-3, (3.0, 8.0))
    resonance = np.sqrt(1e3) / (2 * np.pi)
    assert branch.freq.max() < resonance
    assert not branch.success
    assert "max_points (400)" in branch.reason and "freq_range" in branch.reason
    assert "complete" not in branch.report()
    short = continue_in_frequency(library.get("system_a1_asymmetric"), 1e-3, (20.0, 25.0), max_step=0.2,
                                  max_points=3)
    assert short.n_points == 3 and short.freq[-1] < 25.0 and not short.success


@pytest.mark.parametrize("arguments, name", [
    (dict(amplitude=[1e-3, 2e-3]), "amplitude"),  # TypeError from float()
    (dict(steps_per_period=100.7), "steps_per_period"),  # was truncated to 100
    (dict(steps_per_period=[128, 128]), "steps_per_period"),  # TypeError
    (dict(freq_range=(1e-6, 1e-5)), "steps per period"),  # 2.6e8 steps per period at 1e-6 Hz
])
def test_hostile_continuation_arguments_are_refused_naming_them(arguments, name):
    call = dict(amplitude=1e-3, freq_range=(4.0, 7.0)) | arguments
    with pytest.raises(SimulationError, match=name):
        continue_in_frequency(_duffing(), call.pop("amplitude"), call.pop("freq_range"), **call)


def _hb_turning_frequencies(mass, stiffness, damping, cubic, base, deflection):
    """Frequencies (rad/s) and deflections of the turning points of the first-order HB curve
    ``[(k + 3/4 k3 Y^2 - m w^2)^2 + (c w)^2] Y^2 = (m A w^2)^2`` on ``deflection`` (both roots)."""
    effective = stiffness + 0.75 * cubic * deflection**2
    a = mass**2 * (deflection**2 - base**2)
    b = (damping**2 - 2 * effective * mass) * deflection**2
    discriminant = b * b - 4 * a * effective**2 * deflection**2
    root = np.sqrt(np.where(discriminant >= 0, discriminant, np.nan))
    turns = []
    for sign in (-1.0, 1.0):
        omega = np.sqrt((-b + sign * root) / (2 * a))
        slope = np.diff(omega)
        index = np.flatnonzero(slope[:-1] * slope[1:] < 0) + 1
        turns += [(omega[i], deflection[i]) for i in index]
    return turns


def test_softening_duffing_folds_match_harmonic_balance():
    """A softening Duffing (2 kg, 8 Hz, 2 %, base 2 mm, k3 = -0.12 k / (0.05 m)^2): the resonance
    leans to lower frequencies, both folds near 7.65 Hz; first-order HB turning points within
    the bound of :func:`_hb_error_bound` at k3 Y^2 / k = -0.1 (2.5e-4; measured 1.4e-5 and
    9e-5). Between them the branch is unstable by a real multiplier above 1."""
    mass, stiffness = 2.0, (2 * np.pi * 8.0) ** 2 * 2.0
    damping, base = 2 * 0.02 * np.sqrt(stiffness * mass), 2e-3
    cubic = -0.12 * stiffness / 0.05**2
    system = SDOFSystem(mass, IwanModel(g1=0.9 * stiffness, k=[0.1 * stiffness], fc=[1e6], g3=cubic, c_visc=damping))
    branch = continue_in_frequency(system, base, (5.0, 9.0), steps_per_period=STEPS)
    assert branch.success
    folds = sorted(branch.points("fold"), key=lambda point: point.freq)
    expected = sorted(_hb_turning_frequencies(mass, stiffness, damping, cubic, base, np.linspace(1e-2, 0.07, 200001)))
    assert len(folds) == 2 and len(expected) == 2
    for point, (omega, deflection) in zip(folds, expected):
        nonlinearity = cubic * deflection**2 / stiffness
        bound = 1.5 * (3 / 256 * nonlinearity**2 + (omega / (point.freq * STEPS)) ** 2 / 12)
        assert abs(point.freq / (omega / (2 * np.pi)) - 1) < bound, (point.freq, omega / (2 * np.pi), bound)
    first, second = sorted(point.index for point in folds)
    assert not branch.stable[first + 2:second - 1].any()
    assert (np.abs(branch.multipliers[first + 2:second - 1, 0]) > 1).all()


def test_amplitude_fold_is_a_frequency_fold_of_the_branch_at_that_amplitude():
    """Hardening Duffing (8 Hz, 2 %, k3 = 0.4 k / (0.05 m)^2) at a fixed 9 Hz: the amplitude
    branch folds where the upper orbit ends (jump down, 1.661 mm; HB 1.667 mm). At that base
    amplitude the frequency branch must fold at 9 Hz: both turning points of the same discrete
    orbits, each located by the vertex of a parabola through three branch points (measured
    1e-7 apart here, 2e-4 at the other fold, 3.92 mm, where the frequency steps are coarser):
    tolerance 1e-3."""
    mass, stiffness = 2.0, (2 * np.pi * 8.0) ** 2 * 2.0
    damping = 2 * 0.02 * np.sqrt(stiffness * mass)
    cubic = 0.4 * stiffness / 0.05**2
    system = SDOFSystem(mass, IwanModel(g1=0.9 * stiffness, k=[0.1 * stiffness], fc=[1e6], g3=cubic, c_visc=damping))
    branch = continue_in_amplitude(system, 9.0, (2e-4, 4e-3), steps_per_period=STEPS)
    assert branch.success
    folds = sorted(branch.points("fold"), key=lambda point: point.amplitude)
    assert len(folds) == 2
    # between the folds (in arclength) the middle orbits are unstable, the others stable
    first, second = sorted(point.index for point in folds)
    assert branch.stable[:first].all() and branch.stable[second + 2:].all()
    assert not branch.stable[first + 2:second - 1].any()
    across = continue_in_frequency(system, folds[0].amplitude, (6.0, 12.0), steps_per_period=STEPS)
    assert any(abs(point.freq / 9.0 - 1) < 1e-3 for point in across.points("fold")), across.report()


def test_a_branch_walking_along_friction_memory_reports_no_folds_and_is_not_complete():
    """Chapter 5 hybrid (asymmetric rope), base 5 mm, from 2 Hz up: at 6.364 Hz the orbits become
    a family at fixed frequency (a multiplier at 1 whose conserved quantity the frequency
    changes, u . dG/dp = 0.47): the tangent's frequency component fell to round-off (1e-16) and
    its sign flips were reported as 13 folds on a branch whose every point is stable (a fold
    needs a multiplier through +1), which then walked back below 2 Hz and said "complete"
    without reaching 60 Hz."""
    system = library.get("hybrid_asymmetric")
    branch = continue_in_frequency(system, 5e-3, (2.0, 60.0), max_step=0.02)
    assert branch.stable.all()
    assert not branch.points("fold")
    if branch.freq.max() < 60.0:
        assert not branch.success and "family of orbits" in branch.reason
