"""``python -m idkit.synth [-o data] [--seed 2026] [--force] [--quick] [--truth a|b]``.

The same as ``idkit data generate``; kept free of :mod:`idkit.cli` so that the synth layer
imports only lower layers.
"""

import argparse
import sys

from idkit.synth import generate
from idkit.synth.names import DEFAULT_SEED, SET_NAMES, TRUTH_NAMES


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m idkit.synth",
                                     description="Generate the bundled synthetic measurement data.")
    parser.add_argument("-o", "--output", default="data")
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--force", action="store_true")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--sets", nargs="+", default=list(SET_NAMES), choices=list(SET_NAMES))
    parser.add_argument("--truth", default="a", choices=list(TRUTH_NAMES))
    args = parser.parse_args(argv)
    try:
        summary = generate(args.output, seed=args.seed, force=args.force, quick=args.quick,
                           sets=args.sets, truth=args.truth)
    except FileExistsError as problem:
        print(f"idkit.synth: error: {problem}", file=sys.stderr)
        return 2
    print(summary.report())
    return 0


if __name__ == "__main__":
    sys.exit(main())
