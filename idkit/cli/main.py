"""The ``idkit`` command. It only parses arguments and calls the library."""

from __future__ import annotations

import argparse
import contextlib
import signal
import sys
import threading
import warnings
from pathlib import Path

import numpy as np

from idkit import __version__
from idkit.cli import options as opt
from idkit.cli.allocator import keep_freed_memory
from idkit.cli.hints import cli_message
from idkit.cli.tables import write_table as _write_table
from idkit.errors import IdkitError, SimulationError


def _model_or_system(path, mass):
    from idkit.models import IsolatorModel, SDOFSystem, load_model

    model = load_model(path)
    if isinstance(model, IsolatorModel):
        if mass is None:
            raise IdkitError(f"{path}: holds an isolator model; give --mass (kg) to put a top mass on it")
        return SDOFSystem(mass, model)
    if mass is not None:
        raise IdkitError(f"{path}: holds a whole system; --mass applies to isolator model files only")
    return model


def _failed_points(frame, what: str, valid=None) -> int:
    """Exit status of a simulated table (written in every case): 1 when a point's ``status`` is
    not ``ok`` (a step that did not converge, a run that never settled), else 0. ``valid``
    (a boolean column) replaces that test: drops are valid by their flag, so a drop that cannot
    move (status :data:`idkit.responses.shock.NO_MOTION`) is not a failure."""
    bad = frame["status"] != "ok" if valid is None else ~valid
    failed = frame.loc[bad, "status"]
    if failed.empty:
        return 0
    print(f"idkit: {len(failed)} of {len(frame)} {what} not valid (see the status column), e.g. "
          f"{failed.iloc[0]}", file=sys.stderr)
    return 1


def _check_table_output(args, plot_paths=None):
    """Refuse a bad ``-o`` or ``--plots`` of ``simulate`` before simulating (exists, overlaps the
    model, unwritable; a figure that exists, since figures are never replaced)."""
    from idkit.output_checks import check_output, check_plot_folder

    if args.output is not None:
        check_output(args.output, inputs=[args.model])
    if args.plots is not None:
        check_plot_folder(args.plots, plot_paths(args.plots), inputs=[args.model], beside=("the table -o", args.output))


def _save_plots(save, result, folder) -> None:
    for path in save(result, folder):
        print(f"wrote {path}", file=sys.stderr)


def _cmd_library(args):
    from idkit.models import library, save_model

    if args.name is None:
        if args.output:  # listing writes nothing: an -o without a NAME would end with exit 0 and no file
            raise IdkitError(f"-o {args.output}: found no NAME; expected a parameter set to write (idkit library "
                             "lists them)")
        for name in library.names():
            print(f"{name:24s} {library.describe(name)}")
        return
    model = library.get(args.name)
    if args.output:
        from idkit.output_checks import check_output

        check_output(args.output)
        save_model(model, args.output, provenance={"source": "idkit.models.library", "name": args.name})
        print(f"wrote {args.output}", file=sys.stderr)
    else:
        print(repr(model))


def _cmd_simulate_harmonic(args):
    from idkit.cli.progress import ProgressBar
    from idkit.plot.simulations import harmonic_plot_paths, save_harmonic_plots
    from idkit.studies.harmonic_grid import harmonic_grid_table

    axes = (opt.parse_axis("--freq", args.freq, args.freq_spacing, what="frequencies", unit="Hz"),
            opt.parse_axis("--amplitude", args.amplitude, args.amplitude_spacing, what="amplitudes", unit="m"))
    opt.check_grid_size(axes, args.max_points)
    _check_table_output(args, harmonic_plot_paths)
    system = _model_or_system(args.model, args.mass)
    freq, amplitude = (axis.build() for axis in axes)
    table = harmonic_grid_table(system, freq, amplitude, n_harmonics=args.harmonics, tolerance=args.tolerance,
                                progress=ProgressBar("harmonic", enabled=not args.quiet))
    _write_table(table, args.output)
    if args.plots is not None:
        _save_plots(save_harmonic_plots, table, args.plots)
    return _failed_points(table, "points")


