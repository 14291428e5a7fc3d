"""Benchmark: the README's main command cold (fresh clone, fresh venv, empty kernel cache) and in a
second fresh venv on the cache the first one filled (issue 34, item 3).

    python bench/bench_cold_start.py [--repeats R] [--quick] [--pip-option OPTION ...] [--parallel-bytecode]
                                     [--source REPO]

Each repetition, in a new temporary folder:

1. **cold**: ``git clone`` of ``--source`` (default: this checkout's repository) at the commit
   its ``HEAD`` names when the bench starts (every run the same), then the README's main command (the first ``bash`` block under "Two commands", read
   from the clone and run verbatim, part by part: create the venv, install, ``idkit report``) with
   an empty per-user kernel cache (``IDKIT_CACHE_DIR`` and ``XDG_CACHE_HOME`` new empty folders,
   ``NUMBA_CACHE_DIR`` unset);
2. **second venv**: a second clone and the same command, on the cache the cold run filled: it
   should load every kernel and compile nothing.

Printed per run: wall and CPU seconds (user + system of every process the part started,
forked children included) of each part, the compiled kernels the report wrote to the cache
(``.nbc`` files created or rewritten: numba writes one per compiled specialisation, so a run that
compiles nothing writes none), the report's own stage timings (``provenance.json``) and the load
average; then min and median over the repetitions, wall and CPU (on a shared machine the wall
depends on the other processes' load, the CPU far less). ``--quick`` adds ``--quick`` to the report
(faster, for trying the script); ``--pip-option`` adds an option to the install (e.g.
``--no-compile``: pip then writes no bytecode for the installed packages); ``--parallel-bytecode``
installs with ``--no-compile`` and then writes the same bytecode on every core, as a part of its
own (``bytecode``: ``python -m compileall -q -j 0`` over the venv's ``lib``; pip compiles the
installed files one after the other in its own process). The machine is used
as it is: the load average is printed beside the figures. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def readme_main_command(readme: Path) -> str:
    """The README's main command: the first ``bash`` block after the "Two commands" heading."""
    text = readme.read_text(encoding="utf-8")
    start = text.index("## Two commands")
    block = re.search(r"```bash\n(.*?)```", text[start:], flags=re.S)
    if block is None:
        raise SystemExit(f"{readme}: no bash block under '## Two commands'")
    return " ".join(line.strip() for line in block.group(1).strip().splitlines())


#: the bytecode part of ``--parallel-bytecode``: every ``.py`` of the venv compiled on every core
PARALLEL_BYTECODE = ".venv/bin/python -m compileall -q -j 0 .venv/lib"


def command_parts(command: str, *, quick: bool, pip_options: list[str],
                  parallel_bytecode: bool = False) -> list[tuple[str, str]]:
    """The command's ``&&``-separated parts, labelled venv / install / report (and adapted by the
    options; ``parallel_bytecode``: the install without bytecode, then a ``bytecode`` part)."""
    parts = []
    for part in (piece.strip() for piece in command.split("&&")):
        words = shlex.split(part)
        if "venv" in words and "-m" in words:
            label = "venv"
        elif "pip" in words[0] and "install" in words:
            label = "install"
            part = " ".join([part, *map(shlex.quote, pip_options), *(["--no-compile"] if parallel_bytecode else [])])
            if parallel_bytecode:
                parts.append((label, part))
                label, part = "bytecode", PARALLEL_BYTECODE
        elif words[0].endswith("idkit") and "report" in words:
            label = "report"
            if quick:
                part += " --quick"
        else:
            label = words[0]
        parts.append((label, part))
    return parts


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _cache_files(folder: Path) -> dict[str, int]:
    return {str(path): path.stat().st_mtime_ns for path in folder.rglob("*.nbc")}


def _load() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "n/a"


