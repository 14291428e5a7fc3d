"""Start-up of the ``idkit`` command: ``--version``, ``--help`` and ``report --help``, one core.

Run: python bench/bench_cli_start.py [--repeat N]

Each command runs as ``python -m idkit ...`` (what the ``idkit`` console script runs) in a new
process, pinned to one core where the system allows it, once as a warm-up (page cache,
bytecode) and then ``--repeat`` times; printed per command: wall and CPU seconds (user + system
of the finished child, as the system accounts it) as min and median, then the heavy packages
the command imported, read from one run under ``python -X importtime`` (none is expected but numpy:
building the parser imports only light modules, docs/cli-reference.md "Start-up"). The
machine is used as it is: the load average is printed beside the figures. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time

COMMANDS = (("--version",), ("--help",), ("report", "--help"))
HEAVY = ("pandas", "scipy", "numba", "matplotlib")  # numpy is expected: the option checks need it


def pin_to_one_core() -> str:
    """Pin this process (and so its children) to one core; say which, or why not."""
    if not hasattr(os, "sched_setaffinity"):
        return "not pinned (no sched_setaffinity here)"
    core = min(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {core})
    return f"pinned to core {core}"


def run_once(argv) -> tuple[float, float]:
    """Wall and CPU seconds of one ``python -m idkit ARGV`` (its output discarded)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "idkit", *argv], stdout=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def heavy_imports(argv) -> list[str]:
    """The packages of :data:`HEAVY` that ``python -m idkit ARGV`` imports (``-X importtime``)."""
    completed = subprocess.run([sys.executable, "-X", "importtime", "-m", "idkit", *argv], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True, check=True)
    names = {line.rsplit("|", 1)[-1].strip() for line in completed.stderr.splitlines() if line.startswith("import time:")}
    return sorted(names & set(HEAVY))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10, help="timed runs per command (default 10)")
    args = parser.parse_args()
    if args.repeat < 1:
        parser.error(f"--repeat: found {args.repeat}, expected a whole number >= 1")

    pinned = pin_to_one_core()
    print(f"python -m idkit, {args.repeat} runs each after one warm-up, {pinned}, "
          f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'command':16s} {'wall min':>9s} {'median':>8s} {'cpu min':>9s} {'median':>8s}  heavy imports")
    for argv in COMMANDS:
        run_once(argv)
        walls, cpus = zip(*(run_once(argv) for _ in range(args.repeat)))
        heavy = heavy_imports(argv)
        print(f"{' '.join(argv):16s} {min(walls):9.3f} {statistics.median(walls):8.3f} {min(cpus):9.3f} "
              f"{statistics.median(cpus):8.3f}  {', '.join(heavy) or 'none'}")
    print(f"load average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