def _cmd_simulate_drop(args):
    """Conditioned free falls through :func:`idkit.responses.shock.shock_sweep` (the one drop reduction)."""
    from idkit.plot.simulations import drop_plot_paths, save_drop_plots
    from idkit.responses.shock import default_shock_grid, shock_sweep

    if (args.velocity is None) == (args.height is None):
        raise IdkitError("give exactly one of --velocity and --height")
    _check_table_output(args, drop_plot_paths)
    system = _model_or_system(args.model, args.mass)
    duration, time_step = args.duration, args.time_step
    if duration is None or time_step is None:  # the defaults follow the system's resonance
        try:
            auto_duration, auto_step = default_shock_grid(system)
        except SimulationError as problem:
            what = f"--mass {args.mass:g} kg on {args.model}" if args.mass is not None else f"the system of {args.model}"
            raise SimulationError(f"{what}: {problem}; give --duration and --time-step") from None
        duration = auto_duration if duration is None else duration
        time_step = auto_step if time_step is None else time_step
    opt.check_drop(len(args.velocity or args.height), duration, time_step, args.max_samples)
    if args.velocity is not None:
        sweep = shock_sweep(system, impact_velocity=-np.abs(np.asarray(args.velocity, dtype=float)),
                            duration=duration, time_step=time_step, gravity=args.gravity)
    else:
        sweep = shock_sweep(system, drop_height=args.height, duration=duration, time_step=time_step,
                            gravity=args.gravity)
    table = sweep.to_dataframe()
    _write_table(table, args.output)
    if args.plots is not None:
        _save_plots(save_drop_plots, sweep, args.plots)
    return _failed_points(table, "drops", valid=table["flag"] == 0)


def register(commands) -> None:
    """Add ``idkit library`` and ``idkit simulate harmonic|drop``."""
    lib = commands.add_parser("library", help="list the bundled parameter sets or write one as a model file")
    lib.add_argument("name", nargs="?", help="parameter set to print or write (default: list them)")
    lib.add_argument("-o", "--output", help="model file to write (JSON)")
    lib.set_defaults(handler=_cmd_library)

    simulate = commands.add_parser("simulate", help="simulate a model file")
    kinds = simulate.add_subparsers(dest="kind", required=True)
    harmonic = kinds.add_parser("harmonic", help="steady-state harmonic base excitation over a grid",
                                epilog="exit status (the table is written in every case): 0 every point is ok; "
                                       "1 a point is not (its status says why: a step that did not converge, "
                                       "no steady state within the periods)")
    harmonic.add_argument("model", help="model file (JSON)")
    harmonic.add_argument("--mass", type=opt.real(above=0, unit="kg"), help="top mass in kg (isolator model files)")
    harmonic.add_argument("--freq", type=opt.real(why="frequencies in Hz, or START STOP COUNT"), nargs="+", required=True,
                          help="frequencies in Hz, or START STOP COUNT with --freq-spacing")
    harmonic.add_argument("--freq-spacing", choices=["log", "linear"])
    harmonic.add_argument("--amplitude", type=opt.real(why="amplitudes in m, or START STOP COUNT"), nargs="+", required=True,
                          help="base displacement amplitudes in m, or START STOP COUNT with --amplitude-spacing")
    harmonic.add_argument("--amplitude-spacing", choices=["log", "linear"])
    harmonic.add_argument("--harmonics", default=3,
                          type=opt.integer(at_most=opt.MAX_HARMONICS, why="128 steps per period resolve 64"),
                          help=f"highest harmonic order (1 to {opt.MAX_HARMONICS}, default 3)")
    harmonic.add_argument("--tolerance", default=1e-3,
                          type=opt.real(at_least=opt.MIN_TOLERANCE, below=1, why="a relative change; smaller "
                                        "than round-off is never met"),
                          help="steady-state tolerance, relative (1e-12 to below 1, default 1e-3)")
    harmonic.add_argument("--max-points", default=opt.DEFAULT_MAX_POINTS,
                          type=opt.integer(at_most=opt.MAX_GRID_POINTS, why="a larger grid does not fit in memory"),
                          help=f"refuse grids of more points (default {opt.DEFAULT_MAX_POINTS}, "
                               f"at most {opt.MAX_GRID_POINTS:.0e})")
    harmonic.add_argument("-o", "--output", help="CSV or JSON file (default: print a table)")
    harmonic.add_argument("--plots", metavar="DIR",
                          help="folder for figures (PNG, never overwritten): harmonic_map.png, |H1| and the other "
                               "HOSIDF orders over frequency and amplitude with the resonance line (2 frequencies "
                               "and 2 amplitudes at least), and harmonic_sections.png, |H1| against frequency")
    harmonic.add_argument("--quiet", action="store_true")
    harmonic.set_defaults(handler=_cmd_simulate_harmonic)

    drop = kinds.add_parser("drop", help="conditioned free fall (base fixed)",
                            epilog="exit status (the table is written in every case): 0 every drop is valid "
                                   "(one that cannot move, speed 0 without --gravity, says 'no motion' in its "
                                   "status, its peaks NaN); 1 a drop is not (its status says why)")
    drop.add_argument("model", help="model file (JSON)")
    drop.add_argument("--mass", type=opt.real(above=0, unit="kg"), help="top mass in kg (isolator model files)")
    drop.add_argument("--velocity", type=opt.real(at_least=0, unit="m/s", why="a speed; idkit sets the sign "
                                                   "downward"), nargs="+", help="impact speeds |v0| in m/s")
    drop.add_argument("--height", type=opt.real(at_least=0, unit="m"), nargs="+", help="drop heights in m")
    drop.add_argument("--duration", type=opt.real(above=0, unit="s"),
                      help="simulated time in s, covered by whole steps (the last ends less than a step after it; "
                           "default: 4 periods of the small-amplitude resonance)")
    drop.add_argument("--time-step",
                      type=opt.real(at_least=opt.MIN_TIME_STEP, unit="s", why="a smaller step makes the number "
                                    "of steps duration/time_step too large"),
                      help=f"integration step in s (at least {opt.MIN_TIME_STEP:g}; default: 2000 per period of "
                           "the small-amplitude resonance, see idkit.responses.shock)")
    drop.add_argument("--max-samples", default=opt.DEFAULT_MAX_SAMPLES,
                      type=opt.integer(at_most=opt.MAX_DROP_SAMPLES, why="larger records do not fit in memory"),
                      help=f"refuse drops x steps above this (default {opt.DEFAULT_MAX_SAMPLES}, "
                           f"at most {opt.MAX_DROP_SAMPLES:.0e})")
    drop.add_argument("--gravity", action="store_true", help="include gravity")
    drop.add_argument("-o", "--output", help="CSV or JSON file (default: print a table)")
    drop.add_argument("--plots", metavar="DIR",
                      help="folder for figures (PNG, never overwritten): drop_histories.png (top-mass acceleration "
                           "against time) and drop_peaks.png (peaks against drop height)")
    drop.set_defaults(handler=_cmd_simulate_drop)


