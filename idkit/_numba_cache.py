"""Where and how numba caches idkit's compiled kernels (imported by every module that caches).

Two things are installed on import, before any kernel is decorated:

**A per-user cache folder, shared across environments** (:class:`PackageCacheLocator`). numba's
own locators keep a function's machine code in the ``__pycache__`` beside its source file, which
for an installed package is inside ``site-packages/idkit/``, and key it by that file's path:
every virtual environment and every reinstall compiles again, and the files left there outlive
an uninstall. idkit's kernels are cached instead in :func:`cache_root`:

- ``IDKIT_CACHE_DIR`` when set (not empty);
- else ``NUMBA_CACHE_DIR/idkit`` when numba's own cache folder is set (``NUMBA_CACHE_DIR`` or
  numba's configuration file), so one setting moves every compiled file of a machine;
- else the platform's per-user cache folder: ``$XDG_CACHE_HOME/idkit`` (default
  ``~/.cache/idkit``) on Linux and other POSIX systems, ``~/Library/Caches/idkit`` on macOS,
  ``%LOCALAPPDATA%\\idkit\\Cache`` on Windows.

Below it, :func:`build_key` names one folder per idkit version, content of the kernel sources,
numba version, Python version and CPU (its name and an 8-digit hash of the target triple,
name and features numba compiles for), and each module caches in a subfolder named after it
(``idkit.simulate._kernel``). The folder is named by content, not by the path or the time of
the source files, so a second environment with the same idkit, numba, Python and CPU loads
every kernel and compiles nothing, while a changed kernel source, another numba or another CPU
never meets a stale entry. The content hash covers every idkit module that mentions numba,
not only the file defining a function: a compiled driver holds the machine code of the steps
it calls from other modules, which numba's per-file check misses. A module-level constant read
by a kernel from a module that does not mention numba is frozen into the machine code too
(numba's rule for globals); after editing such a constant, delete the cache folder.

If the folder cannot be created or written, a :class:`RuntimeWarning` says so once, and the
kernels are cached for the running process in a temporary folder removed at exit (every new
process compiles again; nothing is written inside the package). Where no temporary folder can
be made either, numba's own locators decide.

**Process-safe writes** (:func:`locked_save`). numba keeps the compiled functions of one Python
function in an index file, which maps each compiled signature (for a closure kernel also the
values it closes over: one driver per system structure) to a numbered data file holding its
machine code. Adding an entry reads the index, takes the first free number, writes the index
and then the data. Two processes that add different entries to the same index at the same
moment (pytest-xdist workers, the report's forked children on a cold cache, a user's process
pool, two environments sharing the folder) can both take the same number: one entry then names
the other's machine code, which every later process loads and runs for it (wrong numbers or a
crash; numba issue #4807). The save of every cached function takes an exclusive ``flock`` on a
file beside its index, reads the index inside the lock, and writes the data before the index, so
that an index entry always names data written for that entry. A save that fails (a full
disk, a file-size limit) warns and leaves the cache as it was: the compiled code is kept in
memory, and the command goes on to fail, if at all, on its own outputs, whose errors name them.
Loading is unchanged (numba replaces both files atomically). Where ``fcntl`` is missing (Windows) or a numba version lacks
the methods used, numba's own save is left in place and :data:`INSTALLED` says so.

**Each entry compiled once** (:func:`load_or_claim`, :func:`compile_once`). Two processes that
need the same missing entry at the same moment (the report's forked workers on an empty cache)
would both compile it, the same machine code twice. A process that misses an entry of an idkit
kernel takes an exclusive ``flock`` on a claim file named by the entry's index key (beside the
index; one file per compiled signature and closure, so different entries still compile in
parallel) and looks in the cache again: a process that compiled the entry meanwhile has saved
it, and it is loaded; else this process compiles it and releases the claim when its compile
returns or fails. A process waiting for a claim holds claims only on the functions it is
compiling that call the awaited one, so two processes cannot wait on each other (kernels do not
call each other in a cycle).
"""

from __future__ import annotations

import atexit
import functools
import hashlib
import itertools
import os
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

import numba
from numba.core import caching, config
from numba.core.registry import CPUDispatcher

try:
    import fcntl
except ImportError:  # not POSIX
    fcntl = None

__all__ = [
    "CACHE_DIR_VARIABLE",
    "INSTALLED",
    "PackageCacheLocator",
    "build_key",
    "cache_package",
    "cache_root",
    "compile_once",
    "install",
    "kernel_folder",
    "load_or_claim",
    "locked_save",
    "usable_folder",
]

CACHE_DIR_VARIABLE = "IDKIT_CACHE_DIR"
"""Environment variable naming the folder that holds idkit's compiled kernels."""

_NEEDED = ("_load_index", "_save_index", "_save_data", "_data_name")
_NUMBA_SAVE = caching.IndexDataCacheFile.save
_NUMBA_LOAD_OVERLOAD = caching.Cache.load_overload
_NUMBA_COMPILE = CPUDispatcher.compile
_CLAIMS: dict[tuple[int, str], object] = {}  # (id of a Cache, repr of a signature) -> the open, locked claim file
_PACKAGES: dict[str, Path] = {}  # top-level package name -> its source folder


