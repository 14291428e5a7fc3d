"""``idkit inspect PATH``: summary and data-quality warnings of measurements, optional plots."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from idkit.errors import DataError

__all__ = ["load_for_inspection", "register", "save_overview_plots"]

_KIND_BY_COLUMN = (("force", "quasi_static"), ("a_top_1", "drop"), ("x_base", "stepped_sine"),
                   ("u_in", "stepped_sine"))


def _guess_kind(path: Path) -> str:
    """Kind of a lone CSV file from its header (a white-noise and a stepped-sine file differ
    only by the manifest's frequency, so v_base/v_top alone reads as white noise)."""
    from idkit.io.csv_table import decode_text, read_file_bytes

    # the reader's own checks (not a file, corrupt gzip, not UTF-8) and messages
    header = decode_text(path, read_file_bytes(path)).partition("\n")[0]
    names = {cell.split("[")[0].strip() for cell in header.split(",")}
    for column, kind in _KIND_BY_COLUMN:
        if column in names:
            return kind
    if {"v_base", "v_top"} <= names or {"a_base", "a_top"} <= names:
        return "white_noise"
    raise DataError(f"file '{path}': cannot tell the kind from the header {header.strip()!r}; "
                    "expected columns of a quasi_static, white_noise, stepped_sine or drop file "
                    "(or pass --kind)")


def load_for_inspection(path: str | Path, kind: str | None = None):
    """Measurements of a measurement-set folder or of a single data file.

    A single file takes its metadata from the manifest of an enclosing set when one lists
    it, otherwise its kind from ``kind`` or from its header.

    Returns
    -------
    (str, list)
        A title and the measurements.
    """
    from idkit.io import load_measurement_set, read_csv_measurement, read_manifest

    path = Path(path)
    if not path.exists():
        raise DataError(f"'{path}': no such file or folder; expected a measurement-set folder "
                        "(with manifest.json) or a data file")
    if path.is_dir():
        if not (path / "manifest.json").exists():
            raise DataError(f"folder '{path}': no manifest.json; expected a measurement-set "
                            "folder (see docs/data-format.md)")
        measurement_set = load_measurement_set(path)
        title = measurement_set.name or path.name
        return title, list(measurement_set.measurements)
    for parent in path.resolve().parents:
        if (parent / "manifest.json").exists():
            manifest = read_manifest(parent)
            relative = path.resolve().relative_to(parent).as_posix()
            for entry in manifest.entries:
                if entry.file == relative:
                    return path.name, [read_csv_measurement(path, entry.kind, info=entry.info)]
            break
    if path.suffix.lower() == ".mat":
        raise DataError(f"file '{path}': a lone .mat file holds no measurement metadata (kind, units, masses); "
                        "expected a measurement CSV, or a measurement-set folder whose manifest lists the .mat "
                        "file with its variables and units (docs/data-format.md, section 4)")
    return path.name, [read_csv_measurement(path, kind or _guess_kind(path))]


def _axes(_unused=None, nrows=1):
    """Axes of a new figure (matplotlib's object API; pyplot is never imported)."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6.4, 2.4 + 2.2 * nrows), layout="constrained")
    return figure.subplots(nrows, 1, sharex=True)


def save_overview_plots(measurements, folder: str | Path, *, force: bool = False) -> list[Path]:
    """One overview figure per kind present: loops, |H1| and coherence, stepped-sine input
    amplitude and |HOSIDF_1|, drop rest shock levels. Each file is written atomically;
    existing files are replaced only with ``force``.

    Returns
    -------
    list of pathlib.Path
        The written PNG files.
    """
    from idkit.observe.white_noise import frf_from_white_noise
    from idkit.observe.drop import process_drop_measurement
    from idkit.observe.stepped_sine import stepped_sine_sweep
    from idkit.plot.basic import plot_loops, plot_shock_levels, save_figure

    folder = Path(folder)
    kinds = sorted({m.kind for m in measurements})
    targets = {kind: folder / f"overview_{kind}.png" for kind in kinds}
    existing = [str(p) for p in targets.values() if p.exists()]
    if existing and not force:
        raise FileExistsError(f"refusing to overwrite {', '.join(existing)} (use --force)")
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for kind in kinds:
        chosen = [m for m in measurements if m.kind == kind]
        if kind == "quasi_static":
            ax = _axes(None)
            for m in chosen:
                plot_loops(m.deflection, m.force, label=m.id, ax=ax)
            ax.set_title("quasi-static loops")
        elif kind == "white_noise":
            axes = _axes(None, nrows=2)
            for m in chosen:
                frf = frf_from_white_noise(m)
                axes[0].loglog(frf.freq, np.abs(frf.h1), lw=0.8, label=m.id)
                axes[1].semilogx(frf.freq, frf.coherence, lw=0.8)
            axes[0].set_ylabel("|H1| [-]")
            axes[1].set_ylabel("coherence [-]")
            axes[1].set_xlabel("frequency [Hz]")
            axes[0].set_title("white noise: transmissibility v_top / v_base")
            ax = axes[0]
        elif kind == "stepped_sine":
            axes = _axes(None, nrows=2)
            sweep = stepped_sine_sweep(chosen, n_harmonics=3)
            for (isolator, mass, nominal), flat in sweep.flatness.items():
                label = f"{isolator} {mass} kg, {nominal:g}"
                axes[0].loglog(flat.freq, flat.amplitude, marker=".", label=label)
                points = sorted((p for p in sweep.points
                                 if (p.isolator, p.top_mass_kg, p.nominal_amplitude)
                                 == (isolator, mass, nominal)), key=lambda p: p.freq)
                axes[1].loglog([p.freq for p in points], [abs(p.hosidf[0]) for p in points],
                               marker=".")
            axes[0].set_ylabel("base 1st harmonic")
            axes[1].set_ylabel("|HOSIDF 1| [-]")
            axes[1].set_xlabel("frequency [Hz]")
            axes[0].set_title("stepped sine: input amplitude and first HOSIDF")
            ax = axes[0]
        else:
            ax = _axes(None)
            groups: dict = {}
            for m in chosen:
                result = process_drop_measurement(m)
                groups.setdefault((m.info.isolator, m.info.top_mass_kg), []).append(result)
            for (isolator, mass), results in groups.items():
                results.sort(key=lambda r: abs(r.impact_velocity))
                plot_shock_levels([abs(r.impact_velocity) for r in results],
                                  [r.peak_acceleration for r in results],
                                  label=f"{isolator} {mass} kg", ax=ax)
            ax.set_title("drops: rest shock level")
        if len(chosen) <= 12 or kind in ("stepped_sine", "drop"):
            ax.legend(fontsize="x-small")
        written.append(save_figure(ax.figure, targets[kind]))
    return written


def _cmd_inspect(args) -> None:
    from idkit.observe.quality import summarize_measurements

    if args.plots:
        from idkit.output_checks import check_output

        check_output(args.plots, kind="folder", inputs=[args.path], option="--plots")
    title, measurements = load_for_inspection(args.path, args.kind)
    summary = summarize_measurements(measurements)
    print(f"{title}")
    print(summary.report())
    if args.plots:
        for path in save_overview_plots(measurements, args.plots, force=args.force):
            print(f"wrote {path}")


def register(subparsers) -> None:
    """Add ``idkit inspect`` to the ``idkit`` command."""
    parser = subparsers.add_parser(
        "inspect", help="summarize a measurement set or file and flag data problems",
        description="Print measurements, kinds, isolators, ranges, sample rates, durations and "
                    "warnings (clipped signals, non-flat or distorted sine input, low coherence).")
    parser.add_argument("path", help="measurement-set folder (with manifest.json) or a data file")
    parser.add_argument("--kind", choices=["quasi_static", "white_noise", "stepped_sine", "drop"],
                        help="kind of a lone data file (default: from its manifest or header)")
    parser.add_argument("--plots", metavar="DIR", help="save overview plots (PNG) into DIR")
    parser.add_argument("--force", action="store_true", help="replace existing plot files")
    parser.set_defaults(handler=_cmd_inspect)
