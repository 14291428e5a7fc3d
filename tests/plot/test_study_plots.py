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
    assert panels.shape == (3, 2) and all(ax.get_visible() for ax in panels.flat)  # levels x system groups
    assert sorted(transport_figures(study)) == ["transport_output_psd.png", "transport_rest_shock.png"]


def test_psd_panels_hold_at_most_six_curves_and_clip_the_floor():
    """Ten systems split over panels of <= 6 curves; y axis 12 decades under the row's peak; x axis the band."""
    from idkit.plot.studies import PSD_FLOOR_FRACTION, transport_psd_groups

    names = ["reference", "elastomer", "wire rope"] + [f"hybrid r_k={r}" for r in (0.1, 0.2, 0.4, 0.6, 0.8, 1, 1.25)]
    groups = transport_psd_groups(names)
    assert all(len(group) <= 6 for group in groups)
    assert sorted({name for group in groups for name in group}) == sorted(names)
    study = compute_transport_study(levels=(1e-6, 1e-4), n_realizations=2, r_k_values=(0.5,),
                                     speeds=[0.05, 0.1], heights=[0.01, 0.02], seed=1)
    panels = plot_transport_psd(study)
    assert panels.shape == (2, 2)
    for row, level in zip(panels, study.levels):
        peak = max(float(item.output_psd[(item.freq >= 0.1) & (item.freq <= 100)].max()) for item in study.psd_at(level))
        for ax in row:
            low, high = ax.get_ylim()
            assert np.isclose(low, PSD_FLOOR_FRACTION * peak) and high > peak
            assert ax.get_xlim() == (0.1, 100.0)
            assert len(ax.get_lines()) <= 6
    assert "[(m/s$^2$)$^2$/Hz]" in panels[0, 0].get_ylabel()


def test_a_rest_shock_curve_that_ends_says_so():
    import pandas as pd

    from idkit.plot.studies import curve_ends
    from idkit.studies.transport import TransportStudy

    speeds = pd.Index([0.1, 0.2, 0.3])
    study = TransportStudy(tuning=pd.DataFrame(), rms=pd.DataFrame(), psd=(), seed=0, n_realizations=1,
                           flagged_runs=0, shock_velocity=pd.DataFrame({"a": [1.0, 2, 3], "b": [1.0, 2, np.nan]},
                                                                       index=speeds),
                           shock_height=pd.DataFrame({"a": [1.0, 2], "b": [1.0, 2]}, index=pd.Index([0.01, 0.02])))
    assert curve_ends(study.shock_velocity) == {"b": 0.2}
    by_speed, _ = plot_transport_rest_shock(study)
    assert [t.get_text() for t in by_speed.texts] == ["b: model invalid beyond 0.2 m/s"]


def test_ten_rest_shock_curves_are_split_into_columns_of_at_most_six():
    import pandas as pd

    from idkit.studies.transport import TransportStudy

    names = ["reference", "elastomer", "wire rope"] + [f"hybrid r_k={r}" for r in (0.1, 0.2, 0.4, 0.6, 0.8, 1, 1.25)]
    speeds, heights = pd.Index([0.1, 0.2]), pd.Index([0.01, 0.02])
    study = TransportStudy(tuning=pd.DataFrame(), rms=pd.DataFrame(), psd=(), seed=0, n_realizations=1, flagged_runs=0,
                           shock_velocity=pd.DataFrame({n: [1.0 + i, 2.0 + i] for i, n in enumerate(names)}, index=speeds),
                           shock_height=pd.DataFrame({n: [1.0 + i, 2.0 + i] for i, n in enumerate(names)}, index=heights))
    grid = plot_transport_rest_shock(study)
    assert grid.shape == (2, 3)
    drawn = [[line.get_label() for line in ax.get_lines()] for ax in grid.ravel()]
    assert all(len(labels) <= 6 for labels in drawn)
    assert set(sum(drawn, [])) == set(names)
    # one colour per system in every panel (the reference is repeated beside the hybrids)
    colours = {}
    for ax in grid.ravel():
        for line in ax.get_lines():
            assert colours.setdefault(line.get_label(), line.get_color()) == line.get_color()


def _ending_study():
    import pandas as pd

    from idkit.studies.transport import TransportStudy

    names = ["reference", "wire rope", "hybrid r_k=0.2"]
    speeds, heights = pd.Index([0.1, 0.2, 0.3]), pd.Index([0.01, 0.05, 0.10])
    velocity = pd.DataFrame({"reference": [1.0, 2.0, 3.0], "wire rope": [0.5, 1.0, np.nan],
                             "hybrid r_k=0.2": [0.8, 1.6, 2.4]}, index=speeds)
    height = pd.DataFrame({"reference": [10.0, 20.0, 30.0], "wire rope": [np.nan] * 3,
                           "hybrid r_k=0.2": [5.0, np.nan, np.nan]}, index=heights)
    rms = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.3, 0.1, 0.2], "0.001 [(m/s^2)^2/Hz]": [3.0, np.nan, 2.0]},
                       index=pd.Index(names, name="system"))
    return TransportStudy(tuning=pd.DataFrame(), rms=rms, psd=(), seed=0, n_realizations=1, flagged_runs=0,
                          shock_velocity=velocity, shock_height=height)


def test_the_model_invalid_notes_stay_inside_their_axes():
    """A curve ending at the right edge of the sweep wrote its note beyond the axes and the figure."""
    by_speed, by_height = plot_transport_rest_shock(_ending_study())
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(by_speed.figure).get_renderer()
    by_speed.figure.draw(renderer)
    for ax in (by_speed, by_height):
        box = ax.get_window_extent(renderer)
        assert ax.texts
        for text in ax.texts:
            extent = text.get_window_extent(renderer)
            assert box.x0 <= extent.x0 and extent.x1 <= box.x1 and box.y0 <= extent.y0 and extent.y1 <= box.y1
    assert by_height.texts[0].get_text() == ("wire rope: model invalid from 1 cm\n"
                                             "hybrid r_k=0.2: model invalid beyond 1 cm")


def test_the_ranking_puts_the_lowest_value_on_top_and_names_invalid_models():
    from idkit.plot.studies import plot_transport_ranking

    rms_ax, shock_ax = plot_transport_ranking(_ending_study(), height=0.01)
    labels = [tick.get_text() for tick in rms_ax.get_yticklabels()]
    positions = list(rms_ax.get_yticks())
    top_down = [label for _, label in sorted(zip(positions, labels), reverse=True)]
    assert top_down == ["hybrid r_k=0.2", "reference", "wire rope"]  # the highest level's column: 2, 3, invalid
    assert [text.get_text() for text in rms_ax.texts] == [" model invalid"]
    widths = sorted(patch.get_width() for patch in shock_ax.patches)
    assert widths == [5.0, 10.0]  # the 1 cm rest shocks; the wire rope has none
