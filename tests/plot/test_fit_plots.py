"""Figures of fits draw what the caller computed and return the Axes they drew into."""

import numpy as np
import pytest

from idkit.fit import fit_iwan_measurements, maxwell_error_landscape, transmissibility_sets
from idkit.fit.predictions import FitPrediction, predict_loops
from idkit.io import load_measurement_set
from idkit.models import SDOFSystem
from idkit.plot.fits import plot_error_landscape, plot_frf_fit, plot_loop_fit, plot_storage_loss, save_fit_plots
from tests.fit.small_set import ELASTOMER, write_small_set


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    return load_measurement_set(write_small_set(tmp_path_factory.mktemp("set")))


def test_loop_fit_draws_the_predicted_forces(data):
    # the set also holds elastomer loops; one order and family given (the rules choose the same
    # here, and they are not what a figure test checks)
    iwan = fit_iwan_measurements(data, isolator="wire_rope", order=2, family="plain")
    prediction = predict_loops(iwan.model, iwan.data.small, iwan.data.large)
    small_ax, large_ax = plot_loop_fit(prediction)
    # measured and model line per set; the model line holds exactly the predicted force (N)
    assert len(small_ax.get_lines()) == 2 * len(iwan.data.small)
    assert len(large_ax.get_lines()) == 2 * len(iwan.data.large)
    np.testing.assert_array_equal(small_ax.get_lines()[1].get_ydata(), prediction.small[0].model_force)
    np.testing.assert_array_equal(small_ax.get_lines()[1].get_xdata(), 1e3 * prediction.small[0].deflection)
    # the legend names the model once: every model curve has the colour of the labelled one
    for ax in (small_ax, large_ax):
        models = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
        assert {line.get_color() for line in models} == {models[0].get_color()}
        assert [text.get_text() for text in ax.get_legend().get_texts()] == ["measured", "model"]


def test_frf_fit_draws_the_model_law_per_mass(data):
    frfs, _ = transmissibility_sets(data)
    magnitude_ax, phase_ax = plot_frf_fit(ELASTOMER, frfs)
    model_lines = [line for line in magnitude_ax.get_lines() if line.get_linestyle() == "--"]
    assert len(model_lines) == 3  # one model line per mass
    # the dashed line is the SDOF law of models.systems, to round-off
    freq = model_lines[0].get_xdata()
    expected = np.abs(SDOFSystem(0.99, ELASTOMER).transmissibility(freq))
    np.testing.assert_allclose(model_lines[0].get_ydata(), expected, rtol=1e-12)
    assert magnitude_ax.figure is phase_ax.figure


def test_storage_loss_and_landscape(data):
    stiffness_ax, loss_ax = plot_storage_loss(ELASTOMER)
    assert np.all(loss_ax.get_lines()[0].get_ydata() > 0)  # a Maxwell solid dissipates at every frequency
    frfs, _ = transmissibility_sets(data)
    landscape = maxwell_error_landscape(frfs, k0=ELASTOMER.k0, points=15)
    ax = plot_error_landscape(landscape)
    assert ax.get_xscale() == "log" and ax.figure.axes  # contours and a colour bar


def test_save_fit_plots_refuses_to_overwrite_before_drawing(data, tmp_path):
    frfs, _ = transmissibility_sets(data)
    prediction = FitPrediction("maxwell", ELASTOMER, frfs=tuple(frfs), band=(1.0, 100.0))
    written = save_fit_plots(prediction, tmp_path)
    assert [p.name for p in written] == ["maxwell_frf.png", "maxwell_complex_stiffness.png"]  # no landscape given
    with pytest.raises(FileExistsError, match="refusing to overwrite"):
        save_fit_plots(prediction, tmp_path)


def test_frf_figures_split_into_columns_of_at_most_three_top_masses():
    """Eight top masses: three columns (3, 3, 2), each panel at most six curves' worth of
    setups (a legend entry per top mass), every mass drawn once."""
    from idkit.models.laws import sdof_transmissibility
    from idkit.observe.white_noise import TransmissibilitySet
    from idkit.plot._figure import panel_groups

    assert panel_groups(range(8)) == [[0, 1, 2], [3, 4, 5], [6, 7]]
    assert panel_groups(range(3)) == [[0, 1, 2]] and panel_groups([]) == [[]]
    masses = [0.99, 1.29, 1.69, 2.20, 2.88, 3.75, 4.90, 6.40]
    frfs = []
    for mass in masses:
        freq = np.linspace(1.0, 100.0, 200)
        response = sdof_transmissibility(ELASTOMER.small_amplitude_stiffness(freq), mass + ELASTOMER.m_eff,
                                         2 * np.pi * freq)
        frfs.append(TransmissibilitySet(name=f"m{mass}", mass=mass, freq=freq, transmissibility=response))
    grid = plot_frf_fit(ELASTOMER, frfs)
    assert grid.shape == (2, 3)
    labels = [[text.get_text() for text in ax.get_legend().get_texts()] for ax in grid[0]]
    assert [len(column) for column in labels] == [3, 3, 2]
    assert sum(labels, []) == [f"{mass:.2f} kg" for mass in masses]


def test_parameter_spread_legend_does_not_depend_on_the_first_row():
    # the first parameter at a bound (no standard error), the second with one: the legend
    # still names the bars; with no standard error and no refit anywhere the panel says so
    # (an empty legend was a matplotlib warning, an error under the test settings)
    from types import SimpleNamespace

    import pandas as pd

    from idkit.plot import plot_parameter_spread

    def fit(stderrs):
        table = pd.DataFrame({"parameter": ["g1", "k_1"], "unit": ["N/m", "N/m"], "value": [1e4, 2e4],
                              "stderr": stderrs, "fitted": [True, True]})
        return SimpleNamespace(parameters_table=lambda: table, spread=None)

    ax = plot_parameter_spread(fit([None, 400.0]))
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["±2 standard errors", "±1 standard error"]
    empty = plot_parameter_spread(fit([None, None]))
    assert empty.get_legend() is None
    assert any("no standard errors" in t.get_text() for t in empty.texts)
