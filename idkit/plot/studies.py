"""Figures of the studies: chapters 3-5 (:mod:`idkit.studies.chapters`) and the transport study.

Each ``plot_*`` function draws one figure's content into ``ax``/``axes`` (default: a new
figure from :mod:`idkit.plot._figure`) and returns the Axes. :func:`chapter_figures` and
:func:`transport_figures` return every figure of a study keyed by its file name; the files
are written by :mod:`idkit.report.study_files`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from idkit.plot._figure import axes_or_new, new_axes
from idkit.plot.responses import (
    plot_complex_stiffness,
    plot_map_cross_sections,
    plot_map_surface,
    plot_map_top_view,
    plot_resonance_vs_amplitude,
    plot_shock_deflection,
    plot_shock_sweep,
    plot_transmissibility,
)

if TYPE_CHECKING:
    from idkit.studies.chapters import ChapterStudy, ElastomerCase, MapCase, ShockCase
    from idkit.studies.transport import TransportStudy

__all__ = [
    "chapter_figures",
    "plot_shock_cases",
    "plot_transport_psd",
    "plot_transport_rest_shock",
    "transport_figures",
]


def _order_title(order: float) -> str:
    return "1/2 subharmonic" if order == 0.5 else f"harmonic {order:g}"


def _map_figures(case: MapCase) -> dict:
    """Surfaces, top views, cross sections and resonance of one harmonic map."""
    figures = {}
    for quantity, tag, title in (("ratio", "ratio", "peak-peak/2"), (1, "h1", "1st harmonic")):
        ax = plot_map_surface(case.hmap, quantity, ax=new_axes(projection="3d", figsize=(7.0, 5.5)))
        ax.set_title(f"{case.name}: {title}", fontsize="small")
        figures[f"map_{case.name}_{tag}_surface.png"] = ax.figure
    orders = case.top_view_orders
    axes = new_axes(1, len(orders), figsize=(5.0 * len(orders), 4.2), squeeze=False)[0]
    for ax, order in zip(axes, orders):
        plot_map_top_view(case.hmap, order, ax=ax)
        ax.set_title(f"{case.name}: {_order_title(order)}", fontsize="small")
    figures[f"map_{case.name}_top_views.png"] = axes[0].figure
    axes = plot_map_cross_sections(case.hmap, case.cross_amplitudes,
                                   axes=new_axes(2, 1, sharex=True, figsize=(6.4, 4.8)))
    axes[0].set_title(f"{case.name}: 1st harmonic cross sections", fontsize="small")
    figures[f"cross_sections_{case.name}.png"] = axes[0].figure
    ax = plot_resonance_vs_amplitude(case.hmap, ax=new_axes(figsize=(6.4, 4.0)))
    ax.set_title(f"{case.name}: resonance (peak of |H1|)", fontsize="small")
    figures[f"resonance_{case.name}.png"] = ax.figure
    return figures


def plot_shock_cases(shocks: dict[str, ShockCase], *, axes=None):
    """Rest shock level versus |v0| (left) and versus h (right), one line per labelled case.

    Parameters
    ----------
    shocks : dict of str to ShockCase
        Legend label -> the case's sweeps.
    axes : pair of Axes, optional

    Returns
    -------
    (Axes, Axes)
    """
    axes = axes_or_new(axes, 1, 2, figsize=(11.0, 4.2))
    for label, shock in shocks.items():
        plot_shock_sweep(shock.by_speed, label=label, ax=axes[0])
        plot_shock_sweep(shock.by_height, versus="height", label=label, ax=axes[1])
    for ax in axes:
        ax.legend(fontsize="small")
    return axes


def _per_case_figure(shocks: dict[str, ShockCase], draw) -> object:
    axes = new_axes(1, len(shocks), figsize=(5.5 * len(shocks), 4.2), squeeze=False)[0]
    for ax, (label, shock) in zip(axes, shocks.items()):
        draw(shock.by_speed, ax)
        ax.set_title(label, fontsize="small")
        ax.legend(fontsize="small")
    return axes[0].figure


def _map_study_figures(study: ChapterStudy) -> dict:
    figures = {}
    for case in study.cases:
        figures.update(_map_figures(case))
    shocks = {case.symmetry: case.shock for case in study.cases}
    figures["shock_rest_level.png"] = plot_shock_cases(shocks)[0].figure
    figures["shock_phases.png"] = _per_case_figure(
        shocks, lambda sweep, ax: plot_shock_sweep(sweep, quantity="phases", ax=ax))
    figures["shock_deflection.png"] = _per_case_figure(shocks, lambda sweep, ax: plot_shock_deflection(sweep, ax=ax))
    if study.hybrid_linear is not None:
        frf = study.hybrid_linear
        axes = new_axes(2, 1, sharex=True, figsize=(6.4, 6.0))
        plot_complex_stiffness(frf.freq, frf.component_stiffness[0], label="elastomer (Table B.1 medium)", axes=axes)
        plot_complex_stiffness(frf.freq, frf.component_stiffness[1], label="wire rope, stuck (Table A.1)", axes=axes)
        plot_complex_stiffness(frf.freq, frf.stiffness, label="hybrid (series)", axes=axes)
        axes[0].legend(fontsize="small")
        figures["linear_hybrid_stiffness.png"] = axes[0].figure
        axes = plot_transmissibility(frf, label="hybrid, small amplitude",
                                     axes=new_axes(2, 1, sharex=True, figsize=(6.4, 6.0)))
        axes[0].legend(fontsize="small")
        figures["linear_hybrid_transmissibility.png"] = axes[0].figure
    return figures


def _elastomer_figures(cases: tuple[ElastomerCase, ...]) -> dict:
    stiffness_axes = new_axes(2, 1, sharex=True, figsize=(6.4, 6.0))
    frf_axes = new_axes(2, 1, sharex=True, figsize=(6.4, 6.0))
    for case in cases:
        plot_complex_stiffness(case.frf.freq, case.frf.stiffness, label=case.variant, axes=stiffness_axes)
        plot_transmissibility(case.frf, label=case.variant, axes=frf_axes)
    stiffness_axes[0].legend(fontsize="small", title="Table B.1")
    frf_axes[0].legend(fontsize="small", title="Table B.1, 5 kg")
    return {
        "elastomer_complex_stiffness.png": stiffness_axes[0].figure,
        "elastomer_transmissibility.png": frf_axes[0].figure,
        "shock_rest_level.png": plot_shock_cases({case.variant: case.shock for case in cases})[0].figure,
    }


def chapter_figures(study: ChapterStudy) -> dict:
    """Every figure of a chapter study, keyed by its file name (``*.png``).

    Wire rope and hybrid: per case ``map_<case>_ratio_surface``, ``map_<case>_h1_surface``,
    ``map_<case>_top_views``, ``cross_sections_<case>``, ``resonance_<case>``; per study
    ``shock_rest_level``, ``shock_phases``, ``shock_deflection``; hybrid also
    ``linear_hybrid_stiffness`` and ``linear_hybrid_transmissibility``. Elastomer:
    ``elastomer_complex_stiffness``, ``elastomer_transmissibility``, ``shock_rest_level``.

    Returns
    -------
    dict of str to Figure
    """
    if study.name == "elastomer":
        return _elastomer_figures(study.cases)
    return _map_study_figures(study)


def plot_transport_psd(study: TransportStudy, *, axes=None):
    """Output acceleration PSD of every system, one panel per floor level (two panels per row).

    Returns
    -------
    ndarray of Axes
        One per level (unused panels hidden).
    """
    levels = study.levels
    rows = (len(levels) + 1) // 2
    if axes is None:
        axes = new_axes(rows, 2, figsize=(12, 3.2 * rows))
    axes = np.atleast_1d(axes).ravel()
    for ax, level in zip(axes, levels):
        for item in study.psd_at(level):
            keep = item.freq > 0
            ax.loglog(item.freq[keep], item.output_psd[keep], label=item.system, linewidth=1.0)
        ax.set_title(f"floor PSD {level:g} (m/s$^2$)$^2$/Hz, 0.1-100 Hz", fontsize="small")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("top acceleration PSD")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize="xx-small", ncol=2)
    for ax in axes[len(levels):]:
        ax.set_visible(False)
    return axes


def plot_transport_rest_shock(study: TransportStudy, *, axes=None):
    """Rest shock level of every system versus |v0| (left) and drop height in cm (right).

    Returns
    -------
    (Axes, Axes)
    """
    by_speed, by_height = axes_or_new(axes, 1, 2, figsize=(11, 4.2))
    for name in study.shock_velocity.columns:
        by_speed.plot(study.shock_velocity.index, study.shock_velocity[name], marker=".", label=name)
        by_height.plot(study.shock_height.index * 100, study.shock_height[name], marker=".", label=name)
    by_speed.set_xlabel("impact speed |v0| [m/s]")
    by_height.set_xlabel("drop height h [cm]")
    for ax in (by_speed, by_height):
        ax.set_ylabel("rest shock level [m/s$^2$]")
        ax.grid(True, alpha=0.3)
    by_speed.legend(fontsize="xx-small", ncol=2)
    return by_speed, by_height


def transport_figures(study: TransportStudy) -> dict:
    """The transport study's figures keyed by file name: ``transport_output_psd.png``, ``transport_rest_shock.png``."""
    return {"transport_output_psd.png": plot_transport_psd(study)[0].figure,
            "transport_rest_shock.png": plot_transport_rest_shock(study)[0].figure}
