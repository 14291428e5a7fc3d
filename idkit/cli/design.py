"""``idkit design``: choose isolators from a catalogue for a payload, a floor and its drops."""

from __future__ import annotations

from idkit.cli import options as opt

__all__ = ["register"]


def _predicted(catalogue, path):
    """A size never measured, from a JSON file {"family": ..., "dimensions": {...}} (docs/design.md),
    read as strictly as every input file and checked against its declared keys."""
    from idkit.checks import Choice, Field, Instance, Text, check_fields
    from idkit.design import predicted_part
    from idkit.errors import DataError
    from idkit.inputfiles import load_json, read_input_bytes

    label = f"predicted part '{path}'"
    expected = '{"family": "wire_rope" or "elastomer", "dimensions": {...}, "name": optional}'
    document = load_json(read_input_bytes(path, label, DataError), label, DataError, expected=expected)
    fields = (Field("family", Choice(("wire_rope", "elastomer")), required=True),
              Field("dimensions", Instance((dict,), what="an object of dimensions"), required=True),
              Field("name", Text(optional=True)))
    values = check_fields(Instance((dict,), what=expected).check(document, label, DataError), fields, label)
    return predicted_part(catalogue, values["family"], values["dimensions"], name=values.get("name"))


def _cmd_design(args) -> None:
    from idkit.catalogue import load_catalogue
    from idkit.design import load_environment, make_candidates, parts_from_catalogue, run_design

    environment = load_environment(args.environment)
    catalogue = load_catalogue(args.catalogue)
    parts = parts_from_catalogue(catalogue)
    for path in args.predicted_part or ():
        parts.append(_predicted(catalogue, path))
    if not parts:
        from idkit.errors import DataError

        raise DataError(f"{args.catalogue}: found no usable part (identified and not failing its held-out check); "
                        "expected at least one (see its parts.csv)")
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
    design.add_argument("--predicted-part", nargs="+", help="JSON files {family, dimensions[, name]}: sizes never "
                        "measured, predicted from the catalogue's scaling laws, added to the candidates")
    design.add_argument("-o", "--output", required=True, help="new output folder")
    design.set_defaults(handler=_cmd_design)
