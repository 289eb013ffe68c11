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

__all__ = ["run_each"]


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
