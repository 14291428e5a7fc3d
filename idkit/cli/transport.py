"""``idkit study transport``: the transport-tool study of SPEC 6 (thesis chapter 8)."""

from __future__ import annotations

import sys

from idkit.cli import options as opt

__all__ = ["add_transport_parser"]


def _parts(args):
    """Model files if given, else the parts identified from the data folder (fit split)."""
    from idkit.cli.progress import say
    from idkit.errors import IdkitError
    from idkit.models import GeneralizedMaxwell, IwanModel, load_model
    from idkit.studies.pipeline import identify_parts

    if (args.wire_rope is None) != (args.elastomer is None):
        raise IdkitError("give both --wire-rope and --elastomer model files, or neither (bundled data)")
    if args.wire_rope is not None and args.data_dir is not None:
        raise IdkitError(f"--data-dir {args.data_dir}: not used when --wire-rope and --elastomer give the parts; "
                         "expected either the model files or --data-dir")
    if args.wire_rope is None:
        say("identifying the wire rope and the elastomer from the bundled data", enabled=not args.quiet)
        return identify_parts(args.data_dir, seed=args.seed)
    wire_rope, elastomer = load_model(args.wire_rope), load_model(args.elastomer)
    if not isinstance(wire_rope, IwanModel) or not isinstance(elastomer, GeneralizedMaxwell):
        raise IdkitError(f"expected an Iwan wire rope ({args.wire_rope}) and a generalized Maxwell "
                         f"elastomer ({args.elastomer}), found {type(wire_rope).__name__} and "
                         f"{type(elastomer).__name__}")
    return wire_rope, elastomer


def _cmd_transport(args) -> None:
    from idkit.cli.progress import ProgressBar
    from idkit.output_checks import check_output
    from idkit.report.study_files import run_transport_study

    check_output(args.output, kind="replaced", force=args.force, inputs=[args.wire_rope, args.elastomer, args.data_dir])
    wire_rope, elastomer = _parts(args)
    study = run_transport_study(args.output, force=args.force, quick=args.quick, wire_rope=wire_rope,
                                elastomer=elastomer, seed=args.seed, workers=args.workers,
                                progress=ProgressBar("study transport", enabled=not args.quiet))
    print(study.tuning[["system", "moving mass [kg]", "top mass without m_eff [kg]", "intermediate mass [kg]"]]
          .to_string(index=False))
    print(study.summary_table().to_string(float_format=lambda value: f"{value:.4g}"))
    print(f"figures, CSV tables and summary.json written to {args.output}", file=sys.stderr)


def add_transport_parser(studies) -> None:
    """Add ``transport`` to the sub-commands of ``idkit study`` (``studies``, from ``add_subparsers``)."""
    parser = studies.add_parser(
        "transport", help="chapter 8: reference, elastomer, wire rope and hybrids tuned to 5 Hz (PSDs, shock)")
    opt.add_study_options(parser, "transport")
    parser.add_argument("--wire-rope", help="Iwan model file (default: identified from the bundled data)")
    parser.add_argument("--elastomer", help="generalized Maxwell model file (default: identified from the bundled data)")
    parser.add_argument("--data-dir", help="data folder to identify the parts from (default: ./data; not with "
                        "--wire-rope and --elastomer)")
    parser.add_argument("--seed", type=opt.seed, default=2026, help="seed of the random floor signals")
    parser.set_defaults(handler=_cmd_transport)
