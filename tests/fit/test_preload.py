"""A softening elastomer under its top masses: static operating points, the preloaded Maxwell fit
and the FRF validation about the same preload.

The static law is the generator's softening spring ``F = k0 y (1 - a tanh^2(min(y, 0) / y_s))``
(compression negative): its tangent at the static deflection of a top mass is known in closed
form, so the operating points are checked against it, and FRFs built with that tangent in
place of ``k0`` are the truth the preloaded fit must recover.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from idkit.fit import TransmissibilitySet, fit_maxwell, maxwell_objective
from idkit.gravity import STANDARD_GRAVITY
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, WhiteNoiseMeasurement
from idkit.models import GeneralizedMaxwell, SDOFSystem
from idkit.observe.k0 import static_operating_point
from idkit.validate import validate_frf

K0, ALPHA, Y_SOFT = 1.38e4, 0.15, 0.010  # the bundled truth's softening (SPEC 1.4)
AMPLITUDE = 8e-3  # loops of +-8 mm
MASSES = np.geomspace(0.99, 6.40, 8)
BODY = GeneralizedMaxwell(k0=K0, k=[3500.0, 10700.0], rate=[46.6, 841.0], m_eff=0.16)
NOISE = 0.01  # relative complex noise of the FRFs


def static_force(y):
    return K0 * y * (1 - ALPHA * np.tanh(np.minimum(y, 0.0) / Y_SOFT) ** 2)


def static_tangent(y):
    u = np.minimum(y, 0.0) / Y_SOFT
    return K0 * (1 - ALPHA * np.tanh(u) ** 2) - (K0 * y * 2 * ALPHA * np.tanh(u) / np.cosh(u) ** 2 / Y_SOFT
                                                  if y < 0 else 0.0)


def static_deflection(load):
    y = -load / K0
    for _ in range(50):
        y -= (static_force(y) + load) / static_tangent(y)
    return y


@pytest.fixture(scope="module")
def loops():
    deflection = AMPLITUDE * np.sin(np.linspace(0.0, 6 * np.pi, 6001))
    return [QuasiStaticMeasurement(time=np.arange(deflection.size) * 0.01, deflection=deflection,
                                   force=static_force(deflection), info=MeasurementInfo(id="loops"))]


@pytest.mark.parametrize("mass", [0.99, 2.2, 4.9, 6.4, 9.0])
def test_operating_point_is_the_static_law_under_the_weight(loops, mass):
    load = mass * STANDARD_GRAVITY
    point = static_operating_point(loops, load)
    y = static_deflection(load)
    # a quadratic through the window reads a smooth law to its third-order term:
    # |F'''| w^2 / 6 relative to the tangent, below 1e-3 here for w = 1 mm
    assert point.deflection == pytest.approx(y, rel=1e-4)
    assert point.stiffness == pytest.approx(static_tangent(y), rel=1e-3)
    assert point.stiffness < K0  # softening in compression


def test_operating_point_near_and_beyond_the_end_of_the_loops(loops):
    # 10 kg puts the static deflection (-7.57 mm) 0.43 mm inside the loops' end: a narrower window
    near = static_operating_point(loops, 10.0 * STANDARD_GRAVITY)
    assert near is not None and near.deflection > -AMPLITUDE
    assert near.stiffness == pytest.approx(static_tangent(near.deflection), rel=2e-3)
    # 10.5 kg (-7.99 mm): less than a quarter window left; 12 kg (-9.27 mm): beyond the curve
    assert static_operating_point(loops, 10.5 * STANDARD_GRAVITY) is None
    assert static_operating_point(loops, 12.0 * STANDARD_GRAVITY) is None


def preloaded_frfs(seed):
    """Transmissibilities of BODY about each top mass's preload, with complex noise."""
    rng = np.random.default_rng(seed)
    freq = np.arange(1.0, 100.25, 0.25)
    sets = []
    for mass in MASSES:
        tangent = static_tangent(static_deflection(mass * STANDARD_GRAVITY))
        stiffness = BODY.preloaded(tangent).complex_stiffness(freq)
        exact = stiffness / (stiffness - (mass + BODY.m_eff) * (2 * np.pi * freq) ** 2)
        noise = NOISE * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)) / np.sqrt(2)
        sets.append(TransmissibilitySet(float(mass), freq, exact * (1 + noise), f"{mass:.2f}kg",
                                        static_stiffness=float(tangent)))
    return sets


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_preloaded_fit_recovers_the_elements_the_origin_fit_cannot(seed):
    frfs = preloaded_frfs(seed)
    fit = fit_maxwell(frfs, k0=K0, order=2)
    floor = maxwell_objective(BODY, frfs)  # the truth about its preloads: the noise alone
    assert floor == pytest.approx(NOISE, rel=0.1)
    assert fit.error <= 1.01 * floor and fit.success
    for name, value in BODY.params().items():
        parameter = fit.parameters[name]
        if parameter.vary:
            assert abs(parameter.value - value) < 5 * parameter.stderr, name
    # the same data fitted about k0 (no preload): the heavy masses' softer springs cannot be
    # followed, the error is far above the noise
    plain = fit_maxwell([dataclasses.replace(item, static_stiffness=None) for item in frfs], k0=K0, order=2)
    assert plain.error > 2 * floor


