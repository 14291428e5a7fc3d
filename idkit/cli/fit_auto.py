"""``idkit fit auto SET -o MODEL.json``: every candidate family fitted, the one that predicts chosen.

Parses arguments and calls :func:`idkit.fit.auto.fit_auto`; prints the family table (training
and cross-validated error, parameters determined, fit time) and why the family was chosen;
writes the chosen model's file. Exit status: 0 the chosen fit is a success and generalises;
1 it is written but is not a success or "does not generalise" (the records named); 2 bad input.
"""

from __future__ import annotations

import sys

from idkit.cli import options as opt


def _cmd_auto(args) -> int:
    from idkit.fit.auto import fit_auto

    args.check_outputs("auto", args.output, None, args.dataset)
    data = args.load(args.dataset, args)
    split = None if args.split == "all" else args.split
    fit = fit_auto(data, isolator=args.isolator, split=split, seed=args.seed,
                   progress=lambda line: print(f"  {line}", file=sys.stderr))
    print(fit.report())
    fit.save(args.output)
    print(f"wrote {args.output} ({fit.chosen.family.name})", file=sys.stderr)
    if fit.success:
        return 0
    print("idkit: the chosen fit is not a success (the model file says so): " + "; ".join(fit.reasons),
          file=sys.stderr)
    return 1


def add_to(kinds, *, load, check_outputs) -> None:
    """Add ``idkit fit auto`` to the ``fit`` sub-commands; ``load`` and ``check_outputs`` are the
    ``fit`` family's own (:mod:`idkit.cli.fit`, which calls this)."""
    auto = kinds.add_parser(
        "auto", help="fit every candidate family to the force records and keep the one that predicts held-out "
                     "records best (cross-validation; docs/fitting.md)",
        epilog="exit status: 0 the chosen family's fit is a success and predicts its held-out records within the "
               "generalisation factor of its training error; 1 the model file is written but it is not (the "
               "reasons and records are printed); 2 bad input")
    auto.add_argument("dataset", help="measurement set folder (with manifest.json) or one data file")
    auto.add_argument("-o", "--output", required=True, help="model file to write (JSON); never overwritten")
    auto.add_argument("--seed", type=opt.seed, default=0, help="seed of every random choice (default 0)")
    auto.add_argument("--split", choices=["fit", "validation", "all"], default=None,
                      help="which records to fit (default: the fit split of a set; every record of a file)")
    auto.add_argument("--isolator", default=None, help="isolator name in the manifest (default: the set's only isolator "
                                                       "with quasi-static records)")
    auto.set_defaults(handler=_cmd_auto, isolator_kind="quasi_static", load=load, check_outputs=check_outputs)
