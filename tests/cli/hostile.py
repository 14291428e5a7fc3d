"""Harness of the hostile-input corpus: run the real CLI entry point on one case and judge it.

Every case goes through :func:`idkit.cli.main.main` exactly as a user's command line
would, with its standard streams captured, and is judged on what a user sees:

* ``status``: the exit status (argparse usage errors raise ``SystemExit(2)``);
* ``crashed``: an exception escaped ``main`` (a traceback instead of idkit's error);
* ``hung``: the case ran past its time limit (``SIGALRM`` interrupts Python code);
* ``changed``: input files whose bytes changed, or which vanished, during the case;
* ``partial``: files or folders left where the case should have written nothing
  (the output path itself after a refusal, ``.*.partial*``/``.*.tmp`` staging leftovers).

A test states the expected ``kind`` of outcome (``"error"``: exit 2 with the words a
message must contain; ``"flagged"``: a result written but a non-zero status that says
why; ``"ok"``: accepted) and asserts it with :func:`check`. When the environment
variable ``IDKIT_CORPUS_LOG`` names a file, each judged case appends one JSON line
there (for the counts of the closing note: ``python tests/cli/hostile.py LOG``).
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import signal
import sys
import traceback
from dataclasses import dataclass, field
from pathlib import Path

from idkit.cli.main import main

STAGING_MARKERS = (".partial", ".tmp", ".old.")


class _Hang(Exception):
    pass


def _hashes(paths) -> dict[str, str]:
    found = {}
    for root in paths:
        root = Path(root)
        files = [root] if root.is_file() else sorted(p for p in root.rglob("*") if p.is_file()) if root.exists() else []
        for path in files:
            found[str(path)] = hashlib.sha256(path.read_bytes()).hexdigest()
    return found


def _staging_leftovers(folders) -> list[str]:
    left = []
    for folder in folders:
        folder = Path(folder)
        if folder.is_dir():
            left.extend(str(p) for p in folder.iterdir()
                        if p.name.startswith(".") and any(m in p.name for m in STAGING_MARKERS))
    return left


@dataclass
class Outcome:
    argv: list[str]
    status: int | None
    stdout: str
    stderr: str
    crashed: bool = False
    hung: bool = False
    changed: list[str] = field(default_factory=list)
    partial: list[str] = field(default_factory=list)


def run_main(argv, *, inputs=(), must_not_exist=(), watch=(), timeout_s: float = 120.0) -> Outcome:
    """Run ``idkit argv`` in-process and collect what a user would see.

    ``inputs``: files or folders whose bytes must not change. ``must_not_exist``: paths
    that a refused case must not create. ``watch``: folders searched for staging leftovers.
    """
    argv = [str(a) for a in argv]
    before = _hashes(inputs)
    out, err = io.StringIO(), io.StringIO()
    status, crashed, hung = None, False, False

    def alarm(signum, frame):
        raise _Hang()

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout_s)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(argv)
            except SystemExit as stop:
                status = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 2)
    except _Hang:
        hung = True
    except Exception:  # noqa: BLE001 - a crash is exactly what the corpus looks for
        crashed = True
        err.write(traceback.format_exc())
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    after = _hashes(inputs)
    changed = sorted(p for p in before if before[p] != after.get(p))
    partial = [str(p) for p in must_not_exist if Path(p).exists()] + _staging_leftovers(watch)
    return Outcome(argv, status, out.getvalue(), err.getvalue(), crashed, hung, changed, partial)


def check(outcome: Outcome, kind: str, words=(), *, case: str = "") -> None:
    """Assert the expected outcome; log it for the corpus counts."""
    _log(outcome, kind, case)
    text = outcome.stderr + outcome.stdout
    assert not outcome.crashed, f"crash: {outcome.stderr[-2000:]}"
    assert not outcome.hung, "hang"
    assert "Traceback" not in outcome.stderr, outcome.stderr[-2000:]
    assert not outcome.changed, f"inputs modified: {outcome.changed}"
    assert not outcome.partial, f"partial outputs left: {outcome.partial}"
    if kind == "error":
        assert outcome.status == 2, f"expected exit 2, got {outcome.status}: {text[-1500:]}"
        assert "idkit" in outcome.stderr and "error" in outcome.stderr, outcome.stderr
    elif kind == "flagged":
        assert outcome.status not in (0, 2, None), f"expected a flagged non-zero status, got {outcome.status}"
    elif kind == "ok":
        assert outcome.status == 0, f"expected exit 0, got {outcome.status}: {text[-1500:]}"
    else:
        raise ValueError(f"kind: found {kind!r}, expected 'error', 'flagged' or 'ok'")
    for word in words:
        assert word.lower() in text.lower(), f"{word!r} not in: {text[-1500:]}"


def _log(outcome: Outcome, kind: str, case: str) -> None:
    log = os.environ.get("IDKIT_CORPUS_LOG")
    if not log:
        return
    record = {"case": case or " ".join(outcome.argv), "expected": kind, "status": outcome.status,
              "crashed": outcome.crashed, "hung": outcome.hung, "changed": bool(outcome.changed),
              "partial": bool(outcome.partial)}
    with open(log, "a", encoding="utf-8") as handle:
        handle.write(json.dumps(record) + "\n")


def summarise(log: str | Path) -> dict[str, int]:
    """Counts of a corpus log: cases, clear errors, flagged, crashes, hangs, silent, modified, partial."""
    records = [json.loads(line) for line in Path(log).read_text(encoding="utf-8").splitlines() if line.strip()]
    return {
        "cases": len(records),
        "clear errors": sum(r["expected"] == "error" and r["status"] == 2 for r in records),
        "flagged results": sum(r["expected"] == "flagged" and r["status"] not in (0, 2, None) for r in records),
        "accepted valid inputs": sum(r["expected"] == "ok" and r["status"] == 0 for r in records),
        "crashes": sum(r["crashed"] for r in records),
        "hangs": sum(r["hung"] for r in records),
        "silent acceptances": sum(r["expected"] != "ok" and r["status"] == 0 for r in records),
        "modified inputs": sum(r["changed"] for r in records),
        "partial outputs": sum(r["partial"] for r in records),
    }


if __name__ == "__main__":
    print(json.dumps(summarise(sys.argv[1]), indent=1))