def test_frf_validation_about_the_preload(loops):
    # a heavy top mass on the softening mount: 6.4 kg sits 8 % below k0. The run is made by
    # filtering the base velocity with the preloaded model (the estimator's own construction),
    # so the preloaded comparison is exact; about k0 the resonance reads several % high.
    mass = 6.4
    tangent = static_operating_point(loops, mass * STANDARD_GRAVITY).stiffness
    system = SDOFSystem(mass, BODY.preloaded(tangent))
    rng = np.random.default_rng(5)
    fs = 1024.0
    time = np.arange(int(16 * fs)) / fs
    v_base = rng.normal(0.0, 0.01, time.size)
    freq = np.fft.rfftfreq(time.size, 1 / fs)
    v_top = np.fft.irfft(system.transmissibility(freq) * np.fft.rfft(v_base), time.size)
    runs = [WhiteNoiseMeasurement(time=time, v_base=v_base, v_top=v_top,
                                  info=MeasurementInfo(id="wn-heavy", isolator="elastomer", top_mass_kg=mass))]

    def static_stiffness(top_mass_kg):
        return static_operating_point(loops, top_mass_kg * STANDARD_GRAVITY).stiffness

    about_preload = validate_frf(runs, isolator=BODY, static_stiffness=static_stiffness)
    assert about_preload.summary["max_frf_error"] < 1e-9 and about_preload.verdict == "PASS"
    about_k0 = validate_frf(runs, isolator=BODY)
    assert about_k0.summary["max_resonance_frequency_error"] > 0.02


def test_preloaded_keeps_the_elements():
    """static_stiffness is declared (idkit.checks): tests/test_checks.py feeds it its bad values."""
    assert BODY.preloaded(None) is BODY
    softer = BODY.preloaded(1.2e4)
    assert softer.k0 == 1.2e4 and np.array_equal(softer.k, BODY.k) and softer.m_eff == BODY.m_eff


def test_the_model_file_records_each_top_mass_preload(tmp_path):
    # the Maxwell model file keeps k0 at the origin; the tangent stiffness each top mass was
    # fitted about is in its provenance, so a later comparison can use the same preloads
    from pathlib import Path

    from idkit.fit import fit_maxwell_measurements
    from idkit.io import load_measurement_set
    from idkit.models import load_model_document

    data = Path(__file__).resolve().parents[2] / "data" / "elastomer"
    # one order given: what the file records does not depend on it (the order rule is not under test)
    fit = fit_maxwell_measurements(load_measurement_set(data), order=2)
    document = load_model_document(fit.save(tmp_path / "elastomer.json"))
    points = document["provenance"]["operating_points"]
    assert set(points) == {f"{mass:g} kg" for mass in fit.data.operating_points}
    heavy = points["6.4 kg"]
    assert heavy["static_deflection_m"] < 0 and heavy["tangent_stiffness_N_per_m"] < fit.model.k0
