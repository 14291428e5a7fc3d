"""Benchmark: where the CPU of ``idkit report`` goes, cold (empty kernel cache) and warm (issue 34, item 3).

    python bench/bench_report_compiles.py [--quick] [--data DIR] [--top N]

Runs ``idkit report`` (this checkout's idkit, in this Python) twice in a child process: first with
a new, empty kernel cache (``IDKIT_CACHE_DIR`` a new temporary folder), then again on the cache
that run filled. In both runs numba's dispatcher compile and idkit's forked calls
(:func:`idkit.forked.fork_call`) are wrapped to record, in every process of the report (the
forked Bouc-Wen fit, elastomer checks, transport study and figure renderers included):

- each compiled specialisation: the process, the kernel, its signature and the CPU seconds
  spent compiling it alone (the compiles of the functions it calls subtracted), whether it was
  loaded from the cache instead (CPU of the compiling thread: a kernel compiles in the thread that
  first calls it). numba's own helpers (``np.empty`` and the like, compiled once
  per process, never cached) are summed on one line;
- each forked call: its function (a figure renderer: the figure's name) and the CPU seconds
  of its process.

Printed per run: wall and CPU seconds of the report (every process), the report's stage timings
(``provenance.json``), the CPU per process role (main process, each kind of forked call), and for
the cold run the ``--top`` costliest compiles and their sum. The machine is used as it is (the
load average is printed): on a busy machine the wall depends on the others, the CPU far less.
One repetition (each run takes minutes); nothing is asserted.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# Run inside the report's process: wraps numba's compile and idkit's fork, then runs the CLI.
_BOOTSTRAP = r"""
import json, os, resource, sys, threading, time
LOG = os.environ["IDKIT_BENCH_LOG"]

def _cpu():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime

def _write(record):
    with open(LOG, "a") as log:
        log.write(json.dumps(record) + "\n")

import idkit  # installs idkit's cache locator and compile claims first
from numba.core.registry import CPUDispatcher
import idkit.forked as forked

_compile = CPUDispatcher.compile
_local = threading.local()  # per thread: the CPU of the compiles nested in the ones running

def compile_recorded(self, sig):
    nested = _local.__dict__.setdefault("nested", [])
    known, hits = len(self.overloads), sum(self._cache_hits.values())
    started = time.thread_time()  # this thread's CPU: a kernel compiles in the thread that first calls it
    nested.append(0.0)
    try:
        return _compile(self, sig)
    finally:
        inner = nested.pop()
        spent = time.thread_time() - started
        if nested:
            nested[-1] += spent
        if len(self.overloads) > known:
            function = self.py_func
            _write({"pid": os.getpid(), "kernel": f"{function.__module__}.{function.__qualname__}",
                    "signature": str(sig), "cpu": spent - inner, "loaded": sum(self._cache_hits.values()) > hits})

CPUDispatcher.compile = compile_recorded
_start = forked.Forked._start

def start_recorded(self):
    function, args, kwargs = self._call
    role = getattr(function, "__qualname__", repr(function))
    if role == "_render_figure":
        frame = sys._getframe()
        while frame is not None and frame.f_code.co_name != "_fork_render":
            frame = frame.f_back
        role = "figure " + (frame.f_locals.get("name", "?") if frame is not None else "?")

    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        finally:
            _write({"pid": os.getpid(), "role": role, "process cpu": _cpu()})

    self._call = (call, args, kwargs)
    try:
        _start(self)
    finally:
        self._call = (function, args, kwargs)

forked.Forked._start = start_recorded
from idkit.cli.main import run  # the command: its allocator settings included
sys.argv = ["idkit", *sys.argv[1:]]
try:
    status = run()
finally:
    _write({"pid": os.getpid(), "role": "main process", "process cpu": _cpu()})
