"""``idkit design``: choose isolators from a catalogue for a payload, a floor and its drops."""

from __future__ import annotations

from idkit.cli import options as opt

__all__ = ["register"]


def _cmd_design(args) -> None:
    from idkit.catalogue import load_catalogue
    from idkit.design import load_environment, make_candidates, parts_from_catalogue, run_design

    environment = load_environment(args.environment)
    parts = parts_from_catalogue(load_catalogue(args.catalogue))
    candidates = make_candidates(parts, args.payload_mass, counts=tuple(args.mounts))
    result = run_design(candidates, environment, n_draws=args.draws, seed=args.seed, top=args.top,
                        output=args.output, workers=args.workers)
    print(result.report())


def register(commands) -> None:
    """Add ``idkit design``."""
    design = commands.add_parser("design", help="rank catalogue designs against an environment (docs/design.md)")
    design.add_argument("--catalogue", required=True, help="catalogue folder (idkit catalogue build)")
    design.add_argument("--payload-mass", required=True, type=opt.real(above=0, unit="kg"), help="payload in kg")
    design.add_argument("--mounts", nargs="+", default=[4], type=opt.integer(at_most=64), help="mount counts to try")
    design.add_argument("--environment", required=True, help="environment JSON (docs/design.md)")
    design.add_argument("--draws", default=30, type=opt.integer(at_least=0, at_most=10000),
                        help="parameter draws per candidate (default 30)")
    design.add_argument("--top", default=3, type=opt.integer(at_most=1000), help="designs re-simulated in full")
    design.add_argument("--seed", default=0, type=opt.integer(at_least=0, at_most=2**32 - 1))
    design.add_argument("--workers", default=1, type=opt.integer(at_most=1024))
    design.add_argument("-o", "--output", required=True, help="new output folder")
    design.set_defaults(handler=_cmd_design)
