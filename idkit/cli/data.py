"""``idkit data generate``: write the bundled synthetic measurement sets (idkit.synth)."""

from __future__ import annotations

from pathlib import Path

from idkit.cli import options as opt

__all__ = ["register"]


def _cmd_generate(args) -> None:
    from idkit.cli.progress import say
    from idkit.output_checks import check_output
    from idkit.synth import generate

    check_output(args.output, kind="folder")
    summary = generate(Path(args.output), seed=args.seed, force=args.force, quick=args.quick,
                       sets=args.sets, truth=args.truth, progress=lambda message: say(message, enabled=not args.quiet))
    print(summary.report())


def register(subparsers) -> None:
    """Add ``idkit data generate`` to the ``idkit`` command."""
    from idkit.synth import DEFAULT_SEED, SET_NAMES, TRUTH_NAMES

    data = subparsers.add_parser("data", help="synthetic measurement data")
    actions = data.add_subparsers(dest="action", required=True)
    generate = actions.add_parser(
        "generate", help="write the synthetic measurement sets and their truth files",
        description="Generate the bundled synthetic data (deterministic for a given seed).")
    generate.add_argument("-o", "--output", default="data", help="output folder (default: data)")
    generate.add_argument("--seed", type=opt.seed, default=DEFAULT_SEED,
                          help=f"master seed (default: {DEFAULT_SEED})")
    generate.add_argument("--force", action="store_true", help="replace existing sets")
    generate.add_argument("--quick", action="store_true",
                          help="reduced grid and shorter records (tests; not the bundled data)")
    generate.add_argument("--sets", nargs="+", default=list(SET_NAMES), choices=list(SET_NAMES),
                          help="which sets to write (default: all)")
    generate.add_argument("--truth", default="a", choices=list(TRUTH_NAMES),
                          help="generating truth: a = the bundled data (default), b = a second, "
                               "different wire rope and elastomer with their own protocol and "
                               "non-SI file units (not bundled)")
    generate.add_argument("--quiet", action="store_true")
    generate.set_defaults(handler=_cmd_generate)