sys.exit(status)
"""


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _load() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "n/a"


def run_report(cache: Path, out: Path, log: Path, *, data: str | None, quick: bool) -> dict:
    """``idkit report`` in a child process on the kernel cache ``cache``; what it recorded."""
    env = {key: value for key, value in os.environ.items() if key != "NUMBA_CACHE_DIR"}
    env.update(IDKIT_CACHE_DIR=str(cache), IDKIT_BENCH_LOG=str(log), PYTHONPATH=str(ROOT))
    command = [sys.executable, "-c", _BOOTSTRAP, "report", *([data] if data else []), "-o", str(out), "--force",
               *(["--quick"] if quick else [])]
    load, cpu, started = _load(), _children_cpu(), time.perf_counter()
    completed = subprocess.run(command, env=env, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - started, _children_cpu() - cpu
    if completed.returncode not in (0, 3, 4):
        raise SystemExit(f"idkit report: exit status {completed.returncode}\n{completed.stderr[-2000:]}")
    records = [json.loads(line) for line in log.read_text().splitlines()]
    stages = json.loads((out / "provenance.json").read_text())["timings_s"]
    return {"wall": wall, "cpu": cpu, "load": f"{load} -> {_load()}", "records": records, "stages": stages}


def _roles(records: list[dict]) -> dict[int, str]:
    """Process id -> its role; figure renderers share one role in the per-role table."""
    return {r["pid"]: ("figure renderers" if r["role"].startswith("figure ") else r["role"])
            for r in records if "role" in r}


def print_run(name: str, found: dict, top: int) -> None:
    records = found["records"]
    print(f"{name}: {found['wall']:6.1f} s wall, {found['cpu']:6.1f} s CPU (every process; load {found['load']})")
    for stage, seconds in found["stages"].items():
        print(f"    report stage {seconds:7.2f} s  {stage}")
    roles = _roles(records)
    # one record per compiled entry: a thread that waited for another's compile of it records it too
    # (with the CPU it spent waiting, next to none), as does a compile call nested in one of the same entry;
    # below 5 ms a record is such a call, not a compile (the smallest compiles take 20 ms)
    entries = {}
    for record in (r for r in records if "kernel" in r and not r["loaded"] and r["cpu"] >= 0.005):
        key = (record["pid"], record["kernel"], record["signature"])
        if key not in entries or record["cpu"] > entries[key]["cpu"]:
            entries[key] = record
    compiles = list(entries.values())
    compile_cpu, process_cpu, count = collections.Counter(), collections.Counter(), collections.Counter()
    for record in compiles:
        compile_cpu[roles.get(record["pid"], "?")] += record["cpu"]
    for record in records:
        if "role" in record:
            process_cpu[roles[record["pid"]]] += record["process cpu"]
            count[roles[record["pid"]]] += 1
    print(f"    {'process role':40s} {'n':>3s} {'CPU s':>7s} {'of it compiling':>16s}")
    for role, seconds in process_cpu.most_common():
        print(f"    {role[:40]:40s} {count[role]:3d} {seconds:7.1f} {compile_cpu[role]:16.1f}")
    figures = sorted((r for r in records if r.get("role", "").startswith("figure ")), key=lambda r: -r["process cpu"])
    if figures:
        print("    costliest figures (CPU s): " + ", ".join(f"{r['role'][7:]} {r['process cpu']:.2f}"
                                                          for r in figures[:5]))
    if not compiles:
        print("    compiled nothing")
        return
    own = [r for r in compiles if r["kernel"].startswith("idkit.")]
    helpers = [r for r in compiles if not r["kernel"].startswith("idkit.")]
    print(f"    compiled {len(own)} idkit specialisations, {sum(r['cpu'] for r in own):.1f} s CPU; "
          f"{len(helpers)} of numba's own helpers (per process, never cached), {sum(r['cpu'] for r in helpers):.1f} s")
    print(f"    {'CPU s':>6s}  {'process role':24s} kernel [signature]")
    for record in sorted(own, key=lambda r: -r["cpu"])[:top]:
        kernel = record["kernel"].removeprefix("idkit.").replace(".<locals>.", ":")
        signature = record["signature"]
        literal = signature.split(",")[0] if signature.startswith("(Literal") else ""
        print(f"    {record['cpu']:6.2f}  {roles.get(record['pid'], '?')[:24]:24s} {kernel} {literal}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="idkit report --quick (for trying the script)")
    parser.add_argument("--data", help="data folder of the report (default: the bundled data)")
    parser.add_argument("--top", type=int, default=25, help="compiles listed (costliest first)")
    options = parser.parse_args()
    print(f"{os.cpu_count()} CPUs; idkit report of this checkout ({ROOT})" + (" --quick" if options.quick else ""))
    with tempfile.TemporaryDirectory(prefix="idkit-bench-compiles-") as folder:
        folder = Path(folder)
        for name in ("cold", "warm"):
            found = run_report(folder / "cache", folder / f"report-{name}", folder / f"{name}.jsonl",
                               data=options.data, quick=options.quick)
            print_run(name, found, options.top)


if __name__ == "__main__":
    main()
