"""Measurement sets: manifest round trip, filters, provenance, .mat entries, safety."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.io

from idkit.errors import DataError
from idkit.io import (
    DropMeasurement,
    Excitation,
    MeasurementInfo,
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
    file_sha256,
    load_measurement_set,
    read_manifest,
    write_measurement_set,
)

FS_HZ = 1000.0


def _time(n: int = 50) -> np.ndarray:
    return np.arange(n) / FS_HZ


def _measurements() -> list:
    rng = np.random.default_rng(7)
    t = _time()
    out = []
    for rep in (1, 2):
        out.append(QuasiStaticMeasurement(
            time=t, deflection=1e-3 * np.sin(40 * t), force=rng.normal(size=t.size),
            info=MeasurementInfo(id=f"qs_wr_{rep}", isolator="wire_rope", repetition=rep,
                                 sample_rate_hz=FS_HZ, split="fit" if rep == 1 else "validation")))
    for mass in (0.99, 6.40):
        out.append(WhiteNoiseMeasurement(
            time=t, v_base=rng.normal(size=t.size), v_top=rng.normal(size=t.size),
            info=MeasurementInfo(id=f"wn_{mass}", isolator="elastomer", top_mass_kg=mass,
                                 excitation=Excitation(band=(1.0, 500.0)), split="fit")))
    out.append(SteppedSineMeasurement(
        time=t, v_base=np.sin(t), v_top=np.cos(t), x_base=t, u_in=np.ones(t.size),
        info=MeasurementInfo(id="ss_h_20hz", isolator="hybrid", top_mass_kg=0.99,
                             intermediate_mass_kg=0.14, notes="first point",
                             excitation=Excitation(freq=20.0, amplitude=2e-3,
                                                   amplitude_quantity="velocity"))))
    out.append(DropMeasurement(
        time=t, deflection=-t, a_top_1=rng.normal(size=t.size), a_top_2=rng.normal(size=t.size),
        v_rel=rng.normal(size=t.size),
        info=MeasurementInfo(id="drop_el_5cm_1", isolator="elastomer", top_mass_kg=4.37,
                             bottom_mass_kg=7.83, drop_height_m=0.05, repetition=1)))
    return out


@pytest.fixture
def written_set(tmp_path):
    folder = tmp_path / "set"
    write_measurement_set(folder, _measurements(), name="round trip", notes="synthetic")
    return folder


def test_round_trip_preserves_data_and_metadata(written_set):
    original = _measurements()
    mset = load_measurement_set(written_set)
    assert mset.name == "round trip" and mset.notes == "synthetic"
    assert mset.ids == tuple(m.info.id for m in original)
    for before, after in zip(original, mset):
        assert type(before) is type(after)
        assert after.info == before.info
        for name, values in before.signals().items():
            assert np.array_equal(getattr(after, name), values), name


def test_select_by_kind_isolator_split_mass(written_set):
    mset = load_measurement_set(written_set)
    assert mset.select(kind="quasi_static").ids == ("qs_wr_1", "qs_wr_2")
    assert mset.select(isolator="elastomer").ids == ("wn_0.99", "wn_6.4", "drop_el_5cm_1")
    assert mset.select(split="validation").ids == ("qs_wr_2",)
    assert mset.select(top_mass_kg=0.99).ids == ("wn_0.99", "ss_h_20hz")
    assert mset.select(kind="white_noise", top_mass_kg=6.4).ids == ("wn_6.4",)
    assert len(mset.select(kind="drop", split="fit")) == 0


def test_get_and_typed_accessors(written_set):
    mset = load_measurement_set(written_set)
    assert mset.get("ss_h_20hz").freq == 20.0
    assert mset.get("wn_0.99").band == (1.0, 500.0)
    with pytest.raises(KeyError, match="no measurement"):
        mset.get("missing")


def test_hashes_are_sha256_of_every_file(written_set):
    mset = load_measurement_set(written_set)
    hashes = mset.hashes()
    assert list(hashes)[0] == "manifest.json"
    for rel, digest in hashes.items():
        assert file_sha256(written_set / rel) == digest
    assert len(hashes) == len(mset) + 1


def test_to_dataframe_lists_metadata(written_set):
    frame = load_measurement_set(written_set).to_dataframe()
    assert list(frame["id"]) == list(load_measurement_set(written_set).ids)
    row = frame.set_index("id").loc["drop_el_5cm_1"]
    assert row["drop_height [m]"] == 0.05 and row["n_samples"] == 50


def test_loading_leaves_every_file_byte_identical(written_set):
    files = sorted(p for p in written_set.rglob("*") if p.is_file())
    before = [(file_sha256(p), p.stat().st_mtime_ns) for p in files]
    load_measurement_set(written_set)
    assert [(file_sha256(p), p.stat().st_mtime_ns) for p in files] == before
    assert sorted(p for p in written_set.rglob("*") if p.is_file()) == files


def test_write_refuses_existing_files_before_writing_anything(written_set):
    manifest = (written_set / "manifest.json").read_bytes()
    with pytest.raises(FileExistsError, match="refusing to overwrite"):
        write_measurement_set(written_set, _measurements()[:1], name="other")
    assert (written_set / "manifest.json").read_bytes() == manifest
    write_measurement_set(written_set, _measurements()[:1], name="other", overwrite=True)
    assert load_measurement_set(written_set).name == "other"


def test_write_gzip_set(tmp_path):
    write_measurement_set(tmp_path, _measurements()[:2], gzip=True)
    manifest = read_manifest(tmp_path)
    assert all(e.file.endswith(".csv.gz") for e in manifest.entries)
    assert manifest.sha256 == file_sha256(tmp_path / "manifest.json")
    assert len(load_measurement_set(tmp_path)) == 2


def test_write_rejects_bad_or_duplicate_ids(tmp_path):
    m = _measurements()[0]
    with pytest.raises(DataError, match="duplicate id"):
        write_measurement_set(tmp_path / "a", [m, m])
    bad = QuasiStaticMeasurement(time=m.time, deflection=m.deflection, force=m.force,
                                 info=MeasurementInfo(id="../x"))
    with pytest.raises(DataError, match="usable as a file name"):
        write_measurement_set(tmp_path / "b", [bad])
    with pytest.raises(DataError, match="no measurements"):
        write_measurement_set(tmp_path / "c", [])


def _write_manifest(folder, document) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "manifest.json").write_text(json.dumps(document), encoding="utf-8")


def test_defaults_block_applies_to_every_entry(tmp_path):
    t = _time(4)
    csv = "time [s],v_base [m/s],v_top [m/s]\n" + "".join(f"{x!r},0,0\n" for x in t.tolist())
    for freq in (10, 20):
        (tmp_path / f"p{freq}.csv").write_text(csv)
    _write_manifest(tmp_path, {
        "defaults": {"kind": "stepped_sine", "isolator": "wire_rope", "top_mass_kg": 2.98,
                     "sample_rate_hz": FS_HZ,
                     "excitation": {"freq_hz": 1.0, "amplitude": 1.0, "amplitude_unit": "mm/s"}},
        "measurements": [
            {"id": "p10", "file": "p10.csv",
             "excitation": {"freq_hz": 10.0, "amplitude": 2.0, "amplitude_unit": "mm/s"}},
            {"id": "p20", "file": "p20.csv", "top_mass_kg": 1.5},
        ]})
    mset = load_measurement_set(tmp_path)
    assert [m.freq for m in mset] == [10.0, 1.0]
    assert mset.get("p10").nominal_amplitude == pytest.approx(2e-3)
    assert [e.info.top_mass_kg for e in mset.entries] == [2.98, 1.5]


def test_mat_entry_with_column_mapping(tmp_path):
    t = _time(30)
    scipy.io.savemat(tmp_path / "loop.mat", {
        "Tout": t[:, None], "x_F": np.column_stack([np.sin(t), np.cos(t), 3 * t])})
    _write_manifest(tmp_path, {"measurements": [{
        "id": "loop", "kind": "quasi_static", "file": "loop.mat", "sample_rate_hz": FS_HZ,
        "mat_columns": {"time": "Tout [s]", "deflection": "x_F[:,0] [mm]",
                        "force": "x_F[:,2] [kN]"}}]})
    m = load_measurement_set(tmp_path).get("loop")
    np.testing.assert_array_equal(m.deflection, np.sin(t) / 1000)
    np.testing.assert_allclose(m.force, 3000 * t)
    assert m.source.column_label("force") == "x_F[:,2] [kN]"
