"""Prony series pruned to the terms the data hold; DMA tables end to end; moduli stay moduli."""

import json

import numpy as np
import pytest

from idkit.errors import ParameterError
from idkit.fit.dma import PRUNE_FACTOR, default_max_order, fit_dma_table, fit_prony
from idkit.io.complex_stiffness import ComplexStiffnessTable
from idkit.io.provenance import Source
from idkit.models import GeneralizedMaxwell, SDOFSystem, load_model
from idkit.signal.shift_factors import wlf_log_shift

# a material with three relaxations four decades apart (Pa, 1/s)
TRUTH = GeneralizedMaxwell(k0=2.0e6, k=[3.0e6, 8.0e6, 2.0e7], rate=[1.0, 1.0e4, 1.0e8], quantity="modulus")
FREQ = np.logspace(-2, 7, 46)  # 9 decades, 5 points a decade


def noisy(model, freq, noise, seed):
    rng = np.random.default_rng(seed)
    value = model.complex_stiffness(freq)
    return value * (1 + noise * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)) / np.sqrt(2))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_pruning_keeps_the_three_terms_of_a_three_term_law(seed):
    # 1 % noise: order 3 reaches the noise floor (~1 %); order 2 cannot hold three
    # relaxations four decades apart (error > 10 %, far beyond the 1.1 factor); orders
    # above 3 only fit the noise (each pair of parameters removes ~2/92 of the residual)
    value = noisy(TRUTH, FREQ, 0.01, seed)
    pruned = fit_prony(FREQ, value.real, value.imag, quantity="modulus", max_order=6)
    assert pruned.order == 3, pruned.report()
    assert pruned.success and pruned.model.quantity == "modulus"
    errors = pruned.table.set_index("order")["error [%]"]
    assert errors[2] > 3 * PRUNE_FACTOR * errors.min()
    np.testing.assert_allclose(np.sort(pruned.model.rate), TRUTH.rate, rtol=0.1)
    assert list(pruned.table["kept"]).count(True) == 1


# TRUTH with its fast relaxation weak (1e6 Pa) and above the band (1e8 1/s > 2 pi x 1e7 Hz)
WEAK_THIRD = GeneralizedMaxwell(k0=2.0e6, k=[3.0e6, 8.0e6, 1.0e6], rate=[1.0, 1.0e4, 1.0e8], quantity="modulus")


@pytest.mark.parametrize("seed", [0, 1])
def test_at_5_percent_noise_the_pruning_keeps_the_terms_the_data_determine(seed):
    # the third term lowers the error by 4-5 % of itself (within the 1.1 factor), and fitted it
    # has a 95 % interval reaching zero (seed 1: k_3 = 2.1e6 +- 2.4e6 Pa): the data do not
    # determine it, so two terms are what they hold, not an under-fit (docs/fitting.md)
    value = noisy(WEAK_THIRD, FREQ, 0.05, seed)
    pruned = fit_prony(FREQ, value.real, value.imag, quantity="modulus", max_order=3)
    assert pruned.order == 2 and pruned.success, pruned.report()
    third = pruned.table.set_index("order").loc[3]
    assert not third["success"] and "95 % interval" in third["reasons"], third["reasons"]


def test_default_highest_order_is_one_term_a_decade():
    assert default_max_order(FREQ) == 10
    assert default_max_order([1e-12, 1e14]) == 27


# a material with a broad spectrum (one relaxation a decade): |E*| rises with frequency
# everywhere, as time-temperature superposition needs (a plateau cannot be shifted)
BROAD = GeneralizedMaxwell(k0=1.0e6, k=np.full(12, 4.0e6), rate=np.logspace(-4, 7, 12), quantity="modulus")


def _isotherm_table(noise=0.0, seed=0):
    """Isotherms 250-330 K of BROAD under WLF (C1 = 9, C2 = 120 K, Tref = 290 K), 0.1-100 Hz."""
    rng = np.random.default_rng(seed)
    freq = np.logspace(-1, 2, 16)
    rows = []
    for t in np.arange(250.0, 331.0, 10.0):
        shift = wlf_log_shift(t, c1=9.0, c2_k=120.0, reference_temperature_k=290.0)
        value = BROAD.complex_stiffness(freq * 10.0 ** shift) * (1 + noise * rng.standard_normal(freq.size))
        rows.append((freq, value, np.full(freq.size, t)))
    freq, value, temp = (np.concatenate(c) for c in zip(*rows))
    return ComplexStiffnessTable(freq=freq, storage=value.real, loss=value.imag, quantity="modulus",
                                 temperature=temp, source=Source())


