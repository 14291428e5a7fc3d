"""Files of the studies: figures, CSV tables and ``summary.json`` in a folder that appears whole or not at all.

:func:`run_study` (``idkit study wire-rope|elastomer|hybrid``) and
:func:`run_transport_study` (``idkit study transport``) compute a study
(:mod:`idkit.studies`), draw its figures (:mod:`idkit.plot.studies`) and write them with
the numbers behind them. Chapter studies write ``*.png``, ``map_<case>.csv`` (long format,
:meth:`~idkit.responses.harmonic_map.HarmonicMap.to_dataframe`), ``resonance_<case>.csv``,
``shock_<case>_velocity.csv`` / ``shock_<case>_height.csv``, ``linear_<case>.csv``,
``harmonic_check_<case>.csv`` (elastomer) and ``summary.json`` (settings, key numbers,
timings, file list). The transport study writes :func:`write_transport_files`' files and
``summary.json``.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from idkit import __version__
from idkit.atomic import atomic_output_folder
from idkit.plot import save_figure
from idkit.plot.studies import chapter_figures, transport_figures
from idkit.studies.chapters import ChapterStudy, ElastomerCase, compute_chapter_study
from idkit.studies.transport import TransportStudy, compute_transport_study, quick_transport_options

__all__ = ["run_study", "run_transport_study", "write_chapter_files", "write_figures", "write_transport_files"]


def write_figures(figures: dict, folder: Path) -> list[Path]:
    """Save every ``{file name: Figure}`` into ``folder`` (atomically, one by one); returns the files."""
    return [save_figure(figure, Path(folder) / name) for name, figure in figures.items()]


def write_chapter_files(study: ChapterStudy, folder: Path) -> list[Path]:
    """Figures and CSV tables of a chapter study into an existing ``folder``; returns the files."""
    folder = Path(folder)
    tables = {}
    for case in study.cases:
        if isinstance(case, ElastomerCase):
            tables[f"linear_{case.name}.csv"] = case.frf.to_dataframe()
            tables[f"harmonic_check_{case.name}.csv"] = case.harmonic_check_table()
        else:
            tables[f"map_{case.name}.csv"] = case.hmap.to_dataframe()
            tables[f"resonance_{case.name}.csv"] = case.resonance_table()
        tables[f"shock_{case.name}_velocity.csv"] = case.shock.by_speed.to_dataframe()
        tables[f"shock_{case.name}_height.csv"] = case.shock.by_height.to_dataframe()
    if study.hybrid_linear is not None:
        tables["linear_hybrid.csv"] = study.hybrid_linear.to_dataframe()
    written = []
    for name, table in tables.items():
        table.to_csv(folder / name, index=False)
        written.append(folder / name)
    return written + write_figures(chapter_figures(study), folder)


def run_study(name: str, out_dir, *, force: bool = False, quick: bool = False, workers: int | None = None,
              progress=None) -> ChapterStudy:
    """Compute the chapter 3 (``"wire-rope"``), 4 (``"elastomer"``) or 5 (``"hybrid"``) study and write its files.

    Parameters
    ----------
    name : {"wire-rope", "elastomer", "hybrid"}
    out_dir : path
        Output folder; must not exist unless ``force``. Written atomically.
    force : bool
        Replace an existing folder.
    quick : bool
        Small grids (:func:`idkit.studies.chapters.study_grid`): seconds instead of minutes.
    workers : int, optional
        Threads for the simulations (default: all usable cores).
    progress : callable(done, total), optional
        Study-wide progress in work units (harmonic points and drops).

    Returns
    -------
    ChapterStudy
        The computed study; ``summary.json`` holds ``study.summary()`` plus the time spent
        writing (``timings_s["writing"]``) and the file list (``files``).
    """
    with atomic_output_folder(out_dir, force=force) as folder:
        study = compute_chapter_study(name, quick=quick, workers=workers, progress=progress)
        start = time.perf_counter()
        files = write_chapter_files(study, folder)
        summary = study.summary()
        summary["timings_s"]["writing"] = round(time.perf_counter() - start, 3)
        summary["files"] = sorted(path.name for path in files) + ["summary.json"]
        (folder / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    return study


def write_transport_files(study: TransportStudy, folder: Path, *, tables_dir: Path | None = None,
                          figures: bool = True) -> list[Path]:
    """Figures, CSV tables (``transport_*.csv``) and the long PSD table (``transport_psd.csv.gz``).

    Figures go to ``folder`` (none when ``figures`` is false: the caller draws them), tables
    to ``tables_dir`` (default ``folder``). Returns the files.
    """
    folder = Path(folder)
    tables_dir = folder if tables_dir is None else Path(tables_dir)
    written = write_figures(transport_figures(study), folder) if figures else []
    tables = {
        "transport_tuning.csv": (study.tuning, False),
        "transport_rms.csv": (study.rms, True),
        "transport_shock_vs_velocity.csv": (study.shock_velocity, True),
        "transport_shock_vs_height.csv": (study.shock_height, True),
        "transport_summary.csv": (study.summary_table(), True),
    }
    for name, (table, index) in tables.items():
        table.to_csv(tables_dir / name, index=index)
        written.append(tables_dir / name)
    # fast gzip (level 1: a third of the time of the default 9 for a tenth more bytes), no
    # time stamp in the header: the same study gives the same bytes
    study.psd_table().to_csv(tables_dir / "transport_psd.csv.gz", index=False,
                             compression={"method": "gzip", "compresslevel": 1, "mtime": 0})
    written.append(tables_dir / "transport_psd.csv.gz")
    return written


def run_transport_study(out_dir, *, force: bool = False, quick: bool = False, wire_rope=None, elastomer=None,
                        seed: int = 2026, workers=None, progress=None) -> TransportStudy:
    """Compute the transport study and write figures, CSV tables and ``summary.json`` atomically.

    Parameters
    ----------
    out_dir : path
        Output folder; must not exist unless ``force``.
    quick : bool
        :func:`idkit.studies.transport.quick_transport_options` (seconds instead of minutes).
    wire_rope, elastomer : IwanModel, GeneralizedMaxwell, optional
        The parts (default: the study's identified parts, Tables 7.1 and 7.3).
    seed : int
        Seed of the random floor signals.

    Returns
    -------
    TransportStudy
    """
    start = time.perf_counter()
    options = quick_transport_options() if quick else {}
    with atomic_output_folder(out_dir, force=force) as folder:
        study = compute_transport_study(wire_rope=wire_rope, elastomer=elastomer, seed=seed, workers=workers,
                                        progress=progress, **options)
        write_transport_files(study, folder)
        summary = {
            "study": "transport", "idkit_version": __version__, "seed": seed, "quick": quick,
            "n_realizations": study.n_realizations, "flagged_runs": study.flagged_runs,
            "masses": study.tuning.to_dict(orient="records"),
            "rms_m_s2": {system: row.to_dict() for system, row in study.rms.iterrows()},
            "timings_s": {"total": round(time.perf_counter() - start, 3)},
        }
        (folder / "summary.json").write_text(json.dumps(summary, indent=1, default=float) + "\n")
    return study
