"""``idkit report [DATA_DIR] [-o OUT_DIR]``: the main job (fit, validate, study, HTML)."""

from __future__ import annotations

import sys

from idkit.cli import options as opt

__all__ = ["register"]


def _cmd_report(args) -> int:
    from idkit.cli.progress import say
    from idkit.io.discover import default_data_dir
    from idkit.output_checks import check_output
    from idkit.report.main_report import QUICK_NOTE, run_report

    check_output(args.output, kind="replaced", force=args.force, inputs=[args.data_dir or default_data_dir()])
    summary = run_report(args.data_dir, args.output, force=args.force, quick=args.quick, seed=args.seed,
                         workers=args.workers, progress=lambda message: say(message, enabled=not args.quiet),
                         start_state=args.start_state, drop_model=args.drop_model)
    for name, verdict in summary.validation_verdicts.items():
        print(f"{verdict:12s}  {name}")
    if summary.quick:
        print(f"({QUICK_NOTE})")
    print(f"report written to {summary.html}", file=sys.stderr)
    return summary.exit_status


def register(commands) -> None:
    """Add ``idkit report``."""
    parser = commands.add_parser("report", help="fit, validate and study a data set; write an HTML report")
    parser.add_argument("data_dir", nargs="?", default=None,
                        help="folder of measurement sets (default: ./data, the bundled synthetic data)")
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
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    parser.set_defaults(handler=_cmd_report)
