"""A candidate's draws in one call: the one-draw-at-a-time numbers, the screen against the full
simulation, the dissipated-energy limit, and a Dask cluster's rows."""

import math

import numpy as np
import pytest

from idkit.design import Candidate, DesignPart, Environment, evaluate_candidates, judge
from idkit.design.evaluation import METRICS, evaluate_candidate
from idkit.models import library

ENVIRONMENT = Environment.from_dict({
    # the low floor keeps the rope stuck (frequency domain), the high one makes it slip (time domain)
    "floor_psd": [{"name": "low", "flat": 1e-4, "f_lo": 0.1, "f_hi": 100.0},
                  {"name": "high", "flat": 2e-2, "f_lo": 1.0, "f_hi": 100.0}],
    "drops": {"heights_m": [0.01, 0.03]},
    "limits": {"rms_acceleration_m_per_s2": 1.0, "peak_acceleration_m_per_s2": 100.0, "max_deflection_m": 0.05,
               "max_component_deflection_m": 0.04, "max_dissipated_energy_j": 5.0,
               "max_component_dissipated_energy_j": 4.0, "resonance_band_hz": [1.0, 2.0]}})
KERNEL_METRICS = ("peak_acceleration_m_per_s2", "max_deflection_m", "max_component_deflection_m")


def part(name, family, model):
    """The model with a 5 % standard deviation on every stiffness and slip force."""
    names = tuple(k for k, v in model.params().items() if v > 0 and k.startswith(("g1", "k", "fc")))
    return DesignPart(name, family, model, names, np.diag([(0.05 * model.params()[k]) ** 2 for k in names]))


ROPE = part("Table 7.1 rope", "wire_rope", library.get("table_7_1_wire_rope"))
BODY = part("Table 7.3 elastomer", "elastomer", library.get("table_7_3_elastomer"))
CANDIDATES = (Candidate("2 x rope", (ROPE,), 2, 30.0), Candidate("1 x (body on rope)", (BODY, ROPE), 1, 15.0))


def values(row, metric):
    return np.array([row[metric]] + row[f"{metric} draws"], dtype=float)


@pytest.fixture(scope="module")
def screened():
    return [evaluate_candidate(candidate, ENVIRONMENT, n_draws=2, seed=7) for candidate in CANDIDATES]


def test_every_draw_in_one_call_gives_the_one_draw_at_a_time_numbers(screened):
    body = Candidate("1 x body", (BODY,), 1, 15.0)  # linear: the frequency domain for every floor
    linear = evaluate_candidate(body, ENVIRONMENT, n_draws=2, seed=7)
    for candidate, fast in zip(CANDIDATES + (body,), screened + [linear]):
        slow = evaluate_candidate(candidate, ENVIRONMENT, n_draws=2, seed=7, batched=False)
        assert fast["flagged"] == slow["flagged"] == 0
        for metric in METRICS:
            mine, reference = values(fast, metric), values(slow, metric)
            if metric in KERNEL_METRICS:  # the same kernel runs on the same grids: bit for bit
                np.testing.assert_array_equal(mine, reference)
            else:
                # the same operations over arrays of draws (sums in another order, numpy's loops for
                # strided arrays): round-off of the values
                np.testing.assert_allclose(mine, reference, rtol=1e-12)
    # the rope slips under the high floor: its random runs went through the compiled call
    assert values(screened[0], "rms_acceleration_m_per_s2").min() > 0.3


def test_the_screen_is_the_full_simulation_within_2e_3(screened):
    # screen: drops at 5x the default step (400 steps a payload period: a sampled peak within 3e-5,
    # Newmark's period error (omega h)^2 / 12 = 2e-5; a hybrid's intermediate mass, 1 % of the motion, at
    # 8 steps its period, 5 % period error: a few 1e-4 of the peak), floors at 800 Hz instead of 3200 Hz
    # (the trapezoidal warping (omega h)^2 / 3 = 1.3e-4 of |H|^2 at a 5 Hz resonance; the in-band lines
    # of the two floors have the same phases); the energies over the same four periods of each draw
    for candidate, screen in zip(CANDIDATES, screened):
        full = evaluate_candidate(candidate, ENVIRONMENT, n_draws=2, seed=7, screening=False)
        for metric in METRICS:
            np.testing.assert_allclose(values(screen, metric), values(full, metric), rtol=2e-3, err_msg=metric)


def test_the_dissipated_energy_limits_are_judged_with_margins_and_probabilities(screened):
    hybrid = screened[1]
    total, parts = values(hybrid, "max_dissipated_energy_j"), values(hybrid, "max_component_dissipated_energy_j")
    assert np.all(parts < total) and np.all(parts > 0.3 * total)  # both components dissipate
    limit = float(np.median(parts[1:]))  # between the draws: one meets it, one does not
    environment = Environment.from_dict({"drops": {"heights_m": [0.01, 0.03]},
                                         "limits": {"max_component_dissipated_energy_j": limit}})
    row = judge([hybrid], environment).iloc[0]
    assert row["margin max_component_dissipated_energy_j"] == pytest.approx(1.0 - parts[0] / limit)
    assert row["P(max_component_dissipated_energy_j)"] == pytest.approx(np.mean(parts[1:] <= limit))
    # a single mount has no components: the component limit does not apply to it
    single = judge([screened[0]], environment).iloc[0]
    assert "P(max_component_dissipated_energy_j)" not in single or math.isnan(
        single["P(max_component_dissipated_energy_j)"])


def test_a_dask_cluster_gives_the_local_rows():
    distributed = pytest.importorskip("distributed")
    environment = Environment.from_dict({"drops": {"heights_m": [0.01]},
                                         "limits": {"peak_acceleration_m_per_s2": 50.0}})
    candidates = [Candidate(f"{n} x rope", (ROPE,), n, 20.0) for n in range(1, 11)]
    candidates += [Candidate(f"{n} x (body on rope)", (BODY, ROPE), n, 20.0) for n in range(1, 11)]
    local = evaluate_candidates(candidates, environment, n_draws=1, seed=2)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") \
            as cluster, distributed.Client(cluster) as client:
        remote = evaluate_candidates(candidates, environment, n_draws=1, seed=2, executor=client, chunk_size=5)
    assert judge(remote, environment).equals(judge(local, environment))


def test_guided_chunks_cover_the_candidates_in_order_and_shrink_to_one():
    from idkit.design.evaluation import _chunk_bounds

    for count, workers in ((1000, 2), (7, 3), (1, 1)):
        bounds = _chunk_bounds(count, workers)
        assert bounds[0][0] == 0 and bounds[-1][1] == count
        assert all(previous[1] == following[0] for previous, following in zip(bounds, bounds[1:]))
        sizes = [stop - start for start, stop in bounds]
        # each a 2 workers-th of what is left: the first ceil(count / (2 workers)), the last one item
        assert sizes[0] == -(-count // (2 * workers)) and sizes == sorted(sizes, reverse=True) and sizes[-1] == 1
    assert _chunk_bounds(0, 2) == []
