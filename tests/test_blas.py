"""harness.blas.one_thread: NumPy's OpenBLAS on one thread inside the block, restored after."""

import numpy as np
import pytest

from harness import blas


def test_one_thread_sets_and_restores_the_thread_count():
    found = blas._openblas()
    if found is None:
        pytest.skip("NumPy is not built with its bundled OpenBLAS")
    get, _ = found
    before = get()
    rng = np.random.default_rng(0)
    A, b = rng.normal(size=(101, 101)), rng.normal(size=101)   # large enough for OpenBLAS to split getrf
    with blas.one_thread():
        assert get() == 1
        x = np.linalg.solve(A, b)
    assert get() == before
    assert np.allclose(A @ x, b, rtol=0, atol=1e-12 * np.abs(A).sum(axis=1).max() * np.abs(x).max())


def test_one_thread_restores_after_an_error():
    found = blas._openblas()
    if found is None:
        pytest.skip("NumPy is not built with its bundled OpenBLAS")
    before = found[0]()
    with pytest.raises(ZeroDivisionError), blas.one_thread():
        1 / 0
    assert found[0]() == before
