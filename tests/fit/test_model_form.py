"""Model-form check of the array-level loop fits (docs/fitting.md, "Verdicts"): a fit whose error is
more than FLOOR_MARGIN above the noise floor read off its own residual is not a success."""

import numpy as np
import pytest

from idkit.fit import fit_iwan, prepare_loops
from idkit.fit.model_form import FLOOR_MARGIN, MODEL_FORM_PREFIX, residual_floor
from tests.fit.test_boucwen import TRUTH as BOUC_WEN_TRUTH
from tests.fit.test_boucwen import _noisy_loop_sets
from tests.fit.test_iwan import LARGE_AMPLITUDES, SMALL_AMPLITUDES, _truth

POINTS = 200  # the fit's default grid: at 60 samples a cycle it is denser than the record mid-branch


def _loops(model, amplitudes, noise, samples_per_cycle, rng, prefix):
    """Sine loops from the unloaded origin (2.25 cycles), white force noise ``noise`` x RMS force."""
    sets = []
    for index, amplitude in enumerate(amplitudes):
        phase = np.linspace(0.0, 4.5 * np.pi, int(2.25 * samples_per_cycle))
        x = amplitude * np.sin(phase)
        force = model.force(x)
        force = force + noise * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
        sets.append(prepare_loops(x, force, points_per_set=POINTS, name=f"{prefix}{index}"))
    return sets


def _model_form(result):
    return [reason for reason in result.reasons if reason.startswith(MODEL_FORM_PREFIX)]


def test_an_iwan_fit_of_bouc_wen_loops_is_not_a_success():
    # before the check: success at 8.6 / 3.6 % (1 % noise); the floor read off the residual is
    # the 1 % noise, so the small loops are 7.4 points above it (limit 2)
    small, large = _noisy_loop_sets(BOUC_WEN_TRUTH, 0.01, np.random.default_rng(35))
    result = fit_iwan(small, large, order=2)
    assert result.error_small - 0.01 > 2 * FLOOR_MARGIN  # far beyond the margin, whatever the seed
    assert not result.success
    assert any(reason.startswith(f"{MODEL_FORM_PREFIX} small loops") for reason in _model_form(result))


@pytest.mark.parametrize("noise", [0.02, 0.05])  # at and well beyond the margin itself
@pytest.mark.parametrize("samples_per_cycle", [400, 60])  # record denser / sparser than the grid
@pytest.mark.parametrize("seed", [1, 2])
def test_the_right_model_on_noisy_loops_passes_the_model_form_check(noise, samples_per_cycle, seed):
    # the error is the noise (2 or 5 % of the RMS force) and the floor reads it from the repeated
    # branches, interpolated or not: measured error - floor within +-0.5 point (limit 2)
    rng = np.random.default_rng(seed)
    truth = _truth()
    small = _loops(truth, SMALL_AMPLITUDES, noise, samples_per_cycle, rng, "small")
    large = _loops(truth, LARGE_AMPLITUDES, noise, samples_per_cycle, rng, "large")
    result = fit_iwan(small, large, order=2)
    assert result.error_small > 0.8 * noise  # the noise is in the error ...
    assert _model_form(result) == []  # ... and in the floor
    assert result.success, result.reasons


@pytest.mark.parametrize("samples_per_cycle", [400, 60, 30])
@pytest.mark.parametrize("seed", [1, 2])
def test_residual_floor_of_repeated_branches_reads_the_noise_of_the_resampled_points(samples_per_cycle, seed):
    # pure noise as the residual: the floor is the RMS of the resampled noise (the error an exactly
    # right model scores), also where the grid interpolates between sparse samples (there the
    # second-difference estimate alone read 10 times low). 6.25 cycles on 600 points (the
    # measurement fits' grid): 10 pairs of repeated branches; over 30 seeds floor / noise was
    # 0.91-1.10 (standard deviation 2.7-4.5 %), so 20 % is 4.5 standard deviations
    rng = np.random.default_rng(seed)
    phase = np.linspace(0.0, 12.5 * np.pi, int(6.25 * samples_per_cycle))
    x = 1e-3 * np.sin(phase)
    clean = 1e3 * x + 0.5
    loop = prepare_loops(x, clean + 0.01 * rng.standard_normal(x.size), points_per_set=600)
    smooth = prepare_loops(x, clean, points_per_set=600).force  # the interpolated noise-free force
    noise = np.sqrt(np.mean((loop.force - smooth) ** 2)) / np.sqrt(np.mean(loop.force**2))
    floor = residual_floor(loop.force, smooth, loop.reversals, loop.deflection)
    assert floor == pytest.approx(noise, rel=0.2)
