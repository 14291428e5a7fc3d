"""Batches run through any concurrent.futures-style executor, including a Dask cluster."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import library
from idkit.simulate import free_fall, harmonic_response
from idkit.simulate._parallel import default_workers, run_chunked


def test_thread_pool_executor_gives_identical_results():
    system = library.get("hybrid_asymmetric")
    freq = np.logspace(0, 2, 9)
    local = harmonic_response(system, freq, 1e-3, workers=1)
    with ThreadPoolExecutor(max_workers=3) as pool:
        pooled = harmonic_response(system, freq, 1e-3, executor=pool, chunk_size=2)
    np.testing.assert_array_equal(pooled.coefficients, local.coefficients)


def test_local_dask_cluster_runs_grids_and_drops():
    distributed = pytest.importorskip("dask.distributed", reason="dask[distributed] not installed (idkit-isolators[dask])")
    system = library.get("hybrid_symmetric")
    freq = np.logspace(0, 2, 6)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None) as client:
        remote = harmonic_response(system, freq, 1e-3, executor=client, chunk_size=2)
        drops = free_fall(system, impact_velocity=[-0.1, -0.5, -1.0], duration=0.2, time_step=1e-4,
                          executor=client)
    local = harmonic_response(system, freq, 1e-3)
    np.testing.assert_array_equal(remote.coefficients, local.coefficients)
    local_drops = free_fall(system, impact_velocity=[-0.1, -0.5, -1.0], duration=0.2, time_step=1e-4)
    np.testing.assert_array_equal(drops.acceleration, local_drops.acceleration)




def test_run_chunked_takes_whole_float_and_numpy_counts():
    (values,) = run_chunked(lambda part: (np.arange(part.start, part.stop),), 5, workers=2.0,
                            chunk_size=np.int64(2))
    np.testing.assert_array_equal(values, np.arange(5))


@pytest.mark.parametrize("setting", ["2.5", "0", "-1", "abc", "1_0", "\u0663"])
def test_a_bad_idkit_workers_variable_is_refused_by_name(monkeypatch, setting):
    monkeypatch.setenv("IDKIT_WORKERS", setting)
    with pytest.raises(SimulationError, match=f"environment variable IDKIT_WORKERS: found {setting!r}"):
        default_workers()
