"""Design tool: probabilities under the covariance, the study's hybrid choice, executors, files, refusals."""

import json
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from scipy import stats

from idkit.design import Candidate, DesignPart, Environment, evaluate_candidates, judge, run_design
from idkit.errors import DataError
from idkit.gravity import STANDARD_GRAVITY
from idkit.models import GeneralizedMaxwell, load_model, library
from idkit.responses import shock_sweep
from idkit.studies.transport import transport_systems

STIFFNESS = 2.0e4  # N/m
MASS = 10.0  # kg
HEIGHT = 0.03  # m
LOG_SD = 0.2  # of the stiffness


def spring_part(log_sd=LOG_SD):
    """A linear spring as a Maxwell part (one element 1e-6 of k0: its force is negligible) with a
    covariance on k0 alone: drawn k0 = K exp(LOG_SD z)."""
    model = GeneralizedMaxwell(k0=STIFFNESS, k=[1e-6 * STIFFNESS], rate=[100.0])
    return DesignPart("spring", "elastomer", model, ("k0",), np.array([[(log_sd * STIFFNESS) ** 2]]))


def test_a_design_meeting_every_limit_on_the_mean_model_but_missing_30_percent_of_draws_is_reported():
    # undamped linear drop: peak acceleration v0 sqrt(k / m), so log a = log a0 + LOG_SD z / 2 and the
    # limit a0 exp(LOG_SD z_0.7 / 2) is met with probability 0.7 exactly
    v0 = math.sqrt(2.0 * STANDARD_GRAVITY * HEIGHT)
    peak = v0 * math.sqrt(STIFFNESS / MASS)
    limit = peak * math.exp(0.5 * LOG_SD * stats.norm.ppf(0.7))
    environment = Environment.from_dict({"drops": {"heights_m": [HEIGHT]},
                                         "limits": {"peak_acceleration_m_per_s2": limit, "probability": 0.9}})
    candidate = Candidate("1 x spring", (spring_part(),), 1, MASS)
    n_draws = 200
    table = judge(evaluate_candidates([candidate], environment, n_draws=n_draws, seed=3, screening=False),
                  environment)
    row = table.iloc[0]
    # the simulated peak against the analytic one: 2000 steps per period (idkit.responses.shock), 1e-5
    assert row["peak_acceleration_m_per_s2"] == pytest.approx(peak, rel=1e-5)
    assert row["margin peak_acceleration_m_per_s2"] > 0
    # binomial: sd sqrt(0.7 x 0.3 / 200) = 0.032; four of them
    assert row["P(peak_acceleration_m_per_s2)"] == pytest.approx(0.7, abs=4 * math.sqrt(0.21 / n_draws))
    assert row["verdict"] == "meets on the mean model only"


def test_without_uncertainty_the_same_design_meets():
    environment = Environment.from_dict({"drops": {"heights_m": [HEIGHT]},
                                         "limits": {"peak_acceleration_m_per_s2": 1.05 * math.sqrt(
                                             2 * STANDARD_GRAVITY * HEIGHT * STIFFNESS / MASS)}})
    table = judge(evaluate_candidates([Candidate("1 x spring", (spring_part(0.0),), 1, MASS)], environment,
                                      n_draws=5), environment)
    assert table.iloc[0]["P(all)"] == 1.0 and table.iloc[0]["verdict"] == "meets"


def study_candidates():
    """The transport study's seven hybrids (chapter 8: Table 7.1 rope, Table 7.3 elastomer scaled to r_k)."""
    out = []
    for item in transport_systems():
        if item.kind == "hybrid":
            system = item.system
            out.append(Candidate(item.name, (DesignPart(f"Table 7.3 x r_k {item.r_k:g}", "elastomer", system.upper),
                                             DesignPart("Table 7.1", "wire_rope", system.lower)),
                                 1, system.mass, system.intermediate_mass / system.mass))
    return out


def test_the_chosen_hybrid_for_the_study_transport_case_is_the_studys_low_r_k():
    # limits of the study: a 5 Hz resonance kept above the 3 Hz road band, and a rest shock level
    # at most the viscous reference's (thesis 8.3 compares every system with it); drops up to
    # 5 mm, where every hybrid stays inside the identified rope's valid range (docs/design.md)
    heights = [0.002, 0.005]
    reference = next(item.system for item in transport_systems() if item.kind == "reference")
    limit = float(np.max(shock_sweep(reference, drop_height=heights).rest_shock_level))
    environment = Environment.from_dict({"drops": {"heights_m": heights},
                                         "limits": {"peak_acceleration_m_per_s2": limit,
                                                    "resonance_band_hz": [2.0, 4.0]}})
    table = judge(evaluate_candidates(study_candidates(), environment, n_draws=0), environment)
    assert table.iloc[0]["name"] == "hybrid r_k=0.1"
    # thesis 8.3: "for increasing r_k ... the rest shock level is higher"
    by_rk = table.assign(r_k=table["name"].str.split("=").str[1].astype(float)).sort_values("r_k")
    assert np.all(np.diff(by_rk["peak_acceleration_m_per_s2"].to_numpy()) > 0)
    assert (table["resonance_hz"].round(1) == 5.0).all()


