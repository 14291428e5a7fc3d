"""``idkit study wire-rope|elastomer|hybrid|transport``: the numerical studies of thesis chapters 3-5 and 8.

:func:`register` adds the ``study`` command and one sub-command per study: the chapter
studies here, the transport study from :mod:`idkit.cli.transport`
(:func:`~idkit.cli.transport.add_transport_parser`).
"""

from __future__ import annotations

import json
import sys

from idkit.cli import options as opt

__all__ = ["register"]

_HELP = {
    "wire-rope": "chapter 3: Table A.1 wire rope, 8 kg, symmetric and asymmetric (maps, cross sections, shock)",
    "elastomer": "chapter 4: Table B.1 elastomers low/medium/high, 5 kg (stiffness, FRF, shock)",
    "hybrid": "chapter 5: hybrid 2 kg + 0.02 kg, symmetric and asymmetric (maps, linear FRF, shock)",
}


def _cmd_study(args) -> None:
    from idkit.cli.progress import ProgressBar
    from idkit.output_checks import check_output
    from idkit.report.study_files import run_study

    check_output(args.output, kind="replaced", force=args.force)
    study = run_study(args.study, args.output, force=args.force, quick=args.quick, workers=args.workers,
                      progress=ProgressBar(f"study {args.study}", enabled=not args.quiet))
    summary = study.summary()
    print(json.dumps({"study": summary["study"], "timings_s": summary["timings_s"]}, indent=1))
    print(f"figures, CSV tables and summary.json written to {args.output}", file=sys.stderr)


def register(commands) -> None:
    """Add ``idkit study`` with its four studies."""
    from idkit.cli.transport import add_transport_parser

    parser = commands.add_parser("study", help="reproduce a numerical study; write figures and numbers")
    studies = parser.add_subparsers(dest="study", required=True, metavar="STUDY")
    for name, text in _HELP.items():
        chapter = studies.add_parser(name, help=text)
        opt.add_study_options(chapter, name)
        chapter.set_defaults(handler=_cmd_study)
    add_transport_parser(studies)
