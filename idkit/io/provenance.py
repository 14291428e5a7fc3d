"""Provenance of loaded data: source path, SHA-256 of the file bytes, original headers;
which measurements of a set an analysis used (:func:`select_measurements`, :class:`DataProvenance`)."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path


__all__ = ["Source", "file_sha256"]


def file_sha256(path: str | Path) -> str:
    """SHA-256 of a file's bytes as a hex string.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (read in binary mode, never modified).

    Returns
    -------
    str
        64 hex digits.
    """
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


@dataclass(frozen=True)
class Source:
    """Where a measurement came from.

    Parameters
    ----------
    path : pathlib.Path or None
        File the data were read from (``None`` for data built in memory).
    sha256 : str or None
        SHA-256 of the file's bytes as read (the parsed bytes are the hashed
        bytes: the file is read once).
    columns : dict of str to str
        Column name -> the column as the file declared it, e.g.
        ``{"force": "force [daN]"}`` or ``{"force": "x_F[:,2] [N]"}``.
    header_lines : int
        Lines above the first data row (1 for idkit CSV files; 0 for
        ``.mat`` files, whose samples have no line numbers).
    """

    path: Path | None = None
    sha256: str | None = None
    columns: tuple[tuple[str, str], ...] = ()
    header_lines: int = 0

    def column_label(self, name: str) -> str:
        """The column as declared in the file (falls back to ``name``)."""
        return dict(self.columns).get(name, name)

    def where(self, name: str | None = None) -> str:
        """Location prefix for messages: ``"file 'a.csv', column 'force [daN]'"``."""
        text = f"file '{self.path}'" if self.path is not None else "in-memory data"
        if name is not None:
            text += f", column '{self.column_label(name)}'"
        return text

    def row_label(self, index: int) -> str:
        """Describe the 0-based sample ``index`` as a 1-based data row.

        Parameters
        ----------
        index : int
            0-based sample index.

        Returns
        -------
        str
            ``"data row 5 (1-based, file line 6)"`` for CSV files,
            ``"sample 5 (1-based)"`` otherwise.
        """
        if self.header_lines > 0:
            return (f"data row {index + 1} (1-based, first row after the header; "
                    f"file line {index + 1 + self.header_lines})")
        return f"sample {index + 1} (1-based)"
