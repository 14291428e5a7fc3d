"""The overview figures of ``idkit inspect --plots``: one ``overview_<kind>.png`` per kind present."""

from __future__ import annotations

from pathlib import Path

from idkit.plot._figure import save_figure
from idkit.plot.inspect import overview_figures
from idkit.studies.inspection import Inspection

__all__ = ["overview_paths", "save_overview_plots"]


def overview_paths(kinds, folder) -> dict[str, Path]:
    """``{kind: folder / "overview_<kind>.png"}``."""
    return {kind: Path(folder) / f"overview_{kind}.png" for kind in kinds}


def save_overview_plots(inspection: Inspection, folder, *, force: bool = False) -> list[Path]:
    """Compute the overview observables of ``inspection`` and write one figure per kind.

    Each file is written atomically; existing files are replaced only with ``force``
    (FileExistsError before anything is computed otherwise).

    Returns
    -------
    list of pathlib.Path
        The written PNG files, alphabetical by kind.
    """
    targets = overview_paths(inspection.kinds, folder)
    existing = [str(p) for p in targets.values() if p.exists()]
    if existing and not force:
        raise FileExistsError(f"refusing to overwrite {', '.join(existing)} (use --force)")
    Path(folder).mkdir(parents=True, exist_ok=True)
    figures = overview_figures(inspection.overview())
    return [save_figure(figures[kind], targets[kind]) for kind in sorted(figures)]
