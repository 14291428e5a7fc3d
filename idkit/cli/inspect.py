"""``idkit inspect PATH``: summary and data-quality warnings of measurements, optional plots."""

from __future__ import annotations

import sys

from idkit.io.columns import KINDS

__all__ = ["register"]


def _cmd_inspect(args) -> None:
    from pathlib import Path

    from idkit.studies.inspection import inspect_path

    if Path(args.path).is_file() and args.kind is None:
        from idkit.io.discover import is_complex_table as _maybe_table

        if _maybe_table(args.path):
            from idkit.cli.fit import _read_table
            from idkit.studies.inspection import inspect_complex_table

            if args.plots:
                from idkit.output_checks import check_output

                check_output(args.plots, kind="folder", inputs=[args.path], option="--plots")
            table = _read_table(args.path)
            print(Path(args.path).name)
            print(inspect_complex_table(table).report())
            if args.plots:
                from idkit.plot.dma import save_dma_table_plots

                for path in save_dma_table_plots(table, args.plots, overwrite=args.force):
                    print(f"wrote {path}", file=sys.stderr)
            return

    if args.plots:
        from idkit.output_checks import check_output

        check_output(args.plots, kind="folder", inputs=[args.path], option="--plots")
    inspection = inspect_path(args.path, kind=args.kind)
    print(inspection.title)
    print(inspection.summary.report())
    if args.plots:
        from idkit.report.inspect_files import save_overview_plots

        for path in save_overview_plots(inspection, args.plots, force=args.force):
            print(f"wrote {path}", file=sys.stderr)


def register(commands) -> None:
    """Add ``idkit inspect``."""
    parser = commands.add_parser(
        "inspect", help="summarize a measurement set or file and flag data problems",
        description="Print measurements, kinds, isolators, ranges, sample rates, durations and "
                    "warnings (clipped signals, non-flat or distorted sine input, low coherence).")
    parser.add_argument("path", help="measurement-set folder (with manifest.json) or a data file")
    parser.add_argument("--kind", choices=list(KINDS),
                        help="kind of a lone data file (default: from its manifest or header)")
    parser.add_argument("--plots", metavar="DIR", help="save overview plots (PNG) into DIR")
    parser.add_argument("--force", action="store_true", help="replace existing plot files")
    parser.set_defaults(handler=_cmd_inspect)
