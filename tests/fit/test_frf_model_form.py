"""Model form of the transmissibility fits (docs/fitting.md, "Verdicts"): a set whose error (7.5)
its noise floor (the H1's random error) does not explain by more than the FRF validation's
limit is not a success."""

import math

import numpy as np
import pytest

from idkit.fit import fit_maxwell, fit_voigt
from idkit.fit.frf_objective import FRF_MODEL_FORM_LIMIT, frf_noise_floor
from idkit.models import GeneralizedMaxwell, library
from idkit.models.laws import sdof_transmissibility
from idkit.observe.white_noise import TransmissibilitySet
from idkit.signal.frf import estimate_frf
from idkit.validate.frf import FRF_THRESHOLDS

MASSES = (0.99, 6.4)
FREQ = np.arange(1.0, 100.5, 1.0)  # Hz


def _sets(truth, seed: int, epsilon: float, with_floor: bool = True) -> list[TransmissibilitySet]:
    """Exact transmissibilities of ``truth`` with relative complex noise whose magnitude and phase
    each scatter by ``epsilon`` (an H1 of normalized random error ``epsilon``)."""
    rng = np.random.default_rng(seed)
    sets = []
    for mass in MASSES:
        exact = sdof_transmissibility(truth.complex_stiffness(FREQ), mass + truth.m_eff, 2 * np.pi * FREQ)
        noise = epsilon * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size))
        sets.append(TransmissibilitySet(mass, FREQ, exact * (1 + noise), f"{mass:g} kg",
                                        random_error=np.full(FREQ.size, epsilon) if with_floor else None))
    return sets


def test_the_limit_is_the_frf_validations():
    assert FRF_MODEL_FORM_LIMIT == FRF_THRESHOLDS["max_frf_error"]


def _named(result) -> list[str]:
    return [reason for reason in result.reasons if reason.startswith("the model form misses")]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_voigt_on_the_table_7_3_elastomer_is_not_a_success(seed):
    """The thesis's comparison: a viscous model on Table 7.3's two-element elastomer misses the
    6.4 kg H1 by about 23 % against a 1.4 % noise floor (before: a success, its only flaw)."""
    truth = library.get("table_7_3_elastomer")
    truth = GeneralizedMaxwell(k0=truth.k0, k=truth.k, rate=truth.rate, m_eff=0.05)
    result = fit_voigt(_sets(truth, seed, 0.01), k0=truth.k0)
    assert not result.success
    named = _named(result)
    assert named and "6.4 kg" in named[-1] and "noise floor 1.41 %" in named[-1], result.reasons
    assert "max_frf_error" in named[-1] and "higher order" in named[-1]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_one_element_for_two_separated_ones_is_not_a_success(seed):
    """Two strong elements three decades apart (rates 20 and 1500 1/s) fitted with one: about
    17 % on both masses against a 1.4 % floor (before: a success); order 2 recovers them (1.4 %)."""
    truth = GeneralizedMaxwell(k0=1000.0, k=[8000.0, 8000.0], rate=[20.0, 1500.0], m_eff=0.05)
    one = fit_maxwell(_sets(truth, seed, 0.01), k0=truth.k0, order=1)
    assert not one.success and len(_named(one)) == 2, one.reasons
    two = fit_maxwell(_sets(truth, seed, 0.01), k0=truth.k0, order=2)
    assert two.success, two.reasons


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_right_model_on_noisy_data_stays_a_success(seed):
    """A right order-2 model on H1s of 12 % random error: its error (~17 %) is the floor's
    (sqrt(2) x 12 %), above the 15 % limit, and it stays a success because the floor explains it."""
    truth = library.get("table_7_3_elastomer")
    result = fit_maxwell(_sets(truth, seed, 0.12), k0=truth.k0, order=2)
    assert result.error > FRF_MODEL_FORM_LIMIT
    assert abs(result.error - math.sqrt(2) * 0.12) < 0.02  # the floor predicts the error (2 x 100 points)
    assert not result.model_form_reasons, result.reasons


def test_without_coherence_the_whole_error_is_judged():
    truth = GeneralizedMaxwell(k0=1000.0, k=[8000.0, 8000.0], rate=[20.0, 1500.0], m_eff=0.05)
    result = fit_maxwell(_sets(truth, 0, 0.01, with_floor=False), k0=truth.k0, order=1)
    assert any("no noise floor is known" in reason for reason in result.reasons), result.reasons
    assert np.all(np.isnan(result.set_floors))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_noise_floor_is_what_a_right_model_scores_on_a_welch_h1(seed):
    """The floor sqrt(mean 2 epsilon^2) against the error (7.5) of the exact transmissibility on a
    real Welch H1 (7 averages at 50 % overlap, output noise 5 % of the output's RMS): the floor
    reads low by what the overlapping segments share (measured 3-22 % low, seeds 0-7), never high."""
    rng = np.random.default_rng(seed)
    fs, n = 1000.0, 16000
    base = rng.standard_normal(n)
    freq = np.fft.rfftfreq(n, 1.0 / fs)
    truth = library.get("table_7_3_elastomer")
    h = sdof_transmissibility(truth.complex_stiffness(np.maximum(freq, 1e-3)), 2.0, 2 * np.pi * np.maximum(freq, 1e-3))
    top = np.fft.irfft(h * np.fft.rfft(base), n)
    top = top + 0.05 * np.std(top) * rng.standard_normal(n)
    estimate = estimate_frf(base, top, fs=fs, nperseg=4000, f_lo=1.0, f_hi=50.0)
    item = TransmissibilitySet(2.0, estimate.freq, estimate.h1, random_error=estimate.random_error)
    floor = frf_noise_floor(item, (1.0, 50.0))
    exact = sdof_transmissibility(truth.complex_stiffness(estimate.freq), 2.0, 2 * np.pi * estimate.freq)
    error = math.sqrt(float(np.mean(np.abs(exact - estimate.h1) ** 2 / np.abs(estimate.h1) ** 2)))
    assert 0.85 < error / floor < 1.5, (error, floor)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("case", ["dashpot", "spring"])
def test_an_element_on_a_bound_outside_the_band_says_what_it_stands_for(seed, case):
    """An element relaxing above the band's top acts there as a dashpot c = k / rate, one below its
    bottom as a spring beside k0: the data set that one combination and the search runs along it
    to a bound. The reason says so and reads the combination, which matches the truth's to within
    the departure it states (the element is only nearly a dashpot / spring at the band edge)."""
    far = {"dashpot": 2e4, "spring": 0.3}[case]  # 1/s: 32x above 2 pi 100 Hz, 21x below 2 pi 1 Hz
    far_k = {"dashpot": 50000.0, "spring": 3000.0}[case]
    truth = GeneralizedMaxwell(k0=1000.0, k=[8000.0, far_k], rate=[40.0, far], m_eff=0.05)
    result = fit_maxwell(_sets(truth, seed, 0.01), k0=truth.k0, order=2)
    assert not result.success and result.at_bound
    (reason,) = [r for r in result.reasons if r.startswith("at a search bound")]
    element = int(np.argmin(np.abs(np.log(result.model.rate / far)))) + 1
    departure = float(reason.split("(within ")[1].split(" %")[0]) / 100
    if case == "dashpot":
        assert f"element {element} relaxes" in reason and "nearly a dashpot" in reason
        read = result.model.k[element - 1] / result.model.rate[element - 1]
        assert abs(read / (far_k / far) - 1) < departure, (read, reason)
    else:
        assert f"element {element} relaxes" in reason and "nearly a spring" in reason
        assert abs(result.model.k[element - 1] / far_k - 1) < departure, (result.model.k, reason)
