"""Fits on the bundled synthetic data (data/, richer truth than the fitted models).

Stated errors and why:

* Iwan order 2 (7.1), fit split: large loops <= 6 %, small loops <= 11 % (reached:
  5.1 % and 9.9 %). The truth is an order-30 Iwan model with slip forces that change
  with deflection (loops wider in compression) and a bottoming stiffener; two
  elements cannot follow that, and the thesis reached 7.1 % / 7.7 % on real loops.
  The truth's force noise (0.05 N on loops of 100-600 N) alone is below 0.1 %.
* Maxwell (7.5) over 1-100 Hz, all 8 masses x 2 repetitions: order 2 <= 13 %
  (reached 12.1 %), order 3 <= 11.5 % (10.8 %). The truth has an internal 65 g mass
  between two elastomer halves (a mode near 200 Hz) which bends the FRFs above
  50 Hz by up to 20 %: no single-node Maxwell model reaches below ~10 %, which is
  why the table flattens there (thesis on real data: 12.0, 9.4, 8.8, 8.8 and 22.0 %).
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from idkit.fit import (
    bootstrap_measurements,
    fit_iwan_measurements,
    fit_maxwell_measurements,
    k0_from_measurements,
    transmissibility_sets,
)
from idkit.io import load_measurement_set
from idkit.models import load_model, load_model_document

DATA = Path(__file__).resolve().parents[2] / "data"
IWAN_LARGE_MAX = 0.06
IWAN_SMALL_MAX = 0.11
MAXWELL_2_MAX = 0.13
MAXWELL_3_MAX = 0.115
K0_TRUE = 13.8e3  # N/m, truth file: static stiffness of the elastomer
K0_TOL = 0.01  # k0 from the loops within 1 % (the truth softens in compression only, beyond 1 mm)

pytestmark = pytest.mark.skipif(not (DATA / "wire_rope" / "manifest.json").exists(),
                                reason="bundled data set data/ not generated in this checkout")


@pytest.fixture(scope="module")
def wire_rope():
    return load_measurement_set(DATA / "wire_rope").select(kind="quasi_static")


@pytest.fixture(scope="module")
def elastomer():
    full = load_measurement_set(DATA / "elastomer")
    return [m for m in full if m.kind in ("quasi_static", "white_noise")]


@pytest.fixture(scope="module")
def iwan_fit(wire_rope):
    return fit_iwan_measurements(wire_rope)


@pytest.fixture(scope="module")
def maxwell_fit(elastomer):
    return fit_maxwell_measurements(elastomer)


def test_iwan_fit_reaches_the_stated_errors_on_the_fit_split(iwan_fit):
    result = iwan_fit.result
    assert [s.name for s in iwan_fit.data.small] == ["qs_wr_small_1", "qs_wr_small_2"]
    assert [s.name for s in iwan_fit.data.large] == ["qs_wr_large_1", "qs_wr_large_2"]
    assert result.error_large <= IWAN_LARGE_MAX
    assert result.error_small <= IWAN_SMALL_MAX
    assert result.success


def test_k0_from_the_elastomer_loops(elastomer):
    k0 = k0_from_measurements(elastomer)
    assert k0.k0 == pytest.approx(K0_TRUE, rel=K0_TOL)
    assert 0 < k0.stderr < 0.01 * k0.k0
    assert set(k0.per_record) == {"qs_el_loops_1", "qs_el_loops_2"}  # fit split only


def test_maxwell_fit_and_order_table(maxwell_fit, elastomer):
    result = maxwell_fit.result
    assert len(maxwell_fit.data) == 16  # 8 masses x repetitions 1-2
    assert result.error <= MAXWELL_2_MAX
    assert all(result.parameters[name].stderr is not None for name in ("k_1", "k_2", "rate_1", "rate_2", "m_eff"))
    # the table the order rule chose from: order "auto" runs maxwell_order_table on the fit's FRFs and k0
    assert maxwell_fit.options["order_rule"] and maxwell_fit.model.order == 2
    table = maxwell_fit.order_table.set_index("model", append=True)
    errors = table["error_percent"].to_numpy()
    maxwell, voigt = errors[:4], errors[4]
    # orders 1-4 (with the loss rule each drops the non-decreasing constraint, which costs the
    # bundled data 12.2 -> 8.8 % at order 2: the internal mode near 200 Hz bends the loss factor
    # down above 50 Hz): 12.0 / 8.8 / 8.8 / 8.9 %, Voigt 29.9 %
    assert maxwell[1] < 0.8 * maxwell[0]  # falls ...
    assert maxwell[2] <= 100 * MAXWELL_3_MAX
    assert maxwell[3] >= maxwell[2] - 0.2  # ... then flattens (order 4 gains < 0.2 points)
    assert voigt > 2 * maxwell[1]  # Voigt clearly worse


def test_model_file_carries_the_provenance(iwan_fit, wire_rope, tmp_path):
    path = iwan_fit.save(tmp_path / "wr.json")
    model = load_model(path)
    assert model.params() == pytest.approx(iwan_fit.model.params())
    provenance = load_model_document(path)["provenance"]
    files = provenance["data"]["files"]
    assert files == {"quasi_static/qs_wr_small_1.csv.gz": wire_rope.get("qs_wr_small_1").source.sha256,
                     "quasi_static/qs_wr_small_2.csv.gz": wire_rope.get("qs_wr_small_2").source.sha256,
                     "quasi_static/qs_wr_large_1.csv.gz": wire_rope.get("qs_wr_large_1").source.sha256,
                     "quasi_static/qs_wr_large_2.csv.gz": wire_rope.get("qs_wr_large_2").source.sha256}
    assert provenance["settings"]["seed"] == 0 and provenance["settings"]["backend"] == "nlopt"
    assert provenance["idkit_version"] and provenance["options"]["small_threshold"] == pytest.approx(
        math.sqrt(4.5e-3 * 15e-3), rel=1e-3)  # the data's own split: geometric mean of 4.5 and 15 mm
    json.dumps(provenance, allow_nan=False)
    with pytest.raises(FileExistsError):
        iwan_fit.save(path)


@pytest.mark.parametrize("method", ["repetition", "resample"])
def test_bootstrap_is_reproducible_and_brackets_the_fit(iwan_fit, method):
    first = bootstrap_measurements(iwan_fit, method=method, n_resamples=6, seed=11)
    second = bootstrap_measurements(iwan_fit, method=method, n_resamples=6, seed=11)
    assert np.array_equal(first.samples, second.samples)  # bit for bit
    assert first.samples.shape[0] == (2 if method == "repetition" else 6)
    summary = first.summary().set_index("parameter")
    fitted = iwan_fit.model.params()
    for name in ("g1", "k_1", "fc_1", "fc_2"):
        assert abs(summary.loc[name, "mean"] - fitted[name]) <= 4 * summary.loc[name, "std"] + 0.02 * fitted[name]
        assert summary.loc[name, "p05"] <= summary.loc[name, "p95"]
    assert "Bootstrap" in first.report()


def test_maxwell_bootstrap_per_repetition(maxwell_fit):
    spread = bootstrap_measurements(maxwell_fit)
    assert spread.labels == ("repetition 1", "repetition 2")
    summary = spread.summary().set_index("parameter")
    assert summary.loc["rate_2", "relative_std"] < 0.05


def test_transmissibility_sets_use_every_mass_and_repetition(elastomer):
    frfs, provenance = transmissibility_sets(elastomer, split=None)
    assert len(frfs) == 24 and len({f.mass for f in frfs}) == 8
    assert frfs[0].freq.min() >= 1.0 and frfs[0].freq.max() <= 100.0
    assert len(provenance.files) == 24


def test_parameters_table_shows_stderr_and_spread_across_repetitions(iwan_fit):
    """Value, stderr from the residual Jacobian (or why none) and the spread of one refit
    per repetition, side by side (what the report's Iwan table shows)."""
    fit = iwan_fit.with_repetition_spread()
    assert fit.spread is not None and fit.spread.labels == ("repetition 1", "repetition 2")
    table = fit.parameters_table().set_index("parameter")
    for name in ("g1", "g2", "g3", "k_1", "k_2", "fc_1", "fc_2"):
        row = table.loc[name]
        assert (row["stderr"] is not None and row["stderr"] > 0) or row["stderr_note"], name
        assert row["repetitions"] == 2 and np.isfinite(row["repetition_std"]), name
        assert len(row["repetition_values"].split(", ")) == 2
    assert table.loc["c_visc", "stderr_note"] == "fixed in the fit"
    assert "spread across repetitions: repetition, 2 refits" in fit.report()


def test_one_repetition_has_no_spread_and_says_why(wire_rope):
    first = [m for m in wire_rope if m.info.repetition == 1]
    # one order and family given (the rules' chain is not under test): the spread is absent
    # because one repetition leaves nothing to refit, whatever the model
    fit = fit_iwan_measurements(first, order=2, family="plain").with_repetition_spread()
    assert fit.spread is None and "at least 2" in fit.spread_note
    table = fit.parameters_table()
    assert table["repetition_std"].isna().all() and (table["repetitions"] == 0).all()
    assert fit.spread_note in fit.report()


def test_a_model_that_cannot_run_the_largest_sweep_level_is_not_a_success(iwan_fit):
    # the fitted rope runs the data set's largest stepped-sine level (0.12 m/s, base amplitudes
    # up to ~2 mm near resonance); the same rope with a cubic that turns the spring negative
    # at +-1.4 mm cannot, and the measurement-level check names the level and the first point
    from idkit.fit.data_set_checks import survives_the_largest_sweep_level
    from idkit.models import IwanModel

    wire_rope = load_measurement_set(DATA / "wire_rope")  # every record, the sweeps included
    model = iwan_fit.model
    assert survives_the_largest_sweep_level(model, wire_rope, "wire_rope") == ()
    soft = IwanModel(g1=model.g1, g2=model.g2, g3=-3e9, k=model.k, fc=model.fc, c_visc=model.c_visc)
    assert max(abs(x) for x in soft.valid_deflection_range()) < 2e-3
    reasons = survives_the_largest_sweep_level(soft, wire_rope, "wire_rope")
    assert reasons and "largest sweep level (0.12" in reasons[0] and "negative local stiffness" in reasons[0]


def test_the_fit_report_gives_one_c_visc_per_meaning():
    """The loop fit holds c_visc at 0 and the model carries the value from the stepped-sine
    resonance: the report's parameter list said "c_visc 0 (fixed)" under a header giving
    13.9 N s/m, with nothing to tell the two apart."""
    # loops and sweeps; one order and family given: c_visc comes from the sweeps' resonance
    # and is held in the loop fit whatever the order, so the rules' chain is not needed here
    iwan_fit = fit_iwan_measurements(load_measurement_set(DATA / "wire_rope"), order=2, family="plain")
    assert iwan_fit.damping is not None
    text = iwan_fit.report()
    lines = [line for line in text.splitlines() if line.strip().startswith("c_visc")]
    identified = f"{iwan_fit.damping.c_visc:.4g} N s/m"
    assert len(lines) == 2 and all(identified in line for line in lines)
    assert "the loop fit's; the model's" in lines[1] and "(fixed)" in lines[1]
    assert iwan_fit.model.c_visc == pytest.approx(iwan_fit.damping.c_visc, rel=1e-12)


def test_iwan_order_table_shows_the_fit_the_model_is():
    """The report's fit (valid range of the whole set): the bundled rope's own order-3 optimum turns
    negative-stiff inside the range, so the model is the barrier refit. Its row in the order table
    is the one recommended, with the model's own loop errors (before: the table recommended the
    loops' own fit, 4.87 / 4.17 %, while the report's sentence quoted the refit's 4.91 / 4.18 %)."""
    from idkit.studies.pipeline import valid_range_of

    rope = load_measurement_set(DATA / "wire_rope")
    fit = fit_iwan_measurements(rope, family="plain", valid_range=valid_range_of(rope), damping_level=None)
    table = fit.order_table
    chosen = table[table["recommended"]]
    assert len(chosen) == 1
    assert chosen["error_small_percent"].iloc[0] == 100 * fit.result.error_small
    assert chosen["error_large_percent"].iloc[0] == 100 * fit.result.error_large
    assert chosen["stuck_stiffness [N/m]"].iloc[0] == fit.model.stuck_stiffness
    from idkit.fit.measurement_level import VALID_RANGE_FIT

    assert chosen["order"].iloc[0] == fit.model.order and chosen["fit"].iloc[0] == VALID_RANGE_FIT
    # the rule's candidates are the loops' own fits, one per order
    loops = table[table["fit"] == "loops"]
    assert sorted(loops["order"]) == [1, 2, 3, 4, 5, 6]
