"""Selecting the measurements an analysis uses, once, with their provenance.

:func:`select_measurements` takes a loaded :class:`~idkit.io.manifest.MeasurementSet` or a
sequence of typed measurements and returns the matching ones with a
:class:`DataProvenance` (folder, manifest hash, file hashes, ids) that fits and estimates
carry into model files.
"""

from __future__ import annotations

from dataclasses import dataclass

from idkit.checks import Choice, Either, Instance, Items, accepts
from idkit.errors import DataError, Message, Suggestion
from idkit.io.info import SPLITS
from idkit.io.manifest import MANIFEST_NAME, MeasurementSet
from idkit.io.measurements import (
    DropMeasurement,
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
)

__all__ = ["DataProvenance", "ONLY_ISOLATOR", "resolve_isolator", "select_measurements", "split_option"]


class _OnlyIsolator:
    """Type of :data:`ONLY_ISOLATOR` (one instance; its repr is the name of the constant)."""

    def __repr__(self) -> str:
        return "ONLY_ISOLATOR"


#: Default ``isolator`` of the measurement-set fits: the only isolator whose records of the
#: kind the fit reads are in the data (:func:`resolve_isolator`); with several, an error
#: listing them. A string selects that isolator, None every isolator together.
ONLY_ISOLATOR = _OnlyIsolator()


@dataclass(frozen=True)
class DataProvenance:
    """Which measurements an analysis (a fit, a k0 estimate) used and where they came from.

    Attributes
    ----------
    folder : str or None
        The measurement set's folder (None for measurements given as a list).
    manifest_sha256 : str or None
        SHA-256 of the set's ``manifest.json``.
    files : dict of str to str
        Data file (as the manifest names it, else the path or ``<memory:id>``) -> SHA-256
        of its bytes.
    ids : tuple of str
        Measurement ids used, in order.
    selection : dict
        The criteria (kind, isolator, split) that picked them.
    """

    folder: str | None
    manifest_sha256: str | None
    files: dict
    ids: tuple[str, ...]
    selection: dict

    def to_dict(self) -> dict:
        """JSON-ready dictionary (``measurement_ids`` for :attr:`ids`)."""
        return {"folder": self.folder, "manifest_sha256": self.manifest_sha256, "files": dict(self.files),
                "measurement_ids": list(self.ids), "selection": dict(self.selection)}

    def merged(self, other: DataProvenance, *, kind: str) -> DataProvenance:
        """The union of two selections of the same set: ``other``'s files and ids after these.

        Parameters
        ----------
        other : DataProvenance
            A second selection (e.g. the white-noise runs after the quasi-static loops).
        kind : str
            The ``kind`` recorded for the union, e.g. ``"quasi_static (k0) + white_noise"``.

        Returns
        -------
        DataProvenance
            Folder and manifest of ``other``; selection of ``other`` with ``kind`` replaced.
        """
        return DataProvenance(folder=other.folder, manifest_sha256=other.manifest_sha256,
                              files={**self.files, **other.files}, ids=self.ids + other.ids,
                              selection={**other.selection, "kind": kind})


@accepts(split=Choice((*SPLITS, "all"), optional=True), error=DataError)
def split_option(split: str | None) -> str | None:
    """The ``split`` criterion of a selection: ``"fit"``, ``"validation"``, or None for all.

    Parameters
    ----------
    split : {"fit", "validation", "all", None}
        ``"all"`` and None both mean every split.

    Returns
    -------
    str or None

    Examples
    --------
    >>> split_option("all") is None, split_option("fit")
    (True, 'fit')
    """
    return None if split == "all" else split


#: ``data`` of a selection: a measurement set, or a sequence of measurements of any kind.
_DATA = Either((Instance((MeasurementSet,), what="a MeasurementSet"), Items(Instance(
    (QuasiStaticMeasurement, WhiteNoiseMeasurement, SteppedSineMeasurement, DropMeasurement),
    what="a measurement (QuasiStaticMeasurement, WhiteNoiseMeasurement, SteppedSineMeasurement or DropMeasurement)"))))