def test_isotherms_to_master_curve_to_model():
    fit = fit_dma_table(_isotherm_table(), reference_temperature_k=290.0)
    assert fit.shift_source == "estimated"
    # shift factors of a noise-free table: within 0.02 decades (tests/signal/test_shift_factors.py)
    truth = wlf_log_shift(fit.shift_estimate.temperature_k, c1=9.0, c2_k=120.0, reference_temperature_k=290.0)
    np.testing.assert_allclose(fit.shift_estimate.log_a_t, truth, atol=0.02)
    assert fit.wlf.coefficients["C1"] == pytest.approx(9.0, rel=0.05)
    # the master curve is the truth at slightly wrong reduced frequencies: a 0.02-decade shift
    # error moves |E*| by at most 0.02 x max slope d log|E*| / d log f (< 0.5) = 0.01 decades
    # = 2.3 %; the model follows the master curve to its reported RMS error; by the triangle
    # inequality the model is within (error + 2.3 %) RMS of the truth
    model = fit.model
    reduced = fit.master.freq
    truth = BROAD.complex_modulus(reduced)
    deviation = np.sqrt(np.mean(np.abs(model.complex_modulus(reduced) - truth) ** 2 / np.abs(truth) ** 2))
    assert deviation <= fit.result.error + 0.023
    assert model.quantity == "modulus" and model.unit == "Pa"


def test_given_shift_factors_are_checked_and_used_only_on_request():
    from idkit.io.complex_stiffness import ShiftFactorTable

    table = _isotherm_table()
    temps = np.arange(250.0, 331.0, 10.0)
    wrong = ShiftFactorTable(temperature=temps, log_a_t=2.0 * wlf_log_shift(temps, c1=9.0, c2_k=120.0,
                                                                            reference_temperature_k=290.0))
    checked = fit_dma_table(table, order=3, shift_factors=wrong)
    assert checked.shift_source == "estimated" and not checked.check.agrees
    assert checked.shift_estimate.reference_temperature_k == 290.0  # the given set's zero
    used = fit_dma_table(table, order=3, shift_factors=wrong, use_given_shift_factors=True)
    assert used.shift_source == "given" and not used.success
    assert any("disagree" in reason for reason in used.reasons)


def test_modulus_model_file_round_trip_and_refusals(tmp_path):
    fit = fit_dma_table(_isotherm_table(), order=3, reference_temperature_k=290.0)
    path = fit.save(tmp_path / "material.json")
    document = json.loads(path.read_text())
    assert document["model"]["units"]["k0"] == "Pa" and "m_eff" not in document["model"]["params"]
    assert document["provenance"]["shift_factors"]["wlf"]["coefficients"]["C1"] == pytest.approx(9.0, rel=0.05)
    loaded = load_model(path)
    assert loaded == fit.model and loaded.quantity == "modulus"
    with pytest.raises(ParameterError, match="modulus"):
        SDOFSystem(mass=1.0, isolator=loaded)
    with pytest.raises(ParameterError, match="to_stiffness"):
        loaded.force(np.zeros(3), np.arange(3.0))


def test_shape_factor_rules():
    material = GeneralizedMaxwell(k0=1.0e6, k=[2.0e6], rate=[50.0], quantity="modulus")
    area, thickness = 4e-4, 0.02  # 20 mm x 20 mm x 20 mm block
    tension = material.to_stiffness(area_m2=area, thickness_m=thickness)
    assert tension.quantity == "stiffness" and tension.unit == "N/m"
    np.testing.assert_allclose(tension.complex_stiffness([1.0, 10.0]),
                               material.complex_modulus([1.0, 10.0]) * area / thickness, rtol=1e-15)
    # bonded cube in compression: S = a^2 / (4 a h) = 0.25, E_a = E (1 + 2 kappa S^2)
    compression = material.to_stiffness(area_m2=area, thickness_m=thickness, deformation="compression",
                                        shape_factor=0.25, compression_coefficient=0.8)
    assert compression.k0 == pytest.approx(1.0e6 * (1 + 2 * 0.8 * 0.25 ** 2) * area / thickness, rel=1e-15)
    with pytest.raises(ParameterError, match="shape_factor"):
        material.to_stiffness(area_m2=area, thickness_m=thickness, deformation="compression")
    with pytest.raises(ParameterError, match="already a stiffness"):
        tension.to_stiffness(area_m2=area, thickness_m=thickness)
    with pytest.raises(ParameterError, match="m_eff"):
        GeneralizedMaxwell(k0=1.0, k=[1.0], rate=[1.0], m_eff=0.1, quantity="modulus")


