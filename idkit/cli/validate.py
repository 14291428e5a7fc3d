"""``idkit validate MODEL.json DATA``: a model's force predictions against held-out force records.

Parses arguments and calls :func:`idkit.validate.history.validate_histories`; prints the
per-record table and the verdict; writes the table (``-o``) and figures (``--plots``) on
request. Exit status: 0 PASS, 1 FAIL, 3 INCONCLUSIVE (as ``idkit report``), 2 bad input.
"""

from __future__ import annotations

import sys
from pathlib import Path

from idkit.checks import InputPath
from idkit.errors import IdkitError

#: exit status per verdict (``idkit report``'s numbers: 1 a validation failed, 3 inconclusive)
VERDICT_EXIT = {"PASS": 0, "FAIL": 1, "INCONCLUSIVE": 3}


def _cmd_validate(args) -> int:
    from idkit.cli.tables import write_table
    from idkit.io import load_measurement_set
    from idkit.io.discover import load_measurements
    from idkit.models import IsolatorModel, load_model
    from idkit.output_checks import check_output
    from idkit.validate.history import validate_histories

    inputs = [args.model, args.data]
    if args.output is not None:
        check_output(args.output, inputs=inputs)
    if args.plots is not None:
        check_output(args.plots, kind="folder", inputs=inputs, option="--plots")
    model = load_model(args.model)
    if not isinstance(model, IsolatorModel):
        raise IdkitError(f"{args.model}: holds a whole system; expected an isolator model file (the records give "
                         "the isolator's own deflection and force)")
    path = InputPath(what="a measurement set (folder with manifest.json) or a data file of force records").check(
        args.data, "DATA", IdkitError)
    if path.is_dir():
        data, split = load_measurement_set(path), args.split or "validation"
    else:
        data, split = load_measurements(path)[1], "all" if args.split is None else args.split
    baselines = None if args.no_baselines else _baselines(data, args.isolator, split, args.seed)
    result = validate_histories(model, data, isolator=args.isolator, split=split,
                                name=f"force histories, {Path(args.model).name}", baselines=baselines)
    if args.plots is not None:  # refused before anything is written
        from idkit.plot.histories import history_plot_paths

        existing = [str(p) for p in history_plot_paths(result, args.plots) if p.exists()]
        if existing:
            raise FileExistsError(f"refusing to overwrite existing plot(s): {', '.join(existing)}")
    print(result.report())
    columns = ["record", "group", "nrms_error", "nrms_error_strong_motion",
               *[column for column in result.metrics.columns if column.startswith("baseline ")],
               "model_error_strong_motion", "peak_force_error", "energy_error", "noise_floor", "error_over_floor"]
    print(result.metrics[columns].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    if args.output is not None:
        write_table(result.metrics, args.output)
    if args.plots is not None:
        from idkit.plot.histories import save_history_plots

        for written in save_history_plots(result, args.plots):
            print(f"wrote {written}", file=sys.stderr)
    if result.verdict != "PASS":
        print(f"idkit: {result.verdict}: " + "; ".join(result.why), file=sys.stderr)
    return VERDICT_EXIT[result.verdict]


def _baselines(data, isolator, split, seed) -> dict:
    from idkit.fit.baselines import baselines_for_records

    baselines, where = baselines_for_records(data, isolator=isolator, split=split, seed=seed)
    print(f"baselines fitted on {where}", file=sys.stderr)
    return baselines


def register(commands) -> None:
    """Add ``idkit validate``."""
    validate = commands.add_parser(
        "validate", help="predict held-out force records (any deflection history) with a model file and score it",
        epilog="exit status: 0 PASS; 1 FAIL (a metric beyond its limit); 3 INCONCLUSIVE (a record too noisy or "
               "too short to judge, or one the model cannot simulate); 2 bad input. Limits: docs/validation.md")
    validate.add_argument("model", help="isolator model file (JSON)")
    validate.add_argument("data", help="measurement set folder (its quasi-static force records) or one data file")
    validate.add_argument("--split", choices=["fit", "validation", "all"], default=None,
                          help="which records (default: the validation split of a set; every record of a file)")
    validate.add_argument("--isolator", default=None, help="only this isolator's records (default: any)")
    validate.add_argument("-o", "--output", help="per-record table, CSV or JSON (never overwritten)")
    validate.add_argument("--plots", help="folder for one figure per record (PNG; existing files are not overwritten)")
    validate.add_argument("--no-baselines", action="store_true",
                          help="do not fit and score the simple baselines (linear spring and dashpot, Jenkin element, "
                               "zero force) beside the model")
    validate.add_argument("--seed", type=int, default=0, help="seed of the Jenkin baseline's starts (default 0)")
    validate.set_defaults(handler=_cmd_validate)
