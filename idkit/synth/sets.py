"""Write the bundled synthetic measurement sets and their truth files.

Layout written under the output folder (``data/`` in the repository)::

    wire_rope/manifest.json   + quasi_static/, stepped_sine/, drop/       (*.csv.gz)
    elastomer/manifest.json   + quasi_static/, white_noise/, stepped_sine/, drop/
    hybrid/manifest.json      + stepped_sine/, drop/
    truth/wire_rope.json, truth/elastomer.json, truth/hybrid.json

The measurement folders hold only what an experimenter would have (the io format of
``docs/data-format.md``); the truth files hold the generating models, noise levels, seeds,
per-measurement true values and the SHA-256 of every data file as generated.

``truth="b"`` writes the second truth (:mod:`idkit.synth.truth`) with its protocol
(:func:`idkit.synth.experiments.plan`); its quasi-static and drop files declare non-SI units
(:data:`FILE_UNITS`: mm, kN, g, mm/s), so the loaders' unit conversion is part of every run
on it. It is not bundled (``data/`` holds truth "a" only); tests generate it into a
temporary folder.

Each set is written to a temporary sibling folder and moved into place only when complete,
so an interrupted run never leaves a half-written set; an existing set is replaced only with
``force=True``.
"""

from __future__ import annotations

import json
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from idkit import __version__
from idkit.io import file_sha256, write_measurement_set
from idkit.atomic import atomic_output_folder
from idkit.checks import Choice, Flag, Whole, accepts, unchecked
from idkit.atomic import write_bytes_atomic
from idkit.synth.experiments import CONTACT, NOISE, RESOLUTION, Planned, plan, realize
from idkit.synth.names import DEFAULT_SEED, SET_NAMES, TRUTH_NAMES
from idkit.synth.truth import truth_models

__all__ = ["FILE_UNITS", "GenerationSummary", "generate", "generate_measurement"]

TRUTH_FOLDER = "truth"
#: The stepped sines held out for validation, per truth (manifest notes).
SWEEP_SPLIT = {"a": "amplitude level 3", "b": "every other frequency at every level"}
#: Column units written per truth (columns not named are SI): truth "b" writes its
#: quasi-static and drop files in mm, kN, g and mm/s; its shaker files stay SI.
FILE_UNITS = {
    "a": {},
    "b": {"deflection": "mm", "force": "kN", "a_top_1": "g", "a_top_2": "g", "v_rel": "mm/s"},
}


@dataclass(frozen=True)
class GenerationSummary:
    """What :func:`generate` wrote.

    Attributes
    ----------
    folder : pathlib.Path
        Output folder.
    seed : int
        Seed used.
    counts : dict
        ``{set_name: {kind: number of measurements}}``.
    bytes_written : int
        Total size of the written files, bytes.
    seconds : float
        Wall time, s.
    """

    folder: Path
    seed: int
    counts: dict = field(default_factory=dict)
    bytes_written: int = 0
    seconds: float = 0.0

    def report(self) -> str:
        """One line per set plus totals."""
        lines = [f"{name}: " + ", ".join(f"{n} {kind}" for kind, n in kinds.items())
                 for name, kinds in self.counts.items()]
        lines.append(f"{self.bytes_written / 1e6:.1f} MB in {self.seconds:.0f} s, seed {self.seed}, "
                     f"written to {self.folder}")
        return "\n".join(lines)


def generate_measurement(item: Planned, *, seed: int = DEFAULT_SEED, quick: bool = False,
                         wire_rope=None, elastomer=None):
    """Generate one planned measurement (see :func:`idkit.synth.experiments.plan`).

    The models default to those of the item's truth (``item.truth``).

    Returns
    -------
    (Measurement, dict)
        The measurement (SI) and its truth record.
    """
    default_rope, default_body = truth_models(item.truth)
    return realize(item, seed=seed, quick=quick, wire_rope=wire_rope or default_rope,
                   elastomer=elastomer or default_body)


def _truth_document(set_name, seed, quick, wire_rope, elastomer, records, truth):
    models = {}
    if set_name in ("wire_rope", "hybrid"):
        models["wire_rope"] = wire_rope.to_dict()
    if set_name in ("elastomer", "hybrid"):
        models["elastomer"] = elastomer.to_dict()
    document = {
        "synthetic": True,
        "generator": "idkit.synth (idkit data generate)",
        "idkit_version": __version__,
        "seed": seed,
        "quick": quick,
        "set": set_name,
        "models": models,
        "sensor_noise_sd_SI": NOISE,
        "resolution_decimals_SI": RESOLUTION,
        "floor_contact": CONTACT,
        "conventions": "SI units; deflection x_top - x_bottom/base, positive = tension; "
                       "per-measurement seed = [seed, crc32(id)] for numpy.random.default_rng",
        "measurements": records,
    }
    if truth != "a":  # truth "a" documents stay as bundled (no key: truth "a")
        document["truth"] = truth
        document["file_units"] = FILE_UNITS[truth]
        document["conventions"] = (
            "SI units in this document; data files declare their units in the headers "
            "(file_units); deflection x_top - x_bottom/base, positive = tension; per-measurement "
            f"seed = [seed, crc32('{truth}/' + id)] for numpy.random.default_rng")
    return document