def test_pyvisco_isotherms_fitted_end_to_end():
    from idkit.datasets import read_pyvisco_complex_modulus, read_pyvisco_shift_factors, realdata_dir

    folder = realdata_dir("pyvisco_dma")
    if folder is None:
        pytest.skip("../shared/realdata/pyvisco_dma is absent")
    raw = read_pyvisco_complex_modulus(folder / "examples" / "freq_user_raw.csv")
    given = read_pyvisco_shift_factors(folder / "examples" / "time_user_raw__shift_factors.csv")
    fit = fit_dma_table(raw, order=22, shift_factors=given)
    # the reference comes from the given set (3 C); the isotherms superpose and a 22-term
    # series (the order the pruning keeps on this curve) follows them to 1.8 % RMS, where
    # the master curve shipped in the source's verification folder is fitted to 7 % at best
    assert fit.shift_estimate.reference_temperature_k == pytest.approx(276.15)
    assert fit.check.agrees
    assert fit.result.error < 0.02
    assert fit.model.unit == "Pa"


def test_a_fixed_order_does_not_depend_on_the_seeds_start():
    """Order 3 on pyvisco's isotherms: one SQP from the seeded default start stopped in a
    poorer local minimum with seed 3 (26.6 % and "success") where seeds 0-2 and 4 reach 20.4 %
    (with k0 at its bound: flagged). The fixed order now also climbs from order 1 as the pruning
    does and keeps the better fit: every seed gives the same error (to the SQP's ftol) and the
    same verdict."""
    from idkit.datasets import read_pyvisco_complex_modulus, realdata_dir

    folder = realdata_dir("pyvisco_dma")
    if folder is None:
        pytest.skip("../shared/realdata/pyvisco_dma is absent")
    raw = read_pyvisco_complex_modulus(folder / "examples" / "freq_user_raw.csv")
    fits = [fit_dma_table(raw, order=3, seed=seed).result for seed in range(5)]
    errors = np.array([fit.error for fit in fits])
    assert np.ptp(errors) <= 1e-4 * errors.min()
    assert len({fit.success for fit in fits}) == 1


def test_plots_label_a_modulus_as_a_modulus():
    from matplotlib.figure import Figure

    from idkit.plot.fits import plot_storage_loss
    from idkit.plot.responses import plot_complex_stiffness

    material = GeneralizedMaxwell(k0=1.0e6, k=[2.0e6], rate=[50.0], quantity="modulus")
    figure = Figure()
    stiffness_ax, _ = plot_storage_loss(material, axes=figure.subplots(2, 1))
    assert "[Pa]" in stiffness_ax.get_ylabel()
    part = material.to_stiffness(area_m2=1e-3, thickness_m=0.01)
    stiffness_ax, _ = plot_storage_loss(part, axes=figure.subplots(2, 1))
    assert "[N/m]" in stiffness_ax.get_ylabel()
    freq = np.array([1.0, 10.0])
    axes = plot_complex_stiffness(freq, material.complex_modulus(freq), quantity="modulus",
                                  axes=figure.subplots(2, 1))
    assert axes[0].get_ylabel() == "|E*| [Pa]"


@pytest.mark.parametrize("scale, freq_scale, repeat_one, words", [
    # 1e300 Pa: every order's error NaN -> IndexError; 1e-20 Pa or 1e-20 Hz: lmfit 'min == max'
    (1e300, 1.0, False, "expected 1e-06 to 1e+100 Pa"),
    (1e-20, 1.0, False, "expected 1e-06 to 1e+100 Pa"),
    (1.0, 1e-20, False, "expected at least 1e-12 Hz"),
    (1.0, 1e295, False, "expected 1e-100 to 1e+100 Hz"),
    # no Maxwell model has a negative storage part (the fit failed on its own bounds)
    (-1.0, 1.0, False, "expected storage > 0"),
    # one frequency repeated: three parameters from two numbers, written as a success before
    (1.0, 1.0, True, "found 1 distinct frequencies in 46 points, expected at least 2"),
])
def test_tables_no_prony_series_can_be_fitted_to_are_refused(scale, freq_scale, repeat_one, words):
    from idkit.errors import FitError

    freq = np.full(FREQ.size, 5.0) if repeat_one else FREQ * freq_scale
    value = TRUTH.complex_stiffness(freq / freq_scale) * scale
    with pytest.raises(FitError) as refused:
        fit_prony(freq, value.real, value.imag, quantity="modulus")
    assert words in str(refused.value)


def test_default_orders_stop_at_what_the_distinct_frequencies_identify():
    """Three distinct frequencies over 9 decades: orders 1 and 2 only (order 3 has 7 parameters for 6 numbers)."""
    freq = np.repeat(FREQ[[0, 20, -1]], 4)
    value = TRUTH.complex_stiffness(freq)
    pruned = fit_prony(freq, value.real, value.imag, quantity="modulus")
    assert list(pruned.table["order"]) == [1, 2]
