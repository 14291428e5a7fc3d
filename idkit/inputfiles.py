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

__all__ = ["decode_utf8", "load_json", "read_input_bytes"]

_UTF16_32_BOMS = ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"),
                  (b"\xff\xfe", "UTF-16"), (b"\xfe\xff", "UTF-16"))


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
        Not found, a folder, not a regular file, not readable.
    """
    path = Path(path)
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        raise error(f"{label}: not found") from None
    except NotADirectoryError:
        raise error(f"{label}: not found (a part of the path is a file, not a folder)") from None
    except OSError as exc:  # symlink loop, name too long, no permission on a parent folder
        raise error(f"{label}: cannot be read ({exc.strerror or exc})") from None
    except ValueError as exc:  # an embedded NUL byte in the name
        raise error(f"{label}: invalid path ({exc})") from None
    if stat.S_ISDIR(mode):
        raise error(f"{label}: is a folder, expected a file") from None
    if not stat.S_ISREG(mode):
        raise error(f"{label}: not a regular file (a FIFO, socket or device), expected a file")
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
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(f"{label}: not UTF-8 text (byte {exc.start}: {exc.reason}; found "
                    f"{raw[exc.start:exc.start + 1]!r}), expected UTF-8 text") from None


class _Refused(ValueError):
    """Raised by the JSON hooks; turned into the caller's error class."""


def _refuse_constant(token: str) -> float:
    raise _Refused(f"invalid JSON: found the non-finite number {token}, expected a finite "
                   "number (NaN and Infinity are not JSON numbers)")


def _finite_float(token: str) -> float:
    value = float(token)
    if not math.isfinite(value):
        raise _Refused(f"found the number {token}, which overflows to infinity; expected a "
                       "finite number")
    return value


def _bounded_int(token: str) -> int:
    value = int(token)
    try:
        float(value)
    except OverflowError:
        raise _Refused(f"found the integer {token[:20]}... ({len(token)} digits), expected a "
                       "number within the range of a double") from None
    return value


def _unique_keys(pairs: list[tuple[str, object]]) -> dict:
    document: dict = {}
    for key, value in pairs:
        if key in document:
            context = ""
            for name in ("id", "kind"):
                if isinstance(document.get(name), str):
                    context = f" (in the object with {name} {document[name]!r})"
                    break
            raise _Refused(f"key {key!r} given twice in one object{context}: found "
                           f"{document[key]!r} and {value!r}; expected each key once "
                           "(idkit never picks one silently)")
        document[key] = value
    return document


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
        return json.loads(text, object_pairs_hook=_unique_keys, parse_constant=_refuse_constant,
                          parse_float=_finite_float, parse_int=_bounded_int)
    except json.JSONDecodeError as exc:
        raise error(f"{label}: invalid JSON at line {exc.lineno}, column {exc.colno}: "
                    f"{exc.msg}") from None
    except _Refused as exc:
        raise error(f"{label}: {exc}") from None
    except RecursionError:
        raise error(f"{label}: JSON nested too deeply, expected {expected}") from None
    except ValueError as exc:  # e.g. an integer with more digits than Python converts
        raise error(f"{label}: invalid JSON: {exc}") from None
