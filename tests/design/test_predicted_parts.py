"""Parts predicted from the scaling laws: the truth of an unmeasured size inside the prediction, draws spread by it."""

import json
import math

import numpy as np
import pytest

from idkit.catalogue import load_catalogue
from idkit.design import draw_models, predicted_part
from idkit.errors import DataError
from idkit.models import GeneralizedMaxwell, IwanModel, save_model
from idkit.synth.catalogue import elastomer_family, wire_rope_family


def truth_model(part):
    truth = part.truth
    if part.family == "wire_rope":  # beta = 0: the truth is a plain Iwan model of order 9
        return IwanModel(g1=truth.g1, g2=truth.g2, g3=truth.g3, k=truth.k, fc=truth.fc, c_visc=truth.c_visc)
    return GeneralizedMaxwell(k0=truth.k0, k=truth.k, rate=truth.rate, m_eff=truth.moving_mass_kg)


def write_catalogue(folder, parts):
    """A catalogue whose parts are the generating truths (no fit: the laws and the prediction are under test)."""
    (folder / "models").mkdir(parents=True)
    records = []
    for part in parts:
        model = truth_model(part)
        quantities = ({"stuck_stiffness": model.stuck_stiffness, "g1": model.g1,
                       "total_slip_force": float(sum(part.truth.fc))} if part.family == "wire_rope"
                      else {"k0": model.k0})
        save_model(model, folder / "models" / f"{part.part}.json")
        records.append({"part": part.part, "family": part.family, "dimensions": part.dimensions,
                        "status": "identified", "held_out": {"verdict": "PASS"}, "quantities": quantities,
                        "covariance": {"names": [], "matrix": []}, "model_file": f"models/{part.part}.json"})
    (folder / "catalogue.json").write_text(json.dumps({"format": "idkit-catalogue", "version": 1, "parts": records}))
    return load_catalogue(folder)


def test_a_predicted_rope_holds_the_unmeasured_truth_within_its_band_and_draws_carry_it(tmp_path):
    family = wire_rope_family(seed=4)
    unmeasured = family[17]
    catalogue = write_catalogue(tmp_path, [p for p in family if p is not unmeasured])
    part = predicted_part(catalogue, "wire_rope", unmeasured.dimensions)
    assert part.predicted and part.family == "wire_rope"
    for value, truth, sd in ((part.model.stuck_stiffness, unmeasured.truth.stuck_stiffness, part.law_log_sd["stiffness"]),
                             (sum(part.model.fc), sum(unmeasured.truth.fc), part.law_log_sd["slip_force"])):
        # 3 prediction standard deviations: a correct law misses with probability 0.3 %
        assert abs(math.log(value / truth)) < 3 * sd
    drawn = draw_models(part, 400, np.random.default_rng(1))
    spread = np.std(np.log([m.stuck_stiffness for m in drawn]))
    # the sample sd of 400 normal draws is within 4 x sd / sqrt(2 x 400) = 14 % of the law's
    assert spread == pytest.approx(part.law_log_sd["stiffness"], rel=0.14)


def test_a_predicted_elastomer_goes_through_to_stiffness_and_keeps_the_compounds_rates(tmp_path):
    family = elastomer_family(seed=4)
    unmeasured = family[4]
    catalogue = write_catalogue(tmp_path, [p for p in family if p is not unmeasured])
    part = predicted_part(catalogue, "elastomer", unmeasured.dimensions)
    assert abs(math.log(part.model.k0 / unmeasured.truth.k0)) < 3 * part.law_log_sd["stiffness"]
    # the generator's parts of one compound share the modulus model: the prediction keeps its rates
    # and its element-to-static ratios exactly
    np.testing.assert_allclose(part.model.rate, unmeasured.truth.rate, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(part.model.k) / part.model.k0,
                               np.asarray(unmeasured.truth.k) / unmeasured.truth.k0, rtol=1e-9)


def test_cli_laws_prints_each_law_and_its_coverage(tmp_path, capsys):
    from idkit.cli.main import main

    write_catalogue(tmp_path / "cat", wire_rope_family(count=8, seed=4))
    assert main(["catalogue", "laws", str(tmp_path / "cat")]) == 0
    out = capsys.readouterr().out
    for quantity in ("stuck_stiffness", "g1", "total_slip_force"):
        assert f"wire_rope {quantity}: 8 parts" in out
    assert out.count("leave-one-part-out:") == 3


def test_cli_design_adds_a_predicted_size_to_the_candidates(tmp_path, capsys):
    import pandas as pd

    from idkit.cli.main import main

    family = wire_rope_family(count=8, seed=4)
    write_catalogue(tmp_path / "cat", family[1:])
    (tmp_path / "size.json").write_text(json.dumps({"family": "wire_rope", "dimensions": family[0].dimensions,
                                                    "name": "WR predicted"}))
    (tmp_path / "env.json").write_text(json.dumps({"drops": {"heights_m": [0.01]},
                                                   "limits": {"peak_acceleration_m_per_s2": 100.0}}))
    assert main(["design", "--catalogue", str(tmp_path / "cat"), "--payload-mass", "40", "--environment",
                 str(tmp_path / "env.json"), "--predicted-part", str(tmp_path / "size.json"), "--draws", "1",
                 "--top", "1", "-o", str(tmp_path / "out")]) == 0
    table = pd.read_csv(tmp_path / "out" / "candidates.csv")
    assert table.loc[table["name"] == "4 x WR predicted", "predicted parts"].tolist() == [1]
    assert len(table) == 8
    capsys.readouterr()


@pytest.mark.parametrize(("document", "message"), [
    ({"family": "steel", "dimensions": {}}, r"size.json': family: found 'steel', expected one of 'wire_rope'"),
    ({"family": "wire_rope"}, r"size.json': required key 'dimensions' missing"),
    ({"family": "wire_rope", "dimensions": {}, "colour": "red"}, r"unknown key\(s\) colour"),
    (["wire_rope"], r"size.json': found list, expected \{\"family\""),
])
def test_a_predicted_part_file_is_checked_against_its_declared_keys(tmp_path, document, message):
    """--predicted-part FILE: the keys are declared (family, dimensions, name); nothing is ignored."""
    from idkit.cli.design import _predicted

    (tmp_path / "size.json").write_text(json.dumps(document))
    with pytest.raises(DataError, match=message):
        _predicted(None, tmp_path / "size.json")