def run_readme_command(source: str, commit: str, folder: Path, cache: Path, xdg: Path, *, quick: bool,
                       pip_options: list[str], parallel_bytecode: bool = False) -> dict:
    """Clone ``source`` at ``commit`` into ``folder`` and run the README's main command there, part by part."""
    subprocess.run(["git", "clone", "-q", source, str(folder)], check=True)
    subprocess.run(["git", "-C", str(folder), "checkout", "-q", commit], check=True)
    parts = command_parts(readme_main_command(folder / "README.md"), quick=quick, pip_options=pip_options,
                          parallel_bytecode=parallel_bytecode)
    env = {key: value for key, value in os.environ.items()
           if key not in ("NUMBA_CACHE_DIR", "VIRTUAL_ENV", "PYTHONPATH")}
    env.update(IDKIT_CACHE_DIR=str(cache), XDG_CACHE_HOME=str(xdg))
    found = {"load before": _load(), "parts": {}}
    before = _cache_files(cache)
    for label, part in parts:
        cpu, start = _children_cpu(), time.perf_counter()
        completed = subprocess.run(["bash", "-c", part], cwd=folder, env=env, capture_output=True, text=True)
        found["parts"][label] = (time.perf_counter() - start, _children_cpu() - cpu)
        if label == "report" and completed.returncode not in (0, 3, 4):
            raise SystemExit(f"{part}: exit status {completed.returncode}\n{completed.stderr[-2000:]}")
        if label != "report" and completed.returncode != 0:
            raise SystemExit(f"{part}: exit status {completed.returncode}\n{completed.stderr[-2000:]}")
    after = _cache_files(cache)
    found["compiled"] = sum(1 for path, stamp in after.items() if before.get(path) != stamp)
    found["cached kernels"] = len(after)
    found["load after"] = _load()
    provenance = folder / "idkit-report" / "provenance.json"
    found["stages"] = json.loads(provenance.read_text())["timings_s"] if provenance.exists() else {}
    return found


def _print_run(name: str, found: dict) -> None:
    parts = found["parts"]
    wall = sum(seconds for seconds, _ in parts.values())
    cpu = sum(seconds for _, seconds in parts.values())
    print(f"  {name}: {wall:6.1f} s wall, {cpu:6.1f} s CPU (load {found['load before']} -> {found['load after']}); "
          f"compiled {found['compiled']} kernel(s), {found['cached kernels']} in the cache")
    for label, (seconds, used) in parts.items():
        print(f"      {label:8s} {seconds:6.1f} s wall {used:6.1f} s CPU")
    for stage, seconds in found["stages"].items():
        print(f"      report stage {seconds:7.2f} s  {stage}")


def _summary(label: str, values: list[float]) -> str:
    return f"{label:34s} min {min(values):6.1f} s  median {statistics.median(values):6.1f} s"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="idkit report --quick (for trying the script)")
    parser.add_argument("--pip-option", action="append", default=[], dest="pip_options",
                        help="an option added to the install (repeatable), e.g. --pip-option=--no-compile")
    parser.add_argument("--parallel-bytecode", action="store_true",
                        help="install with --no-compile, then write the bytecode on every core (compileall -j 0)")
    parser.add_argument("--source", default=str(ROOT), help="repository to clone (default: this checkout)")
    options = parser.parse_args()
    # every run clones the same commit (a commit made meanwhile would change the kernels' cache key)
    commit = subprocess.run(["git", "-C", options.source, "rev-parse", "HEAD"], check=True, capture_output=True,
                            text=True).stdout.strip()
    print(f"commit {commit}; README main command of {options.source}: {readme_main_command(ROOT / 'README.md')}"
          + (" (report --quick)" if options.quick else "") + (f" (install {' '.join(options.pip_options)})"
                                                              if options.pip_options else "")
          + (" (install --no-compile, then the bytecode on every core)" if options.parallel_bytecode else ""))
    print(f"{os.cpu_count()} CPUs; times are wall clock unless CPU (user + system of every process started)")
    runs = {"cold": [], "second venv": []}
    for repetition in range(options.repeats):
        with tempfile.TemporaryDirectory(prefix="idkit-cold-") as scratch:
            scratch = Path(scratch)
            cache, xdg = scratch / "kernel-cache", scratch / "xdg-cache"
            cache.mkdir()
            xdg.mkdir()
            print(f"repetition {repetition + 1}")
            for name, clone in (("cold", "first"), ("second venv", "second")):
                found = run_readme_command(options.source, commit, scratch / clone, cache, xdg, quick=options.quick,
                                           pip_options=options.pip_options,
                                           parallel_bytecode=options.parallel_bytecode)
                runs[name].append(found)
                _print_run(name, found)
    for name, found in runs.items():
        print(_summary(f"{name}: whole command", [sum(s for s, _ in f["parts"].values()) for f in found]))
        print(_summary(f"{name}: whole command CPU", [sum(c for _, c in f["parts"].values()) for f in found]))
        for label in found[0]["parts"]:
            print(_summary(f"{name}: {label}", [f["parts"][label][0] for f in found]))
            print(_summary(f"{name}: {label} CPU", [f["parts"][label][1] for f in found]))
        print(f"{name}: kernels compiled per run {[f['compiled'] for f in found]}; load average before each run "
              f"{[f['load before'] for f in found]}")


if __name__ == "__main__":
    sys.exit(main())
