"""Catalogue build on a tiny synthetic family: identification, failures, --add, executors, CLI."""

import json
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

from idkit.catalogue import build_catalogue, load_catalogue, read_part
from idkit.cli.main import main
from idkit.errors import DataError, OutputError
from idkit.synth.catalogue import elastomer_family, generate_catalogue, wire_rope_family

# order 3: the synthetic ropes' slip forces sit in three clusters (idkit.synth.catalogue)
ROPE_OPTIONS = {"wire_rope": {"order": 3}}


@pytest.fixture(scope="module")
def family(tmp_path_factory):
    """Two wire ropes, one elastomer (generated) and a broken part; the ropes built into a catalogue."""
    root = tmp_path_factory.mktemp("catalogue")
    ropes = wire_rope_family(count=2, seed=7)
    body = elastomer_family(count=1, compounds=("NR60",), seed=7)
    generate_catalogue(root / "parts", ropes, seed=7)
    generate_catalogue(root / "extra", body, seed=7)
    broken = root / "parts" / "WR-broken"
    broken.mkdir()
    (broken / "part.json").write_text(json.dumps({"part": "WR-broken", "family": "wire_rope", "dimensions": {
        "cable_diameter_m": 0.008, "loops": 8, "height_m": 0.06, "width_m": 0.075}}))
    unreadable = root / "parts" / "WR-unreadable"
    unreadable.mkdir()
    (unreadable / "part.json").write_text("{not json")
    catalogue = build_catalogue(root / "parts", root / "cat", fit_options=ROPE_OPTIONS)
    truths = {p.part: p.truth for p in ropes + body}
    return root, catalogue, truths


def test_every_part_is_identified_and_the_broken_one_is_recorded_with_its_reason(family):
    root, catalogue, truths = family
    status = {r["part"]: r["status"] for r in catalogue.records}
    assert status == {**{name: "identified" for name in truths if name.startswith("WR")}, "WR-broken": "failed",
                      "WR-unreadable": "failed"}
    assert "part.json': invalid JSON" in catalogue.record("WR-unreadable")["reasons"][0]
    broken = catalogue.record("WR-broken")
    assert "manifest.json" in broken["reasons"][0] and "DataError" in broken["reasons"][0]
    table = pd.read_csv(root / "cat" / "parts.csv")
    assert list(table["part"]) == [r["part"] for r in catalogue.records]
    assert (root / "cat" / "parts.parquet").exists() == (pytest.importorskip("importlib.util").find_spec("pyarrow")
                                                          is not None)


def test_identified_ropes_carry_the_truths_stiffness_and_slip_force(family):
    _, catalogue, truths = family
    for name, truth in truths.items():
        if not name.startswith("WR"):
            continue
        record = catalogue.record(name)
        # the order-3 model lumps each cluster of three truth elements into one: the total slip
        # force is a sum over loops it reproduces to the loop error (~1 %); the stuck stiffness
        # misses the micro-slip below the smallest 0.05 mm loop (2 % on these parts): 5 % / 10 %
        assert record["quantities"]["total_slip_force"] == pytest.approx(sum(truth.fc), rel=0.05)
        assert record["quantities"]["stuck_stiffness"] == pytest.approx(truth.stuck_stiffness, rel=0.10)
        assert record["held_out"]["verdict"] == "PASS"
        names, matrix = record["covariance"]["names"], np.asarray(record["covariance"]["matrix"])
        assert {"g1", "k_1", "fc_1"} <= set(names)
        assert np.all(np.linalg.eigvalsh(0.5 * (matrix + matrix.T)) > -1e-9 * np.abs(matrix).max())
        model = catalogue.model(name)
        document = json.loads((catalogue.folder / record["model_file"]).read_text())
        assert document["provenance"]["catalogue"]["dimensions"] == record["dimensions"]
        assert model.stuck_stiffness == pytest.approx(record["quantities"]["stuck_stiffness"], rel=1e-12)


