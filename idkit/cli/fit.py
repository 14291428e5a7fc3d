"""``idkit fit iwan|maxwell|boucwen DATASET -o MODEL.json``: identify a model from a measurement set.

Parses arguments and calls :mod:`idkit.fit`; prints the fit report; writes the
model file (with provenance) and, on request, the figures. Existing outputs are
never replaced: the command stops before fitting (exit code 2). A fit that is not a
success (a parameter on a bound, an evaluation limit, ...) is still written, with
``success: false`` and its reasons in the provenance, and the command exits with 1.
"""

from __future__ import annotations

import sys
from pathlib import Path

from idkit.checks import Choice, Either, InputPath, Whole
from idkit.cli import options as opt
from idkit.errors import IdkitError

#: The data a command reads: a measurement-set folder or one data file.
_DATASET = InputPath(what="a measurement set (folder with manifest.json) or a data file")


def _check_outputs(kind: str, output: str, plots: str | None, dataset: str, *more_inputs: str) -> None:
    """Every output refused before fitting: existing, overlapping the data set, unwritable, a
    figure of ``kind`` (``iwan``, ``boucwen``, ``maxwell``, ``maxwell_table``) that exists."""
    from idkit.output_checks import check_output, check_plot_folder

    check_output(output, inputs=[dataset, *more_inputs])
    if plots is None:
        return
    if kind == "maxwell_table":
        from idkit.plot.dma import dma_fit_plot_paths

        figures = dma_fit_plot_paths(plots)
    else:
        from idkit.plot.fits import fit_plot_paths

        figures = fit_plot_paths(kind, plots)
    # found only after the fit otherwise, the model file written
    check_plot_folder(plots, figures, inputs=[dataset, *more_inputs], beside=("the model file -o", output))


def _load(dataset: str, args=None):
    """A measurement-set folder, or one data file (its enclosing manifest's metadata when it lists
    it, otherwise its kind from the header); resolves the ``--isolator``/``--split`` defaults
    (a set's only isolator with records of the kind the fit reads, its fit split)."""
    from idkit.io import load_measurement_set
    from idkit.io.discover import load_measurements
    from idkit.io.selection import ONLY_ISOLATOR, resolve_isolator

    path = _DATASET.check(dataset, "DATASET", IdkitError)
    if path.is_dir():
        measurement_set = load_measurement_set(path)
        if args is not None:
            args.isolator = resolve_isolator(measurement_set, ONLY_ISOLATOR if args.isolator is None else args.isolator,
                                             kind=args.isolator_kind)
            args.split = "fit" if args.split is None else args.split
        return measurement_set
    # one file: every record in it is fitted unless --isolator/--split say otherwise
    if args is not None:
        args.split = "all" if args.split is None else args.split
    _, measurements = load_measurements(path)
    return measurements


def _finish(fit, args) -> int:
    """Print, save and plot a fit; exit status 0 for a successful fit, 1 for a flagged one."""
    print(fit.report())
    fit.save(args.output)
    print(f"wrote {args.output}", file=sys.stderr)
    if args.plots is not None:
        from idkit.fit.predictions import predict_fit
        from idkit.plot.fits import save_fit_plots

        for path in save_fit_plots(predict_fit(fit), args.plots):
            print(f"wrote {path}", file=sys.stderr)
    if fit.success:
        return 0
    reasons = fit.reasons or (getattr(fit.result, "message", "") or "see the report",)
    print("idkit: the fit is not a success (the model file says so): " + "; ".join(reasons), file=sys.stderr)
    return 1


def _split(value: str):
    return None if value == "all" else value


def _cmd_iwan(args) -> int:
    from idkit.fit import fit_iwan_measurements

    if args.valid_range:
        opt.check_valid_range("--valid-range", args.valid_range)
    _check_outputs("iwan", args.output, args.plots, args.dataset)
    options = {"valid_range": tuple(args.valid_range)} if args.valid_range else {}
    if args.no_valid_range:
        options = {"valid_range": None}
    fit = fit_iwan_measurements(_load(args.dataset, args), order=args.order, small_threshold=args.small_threshold,
                                isolator=args.isolator, split=_split(args.split), backend=args.backend,
                                seed=args.seed, initial_state=args.start_state, remove_offsets=args.remove_offsets,
                                family=args.family, **options)
    if args.order_table or fit.order_table is not None:
        from idkit.fit import iwan_order_table

        table = fit.order_table
        if table is None:
            table = iwan_order_table(list(fit.data.small), list(fit.data.large), backend=args.backend, seed=args.seed,
                                     initial_state=args.start_state,
                                     **{k: v for k, v in options.items() if v is not None})
        print("[[Iwan order table (rule: lowest order within 10 % of the best mean error; modulated rows: lowest "
              "order within 2 points of the noise floor with every parameter determined)]]")
        print(table.to_string(index=False))
    return _finish(fit, args)


