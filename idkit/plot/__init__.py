"""Figures. Every function takes ``ax=None``, returns what it drew and never calls ``show``.

matplotlib is imported lazily so that computation never pulls it in. With ``ax=None`` a
:class:`matplotlib.figure.Figure` is created directly (no pyplot, no figure registry to
leak); pass axes from ``plt.subplots`` to draw into a figure pyplot/Jupyter displays.
The backend is never chosen here: that is the caller's (``MPLBACKEND``, ``%matplotlib``).
"""

from idkit.plot.basic import (
    plot_bode,
    plot_harmonic_cross_sections,
    plot_loops,
    plot_shock_levels,
    save_figure,
)
from idkit.plot.fits import (
    plot_error_landscape,
    plot_frf_fit,
    plot_loop_fit,
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
    plot_drop_validation,
    plot_frf_validation,
    plot_harmonic_validation,
)

__all__ = [
    "plot_bode",
    "plot_complex_stiffness",
    "plot_drop_validation",
    "plot_error_landscape",
    "plot_frf_fit",
    "plot_frf_validation",
    "plot_harmonic_cross_sections",
    "plot_harmonic_validation",
    "plot_loop_fit",
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
