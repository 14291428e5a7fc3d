"""``idkit catalogue report``: the parts of a catalogue side by side (figure and table).

Computes :func:`idkit.catalogue.characteristics.part_characteristics` for every usable part
and writes, into a new folder, ``catalogue.png`` (four panels: secant stiffness and loss factor
versus amplitude with 5-95 % bands, loops at the common amplitudes, transmissibility at a
common payload per mount with bands) and ``characteristics.csv`` (the curves, long format).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from idkit.atomic import write_bytes_atomic
from idkit.catalogue.characteristics import CYCLE_FREQ_HZ, part_characteristics
from idkit.errors import OutputError

__all__ = ["catalogue_characteristics", "plot_catalogue", "write_catalogue_report"]


def catalogue_characteristics(catalogue, *, payload_per_mount_kg: float = 5.0, n_draws: int = 20,
                              seed: int = 0) -> list:
    """Characteristics of every usable part of ``catalogue`` (mean model and draws)."""
    out = []
    for record in catalogue.usable():
        names = tuple(record["covariance"]["names"])
        matrix = np.asarray(record["covariance"]["matrix"], dtype=float).reshape(len(names), len(names))
        out.append(part_characteristics(record["part"], record["family"], catalogue.model(record["part"]), names,
                                        matrix, payload_per_mount_kg=payload_per_mount_kg, n_draws=n_draws,
                                        seed=seed))
    return out


def plot_catalogue(characteristics, *, figure=None):
    """Draw the four panels (module docstring); returns the figure."""
    import matplotlib.pyplot as plt

    figure = figure or plt.figure(figsize=(11, 8))
    axes = figure.subplots(2, 2)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for index, item in enumerate(characteristics):
        colour = colours[index % len(colours)]
        style = "-" if item.family == "wire_rope" else "--"
        millimetres = 1e3 * item.amplitude_m
        axes[0, 0].loglog(millimetres, item.secant_stiffness, style, color=colour, label=item.part)
        axes[0, 0].fill_between(millimetres, *item.secant_stiffness_band, color=colour, alpha=0.2)
        axes[0, 1].semilogx(millimetres, item.loss_factor, style, color=colour)
        axes[0, 1].fill_between(millimetres, *item.loss_factor_band, color=colour, alpha=0.2)
        for deflection, force in item.loops:
            axes[1, 0].plot(1e3 * deflection, force, style, color=colour, lw=1)
        axes[1, 1].loglog(item.freq_hz, item.transmissibility, style, color=colour)
        axes[1, 1].fill_between(item.freq_hz, *item.transmissibility_band, color=colour, alpha=0.2)
    axes[0, 0].set(xlabel="amplitude [mm]", ylabel=f"secant stiffness at {CYCLE_FREQ_HZ:g} Hz [N/m]")
    axes[0, 1].set(xlabel="amplitude [mm]", ylabel="loss factor [-]")
    if characteristics:
        amplitudes = ", ".join(f"{1e3 * a:g}" for a in characteristics[0].loop_amplitudes_m)
        axes[1, 0].set(xlabel="deflection [mm] (positive = tension)", ylabel="force [N]",
                       title=f"loops at {amplitudes} mm, {CYCLE_FREQ_HZ:g} Hz")
        axes[1, 1].set(xlabel="frequency [Hz]", ylabel="|H| [-]",
                       title=f"small-amplitude transmissibility, {characteristics[0].payload_per_mount_kg:g} kg per mount")
    axes[0, 0].legend(fontsize=7)
    for axis in axes.flat:
        axis.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    return figure


def _table(characteristics) -> pd.DataFrame:
    frames = []
    for item in characteristics:
        frames.append(pd.DataFrame({"part": item.part, "amplitude [m]": item.amplitude_m,
                                    "secant stiffness [N/m]": item.secant_stiffness,
                                    "secant stiffness 5 % [N/m]": item.secant_stiffness_band[0],
                                    "secant stiffness 95 % [N/m]": item.secant_stiffness_band[1],
                                    "loss factor [-]": item.loss_factor,
                                    "loss factor 5 % [-]": item.loss_factor_band[0],
                                    "loss factor 95 % [-]": item.loss_factor_band[1]}))
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()


def write_catalogue_report(catalogue, output, *, payload_per_mount_kg: float = 5.0, n_draws: int = 20,
                           seed: int = 0) -> list[Path]:
    """Write ``catalogue.png`` and ``characteristics.csv`` into the new folder ``output``."""
    output = Path(output)
    if output.exists():
        raise OutputError(f"{output}: exists; expected a new report folder")
    characteristics = catalogue_characteristics(catalogue, payload_per_mount_kg=payload_per_mount_kg,
                                                n_draws=n_draws, seed=seed)
    output.mkdir(parents=True)
    import io

    import matplotlib.pyplot as plt

    figure = plot_catalogue(characteristics)
    try:
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=110)
    finally:
        plt.close(figure)
    return [write_bytes_atomic(output / "catalogue.png", buffer.getvalue()),
            write_bytes_atomic(output / "characteristics.csv", _table(characteristics).to_csv(index=False).encode())]