def _cmd_boucwen(args) -> int:
    from idkit.fit import compare_loop_models, fit_boucwen_measurements, fit_iwan_measurements

    _check_outputs("boucwen", args.output, args.plots, args.dataset)
    data = _load(args.dataset, args)
    options = {"small_threshold": args.small_threshold, "isolator": args.isolator, "split": _split(args.split),
               "backend": args.backend, "seed": args.seed, "initial_state": args.start_state,
               "remove_offsets": args.remove_offsets}
    fit = fit_boucwen_measurements(data, global_max_evals=args.global_evals, **options)
    if args.compare:
        iwan = fit_iwan_measurements(data, order=2, **options)
        print(compare_loop_models({"iwan order 2": iwan.result, "bouc-wen": fit.result}).report())
    return _finish(fit, args)


def _read_table(path: str):
    """A complex stiffness / DMA table file in idkit's format or pyvisco's two-line header layout."""
    from idkit.io.discover import complex_table_format

    kind = complex_table_format(path)
    if kind == "complex_stiffness":
        from idkit.io import read_complex_stiffness

        return read_complex_stiffness(path)
    if kind == "pyvisco":
        from idkit.datasets import read_pyvisco_complex_modulus

        return read_pyvisco_complex_modulus(path)
    raise IdkitError(f"file {path}: not a complex stiffness / DMA table; expected the columns 'frequency [Hz]', "
                     "'storage [unit]', 'loss [unit]' (docs/data-format.md) or pyvisco's 'f, E_stor, E_loss' "
                     "with a units line, or a measurement-set folder")


def _read_shift_factors(path: str):
    from idkit.io.discover import shift_factor_format

    if shift_factor_format(path) == "pyvisco":
        from idkit.datasets import read_pyvisco_shift_factors

        return read_pyvisco_shift_factors(path)
    from idkit.io import read_shift_factors

    return read_shift_factors(path)


def _cmd_maxwell_table(args) -> int:
    """``idkit fit maxwell TABLE.csv``: a DMA / complex stiffness table, isotherms or master curve."""
    from idkit.fit import fit_dma_table

    given = [option for option, value in (("--k0", args.k0), ("--k0-method", args.k0_method), ("--band", args.band),
                                          ("--isolator", args.isolator), ("--split", args.split))
             if value is not None] + [option for option, value in (("--order-table", args.order_table),
                                                                   ("--cross-check", args.cross_check)) if value]
    if given:  # each would be accepted and ignored: a table has one material, its whole band is fitted
        raise IdkitError(f"{', '.join(given)}: apply to measurement sets; a DMA table is fitted over its whole master "
                         "curve with --order auto|N (auto prints the order table)")
    _check_outputs("maxwell_table", args.output, args.plots, args.dataset,
                   *(() if args.shift_factors is None else (args.shift_factors,)))
    if args.use_given_shift_factors and args.shift_factors is None:
        raise IdkitError("--use-given-shift-factors: found no --shift-factors FILE, expected one")
    table = _read_table(args.dataset)
    given = None if args.shift_factors is None else _read_shift_factors(args.shift_factors)
    reference = None if args.reference_temperature is None else args.reference_temperature + 273.15
    fit = fit_dma_table(table, order="auto" if args.order in (None, "auto") else args.order,
                        reference_temperature_k=reference, shift_factors=given,
                        use_given_shift_factors=args.use_given_shift_factors, backend=args.backend, seed=args.seed)
    print(fit.report())
    fit.save(args.output)
    print(f"wrote {args.output} ({fit.model.quantity} model, {fit.model.unit})", file=sys.stderr)
    if args.plots is not None:
        from idkit.plot.dma import save_dma_fit_plots

        for path in save_dma_fit_plots(fit, args.plots):
            print(f"wrote {path}", file=sys.stderr)
    if fit.success:
        return 0
    print("idkit: the fit is not a success (the model file says so): " + "; ".join(fit.reasons), file=sys.stderr)
    return 1


def _check_band_in_records(option: str, band, data, *, isolator, split) -> None:
    """Refuse a fit band reaching above the Nyquist frequency of a white-noise record it would fit:
    there the record holds no samples of the response (``--band 1 1e300`` ran the fit over the
    records' whole 0-1000 Hz, flagged it after minutes, and wrote the model file)."""
    from idkit.io.selection import select_measurements

    records, _ = select_measurements(data, kind="white_noise", isolator=isolator, split=split)
    slowest = min(records, key=lambda m: m.sample_rate_hz)
    nyquist = slowest.sample_rate_hz / 2
    if band[1] > nyquist:
        raise opt.OptionError(f"{option}: found F_HIGH {band[1]:g} Hz, above the Nyquist frequency {nyquist:.6g} Hz "
                              f"of record {slowest.id or slowest.source.where()} ({slowest.sample_rate_hz:.6g} Hz "
                              f"samples); expected F_LOW < F_HIGH <= {nyquist:.6g} Hz")


