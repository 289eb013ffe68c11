"""Independent compiled runs on Python threads, as many as numba's: :func:`run_each`.

The fast backend's drivers are compiled with ``nogil=True``, so Python threads run them in
parallel. This replaced numba's ``parallel=True`` batch drivers, which cost a second compile of
each driver (tens of seconds) and could not be interrupted.

While runs go in threads, the BLAS libraries are held to one thread each (threadpoolctl):
the runs' LAPACK calls (ETDRK4's stability estimate, ROS34PW2's LU), made from several threads
at once, otherwise contend for OpenBLAS's own thread pool. A sweep of 24 default runs on
2 cores went from 58 to 72 runs/s (2026-11-30; a single run is unchanged).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from contextlib import contextmanager

import numba
import numpy as np

__all__ = ["run_each", "thread_rows"]

_LINE_BYTES = 128  # a cache line: 64 bytes on x86-64 and most ARM cores, 128 on Apple's


def run_each(run: Callable[[int], object], n: int) -> None:
    """Call ``run(k)`` for ``k`` in ``range(n)``, each on the next free thread.

    ``min(n, numba.get_num_threads())`` Python threads; with one, the runs go in order in the
    calling thread. An exception of a run is raised here. On Ctrl-C (or an error) the runs not
    started are dropped: only those running finish (compiled code cannot be interrupted).

    Parameters
    ----------
    run : callable
        ``run(k)``; its return value is ignored (runs write their results themselves, each to
        its own place).
    n : int
        Number of runs.

    Examples
    --------
    >>> out = [0] * 5
    >>> def square(k):
    ...     out[k] = k * k
    >>> run_each(square, 5)
    >>> out
    [0, 1, 4, 9, 16]
    """
    threads = min(n, numba.get_num_threads())
    if threads <= 1:
        for k in range(n):
            run(k)
        return
    from concurrent.futures import ThreadPoolExecutor

    with _single_threaded_blas():
        pool = ThreadPoolExecutor(threads)
        try:
            for _ in pool.map(run, range(n)):  # re-raises a thread's exception here
                pass
        finally:
            pool.shutdown(cancel_futures=True)


_BLAS_LOCK = threading.Lock()
_blas_users = 0
_blas_limits = None


@contextmanager
def _single_threaded_blas():
    """Every loaded BLAS held to one thread while the context is open (threadpoolctl, installed
    with the twin's extra); nothing changes where threadpoolctl is not installed (the runs are
    then as fast as before it was used, not wrong).

    The limit is the process's: calls of :func:`run_each` from several threads at once (a
    study's worker threads) share one, set by the first to enter and lifted by the last to
    leave, so that none restores a count another is still running under, and the count of
    before is what remains.
    """
    global _blas_users, _blas_limits
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        yield
        return
    with _BLAS_LOCK:
        if _blas_users == 0:
            _blas_limits = threadpool_limits(1, user_api="blas")
        _blas_users += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _blas_users -= 1
            if _blas_users == 0:
                _blas_limits.restore_original_limits()
                _blas_limits = None


def thread_rows(n: int, width: int, dtype=np.int64) -> np.ndarray:
    """Zeros of shape ``(n, width)`` whose rows never share a cache line.

    For results that runs on different threads write while they run (a driver's step
    counters, incremented every step): rows packed side by side, as ``np.zeros((n, width))``
    packs them, put two runs that go at the same time (variants ``k`` and ``k + 1``) on one
    cache line, which the two cores then pass back and forth on every write ("false
    sharing"). Each row here starts at least :data:`_LINE_BYTES` after the last byte of the
    row before, so that no line holds bytes of two rows whatever the array's alignment.
    Measured on the benchmark's sweep (24 default-length runs, 2 threads, 2026-12-03): the two
    threads did 1.84 times one thread's work with packed step counters (5 int64, 40 bytes a
    row), 1.92 times with these.

    Examples
    --------
    >>> rows = thread_rows(3, 5)
    >>> rows.shape, rows.strides[0] >= 5 * 8 + 128, int(rows.sum())
    ((3, 5), True, 0)
    """
    itemsize = np.dtype(dtype).itemsize
    stride = width + -(-_LINE_BYTES // itemsize)
    return np.zeros((n, stride), dtype=dtype)[:, :width]
