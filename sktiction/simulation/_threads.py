"""One BLAS thread for the simulator's tiny matrices.

The simulator's linear algebra works on 2x2 to 6x6 matrices (matrix exponentials
of the plants, frequency responses for tuning). With several OpenBLAS threads such
calls are hundreds of times slower when another process keeps the cores busy: the
threads spin waiting for each other. Limiting BLAS to one thread around the whole
generation costs one context switch per call and nothing per matrix.
"""

from __future__ import annotations

import functools

from threadpoolctl import threadpool_limits


def single_blas_thread(func):
    """Run ``func`` with BLAS limited to one thread (restored afterwards)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with threadpool_limits(limits=1, user_api="blas"):
            return func(*args, **kwargs)

    return wrapper
