"""run_each: every run once, on up to numba's thread count, an exception raised to the caller,
the runs not started dropped after it."""

import threading

import numba
import numpy as np
import pytest

from rollerrig.solve._threads import run_each, thread_rows


@pytest.mark.parametrize("threads", [1, 2])
def test_every_run_once_on_at_most_the_numba_threads(threads, monkeypatch):
    monkeypatch.setattr(numba, "get_num_threads", lambda: threads)
    seen, names = [], set()

    def run(k):
        seen.append(k)
        names.add(threading.current_thread().name)

    run_each(run, 7)
    assert sorted(seen) == list(range(7))
    assert len(names) <= threads
    if threads == 1:
        assert seen == list(range(7)) and names == {threading.current_thread().name}


def test_an_exception_reaches_the_caller_and_later_runs_are_dropped(monkeypatch):
    monkeypatch.setattr(numba, "get_num_threads", lambda: 2)
    started = []
    gate = threading.Event()

    def run(k):
        started.append(k)
        if k == 0:
            raise ValueError("run 0 failed")
        gate.wait(1.0)  # the other thread holds until the failure is seen

    with pytest.raises(ValueError, match="run 0 failed"):
        try:
            run_each(run, 50)
        finally:
            gate.set()
    assert len(started) < 50


def _blas_threads(threadpoolctl):
    info = threadpoolctl.threadpool_info()
    return [i["num_threads"] for i in info if i["user_api"] == "blas"]


def test_runs_in_threads_see_single_threaded_blas_and_it_is_restored_after(monkeypatch):
    """While runs go in threads every BLAS library runs on one thread (their concurrent LAPACK
    calls contended for OpenBLAS's pool), and its own count is back afterwards."""
    threadpoolctl = pytest.importorskip("threadpoolctl")
    monkeypatch.setattr(numba, "get_num_threads", lambda: 2)
    before = _blas_threads(threadpoolctl)
    if not before or set(before) == {1}:
        pytest.skip("no BLAS here that runs more than one thread (OPENBLAS_NUM_THREADS=1?)")
    seen = [None] * 4

    def run(k):
        seen[k] = _blas_threads(threadpoolctl)

    run_each(run, 4)
    assert all(s and set(s) == {1} for s in seen)
    assert _blas_threads(threadpoolctl) == before


@pytest.mark.parametrize(
    ("n", "width", "dtype"),
    [(5, 5, np.int64), (3, 1, float), (2, 40, np.int8), (3, 16, np.int64), (4, 3, np.int16)],
)
def test_thread_rows_never_share_a_cache_line(n, width, dtype):
    """No 64-byte line (x86-64's; 128 covers Apple's) holds bytes of two rows, at any alignment:
    rows written by two threads at once on one line passed it between the cores on every
    write, the batch's step counters included."""
    rows = thread_rows(n, width, dtype)
    assert rows.shape == (n, width) and rows.dtype == np.dtype(dtype) and not rows.any()
    start = rows.__array_interface__["data"][0]
    spans = [
        (start + k * rows.strides[0], start + k * rows.strides[0] + width * rows.itemsize - 1)
        for k in range(n)
    ]
    for line in (64, 128):  # and at every alignment of the first row:
        assert all((b - a) + line <= rows.strides[0] for a, b in spans)
        lines = [set(range(a // line, b // line + 1)) for a, b in spans]
        for k in range(n - 1):
            assert not lines[k] & lines[k + 1]
