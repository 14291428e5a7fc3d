"""``idkit catalogue build`` (identify a folder of parts), ``laws`` (scaling laws) and ``report`` (the parts side by side)."""

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
    parquet = (catalogue.folder / "parts.parquet").exists()
    print(f"catalogue written to {args.output} (catalogue.json, parts.csv, " + ("parts.parquet, models/)" if parquet
          else "models/; no Parquet: pyarrow is not installed)"))


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


def _cmd_report(args) -> None:
    from idkit.catalogue import load_catalogue
    from idkit.catalogue.report import write_catalogue_report

    written = write_catalogue_report(load_catalogue(args.catalogue), args.output,
                                     payload_per_mount_kg=args.payload_mass, n_draws=args.draws, seed=args.seed)
    print("written: " + ", ".join(str(path) for path in written))


def register(commands) -> None:
    """Add ``idkit catalogue build|laws|report``."""
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
    report = kinds.add_parser("report", help="draw the parts side by side (stiffness, loss, loops, FRFs with bands)")
    report.add_argument("catalogue", help="catalogue folder")
    report.add_argument("-o", "--output", required=True, help="new report folder")
    report.add_argument("--payload-mass", type=opt.real(above=0, unit="kg"), default=5.0,
                        help="payload per mount for the transmissibilities, kg (default 5)")
    report.add_argument("--draws", type=opt.integer(at_least=0, at_most=10000), default=20,
                        help="parameter draws for the bands (default 20)")
    report.add_argument("--seed", type=opt.integer(at_least=0, at_most=2**32 - 1), default=0)
    report.set_defaults(handler=_cmd_report)