def _cmd_maxwell(args) -> int:
    from idkit.fit import fit_maxwell_measurements, maxwell_order_table, transmissibility_sets

    if Path(args.dataset).is_file():
        return _cmd_maxwell_table(args)
    for option, value in (("--reference-temperature", args.reference_temperature),
                          ("--shift-factors", args.shift_factors)):
        if value is not None:
            raise IdkitError(f"{option}: applies to a DMA table file; found a measurement-set folder")
    args.order = "auto" if args.order is None else args.order
    args.band = [1.0, 100.0] if args.band is None else args.band
    args.k0_method = "relaxation" if args.k0_method is None else args.k0_method
    opt.check_band("--band", args.band)
    _check_outputs("maxwell", args.output, args.plots, args.dataset)
    data = _load(args.dataset, args)
    _check_band_in_records("--band", args.band, data, isolator=args.isolator, split=_split(args.split))
    fit = fit_maxwell_measurements(data, order=args.order, k0=args.k0, isolator=args.isolator,
                                   split=_split(args.split), band=tuple(args.band), backend=args.backend,
                                   cross_check=args.cross_check, seed=args.seed, k0_method=args.k0_method)
    if args.order_table or fit.order_table is not None:
        table = fit.order_table
        if table is None:
            frfs, _ = transmissibility_sets(data, isolator=args.isolator, split=_split(args.split),
                                            band=tuple(args.band))
            table = maxwell_order_table(list(frfs), k0=fit.model.k0, band=tuple(args.band), backend=args.backend,
                                        seed=args.seed)
        print("[[Order selection (rule: lowest successful order within 10 % of the best error)]]\n"
              + table.to_string(index=False))
    return _finish(fit, args)


def _common(parser, *, loops: bool) -> None:
    parser.add_argument("dataset", help="measurement set folder (with manifest.json) or one data file")
    parser.add_argument("-o", "--output", required=True, help="model file to write (JSON); never overwritten")
    parser.add_argument("--plots", help="folder for figures (PNG; existing files are not overwritten)")
    parser.add_argument("--backend", choices=["nlopt", "scipy"], default="nlopt")
    parser.add_argument("--seed", type=opt.seed, default=0, help="seed of every random choice (default 0)")
    parser.add_argument("--split", choices=["fit", "validation", "all"], default=None,
                        help="which measurements to fit (default: the fit split of a set; every record of a file)")
    parser.add_argument("--isolator", default=None,
                        help="isolator name in the manifest (default for a set: its only isolator with "
                             f"{'loop records' if loops else 'white-noise runs'}, an error listing them when "
                             "there are several; for a file: any)")
    parser.set_defaults(isolator_kind="quasi_static" if loops else "white_noise")
    if loops:
        parser.add_argument("--small-threshold", type=opt.real(above=0, unit="m"), default=None,
                            help="amplitude in m separating small- from large-loop records (default: the geometric "
                                 "mean of the smallest and largest record amplitude)")
        parser.add_argument("--start-state", choices=["auto", "cycled", "virgin"], default="auto",
                            help="model state at the first reversal of each record: 'virgin' (loaded from "
                                 "unloaded), 'cycled' (steady cycling), 'auto' (virgin when the record starts "
                                 "unloaded; default)")
        parser.add_argument("--remove-offsets", action="store_true",
                            help="remove each record's loop-centre drift and force offset before fitting "
                                 "(recorded in the model file's provenance; default: fit the data as measured)")


# ``--order``: an order or ``auto``; more elements than the data identify only slow the fit down
_iwan_order = Either((Whole(ge=1, le=opt.MAX_ORDER, meaning="each order adds two parameters the data do not identify"),
                      Choice(("auto",)))).parse
_maxwell_order = Either((Whole(ge=1, le=opt.MAX_DMA_ORDER, meaning="one term a decade covers any measured master curve"),
                         Choice(("auto",)))).parse


