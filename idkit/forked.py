"""Run a call in a forked child process while the caller goes on; collect its value later.

idkit's heavy loops are compiled and run on all cores, but some steps are plain Python
holding the interpreter lock (an optimiser driving a compiled objective, matplotlib
laying out and rasterising a figure). :func:`fork_call` runs such a step in a child made
by ``os.fork`` -- the child shares the caller's loaded modules, compiled functions and
data at no cost -- and :meth:`Forked.result` returns what the call returned (sent back
pickled through a pipe) or raises what it raised. The child never touches the caller's
state and leaves with ``os._exit``.

Forking is safe only when the caller runs a single Python thread (another thread may
hold a lock the child would wait on forever), so where that does not hold -- on a system
without ``fork``, or when the system refuses a new process -- the call runs in the caller
instead, when its result is asked for: the same value, without the overlap
(:func:`can_fork`).
"""

from __future__ import annotations

import gc
import os
import pickle
import sys
import threading
import traceback

from idkit.errors import IdkitError

__all__ = ["Forked", "can_fork", "fork_call"]


def can_fork() -> bool:
    """True on a system with ``os.fork`` when the calling process runs one Python thread."""
    return hasattr(os, "fork") and threading.active_count() == 1


class Forked:
    """A call started by :func:`fork_call`; :meth:`result` waits for it (once)."""

    def __init__(self, function, args: tuple, kwargs: dict):
        self._call = (function, args, kwargs)
        self._pid: int | None = None
        self._reader: int | None = None
        self._done = False
        self._value = None
        if can_fork():
            try:
                self._start()
            except OSError:  # no process to be had (limits, memory): run it in the caller instead
                self._pid = None

    @property
    def forked(self) -> bool:
        """Whether the call runs in a child process (else it runs in :meth:`result`)."""
        return self._pid is not None

    def _start(self) -> None:
        reader, writer = os.pipe()
        sys.stdout.flush()
        sys.stderr.flush()
        try:
            pid = os.fork()
        except OSError:
            os.close(reader)
            os.close(writer)
            raise
        if pid == 0:  # the child: run, send the outcome, leave without the caller's exit handlers
            os.close(reader)
            # the inherited objects stay alive (the caller holds them): left out of the child's
            # garbage collections, which would otherwise walk them all and copy every page they
            # sit on (a heavy report figure renders about 20 % faster, measured)
            gc.freeze()
            function, args, kwargs = self._call
            try:
                outcome = pickle.dumps(("value", function(*args, **kwargs)), protocol=pickle.HIGHEST_PROTOCOL)
            except BaseException as problem:  # noqa: BLE001 - sent to the caller, who raises it
                text = traceback.format_exc()
                try:
                    outcome = pickle.dumps(("error", problem, text), protocol=pickle.HIGHEST_PROTOCOL)
                except Exception:  # noqa: BLE001 - an exception that cannot be pickled: send its text
                    outcome = pickle.dumps(("error", None, text), protocol=pickle.HIGHEST_PROTOCOL)
            try:
                with os.fdopen(writer, "wb") as pipe:
                    pipe.write(outcome)
            finally:
                os._exit(0)
        os.close(writer)
        self._pid, self._reader = pid, reader

    def abandon(self) -> None:
        """Stop a child whose result will not be asked for (on an error of the caller)."""
        if self._pid is not None and not self._done:
            import signal

            try:
                os.kill(self._pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            os.waitpid(self._pid, 0)
            os.close(self._reader)
            self._done = True

    def result(self):
        """The call's return value; its exception is raised here (with the child's traceback as a note)."""
        if self._done:
            return self._value
        if self._pid is None:  # not forked: run it now, in the caller
            function, args, kwargs = self._call
            self._done = True
            self._value = function(*args, **kwargs)
            return self._value
        with os.fdopen(self._reader, "rb") as pipe:
            payload = pipe.read()
        _, status = os.waitpid(self._pid, 0)
        self._done = True
        name = getattr(self._call[0], "__qualname__", repr(self._call[0]))
        if not payload:
            raise IdkitError(f"{name}: the child process running it ended without a result "
                             f"(exit status {os.waitstatus_to_exitcode(status)})")
        outcome = pickle.loads(payload)
        if outcome[0] == "value":
            self._value = outcome[1]
            return self._value
        _, problem, text = outcome
        if problem is None:
            raise IdkitError(f"{name} failed in its child process:\n{text}")
        problem.add_note(f"raised in the child process running {name}:\n{text}")
        raise problem


def fork_call(function, /, *args, **kwargs) -> Forked:
    """Start ``function(*args, **kwargs)`` in a forked child (module docstring); returns a :class:`Forked`.

    The value and any exception must pickle. Where the caller cannot fork safely the call
    runs when :meth:`Forked.result` is called.

    Examples
    --------
    >>> call = fork_call(sum, [1, 2, 3])
    >>> call.result()
    6
    """
    return Forked(function, args, kwargs)
