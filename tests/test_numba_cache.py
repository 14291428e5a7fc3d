"""numba's on-disk cache of idkit's kernels (:mod:`idkit._numba_cache`): process-safe writes, a
per-user folder outside the package shared by environments with the same sources."""

import os
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import pytest
from numba.core import caching
from numba.core.registry import CPUDispatcher as Dispatcher

import idkit
from idkit import _numba_cache


def _two_writers_interleaved(tmp_path, save, *, locked):
    """Two cache-file objects on one index add different entries; the first is held just after
    reading the index (where numba's own save is open to the race) while the second saves: to
    its end with numba's save, or (``locked``) it waits for the first's lock, which the test
    checks. Returns what each key loads back. No outcome depends on timing."""
    files = [caching.IndexDataCacheFile(str(tmp_path), "kernel-1.py311", ("stamp", 1)) for _ in range(2)]
    has_read, go_on = threading.Event(), threading.Event()
    read_index = files[0]._load_index

    def read_then_wait():
        overloads = read_index()
        has_read.set()
        go_on.wait(timeout=5.0)
        return overloads

    files[0]._load_index = read_then_wait
    first = threading.Thread(target=save, args=(files[0], "structure A", "machine code A"))
    first.start()
    assert has_read.wait(timeout=5.0)
    second = threading.Thread(target=save, args=(files[1], "structure B", "machine code B"))
    second.start()
    if locked:
        second.join(timeout=0.2)
        assert second.is_alive()  # blocked on the first writer's lock, whatever the machine's speed
    else:
        second.join()  # numba's save runs to its end between the first's read and its write
    go_on.set()
    first.join(timeout=10.0)
    second.join(timeout=10.0)
    reader = caching.IndexDataCacheFile(str(tmp_path), "kernel-1.py311", ("stamp", 1))
    return reader.load("structure A"), reader.load("structure B")


@pytest.mark.skipif(not _numba_cache.INSTALLED, reason="no fcntl or another numba: numba's own save is used")
def test_two_processes_adding_entries_at_once_keep_each_its_own_code(tmp_path):
    """numba's save reads the index, takes the first free data-file number and writes: two
    writers between one's read and its write both take number 1, and one entry then loads the
    other's machine code (a closure kernel of another structure: wrong numbers or a crash).
    Under the lock the second writer reads the index after the first wrote it."""
    assert caching.IndexDataCacheFile.save is _numba_cache.locked_save
    assert _two_writers_interleaved(tmp_path, _numba_cache.locked_save, locked=True) == ("machine code A", "machine code B")


@pytest.mark.skipif(not all(hasattr(caching.IndexDataCacheFile, name) for name in _numba_cache._NEEDED),
                    reason="another numba: the cache file's methods differ")
def test_numbas_own_save_is_open_to_the_race(tmp_path):
    """The same interleaving with numba's own save gives one entry the other's data: what the
    lock is for (if numba fixes its save, this test says so and the lock can go)."""
    loaded = _two_writers_interleaved(tmp_path, _numba_cache._NUMBA_SAVE, locked=False)
    assert loaded != ("machine code A", "machine code B")


# --- where the compiled kernels live ------------------------------------------------------

def test_kernel_cache_lies_outside_the_package_and_is_writable():
    """The installed package is never written at run time: idkit's kernels are cached in a
    per-user folder (module docstring of idkit._numba_cache), which accepts a new file."""
    package = Path(idkit.__file__).resolve().parent
    folder = _numba_cache.kernel_folder("idkit")
    assert folder is not None and folder.is_absolute()
    assert package not in folder.resolve().parents and folder.resolve() != package
    with tempfile.NamedTemporaryFile(dir=folder):
        pass
    from idkit.simulate import _kernel, _structured  # modules whose kernels are cached on disk

    for module in (_kernel, _structured):
        cached = [value for value in vars(module).values()
                  if isinstance(value, Dispatcher) and not isinstance(value._cache, caching.NullCache)]
        assert cached, f"{module.__name__} has no cached kernel to check"
        for dispatcher in cached:
            assert isinstance(dispatcher._cache._impl.locator, _numba_cache.PackageCacheLocator)
            assert Path(dispatcher._cache.cache_path) == folder / dispatcher.py_func.__module__