def register(subparsers) -> None:
    """Add ``idkit fit iwan|maxwell|boucwen``."""
    fit = subparsers.add_parser("fit", help="identify a model from a measurement set")
    kinds = fit.add_subparsers(dest="fit_kind", required=True)

    iwan = kinds.add_parser("iwan", help="three-stage Iwan fit to the quasi-static wire-rope loops")
    _common(iwan, loops=True)
    iwan.add_argument("--order", type=_iwan_order, default="auto",
                      help=f"number of Jenkin elements (1 to {opt.MAX_ORDER}), or 'auto' (default): fit orders "
                           "1-6, print their table and keep the one the order rule recommends (docs/fitting.md)")
    iwan.add_argument("--order-table", action="store_true",
                      help="also fit orders 1-6 and print errors, stuck stiffness and the recommended order")
    ranges = iwan.add_mutually_exclusive_group()
    ranges.add_argument("--valid-range", type=opt.real(unit="m"), nargs=2, metavar=("X_MIN", "X_MAX"),
                        help="deflections in m (X_MIN < 0 < X_MAX) over which the spring must stay non-negative-stiff "
                             "(default: 1.25 x the deflections of every record of the isolator, drops included)")
    ranges.add_argument("--no-valid-range", action="store_true",
                        help="fit the loops without the valid-range barrier (the fit is still not a success when "
                             "the spring turns negative-stiff inside the data set's deflections)")
    iwan.add_argument("--family", choices=("auto", "plain", "modulated"), default="auto",
                      help="model family: the plain Iwan model, the slip-modulated one (three parameters more: "
                           "slip forces s(y) fc_i, s = 1 - a t + b t^2, t = tanh(y / y_ref)), or 'auto' (default): "
                           "the modulated model only when the plain one misses the loops by more than 2 points above "
                           "their noise floor or leaves parameters undetermined, and the modulated one does better "
                           "by the order rule's factor or determines them (docs/fitting.md)")
    iwan.set_defaults(handler=_cmd_iwan)

    maxwell = kinds.add_parser("maxwell", help="generalized Maxwell fit: k0 from the loops, the rest from the FRFs; "
                                               "or a Prony series from a DMA / complex stiffness table file")
    _common(maxwell, loops=False)
    maxwell.add_argument("--order", type=_maxwell_order, default=None,
                         help=f"number of Maxwell elements (1 to {opt.MAX_DMA_ORDER}), or 'auto' (the default): for a "
                              "measurement set, orders 1-4 fitted and the lowest successful "
                              "one within 1.1 x the best error kept (the table is printed); for a table (its "
                              "default), the fewest terms within 1.1 x the best error of orders 1 to one a decade")
    maxwell.add_argument("--reference-temperature", type=opt.real(above=-273.15, unit="C"),
                         help="table with isotherms: reference temperature of the master curve in C (default: the "
                              "given shift factors' reference, else the isotherm nearest the median temperature)")
    maxwell.add_argument("--shift-factors", metavar="FILE",
                         help="table with isotherms: given shift factors (temperature [C|K], log_aT [-]) to check "
                              "against the ones estimated from the isotherms")
    maxwell.add_argument("--use-given-shift-factors", action="store_true",
                         help="build the master curve from --shift-factors instead of the estimated ones")
    maxwell.add_argument("--k0", type=opt.real(at_least=opt.MIN_K0, at_most=opt.MAX_K0, unit="N/m",
                                               why="the element stiffnesses are searched in 0.1-10 k0; "
                                                   "outside, the fit's bounds collapse or its squares overflow"),
                         help="static stiffness in N/m (default: from the quasi-static loops)")
    maxwell.add_argument("--k0-method", choices=("relaxation", "secant"), default=None,
                         help="how k0 is read off the loops: with the relaxation of elements not yet relaxed at the "
                              "zero crossings fitted (default), or the loops' secant slope around zero (biased high "
                              "by such elements; docs/fitting.md)")
    maxwell.add_argument("--band", type=opt.real(above=0, unit="Hz"), nargs=2, default=None, metavar=("F_LOW", "F_HIGH"),
                         help="frequency band in Hz (default 1 100)")
    maxwell.add_argument("--cross-check", action="store_true", help="run the seeded global cross-check")
    maxwell.add_argument("--order-table", action="store_true", help="also print errors for orders 1-4 and Voigt")
    maxwell.set_defaults(handler=_cmd_maxwell)

    boucwen = kinds.add_parser("boucwen", help="Bouc-Wen fit (staged, scaled, global search) to the same loops")
    _common(boucwen, loops=True)
    boucwen.add_argument("--global-evals", default=1000,
                         type=opt.integer(at_most=opt.MAX_EVALS, why="evaluations of the global search"),
                         help=f"budget of the global search (1 to {opt.MAX_EVALS:.0e}, default 1000)")
    boucwen.add_argument("--compare", action="store_true", help="also fit Iwan order 2 and print the comparison")
    boucwen.set_defaults(handler=_cmd_boucwen)

    from idkit.cli import fit_auto

    fit_auto.add_to(kinds, load=_load, check_outputs=_check_outputs)
