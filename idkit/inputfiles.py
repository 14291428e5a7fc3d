"""Strict reading of input files: bytes, UTF-8 text and JSON documents.

Shared by the measurement readers (:mod:`idkit.io`) and the model-file reader
(:mod:`idkit.models.modelfile`), so every input file obeys the same rules and every
problem is one of idkit's own errors naming the file, what was found and what was
expected (never an ``OSError``, ``UnicodeDecodeError`` or ``zlib.error`` traceback):

* a missing path, a folder, an unreadable file or anything that is not a regular file
  is refused before it is read (a FIFO or a device would block or never end);
* text is UTF-8; a UTF-8 byte-order mark is accepted, a UTF-16/32 one is named;
* JSON: a key given twice in one object is refused at any depth (Python's ``json`` keeps
  the last one silently); ``NaN``/``Infinity`` literals and numbers that overflow to
  infinity (``1e400``) are refused; nesting too deep for the parser is refused.

The error class is the caller's (:class:`~idkit.errors.DataError` for measurement files,
:class:`~idkit.errors.ModelFileError` for model files), and so is the label that opens
every message (``"file 'a.csv'"``, ``"manifest 'set/manifest.json'"``, ``"model file
'm.json'"``).
"""

from __future__ import annotations

import json
import math
import stat
from pathlib import Path

from idkit.errors import IdkitError

__all__ = ["decode_utf8", "load_json", "path_problem", "read_input_bytes"]

_UTF16_32_BOMS = ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"),
                  (b"\xff\xfe", "UTF-16"), (b"\xfe\xff", "UTF-16"))


def path_problem(path: Path, kind: str = "file") -> str | None:
    """Why ``path`` is not an existing entry of ``kind`` to read, in words (None when it is one).

    ``kind``: ``"file"`` (a regular file: a FIFO or a device would block or never end),
    ``"folder"``, or ``"any"`` (either). The one rule of :func:`read_input_bytes`, of a manifest's
    data files and of the :class:`idkit.checks.InputPath` arguments.
    """
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        return "not found"
    except NotADirectoryError:
        return "not found (a part of the path is a file, not a folder)"
    except OSError as exc:  # symlink loop, name too long, no permission on a parent folder
        return f"cannot be read ({exc.strerror or exc})"
    except ValueError as exc:  # an embedded NUL byte in the name
        return f"invalid path ({exc})"
    if kind == "folder" and not stat.S_ISDIR(mode):
        return "not a folder"
    if kind == "file" and stat.S_ISDIR(mode):
        return "is a folder, expected a file"
    if kind == "file" and not stat.S_ISREG(mode):
        return "not a regular file (a FIFO, socket or device), expected a file"
    return None


def read_input_bytes(path: str | Path, label: str, error: type[IdkitError]) -> bytes:
    """Read a whole input file, refusing anything but a readable regular file.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    label : str
        How messages name it, e.g. ``"model file 'm.json'"``.
    error : type
        The idkit error class to raise.

    Returns
    -------
    bytes
        The file's content (never modified).

    Raises
    ------
    error
        Not found, a folder, not a regular file, not readable (:func:`path_problem`).
    """
    path = Path(path)
    problem = path_problem(path, "file")
    if problem is not None:
        raise error(f"{label}: {problem}")
    try:
        return path.read_bytes()
    except OSError as exc:  # PermissionError, EIO, ...
        raise error(f"{label}: cannot be read ({exc.strerror or exc})") from None


def decode_utf8(raw: bytes, label: str, error: type[IdkitError]) -> str:
    """Decode UTF-8 text (a leading UTF-8 byte-order mark is dropped).

    Raises
    ------
    error
        Naming the first bad byte (0-based offset), or a UTF-16/32 byte-order mark.
    """
    for bom, encoding in _UTF16_32_BOMS:
        if raw.startswith(bom):
            raise error(f"{label}: {encoding} text (byte-order mark {bom.hex(' ')}), "
                        "expected UTF-8 text")
    encoding = _wide_encoding(raw)
    if encoding is not None:
        raise error(f"{label}: not UTF-8 text (NUL bytes between the first characters: {encoding} "
                    "without a byte-order mark), expected UTF-8 text")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(f"{label}: not UTF-8 text (byte {exc.start}: {exc.reason}; found "
                    f"{raw[exc.start:exc.start + 1]!r}), expected UTF-8 text") from None