@accepts(data=_DATA, error=DataError)
def resolve_isolator(data, isolator, *, kind: str) -> str | None:
    """The ``isolator`` a selection uses: :data:`ONLY_ISOLATOR` becomes the data's only one.

    Parameters
    ----------
    data : MeasurementSet or sequence of measurements
    isolator : str, None or ONLY_ISOLATOR
        A name or None (every isolator) is returned as given.
    kind : str
        Only isolators with records of this kind count (a set of rope loops and hybrid
        drops has one isolator with loops).

    Returns
    -------
    str or None
        The isolator's name (None when the records name none, as a lone file's do; also
        when no record has that kind, which the selection then reports with what the data hold).

    Raises
    ------
    DataError
        Records of ``kind`` of several isolators: the message lists them and suggests
        choosing one (``isolator='NAME'``, ``--isolator NAME`` on the command line).

    Examples
    --------
    >>> from idkit.io import MeasurementInfo, QuasiStaticMeasurement
    >>> loops = [QuasiStaticMeasurement([0.0, 1.0], [0.0, 1e-3], [0.0, 5.0],
    ...                                 info=MeasurementInfo(id="l1", isolator="rope_8mm"))]
    >>> resolve_isolator(loops, ONLY_ISOLATOR, kind="quasi_static")
    'rope_8mm'
    """
    if isolator is not ONLY_ISOLATOR:
        return isolator
    everything = data.measurements if isinstance(data, MeasurementSet) else data
    names = sorted({m.info.isolator for m in everything if m.kind == kind}, key=lambda name: name or "")
    if len(names) <= 1:
        return names[0] if names else None
    where = f"{data.folder}: " if isinstance(data, MeasurementSet) and data.folder is not None else ""
    listed = ", ".join("(none)" if name is None else name for name in names)
    first = next(name for name in names if name is not None)
    raise DataError(Message(f"{where}found {kind} records of {len(names)} isolators ({listed}); expected one, "
                            "or the isolator named: choose it with ", Suggestion("isolator", first),
                            " (or another of those listed)"))


@accepts(data=_DATA, error=DataError)
def select_measurements(data, *, kind: str, isolator: str | None, split: str | None) -> tuple[list, DataProvenance]:
    """The measurements of one kind (and isolator, split) of a set, with their provenance.

    Parameters
    ----------
    data : MeasurementSet or sequence of measurements
        A loaded set (its manifest names the files and gives their hashes,
        :meth:`~idkit.io.MeasurementSet.hashes`) or measurements built in memory or read
        one by one (files named by their path, or ``<memory:id>``).
    kind : str
        ``"quasi_static"``, ``"white_noise"``, ``"stepped_sine"`` or ``"drop"``.
    isolator : str or None
        Only measurements of this isolator (None: any).
    split : {"fit", "validation", "all", None}
        Only measurements of this split (None or ``"all"``: any; :func:`split_option`).

    Returns
    -------
    (list of measurements, DataProvenance)
        The matching measurements in order, and what picked them.

    Raises
    ------
    DataError
        ``data`` is neither a MeasurementSet nor a sequence of measurements, or nothing
        matches (the message lists the (kind, isolator, split) groups available).
    """
    split = split_option(split)
    selection = {"kind": kind, "isolator": isolator, "split": split}
    if isinstance(data, MeasurementSet):
        chosen = data.select(kind=kind, isolator=isolator, split=split)
        measurements = list(chosen.measurements)
        files = {name: digest for name, digest in chosen.hashes().items() if name != MANIFEST_NAME}
        folder = None if data.folder is None else str(data.folder)
        manifest = data.manifest_sha256
        everything = list(data.measurements)
    else:
        everything = list(data)
        measurements = [m for m in everything if m.kind == kind
                        and (isolator is None or m.info.isolator == isolator)
                        and (split is None or m.info.split == split)]
        files = {(str(m.source.path) if m.source.path is not None else f"<memory:{m.id}>"): m.source.sha256
                 for m in measurements}
        folder, manifest = None, None
    if not measurements:
        found: dict = {}
        for m in everything:
            key = (m.kind, m.info.isolator, m.info.split)
            found[key] = found.get(key, 0) + 1
        raise DataError(Message(f"measurements: found none with kind={kind!r}, ", Suggestion("isolator", isolator),
                                ", ", Suggestion("split", split), f"; available (kind, isolator, split): {found}"))
    provenance = DataProvenance(folder=folder, manifest_sha256=manifest, files=files,
                                ids=tuple(m.id or f"#{i}" for i, m in enumerate(measurements)), selection=selection)
    return measurements, provenance