def test_an_executor_gives_the_serial_rows():
    environment = Environment.from_dict({"floor_psd": [{"name": "flat", "flat": 1e-4, "f_lo": 0.1, "f_hi": 100.0}],
                                         "drops": {"heights_m": [0.01]},
                                         "limits": {"rms_acceleration_m_per_s2": 1.0}})
    candidates = [Candidate(f"{n} x spring", (spring_part(),), n, MASS) for n in (1, 2, 3)]
    serial = evaluate_candidates(candidates, environment, n_draws=2, seed=5)
    with ThreadPoolExecutor(max_workers=2) as pool:
        pooled = evaluate_candidates(candidates, environment, n_draws=2, seed=5, executor=pool, chunk_size=1)
    assert pooled == serial


def test_run_design_writes_the_best_designs_as_model_files(tmp_path):
    environment = Environment.from_dict({"drops": {"heights_m": [0.01]},
                                         "limits": {"peak_acceleration_m_per_s2": 30.0, "max_deflection_m": 0.02}})
    rope = DesignPart("A.1 rope", "wire_rope", library.get("table_a1_asymmetric"))
    candidates = [Candidate(f"{n} x spring", (spring_part(),), n, MASS) for n in (1, 2)]
    candidates.append(Candidate("1 x (spring on rope)", (spring_part(), rope), 1, MASS))
    result = run_design(candidates, environment, n_draws=3, seed=1, top=2, output=tmp_path / "out")
    assert len(result.best) == 2
    for _, row in result.best.iterrows():
        system = load_model(tmp_path / "out" / "best" / f"{row['rank']}.json")
        assert system.to_dict() == result.candidates[row["name"]].system().to_dict()
    document = json.loads((tmp_path / "out" / "best" / "1.json").read_text())
    assert document["provenance"]["mounts"] == result.candidates[result.best.iloc[0]["name"]].count
    assert (tmp_path / "out" / "pareto.png").stat().st_size > 0
    assert "# Design" in (tmp_path / "out" / "design.md").read_text()


@pytest.mark.parametrize("document, message", [
    ({"limits": {"peak_acceleration_m_per_s2": 1.0}, "wind": 1}, "unknown key"),
    ({"drops": {"heights_m": [0.01]}, "limits": {"peak_acceleration_m_per_s2": -1.0}},
     r"limits: peak_acceleration_m_per_s2: found -1, expected a finite real number > 0"),
    ({"drops": {"heights_m": [0.01]}, "limits": {"resonance_band_hz": [5, 2]}}, "resonance_band_hz"),
    ({"limits": {"rms_acceleration_m_per_s2": 1.0}}, "needs floor_psd"),
    ({"floor_psd": [{"freq_hz": [1, 10]}], "limits": {"rms_acceleration_m_per_s2": 1.0}}, "required key 'level' missing"),
    ({"floor_psd": [{"flat": 1e-4, "f_lo": 10, "f_hi": 1}], "limits": {"probability": 0.5}},
     r"floor_psd\[0\]: f_lo, f_hi: found 10, 1, expected f_lo < f_hi"),
    ({"floor_psd": [{"freq_hz": [1, 10], "level": [1e-3, 1e-3, 1e-3]}], "limits": {"probability": 0.5}},
     r"floor_psd\[0\]: level: found 3 values, expected 2"),
    ({"drops": {"heights_m": [0.01], "impact_velocity_m_per_s": [1.0]}, "limits": {"probability": 0.5}},
     "drops: found .*, expected one of heights_m or impact_velocity_m_per_s"),
    ({"drops": {"heights_m": [[0.01]]}, "limits": {"max_deflection_m": 0.1}}, "drops: heights_m: found an array"),
    ({"limits": {"probability": True}}, "limits: probability: found True"),
    ([{"limits": {}}], "found list, expected an object"),
])
def test_bad_environments_are_refused_naming_the_key(document, message):
    with pytest.raises(DataError, match=message):
        Environment.from_dict(document)


@pytest.mark.parametrize(("text", "message"), [
    (None, r"environment file '.*env.json': not found"),
    ('{"limits": {"probability": 0.5}, "limits": {}}', r"key 'limits' given twice"),
    ('{"limits": {"probability": NaN}}', r"at limits.probability: found the non-finite number NaN"),
    ('{"limits": ', r"invalid JSON at line 1"),
])
def test_an_environment_file_is_read_as_strictly_as_every_input_file(tmp_path, text, message):
    """load_environment reads through idkit.inputfiles: a repeated key or a NaN is refused, not kept."""
    from idkit.design import load_environment

    if text is not None:
        (tmp_path / "env.json").write_text(text)
    with pytest.raises(DataError, match=message):
        load_environment(tmp_path / "env.json")