def test_environment_variable_chooses_the_folder(monkeypatch, tmp_path):
    """IDKIT_CACHE_DIR wins; else NUMBA_CACHE_DIR/idkit; else the platform's per-user folder."""
    monkeypatch.setattr(caching.config, "CACHE_DIR", str(tmp_path / "numba"))
    monkeypatch.setenv("IDKIT_CACHE_DIR", str(tmp_path / "mine"))
    assert _numba_cache.cache_root() == tmp_path / "mine"
    monkeypatch.setenv("IDKIT_CACHE_DIR", "")  # empty: unset
    assert _numba_cache.cache_root() == tmp_path / "numba" / "idkit"
    monkeypatch.setattr(caching.config, "CACHE_DIR", "")
    home = Path("/home/user")
    assert _numba_cache._platform_cache_root({}, "linux", home) == home / ".cache" / "idkit"
    assert _numba_cache._platform_cache_root({"XDG_CACHE_HOME": "/xdg"}, "linux", home) == Path("/xdg/idkit")
    assert _numba_cache._platform_cache_root({"XDG_CACHE_HOME": "rel"}, "linux", home) == home / ".cache" / "idkit"
    assert _numba_cache._platform_cache_root({}, "darwin", home) == home / "Library" / "Caches" / "idkit"
    assert (_numba_cache._platform_cache_root({"LOCALAPPDATA": r"C:\Users\u\AppData\Local"}, "win32", home)
            == Path(r"C:\Users\u\AppData\Local") / "idkit" / "Cache")


def test_a_folder_that_cannot_be_written_falls_back_with_a_warning(tmp_path):
    """Below a regular file nothing can be created (whatever the user's rights): the kernels go
    to a temporary folder of the process, outside the package, and a warning names the folder."""
    blocker = tmp_path / "a file"
    blocker.write_text("")
    with pytest.warns(RuntimeWarning, match="a file.*IDKIT_CACHE_DIR"):
        fallback = _numba_cache.usable_folder(blocker / "cache")
    assert fallback is not None and fallback.is_dir()
    assert Path(idkit.__file__).resolve().parent not in fallback.resolve().parents


_DEMO_KERNEL = '''import numba

SCALE = {scale}


@numba.njit(cache=True)
def scaled(x):
    return SCALE * x
'''

_IMPORT_AND_CALL = '''import sys
from idkit import _numba_cache

_numba_cache.cache_package("cachedemo", sys.argv[1] + "/cachedemo")
sys.path.insert(0, sys.argv[1])
from cachedemo.kernel import scaled

print(scaled(2.0), sum(scaled.stats.cache_hits.values()), sum(scaled.stats.cache_misses.values()),
      scaled._cache.cache_path)
'''


def _install_demo(folder: Path, scale: float, mtime: float) -> Path:
    """A tiny package with one cached kernel in ``folder`` (one "environment")."""
    package = folder / "cachedemo"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "kernel.py").write_text(_DEMO_KERNEL.format(scale=scale))
    for path in package.iterdir():
        os.utime(path, (mtime, mtime))
    return folder


def _import_and_call(environment: Path, cache: Path) -> tuple[float, int, int, str]:
    env = dict(os.environ, IDKIT_CACHE_DIR=str(cache))
    env.pop("NUMBA_CACHE_DIR", None)
    run = subprocess.run([sys.executable, "-c", _IMPORT_AND_CALL, str(environment)], env=env,
                         capture_output=True, text=True, check=True)
    value, hits, misses, path = run.stdout.split(maxsplit=3)
    return float(value), int(hits), int(misses), path.strip()


def test_two_environments_with_the_same_sources_share_the_compiled_code(tmp_path):
    """Two copies of a package at two paths with two modification times (two virtual
    environments, installed at two moments) load one compiled entry: the second process
    compiles nothing. A copy whose source differs gets its own entry and its own result."""
    cache = tmp_path / "cache"
    first = _install_demo(tmp_path / "venv-a", 3.0, mtime=1.0e9)
    second = _install_demo(tmp_path / "venv-b", 3.0, mtime=1.5e9)
    changed = _install_demo(tmp_path / "venv-c", 5.0, mtime=1.0e9)
    value_a, hits_a, misses_a, path_a = _import_and_call(first, cache)
    assert (value_a, hits_a, misses_a) == (6.0, 0, 1)  # empty cache: compiled
    value_b, hits_b, misses_b, path_b = _import_and_call(second, cache)
    assert (value_b, hits_b, misses_b) == (6.0, 1, 0)  # loaded: nothing compiled
    assert path_b == path_a and Path(path_a).parent.parent == cache
    value_c, hits_c, misses_c, path_c = _import_and_call(changed, cache)
    assert (value_c, hits_c, misses_c) == (10.0, 0, 1)  # other source: compiled, not the 6.0 kernel
    assert path_c != path_a


