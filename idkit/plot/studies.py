"""Figures of the studies: chapters 3-5 (:mod:`idkit.studies.chapters`) and the transport study.

Each ``plot_*`` function draws one figure's content into ``ax``/``axes`` (default: a new
figure from :mod:`idkit.plot._figure`) and returns the Axes. :func:`chapter_figures` and
:func:`transport_figures` return every figure of a study keyed by its file name; the files
are written by :mod:`idkit.report.study_files`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from idkit.plot._figure import axes_or_new, column_grid, grid_result, new_axes
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
    "curve_ends",
    "plot_shock_cases",
    "plot_transport_psd",
    "plot_transport_ranking",
    "plot_transport_rest_shock",
    "transport_figures",
    "transport_psd_groups",
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


#: most curves drawn in one panel (more are split over panels)
MAX_CURVES = 6
#: PSD values below this fraction of a row's peak are numerical floor, not response
PSD_FLOOR_FRACTION = 1e-12


def transport_psd_groups(systems, max_curves: int = MAX_CURVES) -> list[list[str]]:
    """Systems split into panels of at most ``max_curves`` curves.

    The non-hybrid systems share the first panel; the hybrids are spread evenly over as
    few further panels as fit, each with the reference repeated for comparison.

    Examples
    --------
    >>> groups = transport_psd_groups(["reference", "elastomer", "wire rope"] + [f"h{r}" for r in range(7)])
    >>> groups[0]
    ['reference', 'elastomer', 'wire rope', 'h0', 'h1', 'h2']
    >>> transport_psd_groups(["reference", "elastomer", "wire rope"] + [f"hybrid {r}" for r in range(7)])[1]
    ['reference', 'hybrid 0', 'hybrid 1', 'hybrid 2', 'hybrid 3']
    """
    systems = list(systems)
    hybrids = [name for name in systems if name.startswith("hybrid")]
    others = [name for name in systems if name not in hybrids]
    groups = [others[i:i + max_curves] for i in range(0, len(others), max_curves)]
    if hybrids:
        per_panel = max_curves - 1 if "reference" in systems else max_curves
        panels = -(-len(hybrids) // per_panel)
        size = -(-len(hybrids) // panels)
        for i in range(0, len(hybrids), size):
            groups.append((["reference"] if "reference" in systems else []) + hybrids[i:i + size])
    return groups


def curve_ends(table) -> dict[str, float]:
    """``{column: last finite index value}`` of every column of ``table`` whose values stop before its last row.

    A rest-shock sweep stops where the model goes invalid (the simulator flags the run and
    the level is NaN from there on).

    Examples
    --------
    >>> import pandas as pd
    >>> curve_ends(pd.DataFrame({"a": [1.0, 2.0, 3.0], "b": [1.0, 2.0, np.nan]}, index=[0.1, 0.2, 0.3]))
    {'b': 0.2}
    """
    ends = {}
    for name in table.columns:
        finite = np.isfinite(table[name].to_numpy(float))
        if finite.any() and not finite[-1]:
            ends[name] = float(table.index.to_numpy(float)[np.flatnonzero(finite)[-1]])
    return ends


def plot_transport_psd(study: TransportStudy, *, axes=None, band_hz: tuple[float, float] = (0.1, 100.0),
                       max_curves: int = MAX_CURVES):
    """Output acceleration PSD per floor level (rows) and group of systems (columns).

    At most ``max_curves`` curves a panel (:func:`transport_psd_groups`); the x axis spans
    the floor band ``band_hz`` (beyond its upper edge the input is zero and the output is an
    artefact of the band edge); the y axis is clipped at :data:`PSD_FLOOR_FRACTION` of the
    row's peak (below it the curves are numerical floor).

    Returns
    -------
    ndarray of Axes, shape (levels, groups)
    """
    levels = study.levels
    systems = [item.system for item in study.psd_at(levels[0])]
    groups = transport_psd_groups(systems, max_curves)
    if axes is None:
        axes = new_axes(len(levels), len(groups), figsize=(4.4 * len(groups), 2.5 * len(levels) + 0.8),
                        squeeze=False, sharex=True)
    axes = np.asarray(axes).reshape(len(levels), len(groups))
    colours = {name: f"C{index % 10}" for index, name in enumerate(systems)}
    for row, level in zip(axes, levels):
        curves = {item.system: item for item in study.psd_at(level)}
        inside = {name: (item.freq >= band_hz[0]) & (item.freq <= band_hz[1]) for name, item in curves.items()}
        peak = max(float(np.nanmax(item.output_psd[inside[name]])) for name, item in curves.items())
        for ax, group in zip(row, groups):
            for name in group:
                item = curves[name]
                keep = inside[name] & (item.output_psd > 0)
                ax.loglog(item.freq[keep], item.output_psd[keep], label=name, color=colours[name], linewidth=1.0)
            ax.set_ylim(PSD_FLOOR_FRACTION * peak, 3.0 * peak)
            ax.set_xlim(*band_hz)
            ax.set_title(f"floor {level:g} (m/s$^2$)$^2$/Hz", fontsize="small")
            ax.grid(True, which="major", alpha=0.3)
        row[0].set_ylabel("top accel. PSD\n[(m/s$^2$)$^2$/Hz]")
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
    for ax in axes[0]:
        ax.legend(fontsize="x-small", loc="lower left")
    return axes


def plot_transport_rest_shock(study: TransportStudy, *, axes=None):
    """Rest shock level versus |v0| (top row) and drop height in cm (bottom row).

    More than :data:`MAX_CURVES` systems are split into columns (without ``axes``;
    :func:`transport_psd_groups`: the non-hybrid systems first, then the hybrids with the
    reference repeated); with a (speed, height) pair every system is drawn into it. A curve that
    stops before the end of its sweep (the model left its valid range and the simulator flagged
    the runs) ends in a cross, and a note in the panel's upper left corner says "model invalid
    beyond ..." (inside the axes, whatever the data's range).
    One colour per system throughout.

    Returns
    -------
    (Axes, Axes) or ndarray of Axes, shape (2, n_columns)
        The pair, or the grid (speed row, height row) when split.
    """
    systems = list(study.shock_velocity.columns)
    colours = {name: f"C{index % 10}" for index, name in enumerate(systems)}
    groups = [systems] if axes is not None or len(systems) <= MAX_CURVES else transport_psd_groups(systems)
    grid = column_grid(axes, len(groups), column_width=4.4, height=7.6)
    for column, group in enumerate(groups):
        for row, (table, scale, unit) in enumerate(((study.shock_velocity, 1.0, "m/s"),
                                                     (study.shock_height, 100.0, "cm"))):
            ax = grid[row, column]
            ends = curve_ends(table)
            notes = []
            for name in group:
                colour = colours[name]
                ax.plot(table.index * scale, table[name], marker=".", color=colour, label=name)
                if name in ends:
                    x_end = ends[name] * scale
                    ax.plot([x_end], [table[name][ends[name]]], "x", color=colour, markersize=9, mew=2)
                    notes.append(f"{name}: model invalid beyond {x_end:.3g} {unit}")
                elif name in table.columns and not np.isfinite(table[name].to_numpy(float)).any():
                    notes.append(f"{name}: model invalid from {table.index.min() * scale:.3g} {unit}")
            if notes:  # inside the axes, in their corner, whatever the data's range
                ax.text(0.02, 0.97, "\n".join(notes), transform=ax.transAxes, ha="left", va="top",
                        fontsize="x-small", bbox={"facecolor": "white", "alpha": 0.8, "edgecolor": "0.7"})
            ax.set_xlabel("impact speed |v0| [m/s]" if row == 0 else "drop height h [cm]")
            ax.grid(True, alpha=0.3)
        grid[0, column].legend(fontsize="x-small", loc="lower right")
    for row in range(2):
        grid[row, 0].set_ylabel("rest shock level [m/s²]")
    return grid_result(grid)


def plot_transport_ranking(study: TransportStudy, *, height: float = 0.05, axes=None):
    """Systems ranked: RMS top acceleration at the highest floor level (left) and rest shock at ``height`` (right).

    Horizontal bars, the lowest (best protecting) value on top; a system without a value
    (its model left its valid range) is listed with the words "model invalid" and no bar. One
    colour per system, as in :func:`plot_transport_rest_shock`.

    Parameters
    ----------
    study : TransportStudy
    height : float
        Drop height (m) of the rest shock (:meth:`~idkit.studies.transport.TransportStudy.rest_shock_at`).
    axes : pair of Axes, optional

    Returns
    -------
    (Axes, Axes)
    """
    axes = axes_or_new(axes, 1, 2, figsize=(7.2, 3.0))
    systems = list(study.shock_velocity.columns)
    colours = {name: f"C{index % 10}" for index, name in enumerate(systems)}
    level = max(study.rms.columns, key=lambda column: float(str(column).split()[0]))  # "<level> [unit]"
    for ax, values, title in ((axes[0], study.rms[level], f"RMS top acceleration, floor {level}"),
                              (axes[1], study.rest_shock_at(height), f"rest shock, drop {100 * height:g} cm")):
        values = values.astype(float)
        ordered = list(values[np.isfinite(values.to_numpy())].sort_values().index)
        ordered += [name for name in values.index if name not in ordered]
        positions = np.arange(len(ordered))[::-1]
        for position, name in zip(positions, ordered):
            value = float(values[name])
            if np.isfinite(value):
                ax.barh(position, value, color=colours.get(name, "0.5"))
            else:
                ax.text(0.0, position, " model invalid", va="center", fontsize="x-small", color="0.3")
        ax.set_yticks(positions, ordered, fontsize="small")
        ax.set_xlabel("[m/s$^2$] (lower protects better)", fontsize="small")
        ax.set_title(title, fontsize="small")
        ax.grid(True, axis="x", alpha=0.3)
    return axes


def transport_figures(study: TransportStudy) -> dict:
    """The transport study's figures keyed by file name: ``transport_output_psd.png``, ``transport_rest_shock.png``."""
    return {"transport_output_psd.png": np.ravel(plot_transport_psd(study))[0].figure,
            "transport_rest_shock.png": np.ravel(plot_transport_rest_shock(study))[0].figure}