def build_parser() -> argparse.ArgumentParser:
    """The ``idkit`` parser: every command family adds itself with its module's ``register(commands)``."""
    from idkit.cli import catalogue, data, design, fit, inspect, report, shock, study, validate

    parser = opt.IdkitArgumentParser(prog="idkit", description="Identify, validate and simulate isolator models.")
    parser.add_argument("--version", action="version", version=f"idkit {__version__}")
    commands = parser.add_subparsers(dest="command", required=True)
    for register_family in (register, data.register, fit.register, inspect.register, report.register, shock.register,
                            study.register, catalogue.register, design.register, validate.register):
        register_family(commands)
    return parser


#: Output options of the commands, as ``args`` attribute and option name.
_OUTPUT_OPTIONS = (("output", "-o"), ("plots", "--plots"))


def _outputs_of(args, problem: OSError) -> str:
    """For an error that names no file (a write that hit a full disk or a file-size limit deep in
    a library): the outputs this command was asked to write, so that the message names them."""
    if problem.filename:
        return ""
    given = [f"{option} '{getattr(args, name)}'" for name, option in _OUTPUT_OPTIONS
             if isinstance(getattr(args, name, None), (str, Path))]
    return f" (while running; this command writes {', '.join(given)})" if given else ""


class Terminated(BaseException):
    """Raised in the main thread when the process receives ``SIGTERM``, so that every
    ``finally`` and context manager runs (staging folders removed, old outputs restored)."""


def _raise_terminated(signum, frame):
    raise Terminated()


@contextlib.contextmanager
def _sigterm_as_exception():
    """Turn ``SIGTERM`` into :class:`Terminated` while the command runs (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as the command's own line (``idkit: warning: ...``), without the library's source line."""
    print(f"idkit: warning: {message}", file=sys.stderr if file is None else file)


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        with _sigterm_as_exception(), warnings.catch_warnings():
            warnings.showwarning = _show_warning  # the filters stay the caller's (errors under pytest)
            status = args.handler(args)
    except (IdkitError, FileExistsError, FileNotFoundError) as problem:
        print(f"idkit: error: {cli_message(problem)}", file=sys.stderr)
        return 2
    except OSError as problem:  # last resort: a write or read that no check foresaw
        where = f"{problem.filename}: " if problem.filename else ""
        print(f"idkit: error: {where}{problem.strerror or problem}{_outputs_of(args, problem)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("idkit: interrupted; partial outputs removed, previous outputs kept", file=sys.stderr)
        return 130
    except Terminated:
        print("idkit: terminated (SIGTERM); partial outputs removed, previous outputs kept", file=sys.stderr)
        return 128 + signal.SIGTERM
    return int(status or 0)


def run() -> int:
    """The ``idkit`` command (its console script, ``python -m idkit``): :func:`main` in a process whose
    allocator keeps freed memory for the next allocation (:mod:`idkit.cli.allocator`)."""
    keep_freed_memory()
    return main()


if __name__ == "__main__":
    sys.exit(run())
