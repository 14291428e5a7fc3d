"""Figures of results. Every function takes ``ax``/``axes=None``, returns the Axes it drew into and never calls ``show``.

Plots draw what the caller computed: they never run a fitter or a simulation (model forces
along loops and error landscapes come from :mod:`idkit.fit.predictions`, studies from
:mod:`idkit.studies`). matplotlib is imported lazily, and only by the one axes helper
:mod:`idkit.plot._figure`: with ``ax=None`` it creates a :class:`matplotlib.figure.Figure`
directly (no pyplot, no figure registry to leak); pass axes from pyplot to draw into a
figure pyplot/Jupyter displays. The backend is never chosen here: that is the caller's
(``MPLBACKEND``, ``%matplotlib``).
"""

from idkit.plot.basic import (
    plot_bode,
    plot_harmonic_cross_sections,
    plot_loops,
    plot_shock_levels,
    save_figure,
)
from idkit.plot.branches import plot_branch
from idkit.plot.fits import (
    plot_error_landscape,
    plot_frf_fit,
    plot_loop_fit,
    plot_parameter_spread,
    plot_storage_loss,
    save_fit_plots,
)
from idkit.plot.responses import (
    plot_complex_stiffness,
    plot_map_cross_sections,
    plot_map_surface,
    plot_map_top_view,
    plot_output_psd,
    plot_resonance_vs_amplitude,
    plot_shock_deflection,
    plot_shock_sweep,
    plot_transmissibility,
)
from idkit.plot.validation import (
    plot_drop_histories,
    plot_drop_validation,
    plot_frf_validation,
    plot_harmonic_validation,
    plot_sweep_bode,
    plot_sweep_maps,
)

__all__ = [
    "plot_bode",
    "plot_branch",
    "plot_complex_stiffness",
    "plot_drop_histories",
    "plot_drop_validation",
    "plot_error_landscape",
    "plot_frf_fit",
    "plot_frf_validation",
    "plot_harmonic_cross_sections",
    "plot_harmonic_validation",
    "plot_sweep_bode",
    "plot_sweep_maps",
    "plot_loop_fit",
    "plot_parameter_spread",
    "plot_loops",
    "plot_map_cross_sections",
    "plot_map_surface",
    "plot_map_top_view",
    "plot_output_psd",
    "plot_resonance_vs_amplitude",
    "plot_shock_deflection",
    "plot_shock_levels",
    "plot_shock_sweep",
    "plot_storage_loss",
    "plot_transmissibility",
    "save_figure",
    "save_fit_plots",
]
