"""idkit.forked: a call in a forked child gives what the call gives in the caller."""

import subprocess
import sys
import threading

import pytest

from idkit.forked import can_fork, fork_call

_SCRIPT = r'''
import time
import numpy as np
from idkit.forked import can_fork, fork_call
from idkit.errors import IdkitError

assert can_fork()


def draws(seed, n):
    return np.random.default_rng(seed).normal(size=n)


def fails(message):
    raise ValueError(message)


class Unpicklable(Exception):
    def __reduce__(self):
        raise TypeError("no")


def fails_oddly():
    raise Unpicklable("odd")


call = fork_call(draws, 7, n=200_000)  # 1.6 MB back through the pipe: larger than its buffer
assert call.forked
assert np.array_equal(call.result(), draws(7, 200_000))
assert np.array_equal(call.result(), draws(7, 200_000))  # asked twice: the same value
try:
    fork_call(fails, "bad value 42").result()
except ValueError as problem:
    assert "bad value 42" in str(problem)
    assert any("raised in the child process running fails" in note for note in problem.__notes__)
else:
    raise AssertionError("the child's exception was not raised")
try:
    fork_call(fails_oddly).result()
except IdkitError as problem:
    assert "fails_oddly failed in its child process" in str(problem) and "Unpicklable" in str(problem)
else:
    raise AssertionError("an exception that does not pickle was lost")
import os
slow = fork_call(time.sleep, 600)
pid = slow._pid
slow.abandon()  # killed and reaped: no such process any more
try:
    os.kill(pid, 0)
except ProcessLookupError:
    pass
else:
    raise AssertionError("the abandoned child is still there")
print("ok")
'''


def test_forked_calls_return_values_and_raise_exceptions_of_the_child():
    # a fresh interpreter: one Python thread, so it may fork (pytest-xdist workers run two)
    done = subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr


def test_with_another_thread_alive_the_call_runs_in_the_caller():
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert not can_fork()
        call = fork_call(sum, [1, 2, 3])
        assert not call.forked and call.result() == 6
        with pytest.raises(ZeroDivisionError):
            fork_call(divmod, 1, 0).result()
    finally:
        stop.set()
        thread.join()


def test_a_child_that_dies_without_a_result_is_reported():
    script = ("import os\nfrom idkit.forked import fork_call\nfrom idkit.errors import IdkitError\n"
              "try:\n    fork_call(os._exit, 3).result()\nexcept IdkitError as problem:\n    print(problem)\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert "ended without a result (exit status 3)" in done.stdout, done.stderr


def test_a_refused_fork_runs_the_call_in_the_caller(monkeypatch):
    import os

    import idkit.forked as forked

    def refuse():
        raise BlockingIOError(11, "Resource temporarily unavailable")

    monkeypatch.setattr(forked, "can_fork", lambda: True)
    monkeypatch.setattr(os, "fork", refuse)
    call = fork_call(sum, [4, 5])
    assert not call.forked and call.result() == 9



def test_the_child_leaves_the_inherited_objects_out_of_its_garbage_collections():
    """The child freezes what it inherits (alive in the caller anyway): its collections walk only
    what it makes, instead of touching, and so copying, every inherited page. The caller's
    objects are left as they were. A fresh interpreter, as above."""
    script = ("import gc\nfrom idkit.forked import fork_call\n"
              "before = gc.get_freeze_count()\n"
              "child = fork_call(gc.get_freeze_count).result()\n"
              "print(before, child > 0, gc.get_freeze_count())\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "0 True 0", done.stderr
