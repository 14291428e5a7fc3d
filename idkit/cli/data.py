"""``idkit data generate`` (the bundled synthetic sets) and ``idkit data init`` (a manifest for your files)."""

from __future__ import annotations

import sys
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


def _cmd_init(args) -> None:
    from idkit.errors import IdkitError
    from idkit.io.manifest_init import init_manifest

    metadata = {key: value for key, value in (
        ("isolator", args.isolator), ("top_mass_kg", args.top_mass), ("intermediate_mass_kg", args.intermediate_mass),
        ("bottom_mass_kg", args.bottom_mass), ("drop_height_m", args.drop_height), ("repetition", args.repetition),
        ("sample_rate_hz", args.sample_rate), ("split", args.split), ("notes", args.notes)) if value is not None}
    excitation = {}
    if args.freq is not None:
        excitation["freq_hz"] = args.freq
    if args.band is not None:
        excitation["band_hz"] = list(args.band)
    if excitation:
        metadata["excitation"] = excitation
    mat_columns = {}
    for item in args.mat_column or ():
        name, sep, spec = item.partition("=")
        if not sep or not name.strip() or not spec.strip():
            raise IdkitError(f"--mat-column: found {item!r}, expected NAME='var [unit]' or NAME='var[:,k] [unit]'")
        mat_columns[name.strip()] = spec.strip()
    manifest = init_manifest(args.folder, kind=args.kind, files=args.files, metadata=metadata,
                             mat_columns=mat_columns or None, name=args.name or "", append=args.append,
                             force=args.force)
    print(f"wrote {manifest.path}: {len(manifest.entries)} measurement(s); every file read back with the stated "
          "metadata. Check the values that differ between files (drop heights, masses, splits) and edit them.",
          file=sys.stderr)


def register(subparsers) -> None:
    """Add ``idkit data generate`` to the ``idkit`` command."""
    from idkit.synth.names import DEFAULT_SEED, SET_NAMES, TRUTH_NAMES

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

    from idkit.io.columns import KINDS

    init = actions.add_parser(
        "init", help="write manifest.json for the data files of a folder, from what you state",
        description="List the .csv/.csv.gz/.mat files of FOLDER in a new manifest.json with the kind and "
                    "metadata given here (nothing is guessed; CSV units come from the headers, .mat units from "
                    "--mat-column). Every file is read back with the manifest's rules before it is written.")
    init.add_argument("folder", help="folder holding the data files")
    init.add_argument("--kind", required=True, choices=list(KINDS), help="kind of every listed file")
    init.add_argument("--files", help="glob relative to FOLDER (default: every data file below it)")
    init.add_argument("--isolator", help="isolator name (wire_rope, elastomer, hybrid or free text)")
    init.add_argument("--top-mass", type=opt.real(above=0, unit="kg"), help="top mass in kg")
    init.add_argument("--intermediate-mass", type=opt.real(above=0, unit="kg"), help="intermediate mass in kg")
    init.add_argument("--bottom-mass", type=opt.real(above=0, unit="kg"), help="bottom mass in kg")
    init.add_argument("--drop-height", type=opt.real(above=0, unit="m"), help="drop height in m (drops)")
    init.add_argument("--freq", type=opt.real(above=0, unit="Hz"), help="excitation frequency in Hz (stepped sine)")
    init.add_argument("--band", type=opt.real(above=0, unit="Hz"), nargs=2, metavar=("LOW", "HIGH"),
                      help="white-noise band in Hz")
    init.add_argument("--sample-rate", type=opt.real(above=0, unit="Hz"), help="declared sample rate in Hz")
    from idkit.io.info import MAX_REPETITION

    init.add_argument("--repetition", type=opt.integer(at_most=MAX_REPETITION, why="exact in every JSON reader"),
                      help="repetition number (1 to 2^53 - 1)")
    init.add_argument("--split", choices=["fit", "validation"], help="fit or validation split")
    init.add_argument("--notes", help="free text for every entry")
    init.add_argument("--mat-column", action="append", metavar="NAME=SPEC",
                      help="for .mat files: e.g. time='Tout [s]' deflection='x_F[:,0] [mm]' (repeat)")
    init.add_argument("--name", help="the set's name")
    mode = init.add_mutually_exclusive_group()
    mode.add_argument("--append", action="store_true", help="add the files to an existing manifest")
    mode.add_argument("--force", action="store_true", help="replace an existing manifest")
    init.set_defaults(handler=_cmd_init)


