"""Figures. Every function takes ``ax=None``, returns what it drew and never calls ``show``.

pyplot is imported lazily so that computation never pulls in matplotlib.
"""

from idkit.plot.basic import (
    plot_bode,
    plot_harmonic_cross_sections,
    plot_loops,
    plot_shock_levels,
    save_figure,
)

__all__ = ["plot_loops", "plot_bode", "plot_harmonic_cross_sections", "plot_shock_levels", "save_figure"]