def locked_save(self, key, data) -> None:
    """:meth:`numba.core.caching.IndexDataCacheFile.save` under an exclusive lock (module docstring)."""
    try:
        lock = open(self._index_path + ".lock", "ab")  # noqa: SIM115 - held for the block below
    except OSError:  # the lock cannot be made where numba could still write: its own save
        _NUMBA_SAVE(self, key, data)
        return
    with lock:
        fcntl.flock(lock.fileno(), fcntl.LOCK_EX)  # released when the file closes
        overloads = self._load_index()
        name = overloads.get(key)
        if name is None:
            taken = set(overloads.values())
            name = next(candidate for candidate in map(self._data_name, itertools.count(1))
                        if candidate not in taken)
            overloads[key] = name
        try:
            self._save_data(name, data)  # first: an index entry never names data not yet written
            self._save_index(overloads)
        except OSError as problem:  # a full disk or a file-size limit: the cache is not an output
            warnings.warn(f"numba cache not written ({problem.strerror or problem}, in "
                          f"{Path(self._index_path).parent}); the compiled code is used from memory and "
                          "compiled again by the next run", RuntimeWarning, stacklevel=2)


def load_or_claim(self, sig, target_context):
    """:meth:`numba.core.caching.Cache.load_overload`; on a miss of an idkit kernel, the entry's
    compile claim is taken (waiting while another process holds it) and the cache looked at again
    (module docstring). Returns the loaded entry, or None: then this process holds the claim until
    :func:`compile_once` returns."""
    data = _NUMBA_LOAD_OVERLOAD(self, sig, target_context)
    if data is not None or not getattr(self, "_enabled", False) \
            or not isinstance(getattr(self._impl, "locator", None), PackageCacheLocator):
        return data
    key = self._index_key(sig, target_context.codegen())
    claim_path = f"{self._cache_file._index_path}.{hashlib.sha256(repr(key).encode()).hexdigest()[:16]}.claim"
    try:
        claim = open(claim_path, "ab")  # noqa: SIM115 - held until the compile returns (compile_once)
    except OSError:  # cannot be made where the cache could still be read: compile unclaimed
        return None
    fcntl.flock(claim.fileno(), fcntl.LOCK_EX)  # waits while another process compiles this entry
    data = _NUMBA_LOAD_OVERLOAD(self, sig, target_context)
    if data is not None:
        claim.close()
        return data
    previous = _CLAIMS.pop((id(self), repr(sig)), None)
    if previous is not None:  # a compile that never returned through compile_once
        previous.close()
    _CLAIMS[(id(self), repr(sig))] = claim
    return None


def compile_once(self, sig):
    """:meth:`numba.core.registry.CPUDispatcher.compile`, releasing the compile claim
    :func:`load_or_claim` took for ``sig`` when it returns or raises."""
    try:
        return _NUMBA_COMPILE(self, sig)
    finally:
        claim = _CLAIMS.pop((id(self._cache), repr(sig)), None)
        if claim is not None:
            claim.close()


def _platform_cache_root(environ, platform: str, home: Path) -> Path:
    """The per-user cache folder of idkit by the platform's convention (module docstring)."""
    if platform == "win32":
        local = environ.get("LOCALAPPDATA") or str(home / "AppData" / "Local")
        return Path(local) / "idkit" / "Cache"
    if platform == "darwin":
        return home / "Library" / "Caches" / "idkit"
    xdg = environ.get("XDG_CACHE_HOME", "")
    base = Path(xdg) if os.path.isabs(xdg) else home / ".cache"  # XDG: a relative value is ignored
    return base / "idkit"


def cache_root() -> Path:
    """The folder holding idkit's compiled kernels: ``IDKIT_CACHE_DIR``, else
    ``NUMBA_CACHE_DIR/idkit``, else the platform's per-user cache folder (module docstring).

    Returns
    -------
    pathlib.Path
        An absolute path; it may not exist yet.
    """
    chosen = os.environ.get(CACHE_DIR_VARIABLE, "")
    if chosen:
        return Path(os.path.abspath(os.path.expanduser(chosen)))
    if config.CACHE_DIR:
        return Path(os.path.abspath(os.path.expanduser(config.CACHE_DIR))) / "idkit"
    return _platform_cache_root(os.environ, sys.platform, Path.home())


def _cpu_tag() -> str:
    """The CPU numba compiles for: its name and a hash of triple, name and features (numba's
    ``NUMBA_CPU_NAME`` / ``NUMBA_CPU_FEATURES`` included), as numba's own index key does."""
    import llvmlite.binding as llvm
    from numba.core.codegen import get_host_cpu_features

    name = config.CPU_NAME or llvm.get_host_cpu_name()
    features = config.CPU_FEATURES if config.CPU_FEATURES is not None else get_host_cpu_features()
    digest = hashlib.sha256(repr((llvm.get_process_triple(), name, features)).encode()).hexdigest()
    safe_name = "".join(c if c.isalnum() or c in "-_." else "_" for c in name)
    return f"{safe_name}-{digest[:8]}"