_COMPILE_SLOWLY = '''import os, sys, time
from idkit import _numba_cache

_numba_cache.cache_package("cachedemo", sys.argv[1] + "/cachedemo")
sys.path.insert(0, sys.argv[1])
from cachedemo.kernel import scaled

signals = sys.argv[2]
compile_for_real = scaled._compiler.compile


def slow_compile(*args, **kwargs):  # holds the claim until the other process is about to look
    open(os.path.join(signals, "claimed"), "w").close()
    while not os.path.exists(os.path.join(signals, "looking")):
        time.sleep(0.01)
    time.sleep(1.0)
    return compile_for_real(*args, **kwargs)


scaled._compiler.compile = slow_compile
print(scaled(2.0), sum(scaled.stats.cache_hits.values()), sum(scaled.stats.cache_misses.values()))
'''

_LOOK_AFTER_CLAIM = '''import os, sys, time
from idkit import _numba_cache

_numba_cache.cache_package("cachedemo", sys.argv[1] + "/cachedemo")
sys.path.insert(0, sys.argv[1])
from cachedemo.kernel import scaled

import numba

numba.njit(lambda x: x + 1.0)(1.0)  # numba's compiler set up first: the look below comes at once
signals = sys.argv[2]
while not os.path.exists(os.path.join(signals, "claimed")):
    time.sleep(0.01)
open(os.path.join(signals, "looking"), "w").close()
print(scaled(2.0), sum(scaled.stats.cache_hits.values()), sum(scaled.stats.cache_misses.values()))
'''


@pytest.mark.skipif(not _numba_cache.INSTALLED, reason="no fcntl or another numba: numba's own save is used")
def test_an_entry_another_process_is_compiling_is_waited_for_and_loaded(tmp_path):
    """Two processes need the same missing kernel at once (the report's workers on an empty
    cache): the first claims and compiles it, slowly; the second, looking while the first still
    compiles, waits for the claim and loads the entry instead of compiling it too (without the
    claim it finds the cache empty and compiles: one miss)."""
    environment = _install_demo(tmp_path / "venv", 3.0, mtime=1.0e9)
    signals = tmp_path / "signals"
    signals.mkdir()
    env = dict(os.environ, IDKIT_CACHE_DIR=str(tmp_path / "cache"))
    env.pop("NUMBA_CACHE_DIR", None)
    first = subprocess.Popen([sys.executable, "-c", _COMPILE_SLOWLY, str(environment), str(signals)], env=env,
                             stdout=subprocess.PIPE, text=True)
    second = subprocess.run([sys.executable, "-c", _LOOK_AFTER_CLAIM, str(environment), str(signals)], env=env,
                            capture_output=True, text=True, check=True, timeout=120)
    first_out, _ = first.communicate(timeout=120)
    assert first.returncode == 0
    assert first_out.split() == ["6.0", "0", "1"]  # compiled
    assert second.stdout.split() == ["6.0", "1", "0"]  # loaded what the first compiled


@pytest.mark.skipif(not _numba_cache.INSTALLED, reason="no fcntl or another numba: numba's own save is used")
def test_a_compile_that_fails_releases_its_claim(tmp_path, monkeypatch):
    """A compile that raises (here numba's typing error for a text argument) leaves no claim held:
    another process could otherwise wait for that entry until this one exits."""
    import fcntl

    import numba.core.errors

    package = tmp_path / "src" / "claimdemo"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "kernel.py").write_text("import numba\n\n\n@numba.njit(cache=True)\ndef half(x):\n    return x / 2.0\n")
    monkeypatch.setenv("IDKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setitem(_numba_cache._PACKAGES, "claimdemo", package)
    monkeypatch.syspath_prepend(str(tmp_path / "src"))
    try:
        from claimdemo.kernel import half

        with pytest.raises(numba.core.errors.TypingError):
            half("text")
        assert _numba_cache._CLAIMS == {}
        claims = list((tmp_path / "cache").rglob("*.claim"))
        assert len(claims) == 1  # the failed entry was claimed, and released:
        with open(claims[0], "ab") as claim:
            fcntl.flock(claim.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)  # raises BlockingIOError if still held
        assert half(4.0) == 2.0
    finally:
        for name in ("claimdemo.kernel", "claimdemo"):
            sys.modules.pop(name, None)
