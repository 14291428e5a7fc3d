"""Scaling laws: the generator's exponents come back within their standard errors; bands cover."""

import math

import numpy as np
import pytest

from idkit.catalogue.scaling import fit_scaling_law, leave_one_part_out
from idkit.errors import FitError
from idkit.synth.catalogue import COMPOUNDS, WIRE_ROPE_EXPONENTS, elastomer_family, wire_rope_family

#: standard errors an estimate may stray by: 3.5 SE leaves a 5e-4 chance per exponent for a
#: correct law (normal), so a seed that fails points at the method, not at bad luck
SE_BOUND = 3.5


def rope_records(**options):
    return [{"part": p.part, "family": "wire_rope", "dimensions": p.dimensions,
             "quantities": {"stuck_stiffness": p.truth.stuck_stiffness, "total_slip_force": float(sum(p.truth.fc)),
                            "g1": p.truth.g1},
             "covariance": {"names": [], "matrix": []}} for p in wire_rope_family(**options)]


def elastomer_records(**options):
    return [{"part": p.part, "family": "elastomer", "dimensions": p.dimensions, "quantities": {"k0": p.truth.k0},
             "covariance": {"names": [], "matrix": []}} for p in elastomer_family(**options)]


@pytest.mark.parametrize("seed", [1, 2026])
@pytest.mark.parametrize("quantity, law", [("stuck_stiffness", "stiffness"), ("total_slip_force", "slip_force")])
def test_wire_rope_power_laws_recover_the_generator_exponents(seed, quantity, law):
    fitted = fit_scaling_law(rope_records(seed=seed), quantity)
    for dimension in fitted.dimensions:
        value, stderr = fitted.exponent(dimension)
        assert abs(value - WIRE_ROPE_EXPONENTS[law][dimension]) < SE_BOUND * stderr, (dimension, value, stderr)
    # the part-to-part scatter the generator put in (0.04 in log; two factors enter each part's
    # stuck stiffness only through S_k): an estimate of 36 parts within 40 %
    assert fitted.tau == pytest.approx(0.04, rel=0.4)


def test_elastomer_law_recovers_the_compression_rule_and_the_compounds_moduli():
    fitted = fit_scaling_law(elastomer_records(seed=3), "k0")
    value, stderr = fitted.exponent("geometry")
    assert abs(value - 1.0) < SE_BOUND * stderr  # to_stiffness: k = E (1 + 2 S^2) A / h
    for index, compound in enumerate(fitted.compounds):
        modulus = math.exp(fitted.coefficients[index]) / fitted.reference["geometry"]
        stderr = math.sqrt(fitted.covariance[index, index])
        assert abs(math.log(modulus / COMPOUNDS[compound].k0)) < SE_BOUND * stderr + 1e-12


def test_noise_free_laws_are_exact_and_predict_an_unmeasured_part_exactly():
    # the truths round k_i to 0.01 N/m and fc_i to 1e-5 N (relative 1e-7 at most): tolerance 1e-6
    records = rope_records(scatter=0.0)
    fitted = fit_scaling_law(records[1:], "stuck_stiffness")
    for dimension in fitted.dimensions:
        assert fitted.exponent(dimension)[0] == pytest.approx(WIRE_ROPE_EXPONENTS["stiffness"][dimension], abs=1e-6)
    assert fitted.tau < 1e-6
    prediction = fitted.predict(records[0]["dimensions"])
    assert prediction.value == pytest.approx(records[0]["quantities"]["stuck_stiffness"], rel=1e-6)


def test_leave_one_part_out_coverage_of_the_95_percent_band():
    coverage = leave_one_part_out(rope_records(seed=11), "stuck_stiffness")
    # nominal 95 %: with 36 parts the count inside is binomial (sd 1.3 parts); the target is 90 %
    assert coverage["inside"].mean() >= 0.9
    assert np.all(coverage["low"] < coverage["predicted"]) and np.all(coverage["predicted"] < coverage["high"])


def test_too_few_parts_and_collinear_dimensions_are_refused():
    records = rope_records(count=3)
    with pytest.raises(FitError, match="found 3 parts, expected at least 5"):
        fit_scaling_law(records, "stuck_stiffness")
    with pytest.raises(FitError, match="do not vary independently"):
        fit_scaling_law(rope_records(), "stuck_stiffness", dimensions=("cable_diameter_m", "height_m", "width_m"))