def test_add_identifies_the_new_part_without_refitting_the_others(family):
    root, catalogue, truths = family
    before = {r["part"]: (catalogue.folder / r["model_file"]).stat().st_mtime_ns
              for r in catalogue.records if "model_file" in r}
    body = next(name for name in truths if name.startswith("EL"))
    added = build_catalogue(None, root / "cat", add=[root / "extra" / body])
    assert [r["part"] for r in added.records][:-1] == [r["part"] for r in catalogue.records]
    record = added.record(body)
    assert record["status"] == "identified" and record["held_out"]["verdict"] == "PASS"
    # k0 from the loops: within 5 % of the truth's static spring (its softening in compression is 3 %)
    assert record["quantities"]["k0"] == pytest.approx(truths[body].k0, rel=0.05)
    after = {r["part"]: (added.folder / r["model_file"]).stat().st_mtime_ns for r in added.records
             if r["part"] in before}
    assert after == before
    assert load_catalogue(root / "cat").records == added.records
    with pytest.raises(DataError, match="already in the catalogue"):
        build_catalogue(None, root / "cat", add=[root / "extra" / body])


def test_an_executor_gives_the_serial_result(family, tmp_path):
    root, catalogue, truths = family
    rope = sorted(name for name in truths if name.startswith("WR"))[0]
    with ThreadPoolExecutor(max_workers=2) as pool:
        other = build_catalogue(root / "parts" / rope, tmp_path / "cat", executor=pool, fit_options=ROPE_OPTIONS)
    assert other.record(rope)["quantities"] == catalogue.record(rope)["quantities"]
    assert other.record(rope)["covariance"] == catalogue.record(rope)["covariance"]


def test_bad_inputs_are_refused_naming_what_is_wrong(family, tmp_path):
    root, _, _ = family
    with pytest.raises(OutputError, match="exists"):
        build_catalogue(root / "parts", root / "cat")
    part = tmp_path / "bad"
    part.mkdir()
    (part / "part.json").write_text(json.dumps({"part": "x", "family": "elastomer", "dimensions": {
        "area_m2": 1e-3, "thickness_m": -0.01, "shape_factor": 0.5, "compound": "NR"}}))
    with pytest.raises(DataError, match=r"part.json': dimensions: thickness_m: found -0.01, expected a finite real"):
        read_part(part)
    for document, message in [({"part": "x", "family": "steel", "dimensions": {}}, "family: found 'steel'"),
                              ({"part": "a/b", "family": "wire_rope", "dimensions": {}},
                               "part: found 'a/b', expected a non-empty name without '/'"),
                              ({"part": "x", "family": "wire_rope", "dimensions": {"loops": 8}},
                               "dimensions: required key 'cable_diameter_m' missing"),
                              ({"part": "x", "family": "elastomer", "dimensions": {
                                  "area_m2": 1e-3, "thickness_m": 0.01, "shape_factor": 0.5, "compound": " "}},
                               "dimensions: compound: found ' ', expected a compound name")]:
        (part / "part.json").write_text(json.dumps(document))
        with pytest.raises(DataError, match=message):
            read_part(part)
    with pytest.raises(OutputError, match="fit_options: unknown key.s. order; expected keys from elastomer, wire_rope"):
        build_catalogue(root / "parts", tmp_path / "c2", fit_options={"order": 3})


def test_cli_design_on_the_catalogue_writes_its_files(family, tmp_path, capsys):
    root, _, _ = family
    environment = tmp_path / "env.json"
    environment.write_text(json.dumps({"drops": {"heights_m": [0.03]},
                                       "limits": {"peak_acceleration_m_per_s2": 200.0, "max_deflection_m": 0.02}}))
    code = main(["design", "--catalogue", str(root / "cat"), "--payload-mass", "40", "--mounts", "4",
                 "--environment", str(environment), "--draws", "1", "--top", "1", "-o", str(tmp_path / "out")])
    assert code == 0
    assert {p.name for p in (tmp_path / "out").iterdir()} == {"candidates.csv", "best.csv", "best", "pareto.png",
                                                             "design.md"}
    assert "# Design" in capsys.readouterr().out


def test_catalogue_report_draws_every_usable_part(family, tmp_path):
    root, _, _ = family
    assert main(["catalogue", "report", str(root / "cat"), "-o", str(tmp_path / "report"), "--draws", "2"]) == 0
    table = pd.read_csv(tmp_path / "report" / "characteristics.csv")
    assert set(table["part"]) == {r["part"] for r in load_catalogue(root / "cat").usable()}
    assert (tmp_path / "report" / "catalogue.png").stat().st_size > 0
