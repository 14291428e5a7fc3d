"""The synthetic-data generator: determinism, bundled data = generator output, physics of the truth."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from idkit.io import file_sha256, load_measurement_set, read_csv_measurement, read_manifest
from idkit.io import write_csv_measurement
from idkit.synth import DEFAULT_SEED, SET_NAMES, default_elastomer, generate, generate_measurement, plan

DATA = Path(__file__).resolve().parents[2] / "data"
MAX_DATA_BYTES = 30e6


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.mark.slow
def test_same_seed_gives_byte_identical_files_and_another_seed_differs(tmp_path):
    first = generate(tmp_path / "a", quick=True, sets=("elastomer",))
    generate(tmp_path / "b", quick=True, sets=("elastomer",))
    generate(tmp_path / "c", quick=True, sets=("elastomer",), seed=DEFAULT_SEED + 1)
    tree_a, tree_b, tree_c = (_tree(tmp_path / name) for name in "abc")
    assert first.counts["elastomer"] == {"quasi_static": 2, "white_noise": 4, "stepped_sine": 12,
                                         "drop": 4}
    assert tree_a == tree_b
    data_files = [name for name in tree_a if name.endswith(".csv.gz")]
    assert all(tree_a[name] != tree_c[name] for name in data_files)
    # the written set loads and declares the validation split
    loaded = load_measurement_set(tmp_path / "a" / "elastomer")
    assert {m.info.split for m in loaded.measurements} == {"fit", "validation"}


def test_generate_refuses_to_overwrite_without_force(tmp_path):
    generate(tmp_path, quick=True, sets=("hybrid",))
    before = _tree(tmp_path)
    with pytest.raises(FileExistsError, match="refusing to overwrite"):
        generate(tmp_path, quick=True, sets=("hybrid",))
    assert _tree(tmp_path) == before
    generate(tmp_path, quick=True, sets=("hybrid",), force=True)
    assert _tree(tmp_path) == before  # deterministic replacement, no leftovers
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hybrid", "truth"]


@pytest.fixture(scope="module")
def truth():
    if not (DATA / "truth").exists():
        pytest.skip("bundled data/ not generated")
    return {name: json.loads((DATA / "truth" / f"{name}.json").read_text()) for name in SET_NAMES}


def test_bundled_files_match_the_hashes_recorded_by_the_generator(truth):
    total = 0
    for name in SET_NAMES:
        manifest = read_manifest(DATA / name)
        records = truth[name]["measurements"]
        assert truth[name]["seed"] == DEFAULT_SEED and truth[name]["synthetic"] is True
        assert sorted(e.id for e in manifest.entries) == sorted(records)
        for entry in manifest.entries:
            path = DATA / name / entry.file
            assert file_sha256(path) == records[entry.id]["sha256"], entry.file
            total += path.stat().st_size
    total += sum(p.stat().st_size for p in DATA.rglob("*") if p.suffix in (".json", ".md"))
    assert total < MAX_DATA_BYTES


@pytest.mark.parametrize("ident", ["qs_el_loops_2", "wn_el_6.40kg_3", "ss_hy_a5_010.92Hz",
                                   "ss_wr_a1_047.80Hz", "drop_wr_7.39kg_14cm_2",
                                   "drop_el_4.37kg_01cm_1"])
def test_regenerated_measurement_is_bit_identical_to_the_bundled_file(truth, tmp_path, ident):
    item = next(i for i in plan() if i.id == ident)
    measurement, record = generate_measurement(item, seed=DEFAULT_SEED)
    target = tmp_path / f"{ident}.csv.gz"
    write_csv_measurement(measurement, target)
    bundled = truth[item.set_name]["measurements"][ident]
    assert file_sha256(target) == bundled["sha256"]
    assert record["seed"] == bundled["seed"]


def test_plan_follows_the_experiment_grid_of_spec_3():
    items = plan()
    by_kind = {kind: [i for i in items if i.kind == kind]
               for kind in ("quasi_static", "white_noise", "stepped_sine", "drop")}
    masses = sorted({i.settings["top_mass_kg"] for i in by_kind["white_noise"]})
    assert len(masses) == 8 and masses[0] == 0.99 and masses[-1] == 6.40
    heights = sorted({i.settings["drop_height_m"] for i in by_kind["drop"]})
    assert heights == [h / 100 for h in range(1, 15)]
    assert len(by_kind["drop"]) == 3 * 2 * 14 * 3
    assert {i.set_name for i in by_kind["stepped_sine"]} == set(SET_NAMES)
    for item in items:  # the validation split is repetition 3 or amplitude level 3
        if item.kind == "stepped_sine":
            assert (item.split == "validation") == (item.settings["amplitude_index"] == 2)
        else:
            assert (item.split == "validation") == (item.settings["repetition"] == 3)


def test_truth_is_richer_than_the_fitted_models(truth):
    wire_rope = truth["wire_rope"]["models"]["wire_rope"]
    elastomer = truth["elastomer"]["models"]["elastomer"]
    assert wire_rope["order"] >= 20 and wire_rope["beta"] > 0 and wire_rope["k_bottom"] > 0
    assert elastomer["order"] >= 6 and elastomer["internal_mass_kg"] > 0 and elastomer["alpha"] > 0


def _read(name, ident):
    manifest = read_manifest(DATA / name)
    entry = next(e for e in manifest.entries if e.id == ident)
    return read_csv_measurement(DATA / name / entry.file, entry.kind, info=entry.info)


def test_elastomer_is_about_15_percent_stiffer_than_the_catalogue_and_softens_in_compression(truth):
    loops = _read("elastomer", "qs_el_loops_1")
    x, force = loops.deflection, loops.force
    near = np.abs(x) < 1.5e-3
    slope = np.polyfit(x[near], force[near], 1)[0]
    assert slope == pytest.approx(1.15 * 12e3, rel=0.05)  # SPEC 3: ~15 % above 12e3 N/m
    tension = force[x > 7.5e-3].mean() / x[x > 7.5e-3].mean()
    compression = force[x < -7.5e-3].mean() / x[x < -7.5e-3].mean()
    assert compression < 0.97 * tension  # secant stiffness lower in compression


def test_white_noise_frf_shows_the_internal_mode_near_200_hz(truth):
    from idkit.observe.white_noise import frf_from_white_noise

    run = _read("elastomer", "wn_el_0.99kg_1")
    frf = frf_from_white_noise(run, band=(120.0, 300.0), resolution_hz=run.sample_rate_hz / 2000)
    magnitude = np.abs(frf.h1)
    peak = frf.freq[np.argmax(magnitude)]
    assert 170.0 <= peak <= 230.0
    assert magnitude.max() > 2 * magnitude[-1]  # a local maximum, not the roll-off
    resonance = frf_from_white_noise(run, band=(5.0, 60.0))
    assert resonance.freq[np.argmax(np.abs(resonance.h1))] == pytest.approx(19.5, abs=2.0)
    assert default_elastomer().internal_mass_kg > 0


def test_module_entry_point_writes_a_set(tmp_path, capsys):
    from idkit.synth.__main__ import main

    assert main(["-o", str(tmp_path), "--quick", "--sets", "hybrid"]) == 0
    assert "hybrid: 12 stepped_sine, 4 drop" in capsys.readouterr().out
    assert main(["-o", str(tmp_path), "--quick", "--sets", "hybrid"]) == 2
