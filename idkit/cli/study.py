"""``idkit study wire-rope|elastomer|hybrid``: the numerical studies of thesis chapters 3-5.

The ``study`` command has one sub-command per study. Other command modules add their own
studies to it with :func:`study_subparsers` (it creates the ``study`` parser on first use,
so the registration order of the modules does not matter)::

    from idkit.cli.study import study_subparsers

    def register(commands):
        transport = study_subparsers(commands).add_parser("transport", help="...")
        add_common_study_options(transport, "transport")
        transport.set_defaults(handler=...)
"""

from __future__ import annotations

import json
import sys

from idkit.cli import options as opt

__all__ = ["register", "study_subparsers", "add_common_study_options"]

_HELP = {
    "wire-rope": "chapter 3: Table A.1 wire rope, 8 kg, symmetric and asymmetric (maps, cross sections, shock)",
    "elastomer": "chapter 4: Table B.1 elastomers low/medium/high, 5 kg (stiffness, FRF, shock)",
    "hybrid": "chapter 5: hybrid 2 kg + 0.02 kg, symmetric and asymmetric (maps, linear FRF, shock)",
}


def study_subparsers(commands):
    """The sub-parsers action of ``idkit study`` (created on the first call).

    Parameters
    ----------
    commands : argparse._SubParsersAction
        The top-level ``idkit`` sub-commands (what ``register`` receives).
    """
    parser = commands.choices.get("study")
    if parser is None:
        parser = commands.add_parser("study", help="reproduce a numerical study; write figures and numbers")
        kinds = parser.add_subparsers(dest="study", required=True, metavar="STUDY")
        parser._idkit_study_kinds = kinds  # looked up again by later callers
    return parser._idkit_study_kinds


def add_common_study_options(parser, name: str) -> None:
    """``-o/--output``, ``--force``, ``--quick``, ``--workers``, ``--quiet`` for a study parser."""
    parser.add_argument("-o", "--output", default=f"idkit-study-{name}",
                        help=f"output folder (default: idkit-study-{name})")
    parser.add_argument("--force", action="store_true", help="replace an existing output folder")
    parser.add_argument("--quick", action="store_true", help="small grids (seconds instead of minutes)")
    parser.add_argument("--workers", type=opt.workers, default=None, help="simulation threads (default: all cores)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def _cmd_study(args) -> None:
    from idkit.cli.progress import ProgressBar
    from idkit.output_checks import check_output
    from idkit.report.studies import run_study

    check_output(args.output, kind="replaced", force=args.force)
    summary = run_study(args.study, args.output, force=args.force, quick=args.quick, workers=args.workers,
                        progress=ProgressBar(f"study {args.study}", enabled=not args.quiet))
    print(json.dumps({"study": summary["study"], "timings_s": summary["timings_s"]}, indent=1))
    print(f"figures, CSV tables and summary.json written to {args.output}", file=sys.stderr)


def register(commands) -> None:
    """Add ``idkit study wire-rope|elastomer|hybrid``."""
    kinds = study_subparsers(commands)
    for name, text in _HELP.items():
        parser = kinds.add_parser(name, help=text)
        add_common_study_options(parser, name)
        parser.set_defaults(handler=_cmd_study)
