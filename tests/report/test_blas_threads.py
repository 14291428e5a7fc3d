"""One BLAS thread per process while the report computes (idkit.report.blas_threads)."""

import numpy as np
import pytest

from idkit.forked import can_fork, fork_call
from idkit.report.blas_threads import loaded_openblas, one_blas_thread


def _counts() -> list[int]:
    return [get() for _, get, _ in loaded_openblas()]


def test_numpy_and_scipy_openblas_are_found():
    """The wheels of constraints/ci.txt bundle OpenBLAS in NumPy and in SciPy: both are found."""
    import scipy.linalg  # noqa: F401 - loads SciPy's library

    if "openblas" not in np.__config__.CONFIG["Build Dependencies"]["blas"]["name"].lower():
        pytest.skip("this NumPy is not built on OpenBLAS")
    paths = [path for path, _, _ in loaded_openblas()]
    assert any("numpy" in path for path in paths) and any("scipy" in path for path in paths), paths


def test_one_thread_inside_restored_after_and_inherited_by_children():
    before = _counts()
    rows = np.random.default_rng(1).normal(size=(3000, 4)) * (1 + 1j)
    weights = np.arange(1.0, 5.0).astype(complex)
    outside = rows.dot(weights)
    with one_blas_thread():
        assert _counts() == [1] * len(before)
        # a matrix-vector product sums each row in the same order on any number of threads
        np.testing.assert_array_equal(rows.dot(weights), outside)
        if can_fork():
            assert fork_call(_counts).result() == [1] * len(before)
    assert _counts() == before


def test_restored_when_the_block_raises():
    before = _counts()
    with pytest.raises(RuntimeError), one_blas_thread():
        raise RuntimeError("inside")
    assert _counts() == before
