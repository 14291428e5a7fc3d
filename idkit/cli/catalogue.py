"""``idkit catalogue build`` (identify a folder of parts) and ``idkit catalogue laws`` (scaling laws)."""

from __future__ import annotations

from idkit.cli import options as opt

__all__ = ["register"]


def _cmd_build(args) -> None:
    from idkit.catalogue import build_catalogue

    options = {}
    if args.rope_order is not None:
        options["wire_rope"] = {"order": args.rope_order}
    catalogue = build_catalogue(args.parts, args.output, add=args.add, workers=args.workers, fit_options=options,
                                progress=None if args.quiet else print)
    table = catalogue.table()
    print(table[["part", "family", "status", "held-out verdict", "model", "order"]].to_string(index=False))
    print(f"catalogue written to {args.output} (catalogue.json, parts.csv"
          + (", parts.parquet" if (catalogue.folder / "parts.parquet").exists() else "; no Parquet: pyarrow is not "
             "installed") + ", models/)")


def _cmd_laws(args) -> None:
    from idkit.catalogue import load_catalogue
    from idkit.catalogue.scaling import LAW_QUANTITIES, fit_scaling_law, leave_one_part_out

    catalogue = load_catalogue(args.catalogue)
    for family, quantities in LAW_QUANTITIES.items():
        records = [r for r in catalogue.usable() if r["family"] == family]
        if not records:
            continue
        for quantity in quantities:
            law = fit_scaling_law(records, quantity)
            print(law.report())
            coverage = leave_one_part_out(records, quantity)
            print(f"    leave-one-part-out: {int(coverage['inside'].sum())} of {len(coverage)} parts inside their "
                  f"95 % prediction band")


def register(commands) -> None:
    """Add ``idkit catalogue build|laws``."""
    catalogue = commands.add_parser("catalogue", help="catalogues of identified parts and their scaling laws")
    kinds = catalogue.add_subparsers(dest="kind", required=True)
    build = kinds.add_parser("build", help="identify every part of a folder into a catalogue (docs/catalogue.md)")
    build.add_argument("parts", nargs="?", help="folder of part folders (each a measurement set with part.json)")
    build.add_argument("-o", "--output", required=True, help="catalogue folder (new; with --add an existing one)")
    build.add_argument("--add", nargs="+", help="part folders to add to the existing catalogue -o")
    build.add_argument("--workers", type=opt.integer(at_most=1024), default=1, help="parts identified at once")
    build.add_argument("--rope-order", type=opt.integer(at_most=12), help="wire-rope Iwan order (default: order rule)")
    build.add_argument("--quiet", action="store_true")
    build.set_defaults(handler=_cmd_build)
    laws = kinds.add_parser("laws", help="fit the scaling laws of a catalogue and check them part by part")
    laws.add_argument("catalogue", help="catalogue folder")
    laws.set_defaults(handler=_cmd_laws)
