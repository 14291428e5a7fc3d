"""Figures of the transport study draw the study's numbers and return their Axes."""

import numpy as np

from idkit.plot.studies import plot_transport_psd, plot_transport_rest_shock, transport_figures
from idkit.studies.transport import compute_transport_study


def test_transport_figures_draw_the_study():
    study = compute_transport_study(levels=(1e-6, 1e-5, 1e-4), n_realizations=2, r_k_values=(0.5,),
                                    speeds=[0.05, 0.1], heights=[0.01, 0.02], seed=1)
    by_speed, by_height = plot_transport_rest_shock(study)
    assert len(by_speed.get_lines()) == len(study.shock_velocity.columns) == 4
    np.testing.assert_allclose(by_height.get_lines()[0].get_xdata(), [1.0, 2.0])  # m drawn in cm
    np.testing.assert_array_equal(by_speed.get_lines()[0].get_ydata(), study.shock_velocity["reference"])
    panels = plot_transport_psd(study)
    assert len(panels) == 4 and [ax.get_visible() for ax in panels] == [True, True, True, False]
    assert sorted(transport_figures(study)) == ["transport_output_psd.png", "transport_rest_shock.png"]
