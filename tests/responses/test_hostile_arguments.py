"""Public response functions given what is no number: an idkit error naming the argument (these
raised numpy's bare ValueError/TypeError or AttributeError), and abscissae that are not finite and
increasing (a NaN gave a NaN peak, a repeated one a division by zero)."""

import warnings

import numpy as np
import pytest

from idkit.errors import IdkitError
from idkit.models import SDOFSystem, VoigtModel
from idkit import responses as R

SYSTEM = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=0.5))


@pytest.mark.parametrize("name, call, words", [
    ("loss_factor", lambda: R.loss_factor("abc"), "stiffness: found 'abc'"),
    ("shock_sweep height", lambda: R.shock_sweep(SYSTEM, drop_height="abc"), "drop_height: found 'abc'"),
    ("shock_sweep velocity", lambda: R.shock_sweep(SYSTEM, impact_velocity=["fast"]), "impact_velocity: found"),
    ("is_linear_system", lambda: R.is_linear_system("abc"), "system: found str"),
])
def test_bad_argument_raises_an_idkit_error_naming_it(name, call, words):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy warning on the way
        with pytest.raises(IdkitError) as raised:
            call()
    assert words in str(raised.value)


def test_loss_factor_of_zero_storage_is_nan_or_inf_without_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        values = R.loss_factor([0j, 1j, 2 + 1j])
    assert np.isnan(values[0]) and values[1] == np.inf and values[2] == 0.5


@pytest.mark.parametrize("call, words", [
    # numpy's "Maximum allowed size exceeded" / "int too big to convert"
    (lambda: R.random_response(SYSTEM, R.flat_input_psds([1e-4])[1e-4], seed=1, n_realizations=1, fs=1e300),
     "floor samples to synthesize, expected at most 1e+08"),
    (lambda: R.random_response(SYSTEM, R.flat_input_psds([1e-4])[1e-4], seed=1, n_realizations=1e300),
     "found 1e+300 x 800 Hz"),
    (lambda: R.harmonic_map(SYSTEM, [5.0], [1e-3], max_periods=1e300), "max_periods: found 1e+300 periods"),
])
def test_absurd_sizes_and_flags_are_refused_naming_them(call, words):
    with pytest.raises(IdkitError) as raised:
        call()
    assert words in str(raised.value)


def test_linear_resonance_band_and_shock_relaxation_flag_are_checked():
    with pytest.raises(IdkitError, match=r"f_min, f_max: found 10.0, 1.0"):
        R.linear_resonance(SYSTEM, f_min=10, f_max=1)
    with pytest.raises(IdkitError, match=r"relaxation: found 'no', expected True or False"):  # relaxed before
        R.shock_sweep(SYSTEM, drop_height=[0.1], relaxation="no")


@pytest.mark.parametrize("arguments, words", [
    (dict(f_lo=100.0, f_hi=10.0), "f_lo, f_hi: found 100.0 and 10.0 Hz, expected f_lo < f_hi"),
])
def test_flat_input_psds_refuses_a_band_out_of_range(arguments, words):
    with pytest.raises(IdkitError) as raised:
        R.flat_input_psds([1e-4], **arguments)
    assert words in str(raised.value)


def test_flat_input_psds_band_limit_is_the_nyquist_frequency_of_the_smallest_step():
    from idkit.cli.options import MIN_TIME_STEP
    from idkit.responses.random_vibration import MAX_PSD_FREQ

    assert MAX_PSD_FREQ == pytest.approx(0.5 / MIN_TIME_STEP, rel=1e-15)
    profile = R.flat_input_psds([1e-4], f_lo=1.0, f_hi=MAX_PSD_FREQ)[1e-4]
    assert profile.rms() == pytest.approx(np.sqrt(1e-4 * (MAX_PSD_FREQ - 1.0)), rel=1e-12)
