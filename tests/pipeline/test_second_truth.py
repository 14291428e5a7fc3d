"""The whole pipeline on a second, different truth (issue 10 item 8).

The bundled data come from truth "a"; fitting and validating only against it invites
tuning to it. Truth "b" (:func:`idkit.synth.truth_models`) is generated here into a
temporary folder, reduced grid (``quick=True``: loops, sweeps at 5 levels with every other
frequency held out, white noise on 3 top masses, drops), and run through the public API and
what ``idkit report --quick`` computes with the defaults of the CLI.

Tolerances (issue 10 "Targets"), each a physical statement:

* loop error within 2 percentage points of what the generating force law scores on the
  same loop sets under the same objective (7.1) from the same start state: the sensor noise
  (0.05 N) and load-cell offset (0.1 N) give the truth's own floor, anything above it by
  more than 2 pp is model error;
* stuck stiffness within 20 % of ``g1 + sum k_i``; the fitted spring's tangent stiffness
  positive over every deflection of the set (loops, sweeps and drops);
* elastomer ``k0`` within 1 % (fitted with the loops' relaxation; the secant slope is biased
  high by the unrelaxed slow element), ``|k*|`` at 5, 20, 50 Hz within 5 %, loss factor within 15 %,
  small-amplitude resonance per white-noise top mass within 2 % (top mass + moving mass
  with the complex stiffness, both for the truth and the fitted model);
* validations PASS, and a model whose stiffness is doubled FAILs each of them;
* one ulp on every force moves no rope parameter by 1e-3 (relative).

Where the defaults miss a target the test is a strict xfail whose reason states the
numbers measured on this data (seed 2026); a strict xfail turns red when the target is met.
"""

from __future__ import annotations

import dataclasses
import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from idkit.fit import iwan_set_errors
from idkit.fit import fit_iwan_measurements, fit_maxwell_measurements
from idkit.io import load_measurement_set, write_measurement_set
from idkit.studies.pipeline import compute_report_data, valid_range_of, wire_rope_fit_options
from idkit.synth import (
    FILE_UNITS,
    DEFAULT_SEED,
    generate,
    generate_measurement,
    plan,
    truth_models,
)
from idkit.validate import validate_drops, validate_frf, validate_harmonic

ROPE, BODY = truth_models("b")
FREQ_HZ = np.array([5.0, 20.0, 50.0])