def _wide_encoding(raw: bytes) -> str | None:
    """``"UTF-16-LE"`` etc. when the first characters of ``raw`` are ASCII text stored in two
    or four bytes each (NUL bytes in the pattern of UTF-16/32 without byte-order mark), else
    None. Only the first 64 bytes are looked at; a NUL byte elsewhere is left to the parsers,
    which name its row and column."""
    head = raw[:64]
    if b"\x00" not in head or len(head) < 4:
        return None
    units = len(head) // 4 * 4
    if units and not head[1:units:4].strip(b"\x00") and not head[2:units:4].strip(b"\x00") \
            and not head[3:units:4].strip(b"\x00") and b"\x00" not in head[0:units:4]:
        return "UTF-32-LE"
    if units and not head[0:units:4].strip(b"\x00") and not head[1:units:4].strip(b"\x00") \
            and not head[2:units:4].strip(b"\x00") and b"\x00" not in head[3:units:4]:
        return "UTF-32-BE"
    pairs = len(head) // 2 * 2
    if not head[1:pairs:2].strip(b"\x00") and b"\x00" not in head[0:pairs:2]:
        return "UTF-16-LE"
    if not head[0:pairs:2].strip(b"\x00") and b"\x00" not in head[1:pairs:2]:
        return "UTF-16-BE"
    return None


class _Bad:
    """Stands in for a refused number while parsing; located by key path afterwards."""

    def __init__(self, problem: str) -> None:
        self.problem = problem


class _DuplicateKeys(dict):
    """An object that had a key twice (the problem is reported with its key path)."""

    problem = ""


def _refuse_constant(token: str) -> _Bad:
    return _Bad(f"found the non-finite number {token}, expected a finite number (NaN and "
                "Infinity are not JSON numbers)")


def _finite_float(token: str) -> float | _Bad:
    value = float(token)
    if not math.isfinite(value):
        return _Bad(f"found the number {token}, which overflows to infinity; expected a "
                    "finite number")
    return value


def _bounded_int(token: str) -> int | _Bad:
    value = int(token)
    try:
        float(value)
    except OverflowError:
        return _Bad(f"found an integer of {len(token)} digits, expected a number within the "
                    "range of a double")
    return value


def _unique_keys(pairs: list[tuple[str, object]]) -> dict:
    document: dict = {}
    for key, value in pairs:
        if key in document:
            marked = _DuplicateKeys(document)
            marked.problem = (f"key {key!r} given twice in one object: found "
                              f"{document[key]!r:.60} and {value!r:.60}; expected each key once "
                              "(idkit never picks one silently)")
            return marked
        document[key] = value
    return document


def _first_problem(document: object) -> str | None:
    """The first refused value or duplicated key in document order, with its key path."""
    stack: list[tuple[str, object]] = [("", document)]
    while stack:
        path, value = stack.pop()
        where = f"at {path}{' (list positions 0-based)' if '[' in path else ''}: " if path else ""
        if isinstance(value, _Bad):
            return where + value.problem
        if isinstance(value, _DuplicateKeys):
            return where + value.problem
        if isinstance(value, dict):
            stack.extend((f"{path}.{key}" if path else str(key), item)
                         for key, item in reversed(value.items()))
        elif isinstance(value, list):
            stack.extend((f"{path}[{index}]", item)
                         for index, item in reversed(list(enumerate(value))))
    return None


def load_json(raw: bytes, label: str, error: type[IdkitError], *, expected: str) -> object:
    """Parse a JSON document strictly (see module docstring).

    Parameters
    ----------
    raw : bytes
        The file's bytes.
    label : str
        How messages name the file.
    error : type
        The idkit error class to raise.
    expected : str
        What the document should be, for the empty-file message (e.g. ``"a JSON object
        with a 'measurements' list"``).

    Returns
    -------
    object
        The document (objects as dicts in file order).
    """
    text = decode_utf8(raw, label, error)
    if not text.strip():
        raise error(f"{label}: empty file, expected {expected}")
    try:
        document = json.loads(text, object_pairs_hook=_unique_keys,
                              parse_constant=_refuse_constant, parse_float=_finite_float,
                              parse_int=_bounded_int)
    except json.JSONDecodeError as exc:
        raise error(f"{label}: invalid JSON at line {exc.lineno}, column {exc.colno}: "
                    f"{exc.msg}") from None
    except RecursionError:
        raise error(f"{label}: JSON nested too deeply, expected {expected}") from None
    except ValueError as exc:  # e.g. an integer with more digits than Python converts
        raise error(f"{label}: invalid JSON: {exc}") from None
    problem = _first_problem(document)
    if problem is not None:
        raise error(f"{label}: {problem}")
    return document