def _sources_digest(folder: Path) -> str:
    """sha256 of every ``.py`` file below ``folder`` that mentions numba (relative path and
    content, in path order): what a change of any kernel, or of a compiled function a kernel
    calls, changes."""
    digest = hashlib.sha256()
    for path in sorted(folder.rglob("*.py")):
        content = path.read_bytes()
        if b"numba" in content:
            digest.update(path.relative_to(folder).as_posix().encode() + b"\0")
            digest.update(hashlib.sha256(content).digest())
    return digest.hexdigest()


@functools.cache
def build_key(package: str) -> str:
    """Name of the cache folder of ``package``'s kernels on this machine: the package version,
    a hash of its kernel sources, the numba and Python versions and the CPU.

    Two environments with the same package, numba, Python and CPU get the same key; anything
    else that changes machine code gives another.
    """
    release = getattr(sys.modules.get(package), "__version__", "0+unknown")
    sources = _sources_digest(_PACKAGES[package])[:16]
    python = f"py{sys.version_info[0]}{sys.version_info[1]}{getattr(sys, 'abiflags', '')}"
    return f"{package}-{release}-{sources}_numba-{numba.__version__}-{python}_{_cpu_tag()}"


def _writable(folder: Path) -> OSError | None:
    """Create ``folder`` and a probe file in it; the error if that fails, else None."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError as error:
        return error
    return None


@functools.cache
def _process_folder() -> Path | None:
    """A temporary folder for this process's kernels, removed at exit by the process that made
    it (forked children share it and leave it); None where none can be made."""
    try:
        folder = Path(tempfile.mkdtemp(prefix="idkit-numba-"))
    except OSError:
        return None
    owner = os.getpid()

    def remove() -> None:
        if os.getpid() == owner:
            shutil.rmtree(folder, ignore_errors=True)

    atexit.register(remove)
    return folder


@functools.cache
def kernel_folder(package: str = "idkit") -> Path | None:
    """The folder ``package``'s modules cache their kernels in: ``cache_root() / build_key()``
    if it can be written, else a temporary folder of this process (:func:`usable_folder`)."""
    return usable_folder(cache_root() / build_key(package))


def usable_folder(folder: Path) -> Path | None:
    """``folder`` if it can be created and written; else, with a :class:`RuntimeWarning` naming
    it and the reason, a temporary folder of this process (None if none can be made: numba's
    own locators then decide)."""
    error = _writable(folder)
    if error is None:
        return folder
    warnings.warn(
        f"idkit cannot write its compiled-kernel cache {str(folder)!r} ({error.strerror or error}); "
        f"kernels are compiled again in every process. Set {CACHE_DIR_VARIABLE} to a writable folder.",
        RuntimeWarning, stacklevel=2)
    return _process_folder()


class PackageCacheLocator(caching._CacheLocator):
    """numba cache locator for the functions of a registered package (:func:`cache_package`):
    ``kernel_folder(package) / module name``, stamped by the content hash of the build key
    instead of a file's modification time (installers do not keep modification times)."""

    def __init__(self, py_func, py_file, folder: Path, stamp: str):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._cache_path = str(folder / py_func.__module__)
        self._stamp = stamp

    def get_cache_path(self) -> str:
        return self._cache_path

    def get_source_stamp(self) -> str:
        return self._stamp

    def get_disambiguator(self) -> str:
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func, py_file):
        package = (getattr(py_func, "__module__", None) or "").partition(".")[0]
        if package not in _PACKAGES:
            return None
        folder = kernel_folder(package)
        if folder is None:
            return None
        self = cls(py_func, py_file, folder, folder.name)
        try:
            self.ensure_cache_path()
        except OSError:  # removed or made read-only since kernel_folder checked it
            return None
        return self


def cache_package(package: str, source_folder: Path | str) -> None:
    """Cache the compiled functions of the top-level ``package`` (source files in
    ``source_folder``) with :class:`PackageCacheLocator`. idkit registers itself on import."""
    _PACKAGES[package] = Path(source_folder)


def install() -> bool:
    """Put :class:`PackageCacheLocator` first among numba's locators, replace numba's cache save by
    :func:`locked_save` and its load and compile by :func:`load_or_claim` and :func:`compile_once`
    (idempotent); whether the locked save is in place."""
    if PackageCacheLocator not in caching.CacheImpl._locator_classes:
        caching.CacheImpl._locator_classes = [PackageCacheLocator, *caching.CacheImpl._locator_classes]
    if fcntl is None or not all(hasattr(caching.IndexDataCacheFile, name) for name in _NEEDED):
        return False
    caching.IndexDataCacheFile.save = locked_save
    if hasattr(caching.Cache, "_index_key"):  # the claim is named by numba's index key
        caching.Cache.load_overload = load_or_claim
        CPUDispatcher.compile = compile_once
    return True


cache_package("idkit", Path(__file__).resolve().parent)
INSTALLED = install()
