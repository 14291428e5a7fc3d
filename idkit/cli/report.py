"""``idkit report [DATA_DIR] [-o OUT_DIR]``: the main job (fit, validate, study, HTML)."""

from __future__ import annotations

import sys

from idkit.cli import options as opt
from idkit.errors import IdkitError

__all__ = ["register"]


def _cmd_file_report(args) -> int:
    """``idkit report FILE``: the report of one data file."""
    from idkit.cli.progress import say
    from idkit.io.discover import is_complex_table as _maybe_table
    from idkit.output_checks import check_output
    from idkit.report.file_report import write_file_report

    for option, given in (("--quick", args.quick), ("--workers", args.workers is not None), ("--pdf", args.pdf),
                          ("--drop-model", args.drop_model != "auto"), ("--start-state", args.start_state != "auto")):
        if given:
            raise IdkitError(f"{option}: applies to the report of a data folder; found a single file "
                             f"({args.data_dir})")
    is_table = _maybe_table(args.data_dir)
    order = "auto" if args.order is None else _file_order(args.order, table=is_table)
    if args.order is not None and not is_table:
        from idkit.io.discover import load_measurements

        kind = load_measurements(args.data_dir)[1][0].kind
        if kind != "quasi_static":  # inspected only: an order would be accepted and ignored
            raise IdkitError(f"--order: applies to a file the report fits (a DMA table or a loop record); found a "
                             f"{kind} record ({args.data_dir}), which is inspected only")
    check_output(args.output, kind="replaced", force=args.force, inputs=[args.data_dir])
    table = None
    if is_table:
        from idkit.cli.fit import _read_table

        table = _read_table(args.data_dir)
    summary = write_file_report(args.data_dir, args.output, table=table, force=args.force, seed=args.seed,
                                order=order, progress=lambda message: say(message, enabled=not args.quiet))
    verdict = "PASS" if summary.success else "FLAGGED"
    print(f"{verdict:12s}  {summary.kind} fit" if summary.kind in ("complex_stiffness", "quasi_static")
          else f"{'-':12s}  {summary.kind}: inspection only")
    for reason in summary.reasons:
        print(f"  not a success: {reason}")
    print(f"report written to {summary.html}", file=sys.stderr)
    return summary.exit_status


def _file_order(text: str, *, table: bool):
    """``--order`` of a file's report, checked as ``idkit fit maxwell`` (a table) or ``idkit fit iwan``
    (a loop record) checks it: ``auto`` or a whole number within that fit's limit."""
    import argparse

    from idkit.cli.fit import _iwan_order, _maxwell_order

    what = "Prony terms of a table" if table else "Jenkin elements of a loop record"
    try:
        return (_maxwell_order if table else _iwan_order)(text)
    except argparse.ArgumentTypeError as problem:
        raise opt.OptionError(f"--order: {problem} (the {what})") from None


def _cmd_report(args) -> int:
    from pathlib import Path

    from idkit.cli.progress import say
    from idkit.io.discover import default_data_dir
    from idkit.output_checks import check_output
    from idkit.report.main_report import run_report
    from idkit.studies.pipeline import QUICK_NOTE

    if args.data_dir is not None and Path(args.data_dir).is_file():
        return _cmd_file_report(args)
    if args.order is not None:  # the folder's report fits every family by its own order rule
        raise IdkitError(f"--order: applies to the report of one data file (a DMA table or a loop record); "
                         f"found a data folder ({args.data_dir or default_data_dir()})")

    check_output(args.output, kind="replaced", force=args.force, inputs=[args.data_dir or default_data_dir()])
    summary = run_report(args.data_dir, args.output, force=args.force, quick=args.quick, seed=args.seed,
                         workers=args.workers, progress=lambda message: say(message, enabled=not args.quiet),
                         start_state=args.start_state, drop_model=args.drop_model, pdf=args.pdf)
    print(verdict_lines(summary, QUICK_NOTE))
    print(f"report written to {summary.html}", file=sys.stderr)
    return summary.exit_status


def verdict_lines(summary, quick_note: str) -> str:
    """What ``idkit report`` prints: one line per validation verdict (with what keeps it from
    PASS and its notes indented under it), one per flagged fit, and the quick note of a quick
    run."""
    lines = []
    for name, verdict in summary.validation_verdicts.items():
        lines.append(f"{verdict:12s}  {name}")
        lines.extend(f"{'':12s}    why: {reason}" for reason in summary.validation_reasons.get(name, ()))
        lines.extend(f"{'':12s}    note: {note}" for note in summary.validation_notes.get(name, ()))
    lines.extend(f"{'FLAGGED':12s}  {name} fit: " + "; ".join(summary.fit_reasons[name])
                 for name in summary.flagged_fits)
    if summary.quick:
        lines.append(f"({quick_note})")
    return "\n".join(lines)


def register(commands) -> None:
    """Add ``idkit report``."""
    from idkit.exit_status import REPORT_EXIT_STATUSES

    parser = commands.add_parser(
        "report", help="fit, validate and study a data set; write an HTML report",
        epilog="exit status (the report is written in every case): "
               + "; ".join(f"{code} {meaning}" for code, meaning in REPORT_EXIT_STATUSES.items()))
    parser.add_argument("data_dir", nargs="?", default=None,
                        help="folder of measurement sets (default: ./data, the bundled synthetic data), or one "
                             "data file (a DMA table or a loop record is fitted; other records are inspected)")
    parser.add_argument("-o", "--output", default="idkit-report", help="output folder (default: idkit-report)")
    parser.add_argument("--force", action="store_true", help="replace an existing output folder")
    parser.add_argument("--quick", action="store_true", help="smaller study and validation (seconds, for tests)")
    parser.add_argument("--seed", type=opt.seed, default=2026, help="seed of every stochastic step (default 2026)")
    parser.add_argument("--workers", type=opt.workers, default=None, help="simulation threads (default: all cores)")
    parser.add_argument("--start-state", choices=["auto", "cycled", "virgin"], default="auto",
                        help="wire-rope fits: model state at each record's first reversal (default auto: "
                             "virgin when the record starts unloaded, else cycled)")
    parser.add_argument("--drop-model", choices=["auto", "rig", "conditioned"], default="auto",
                        help="drop model of the drop validations: the drop rig (bottom mass on the floor, from the "
                             "statically loaded rest state), the conditioned free fall of the study, or auto (the rig "
                             "when the drops give bottom mass and height; default)")
    parser.add_argument("--order", default=None, metavar="N|auto",
                        help="report of one file: order of its fit, as idkit fit's --order (a DMA table: Prony "
                             f"terms, 1 to {opt.MAX_DMA_ORDER}; a loop record: Jenkin elements, 1 to {opt.MAX_ORDER}); "
                             "default auto, the order rule")
    parser.add_argument("--pdf", action="store_true",
                        help="also write report.pdf (text, figures with captions; tables stay CSV files)")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    parser.set_defaults(handler=_cmd_report)