@accepts(seed=Whole(ge=0), force=Flag(), quick=Flag(), truth=Choice(TRUTH_NAMES), error=ValueError)
def generate(folder: str | Path, *, seed: int = DEFAULT_SEED, force: bool = False,
             quick: bool = False, sets: Sequence[str] = SET_NAMES, truth: str = "a",
             progress: Callable[[str], None] | None = None) -> GenerationSummary:
    """Generate the synthetic measurement sets and truth files into ``folder``.

    Parameters
    ----------
    folder : str or pathlib.Path
        Output folder (``data/`` for the bundled data); created if missing.
    seed : int, default 2026
        Master seed; identical seeds give byte-identical files.
    force : bool
        Replace existing sets and truth files.
    quick : bool
        Reduced grid and shorter records (for tests); not the bundled data.
    sets : sequence of str
        Which of ``wire_rope``, ``elastomer``, ``hybrid`` to write.
    truth : {"a", "b"}, default "a"
        Generating truth (:func:`idkit.synth.truth.truth_models`); ``"a"`` made the bundled
        data, ``"b"`` is the second truth with its own protocol and non-SI file units.
    progress : callable, optional
        Called with a short message per set.

    Returns
    -------
    GenerationSummary

    Raises
    ------
    FileExistsError
        If a set folder or truth file exists and ``force`` is false (checked first).

    Examples
    --------
    >>> summary = generate("/tmp/idkit-data", quick=True, force=True)  # doctest: +SKIP
    """
    start = _time.perf_counter()
    folder = Path(folder)
    unknown = sorted(set(sets) - set(SET_NAMES))
    if unknown:
        raise ValueError(f"sets: unknown {unknown}, expected names from {SET_NAMES}")
    targets = [folder / name for name in sets] + [folder / TRUTH_FOLDER / f"{n}.json" for n in sets]
    existing = [str(p) for p in targets if p.exists()]
    if existing and not force:
        raise FileExistsError(f"refusing to overwrite {', '.join(existing)} (use --force)")
    folder.mkdir(parents=True, exist_ok=True)
    (folder / TRUTH_FOLDER).mkdir(exist_ok=True)
    wire_rope, elastomer = truth_models(truth)
    items = unchecked(plan)(quick=quick, truth=truth)
    name_suffix = "" if truth == "a" else f", truth {truth}"
    counts: dict = {}
    total_bytes = 0
    for set_name in sets:
        chosen = [item for item in items if item.set_name == set_name]
        measurements, records = [], {}
        for item in chosen:
            measurement, record = realize(item, seed=seed, quick=quick, wire_rope=wire_rope,
                                         elastomer=elastomer)
            measurements.append(measurement)
            records[item.id] = record
        # existing sets were refused above unless force: replace by the one folder swap
        with atomic_output_folder(folder / set_name, force=True) as staging:
            write_measurement_set(
                staging, measurements, gzip=True, units=FILE_UNITS[truth],
                name=f"synthetic {set_name.replace('_', ' ')} isolator (idkit.synth, seed {seed}{name_suffix})",
                notes="SYNTHETIC data made by idkit.synth; the generating truth is in "
                      f"../{TRUTH_FOLDER}/{set_name}.json; split: repetition 3 (stepped sine: "
                      f"{SWEEP_SPLIT[truth]}) is the validation split")
            for item, measurement in zip(chosen, measurements):
                relative = f"{item.kind}/{item.id}.csv.gz"
                path = staging / relative
                records[item.id]["file"] = relative
                records[item.id]["sha256"] = file_sha256(path)
                total_bytes += path.stat().st_size
            total_bytes += (staging / "manifest.json").stat().st_size
            document = _truth_document(set_name, seed, quick, wire_rope, elastomer, records, truth)
            text = json.dumps(document, indent=1, allow_nan=False) + "\n"
            truth_path = folder / TRUTH_FOLDER / f"{set_name}.json"
            write_bytes_atomic(truth_path, text.encode(), overwrite=True)
            total_bytes += len(text.encode())
        counts[set_name] = {kind: sum(1 for i in chosen if i.kind == kind)
                            for kind in ("quasi_static", "white_noise", "stepped_sine", "drop")
                            if any(i.kind == kind for i in chosen)}
        if progress is not None:
            progress(f"{set_name}: {len(chosen)} measurements written")
    return GenerationSummary(folder=folder, seed=seed, counts=counts, bytes_written=total_bytes,
                             seconds=_time.perf_counter() - start)
