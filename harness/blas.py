"""NumPy's BLAS on one thread for work on small matrices (:func:`one_thread`).

NumPy's bundled OpenBLAS splits a LAPACK call over its threads (one per core) from a modest size on: an LU
factorization from 100 x 100 on (``getrf``: ``np.linalg.solve``, ``inv``), e.g. the mass matrix of the 101-DoF
``tiago_dual`` in ``harness robots``. Its threads then wait for each other by spinning; on a 2-core machine whose
other core is busy (the other worker of a phase, other work) a 101 x 101 solve and inverse took 47 ms of CPU
(79 ms wall) against 0.8 ms on one thread (50 of each, measured with two busy processes beside: 2.3 s against
0.04 s), and a sweep of every robot spent 1.3 s in the second thread alone. On one thread the factorization is
done serially: from 100 x 100 on its round-off differs from the split one's in the last bits (a random 101 x 101
solve: 9e-15 relative), and no longer depends on the number of cores.
"""

from __future__ import annotations

import ctypes
from contextlib import contextmanager
from functools import cache
from pathlib import Path


@cache
def _openblas() -> tuple | None:
    """``(get, set)``: the thread count of NumPy's bundled OpenBLAS (``numpy.libs/libscipy_openblas*``), or None
    (NumPy built with another BLAS: nothing to set)."""
    import numpy as np

    for path in sorted((Path(np.__file__).resolve().parent.parent / "numpy.libs").glob("libscipy_openblas*")):
        try:
            lib = ctypes.CDLL(str(path))   # already loaded by NumPy: the same library, not a second copy
        except OSError:
            continue
        for prefix, suffix in (("scipy_openblas", "64_"), ("scipy_openblas", ""), ("openblas", "64_"), ("openblas", "")):
            get = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
            set_ = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
            if get is not None and set_ is not None:
                get.restype, set_.argtypes = ctypes.c_int, [ctypes.c_int]
                return get, set_
    return None


@contextmanager
def one_thread():
    """NumPy's OpenBLAS on one thread inside the block, its former thread count restored after (no-op without
    it)."""
    found = _openblas()
    if found is None:
        yield
        return
    get, set_ = found
    before = get()
    set_(1)
    try:
        yield
    finally:
        set_(before)