def _tree(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _header(path):
    with gzip.open(path, "rt") as handle:
        return handle.readline().strip()


# --------------------------------------------------------------------------- fast: the generator


def test_truth_b_differs_from_truth_a_where_identification_is_sensitive():
    rope_a, body_a = truth_models("a")
    slip = np.asarray(ROPE.fc) / np.asarray(ROPE.k)
    largest_loop = 15e-3  # SPEC 3: large loops up to 15 mm
    assert slip.max() == pytest.approx(0.5 * largest_loop, rel=0.01)  # slip goes on across them
    assert slip.max() > 1.4 * max(np.asarray(rope_a.fc) / np.asarray(rope_a.k))
    # nearly linear spring: g2 y^2 and g3 y^3 below 2 % of g1 y at the largest loop
    assert (abs(ROPE.g2) * largest_loop + abs(ROPE.g3) * largest_loop**2) < 0.02 * ROPE.g1
    assert ROPE.c_visc != rope_a.c_visc
    # loop width modulated over the whole hysteretic force, alike in tension and compression:
    # the same Jenkin states as without modulation, the loop width times m(y) = 1 + beta tanh^2
    y = np.concatenate([np.linspace(0, 12e-3, 401), np.linspace(12e-3, -12e-3, 801)[1:],
                        np.linspace(-12e-3, 12e-3, 801)[1:]])

    def width(truth):
        force = truth.quasi_static_force(y)
        return force[1200:] - force[400:1201][::-1]  # rising minus falling branch, y from -12 mm

    ratio = width(ROPE)[[100, 400, 700]] / width(dataclasses.replace(ROPE, beta=0.0))[[100, 400, 700]]
    modulation = 1 + ROPE.beta * np.tanh(np.array([-9e-3, 0.0, 9e-3]) / ROPE.y_ref) ** 2
    np.testing.assert_allclose(ratio, modulation, rtol=1e-9)
    assert modulation[0] == modulation[2] > 1.3
    rates = np.asarray(BODY.rate)
    assert rates.max() / rates.min() >= 1e3
    assert not hasattr(BODY, "internal_mass_kg") or BODY.internal_mass_kg == 0
    assert BODY.moving_mass_kg > 2 * body_a.moving_mass_kg


def test_truth_b_plan_has_every_sweep_level_in_both_splits_and_a_reduced_grid():
    items = plan(quick=True, truth="b")
    for isolator in ("wire_rope", "elastomer", "hybrid"):
        sweeps = [i for i in items if i.kind == "stepped_sine" and i.set_name == isolator]
        levels = {i.settings["amplitude_m_per_s"] for i in sweeps}
        assert min(levels) == 5e-4 and len(levels) >= 5  # near-stuck level included
        for level in levels:
            splits = {i.split for i in sweeps if i.settings["amplitude_m_per_s"] == level}
            assert splits == {"fit", "validation"}, (isolator, level)
        drops = [i for i in items if i.kind == "drop" and i.set_name == isolator]
        assert {i.split for i in drops} == {"fit", "validation"}
    masses = {i.settings["top_mass_kg"] for i in items if i.kind == "white_noise"}
    assert len(masses) >= 3
    assert plan(quick=True) == plan(quick=True, truth="a")  # the first truth's plan unchanged


def test_truth_b_files_are_deterministic_and_declare_non_si_units(data_b, tmp_path):
    # the elastomer set generated again, alone: byte for byte the files of the module's data
    # (every record draws from its own random stream, whatever else is generated)
    first = generate(tmp_path / "a", quick=True, truth="b", sets=("elastomer",))
    assert _tree(tmp_path / "a" / "elastomer") == _tree(data_b["folder"] / "elastomer")
    truth_file = data_b["folder"] / "truth" / "elastomer.json"
    assert _tree(tmp_path / "a" / "truth") == {"elastomer.json": truth_file.read_bytes()}
    assert first.counts["elastomer"]["white_noise"] == 6
    folder = tmp_path / "a" / "elastomer"
    assert _header(folder / "quasi_static" / "qs_el_loops_1.csv.gz") == \
        "time [s],deflection [mm],force [kN]"
    drop = next((folder / "drop").iterdir())
    assert _header(drop) == "time [s],deflection [mm],a_top_1 [g],a_top_2 [g],v_rel [mm/s]"
    assert "[m/s]" in _header(next((folder / "white_noise").iterdir()))
    truth = json.loads((tmp_path / "a" / "truth" / "elastomer.json").read_text())
    assert truth["truth"] == "b" and truth["file_units"] == FILE_UNITS["b"]
    # the loader converts back to SI: the generator's own SI values to the last bits
    loaded = {m.info.id: m for m in load_measurement_set(folder).measurements}
    for ident in ("qs_el_loops_1", drop.name.removesuffix(".csv.gz")):
        item = next(i for i in plan(quick=True, truth="b") if i.id == ident)
        made, _ = generate_measurement(item, seed=DEFAULT_SEED, quick=True)
        for column, values in made.signals().items():
            np.testing.assert_allclose(loaded[ident].signals()[column], values, rtol=1e-12, atol=1e-15)
    # independent random streams: truth "b" does not reuse truth "a"'s noise for an id
    item_b = next(i for i in plan(quick=True, truth="b") if i.id == "qs_el_loops_1")
    item_a = next(i for i in plan(quick=True) if i.id == "qs_el_loops_1")
    assert generate_measurement(item_b)[1]["seed"] != generate_measurement(item_a)[1]["seed"]


# --------------------------------------------------------------------------- slow: the pipeline


@pytest.fixture(scope="module")
def data_b(tmp_path_factory):
    folder = tmp_path_factory.mktemp("truth_b")
    generate(folder, quick=True, truth="b")
    return {name: load_measurement_set(folder / name) for name in ("wire_rope", "elastomer", "hybrid")} | \
        {"folder": folder}


@pytest.fixture(scope="module")
def report_b(data_b):
    """What ``idkit report --quick`` computes with the CLI's defaults
    (:func:`~idkit.studies.pipeline.compute_report_data`, the call ``run_report`` makes); its
    transport study is not read here."""
    data = compute_report_data(data_b["folder"], quick=True)
    data.abandon_transport()
    return data


@pytest.fixture(scope="module")
def rope_fit(report_b):
    # the report's wire-rope fit (order="auto", family="auto", the set's valid range: the
    # options of wire_rope_fit_options), computed once for the report test and the rope's tests
    return report_b.iwan


@pytest.fixture(scope="module")
def body_fit_quick(data_b):
    return fit_maxwell_measurements(data_b["elastomer"])  # order="auto", monotone_loss="auto"


@pytest.fixture(scope="module")
def body_fit(tmp_path_factory):
    # the elastomer's targets on full-length records: the quick set's 4 s white-noise runs give
    # H1 steps of 1 Hz that cannot resolve the resonances (see the resolution test below).
    # The fit reads only the fit split's loops and white-noise runs (fit_maxwell_measurements),
    # so only those of the full elastomer plan are generated, and written and read back in the
    # files' non-SI units as `idkit data generate` writes them: the same records, the same fit.
    # Not compressed: gzip changes no value read back and is the costliest part of writing
    # (the .csv.gz reading path is the quick set's, data_b above)
    items = [item for item in plan(truth="b") if item.set_name == "elastomer" and item.split == "fit"
             and item.kind in ("quasi_static", "white_noise")]
    folder = tmp_path_factory.mktemp("truth_b_elastomer") / "elastomer"
    write_measurement_set(folder, [generate_measurement(item, seed=DEFAULT_SEED)[0] for item in items],
                          gzip=False, units=FILE_UNITS["b"])
    return fit_maxwell_measurements(load_measurement_set(folder))


def _validation(measurement_set, kind):
    return [m for m in measurement_set.measurements if m.kind == kind and m.info.split == "validation"]


def _truth_loop_error(loop_set) -> float:
    """Relative RMS error (7.1) of the generating force law on a loop set from the virgin
    state (every record of truth "b" starts unloaded: loaded monotonically to the first point)."""
    ramp = np.linspace(0.0, loop_set.deflection[0], 200)
    force = ROPE.quasi_static_force(np.concatenate([ramp, loop_set.deflection[1:]]))[ramp.size - 1:]
    return float(np.sqrt(np.sum((force - loop_set.force) ** 2) / np.sum(loop_set.force**2)))


def _resonance(stiffness, mass, freq):
    transmissibility = np.abs(stiffness / (stiffness - mass * (2 * np.pi * freq) ** 2))
    return freq[np.argmax(transmissibility)]


@pytest.mark.slow
def test_rope_fit_is_valid_over_the_data_and_its_damping_is_identified(data_b, rope_fit):
    assert rope_fit.success, rope_fit.reasons
    assert all(s.starts_unloaded for s in rope_fit.data.small + rope_fit.data.large)
    lower, upper = rope_fit.model.valid_deflection_range()
    seen = [m.deflection for m in data_b["wire_rope"].measurements if getattr(m, "deflection", None) is not None]
    assert lower <= min(d.min() for d in seen) and max(d.max() for d in seen) <= upper
    # c_visc from the largest fit level's resonance: the truth's 12 N s/m within 25 %
    # (the order-2 hysteresis dissipates differently, the viscous term absorbs the rest)
    assert rope_fit.model.c_visc == pytest.approx(ROPE.c_visc, rel=0.25)


@pytest.mark.slow
def test_rope_family_rule_picks_a_model_whose_parameters_the_loops_determine(rope_fit):
    # order 2 (the thesis's) scored 5.6 % / 3.4 %: two elements cannot hold slip spread over
    # 20 um - 7.5 mm. The plain rule reaches 1.5 / 1.8 % at order 6, but orders 5 and 6 carry
    # an element slipping only at the tips of the largest loops, traded against g1
    # (correlation 1.000), so they are not successes (docs/fitting.md, "Verdicts") and the plain
    # rule keeps a lower, determined order, above the loops' noise floor: the family rule then
    # tries the slip-modulated model, whose symmetric term follows the truth's loop width
    # growing alike in tension and compression
    table = rope_fit.order_table
    plain = table[table["family"] == "plain"]
    traded = plain[plain["reasons"].str.contains("determined only in combination")]
    assert len(traded) and not traded["success"].any()
    assert not rope_fit.family_fits["plain"].undetermined
    assert rope_fit.result.settings.family == "modulated" and not rope_fit.result.undetermined
    assert rope_fit.model.slip_growth > 0.2  # the loops widen at both ends (truth: 0.4 tanh^2)
    chosen = table[table["recommended"]]
    assert len(chosen) == 1 and bool(chosen["success"].iloc[0])
    mean = 0.5 * (chosen["error_small_percent"] + chosen["error_large_percent"]).iloc[0]
    assert mean < (0.5 * (plain["error_small_percent"] + plain["error_large_percent"])).min()


@pytest.mark.slow
def test_rope_loop_errors_within_2_points_of_the_truth(rope_fit):
    sets = list(rope_fit.data.small) + list(rope_fit.data.large)
    fitted = iwan_set_errors(rope_fit.model, sets)
    truth = np.array([_truth_loop_error(s) for s in sets])
    assert np.all(truth < 0.005)  # the truth's floor: noise and offset only
    assert np.all(fitted - truth <= 0.02), (fitted, truth)


@pytest.mark.slow
def test_rope_stuck_stiffness_within_20_percent(rope_fit):
    model = rope_fit.model
    assert model.g1 + sum(model.k) == pytest.approx(ROPE.stuck_stiffness, rel=0.20)


@pytest.mark.slow
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_rope_tangent_stiffness_at_large_amplitude_within_10_percent(rope_fit, side):
    # loading from rest to 90 % of the largest loop amplitude, either way: the tangent there
    # (central difference over 1 % of the stroke, both models on the same path) is the spring
    # plus the slip-force modulation of the truth once every element slips
    large = max(float(np.max(np.abs(s.deflection))) for s in rope_fit.data.large)
    path = side * np.linspace(0.0, 0.91 * large, 9101)
    at, step = 9000, 90  # index of 0.90 x the amplitude, +-1 % of the stroke

    def tangent(force):
        return (force[at + step] - force[at - step]) / (path[at + step] - path[at - step])

    fitted = tangent(rope_fit.model.force(path))
    truth = tangent(ROPE.quasi_static_force(path))
    assert fitted == pytest.approx(truth, rel=0.10)


@pytest.mark.slow
def test_elastomer_k0_within_1_percent(body_fit_quick, body_fit):
    # the loops' secant slope reads the slowest Maxwell element (900 N/m, rate 2 1/s), not yet
    # relaxed at the zero crossings 1-4 s after a reversal: +1.0 % (full records) and +1.5 %
    # (quick); the default k0 fits the loops' relaxation (idkit.fit.static_stiffness)
    for fit in (body_fit_quick, body_fit):
        assert fit.k0.method == "relaxation"
        assert fit.model.params()["k0"] == pytest.approx(BODY.k0, rel=0.01)
        assert fit.k0.secant_k0 > 1.005 * BODY.k0  # the bias the fit removes


@pytest.mark.slow
def test_elastomer_fit_on_records_too_short_for_the_resonances_says_so(body_fit_quick, body_fit):
    # 4 s runs: the H1 step is 1 Hz (window bandwidth 1.5 Hz) for resonances 1-4 Hz wide
    assert not body_fit_quick.success
    assert any("cannot resolve its resonance" in reason for reason in body_fit_quick.reasons)
    assert body_fit.success, body_fit.reasons  # the full-length records resolve them


@pytest.mark.slow
def test_elastomer_loss_factor_falls_so_the_constraint_is_dropped(body_fit):
    # truth "b"'s loss factor falls from 0.145 at 5 Hz to 0.101 at 100 Hz; with the SPEC's
    # non-decreasing constraint the order-2 fit scored 15.6 % (|k*| -21..-17 %, loss factor
    # +72 % at 50 Hz, m_eff 0.04 kg for 0.30 kg); without it 3.7 %
    truth = BODY.complex_stiffness(np.array([5.0, 100.0]))
    assert (truth.imag / truth.real)[1] < (truth.imag / truth.real)[0]
    settings = body_fit.result.settings
    assert settings.monotone_loss is False and "dropped" in settings.loss_rule
    # the constrained fit put m_eff at 0.04 kg for 0.30 (-87 %); free and about each preload, a
    # three-element model of the seven-element truth reads 0.297 kg (0.272 about k0): within
    # 5 %, the issue's |k*| tolerance (m_eff and stiffness trade off in the transmissibility)
    assert body_fit.model.m_eff == pytest.approx(BODY.moving_mass_kg, rel=0.05)


@pytest.mark.slow
def test_elastomer_complex_stiffness_within_5_percent(body_fit):
    truth = BODY.complex_stiffness(FREQ_HZ)
    np.testing.assert_allclose(np.abs(body_fit.model.complex_stiffness(FREQ_HZ)), np.abs(truth), rtol=0.05)


@pytest.mark.slow
def test_elastomer_loss_factor_within_15_percent_at_20_and_50_hz(body_fit):
    truth = BODY.complex_stiffness(FREQ_HZ[1:])
    np.testing.assert_allclose(body_fit.model.loss_factor(FREQ_HZ[1:]), truth.imag / truth.real, rtol=0.15)


@pytest.mark.slow
def test_elastomer_loss_factor_within_15_percent_at_5_hz(body_fit):
    # on the quick set's 4 s runs it read 0.23 for 0.145 (+60 %): the 1 Hz H1 step smears the
    # heavy masses' resonances (the fit says so, test above)
    truth = BODY.complex_stiffness(FREQ_HZ[:1])
    np.testing.assert_allclose(body_fit.model.loss_factor(FREQ_HZ[:1]), truth.imag / truth.real, rtol=0.15)


@pytest.mark.slow
def test_elastomer_resonance_per_top_mass_within_2_percent(data_b, body_fit):
    freq = np.linspace(1.0, 100.0, 19801)
    model = body_fit.model
    masses = sorted({m.info.top_mass_kg for m in data_b["elastomer"].measurements if m.kind == "white_noise"})
    assert len(masses) >= 3
    for mass in masses:
        truth = _resonance(BODY.complex_stiffness(freq), mass + BODY.moving_mass_kg, freq)
        fitted = _resonance(model.complex_stiffness(freq), mass + model.m_eff, freq)
        assert fitted == pytest.approx(truth, rel=0.02), mass


@pytest.mark.slow
def test_validations_that_pass_and_fail_for_a_doubled_stiffness(data_b, rope_fit, body_fit):
    body, rope = body_fit.model, rope_fit.model
    elastomer, hybrid, wire_rope = data_b["elastomer"], data_b["hybrid"], data_b["wire_rope"]
    passing = {
        "harmonic elastomer": lambda b: validate_harmonic(_validation(elastomer, "stepped_sine"), isolator=b),
        "harmonic hybrid": lambda b: validate_harmonic(_validation(hybrid, "stepped_sine"), upper=b, lower=rope),
        "drops elastomer": lambda b: validate_drops(_validation(elastomer, "drop"), isolator=b),
    }
    for name, run in passing.items():
        assert run(body).verdict == "PASS", name
        assert run(body.scaled(2.0)).verdict == "FAIL", name
    drops = validate_drops(_validation(wire_rope, "drop"), isolator=rope)
    assert drops.verdict == "PASS", drops.report()
    drops_hybrid = validate_drops(_validation(hybrid, "drop"), upper=body, lower=rope)
    assert drops_hybrid.verdict == "PASS", drops_hybrid.report()


@pytest.mark.slow
def test_a_feasible_loop_optimum_is_kept_by_the_valid_range_fit(data_b, rope_fit):
    """Truth "b"'s rope: the loops' own optimum keeps the spring stiff over 1.25 x the data
    set's deflections, so the barrier is inactive there and the report's (valid-range) fit is
    that optimum, the same on every numpy CPU path (a refit from it wandered into a 2.1 %
    minimum on one path)."""
    from idkit.models.laws import lowest_spring_stiffness

    low, high = valid_range_of(data_b["wire_rope"])
    ranged = rope_fit  # the report's fit: its valid range is 1.25 x the set's deflections
    assert ranged.result.settings.valid_range == (low, high) and ranged.success, ranged.reasons
    # the loops' own optimum: the same options without the valid range
    options = wire_rope_fit_options(data_b["wire_rope"]) | {"valid_range": None}
    free = fit_iwan_measurements(data_b["wire_rope"], **options).model
    assert lowest_spring_stiffness(free.g1, free.g2, free.g3, low, high) >= 0.0
    # an inactive barrier changes the objective by rounding only, which moves a determined
    # optimum by about that perturbation over the conditioning (measured 2e-15 here; one ulp
    # on every force moves it by ~1e-13, the ulp test below): 1e-6 leaves room for other CPUs
    assert ranged.model.params().keys() == free.params().keys()
    for name, value in free.params().items():
        assert ranged.model.params()[name] == pytest.approx(value, rel=1e-6), name


@pytest.mark.slow
def test_wire_rope_sweeps_and_elastomer_frf_pass(data_b, rope_fit, body_fit):
    harmonic = validate_harmonic(_validation(data_b["wire_rope"], "stepped_sine"), isolator=rope_fit.model)
    frf = validate_frf(_validation(data_b["elastomer"], "white_noise"), isolator=body_fit.model)
    assert harmonic.verdict == "PASS", harmonic.report()
    assert frf.verdict == "PASS", frf.report()
    doubled = validate_frf(_validation(data_b["elastomer"], "white_noise"), isolator=body_fit.model.scaled(2.0))
    assert doubled.verdict == "FAIL", doubled.report()


@pytest.mark.slow
def test_report_on_truth_b_passes_every_validation_and_flags_only_the_unresolved_frf(report_b):
    """Every validation PASS; exit status 4 because the quick set's 4 s white-noise records
    cannot resolve the elastomer's resonances (the Maxwell fit says so, see the resolution
    test below; on full-length records the same fit is a success), while the wire-rope fit is
    a success.

    What ``idkit report --quick`` computes with the CLI's defaults (fits, validations:
    :func:`~idkit.studies.pipeline.compute_report_data`, the call ``run_report`` makes), and
    the status and lines the CLI derives from it; the page itself (its figures, tables and
    the CLI's exit status end to end) is tested on the bundled data in tests/report/test_report.py.
    """
    from idkit.cli.report import verdict_lines
    from idkit.report.front_page import PREDICTING_FITS
    from idkit.report.main_report import ReportSummary

    data = report_b
    # the summary the CLI prints from (no page is written here, hence no folder)
    summary = ReportSummary(out_dir=Path("."), html=Path("report.html"), sections=(),
                            validation_passed={}, timings_s={}, validation_verdicts=data.verdicts, quick=True,
                            fit_reasons=dict(zip(PREDICTING_FITS, (tuple(data.iwan.reasons),
                                                                   tuple(data.maxwell.reasons)))))
    lines = verdict_lines(summary, "quick").splitlines()
    printed = dict(line.split(None, 1)[::-1] for line in lines
                   if line.split(None, 1)[0] in ("PASS", "FAIL", "INCONCLUSIVE"))
    flagged = [line.split(None, 1)[1] for line in lines if line.startswith("FLAGGED")]
    assert len(flagged) == 1 and flagged[0].startswith("elastomer (generalized Maxwell) fit:"), flagged
    assert "cannot resolve its resonance" in flagged[0]
    # PASS for physical reasons: the components each validation sees are right (the
    # tests above), and a doubled stiffness fails them (test_validations_that_pass_and_fail_...).
    # With the thesis's order 2 the wire-rope sweeps failed (rms 3.5 dB, peak 6.3 dB) and the
    # elastomer FRF failed (resonance 12.5 %) with the loss-factor constraint imposed.
    assert set(printed) == {"wire rope sweeps", "wire rope drops", "elastomer FRF", "elastomer sweeps",
                            "elastomer drops", "hybrid sweeps", "hybrid drops", "wire rope force histories",
                            "elastomer force histories"}, printed  # the held-out loop records (validate.history)
    assert set(printed.values()) == {"PASS"}, printed
    assert summary.exit_status == 4


@pytest.mark.slow
@pytest.mark.parametrize("direction", [-np.inf])  # one ulp down; test_first_truth moves them up
def test_rope_parameters_agree_to_1e3_when_the_forces_move_by_one_ulp(data_b, rope_fit, direction):
    """Issue 10's target: one ulp on every force sample moves every parameter by less than
    1e-3 (relative), and the verdict, family and order not at all. It did not hold: the plain
    fits of orders 5 and 6 trade g1 against a tip element (g1 12.6e3 or 19.6e3 N/m one ulp
    apart), and a modulation stage started from the plain fit of each order followed them
    into other local minima. The chosen fit now determines every parameter and the modulated
    orders are built by continuation (each from the one below, fit_modulated_orders): the
    parameters agree to ~1e-13 on both CPU paths (measured). 1e-3 is the target; a
    determined optimum (largest |correlation| well below 1) moves by about the perturbation's
    own size over the conditioning, orders of magnitude below it."""
    records = [dataclasses.replace(m, force=np.nextafter(m.force, direction)) if m.kind == "quasi_static" else m
               for m in data_b["wire_rope"].measurements]
    again = fit_iwan_measurements(records, **wire_rope_fit_options(data_b["wire_rope"]))  # the report's options
    assert again.success == rope_fit.success
    assert again.result.settings.family == rope_fit.result.settings.family
    assert again.model.order == rope_fit.model.order
    first, second = rope_fit.model.params(), again.model.params()
    assert first.keys() == second.keys()
    moved = {name: second[name] / first[name] - 1 for name in first if first[name]}
    assert max(abs(v) for v in moved.values()) < 1e-3, moved


@pytest.mark.slow
def test_elastomer_parameters_agree_to_1e3_when_every_sample_moves_by_one_ulp(data_b, body_fit_quick):
    # every floating-point sample of every elastomer record (loops, white noise, sweeps, drops;
    # not the time base) one ulp up, CLI defaults: measured 3e-7 (quick set) and 2.5e-6 (full)
    def moved(measurement):
        fields = {f.name: np.nextafter(getattr(measurement, f.name), np.inf) for f in dataclasses.fields(measurement)
                  if f.name != "time" and isinstance(getattr(measurement, f.name), np.ndarray)
                  and getattr(measurement, f.name).dtype.kind == "f"}
        return dataclasses.replace(measurement, **fields)

    again = fit_maxwell_measurements([moved(m) for m in data_b["elastomer"].measurements])
    first = body_fit_quick.model.params()
    assert again.success == body_fit_quick.success and again.model.params().keys() == first.keys()
    for name, value in first.items():
        assert again.model.params()[name] == pytest.approx(value, rel=1e-3, abs=1e-12), name
