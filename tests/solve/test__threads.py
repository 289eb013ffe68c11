"""run_each: every run once, on up to numba's thread count, an exception raised to the caller,
the runs not started dropped after it."""

import threading

import numba
import pytest

from rollerrig.solve._threads import run_each


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
