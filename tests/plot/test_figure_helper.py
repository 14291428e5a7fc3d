"""The one axes helper: new figures, caller's axes, atomic saving; plot functions return their Axes."""

import numpy as np

from idkit.plot import plot_bode, plot_loops, plot_shock_levels, save_figure
from idkit.plot._figure import axes_or_new, default_size, new_axes


def test_new_axes_shapes_and_sizes():
    assert new_axes().figure.get_size_inches().tolist() == list(default_size(1, 1))
    top, bottom = new_axes(2, sharex=True)
    assert top.figure is bottom.figure
    grid = new_axes(2, 3, squeeze=False)
    assert grid.shape == (2, 3)
    assert new_axes(projection="3d").name == "3d"


def test_caller_axes_are_used_and_returned():
    ax = new_axes()
    assert axes_or_new(ax) is ax
    assert plot_loops([0.0, 1e-3], [0.0, 5.0], ax=ax) is ax
    np.testing.assert_allclose(ax.get_lines()[0].get_xdata(), [0.0, 1.0])  # m drawn in mm
    assert plot_shock_levels([0.1, 0.2], [3.0, 6.0], ax=ax) is ax
    magnitude, phase = plot_bode([1.0, 10.0], np.array([1.0 + 0j, 0.5j]))
    assert magnitude.figure is phase.figure
    np.testing.assert_allclose(phase.get_lines()[0].get_ydata(), [0.0, 90.0])


def test_save_figure_writes_the_file_atomically(tmp_path):
    ax = plot_loops([0.0, 1e-3], [0.0, 5.0])
    path = save_figure(ax.figure, tmp_path / "loops.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["loops.png"]  # no staging file left
