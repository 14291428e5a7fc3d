"""``idkit shock FILE...``: pulses, shock response spectra and response/input of shock records."""

from __future__ import annotations

import sys

from idkit.cli import options as opt

__all__ = ["register"]

LAYOUTS = ("csv", "afrl")


def _read(path, layout):
    if layout == "afrl":
        from idkit.datasets import read_afrl_accel

        return read_afrl_accel(path)
    from idkit.io.shock_csv import read_shock_file

    return read_shock_file(path)


def _cmd_shock(args) -> None:
    import numpy as np

    from idkit.errors import IdkitError
    from idkit.output_checks import check_output
    from idkit.studies.shock import analyse_shock

    inputs = list(args.files) + ([args.input] if args.input else [])
    if args.output is not None:
        check_output(args.output, kind="replaced", inputs=inputs, force=args.force)
    if (args.freq_min is None) != (args.freq_max is None):
        raise IdkitError("give both --freq-min and --freq-max (Hz), or neither for the default band")
    if args.freq_min is not None and not args.freq_min < args.freq_max:
        raise IdkitError(f"--freq-min {args.freq_min:g} Hz / --freq-max {args.freq_max:g} Hz: expected min < max")
    if args.offset is None:  # drop records start at impact and are zeroed at rest: no pre-trigger window
        from idkit.io.shock_csv import is_drop_record_file

        drops = args.layout == "csv" and all(is_drop_record_file(path) for path in inputs)
        args.offset = "none" if drops else "pre-trigger"
    records = [_read(path, args.layout) for path in args.files]
    # --points sets the default band's count too
    freq = (None if args.freq_min is None else
            np.logspace(np.log10(args.freq_min), np.log10(args.freq_max), args.points))
    base = _read(args.input, args.layout) if args.input else None
    analysis = analyse_shock(records, input=base, freq=freq, n_points=args.points, damping_ratio=args.damping,
                             offset=args.offset, lowpass_hz=args.lowpass)
    print(analysis.report())
    if args.output is not None:
        from idkit.report.shock_files import write_shock_analysis

        written = write_shock_analysis(analysis, args.output, force=args.force)
        print(f"wrote {len(written)} files to {args.output}", file=sys.stderr)


def register(subparsers) -> None:
    """Add ``idkit shock`` to the ``idkit`` command."""
    shock = subparsers.add_parser(
        "shock", help="shock records: pulse peak, duration, velocity change, SRS, response/input",
        description="Read shock records (one channel per file, one column per test), remove each test's "
                    "pre-trigger offset, print peak, duration and velocity change, and with -o write the "
                    "three ISO 18431-4 shock response spectra (tables and figures).")
    shock.add_argument("files", nargs="+", help="shock record files (response channels), or idkit drop records "
                                                "(their top-mass accelerometers a_top_1, a_top_2)")
    shock.add_argument("--input", help="the input (fixture) channel: response/input SRS ratios")
    shock.add_argument("--layout", choices=LAYOUTS, default="csv",
                       help="csv: 'time [s], <test> [unit], ...', or an idkit drop record (told by its header: "
                            "deflection, a_top_1, a_top_2; docs/data-format.md); afrl: the AFRL drop-tower "
                            "files of ../shared/realdata (default csv)")
    shock.add_argument("--freq-min", type=opt.real(above=0, unit="Hz"), help="lowest natural frequency, Hz")
    shock.add_argument("--freq-max", type=opt.real(above=0, unit="Hz"), help="highest natural frequency, Hz")
    shock.add_argument("--points", type=opt.integer(at_least=2, at_most=2000), default=60, help="natural frequencies, log-spaced over the band (default 60; default band: 1 / record length "
                            "to sample rate / 10)")
    shock.add_argument("--damping", type=opt.real(at_least=0, below=1, unit="-"), default=0.05,
                       help="damping ratio of the SRS oscillators (default 0.05)")
    shock.add_argument("--offset", choices=("pre-trigger", "none"), default=None,
                       help="offset removal (default: the median of the pre-trigger window; none when every file "
                            "is an idkit drop record, which starts at impact with its accelerometers zeroed at rest)")
    shock.add_argument("--lowpass", type=opt.real(above=0, unit="Hz"),
                       help="zero-phase Butterworth low-pass cut-off, Hz (default: none)")
    shock.add_argument("-o", "--output", help="folder for tables and figures")
    shock.add_argument("--force", action="store_true", help="replace an existing output folder")
    shock.set_defaults(handler=_cmd_shock)
