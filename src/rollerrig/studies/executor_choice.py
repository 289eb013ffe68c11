"""Which executor a study runs on when it is ``"auto"``: local unless dask repays its start-up.

The two executors of :mod:`rollerrig.studies.runner` integrate the points equally fast: the
local one with numba's threads over all cores, dask with one single-threaded worker process
per core. They differ in two ways:

- the per-point Python work (setting the point up, assembling its model, measuring its run:
  the metrics) runs on one core in the local executor and on every worker at once on dask;
- dask pays a fixed cost first: the local cluster starts (a scheduler and a process per
  worker) and each worker imports rollerrig and loads the compiled solver.

So a study of ``n`` points on ``c`` cores, whose per-point Python work takes ``s`` seconds,
is faster on dask by about

.. math:: \\Delta t = n\\,s\\,(1 - 1/c_\\mathrm{free})
          - t_\\mathrm{fixed}(c) / a, \\qquad c_\\mathrm{free} = \\max(1, a\\,c)

where ``a`` is the share of a core this process gets (its thread's CPU time over wall time
in the first batch's Python work, :func:`cpu_share`: 1 on a quiet machine, 0.4 with four
other busy processes on 2 cores). Other load takes the cores dask would add (``c_free``)
and slows the start-up (the workers' imports are CPU work too): on a machine busy with other
work dask gains nothing. ``"auto"`` takes dask when the saving exceeds :data:`MARGIN` times
the start-up: the start-up swings with the load far more than the points do (3 s on a quiet
2-core machine, 42 s under load, issue 20), and a wrong dask costs that swing where a wrong
local costs at most the saving. ``s`` and ``a`` are measured on the study's first batch,
which always runs locally (its points count; the executors give identical results), ``s``
as the median per point so that the first point's imports do not count. With one core dask
cannot gain. A given scheduler address means dask, and so do ``workers`` (they only exist
on dask): both are requests, not estimates.

The numbers behind the rule, measured with ``python benchmarks/bench_studies.py --crossover``
on the 2-core development machine shared with other work (load average 6 and 10, a share
``a`` of 0.4 and 0.5; the release test, 6.52 s, nine metrics; studies of 32, 128 and 400
points): a local cluster of 2 workers started in 11.7-14.8 s, its workers warmed up (rollerrig
imported, the compiled solver loaded, the metrics' first run) in 9.7-14.4 s and it closed in
3.8-4.4 s, against 1.8-2.0 s for the solver's load in this process; per point, local 55-74 ms
(20-38 ms of it the Python work), dask 80-115 ms. Dask took 2.1-6.0 times the local wall time
at every size, and the rule chose local at each. :data:`DASK_START_S`, :data:`DASK_WARM_S` and
:data:`DASK_CLOSE_S` are the first run's start-up times times its share (12 s, 12.5 s and
4.3 s at 0.4: their CPU time on a free core; the second run gives 15.1 s in all against their
11.5 s). On the same machine quiet (``a = 1``, the Python work its CPU time, 10-15 ms) the
break-even ``n = t_fixed / (s (1 - 1/c))`` is 11.5 s / 5-7.5 ms = 1500-2200 points, and
``"auto"`` takes dask from 3000-4400; on 16 free cores from about 1600-2500 (15/16 of ``s``
saved a point).

Examples
--------
>>> choose_executor(200, cores=2, serial_s=0.038).executor
'local'
>>> choose_executor(5000, cores=16, serial_s=0.038).executor
'dask'
>>> choose_executor(5000, cores=2, serial_s=0.038, share=0.4).executor  # a busy machine
'local'
>>> choose_executor(10, cores=1, scheduler="tcp://10.0.0.5:8786").executor
'dask'
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rollerrig._machine import available_cores

__all__ = [
    "DASK_CLOSE_S",
    "DASK_START_S",
    "DASK_WARM_S",
    "MARGIN",
    "ExecutorChoice",
    "available_cores",
    "choose_executor",
    "cpu_share",
    "dask_fixed_cost",
]

DASK_START_S = 4.8
"""Start of a local dask cluster of 2 workers (scheduler and worker processes, up to each
worker's registration) on a free core [s]: 12 s measured at a share of 0.4."""
DASK_WARM_S = 5.0
"""One worker's warm-up on a free core [s]: importing rollerrig, loading the compiled solver
from the on-disk cache, the metrics' first run (12.5 s measured at a share of 0.4); workers
warm up in parallel, one per core."""
DASK_CLOSE_S = 1.7
"""Closing a local cluster on a free core [s] (4.3 s measured at a share of 0.4)."""
MARGIN = 2.0
"""How many times its estimated start-up dask must save before ``"auto"`` takes it [-]."""


@dataclass(frozen=True)
class ExecutorChoice:
    """The executor a study runs on and why.

    Attributes
    ----------
    executor : {"local", "dask"}
    reason : str
        One line, with the numbers the choice rests on.
    workers : int or None
        Worker processes of a local dask cluster (None: the default, or local).
    fixed_s : float or None
        Estimated start-up (and close) of a local dask cluster [s] (None where no estimate was
        needed).
    saving_s : float or None
        Estimated time dask's workers save on the points [s], before its start-up.
    share : float or None
        The share of a core this process got in the first batch [-] (:func:`cpu_share`).
    """

    executor: str
    reason: str
    workers: int | None = None
    fixed_s: float | None = None
    saving_s: float | None = None
    share: float | None = None


def cpu_share(cpu_s, wall_s) -> float:
    """The share of a core a thread got [-]: its CPU time over the wall time, in (0, 1].

    Parameters
    ----------
    cpu_s, wall_s : sequence of float
        CPU time (``time.thread_time``) and wall time of the same stretches of work [s].

    Examples
    --------
    >>> round(cpu_share([0.02, 0.02], [0.05, 0.05]), 6)
    0.4
    """
    wall = float(sum(wall_s))
    if not wall > 0:
        return 1.0
    return min(1.0, max(1e-3, float(sum(cpu_s)) / wall))


def dask_fixed_cost(workers: int, cores: int, share: float = 1.0) -> float:
    """Estimated start-up and close of a local dask cluster of ``workers`` on ``cores`` [s].

    ``(DASK_START_S + DASK_WARM_S * ceil(workers / cores) + DASK_CLOSE_S) / share``: the
    workers warm up in parallel, as many at a time as there are cores, each at the ``share``
    of a core that other load leaves.

    Examples
    --------
    >>> round(dask_fixed_cost(2, 2), 1), round(dask_fixed_cost(2, 2, share=0.5), 1)
    (11.5, 23.0)
    """
    once = DASK_START_S + DASK_WARM_S * math.ceil(workers / max(1, cores)) + DASK_CLOSE_S
    return once / share


def choose_executor(
    points: int,
    *,
    cores: int,
    serial_s: float | None = None,
    share: float = 1.0,
    scheduler: str | None = None,
    workers: int | None = None,
) -> ExecutorChoice:
    """The executor for ``points`` points still to run (the rule in the module docstring).

    Parameters
    ----------
    points : int
        Points still to compute (after the measured first batch).
    cores : int
        Cores this process may use (:func:`available_cores`).
    serial_s : float, optional
        Per-point Python work measured on the first batch [s] (median per point); None when
        nothing was measured (then local, unless a scheduler or workers ask for dask).
    share : float
        The share of a core this process gets (:func:`cpu_share`) [-], in (0, 1].
    scheduler : str, optional
        A dask scheduler address: dask.
    workers : int, optional
        Worker processes asked for: a local dask cluster of that many.

    Returns
    -------
    ExecutorChoice
    """
    if scheduler:
        return ExecutorChoice("dask", f"a dask scheduler was given ({scheduler})")
    if workers:
        return ExecutorChoice(
            "dask", f"{workers} workers asked for: a local dask cluster", workers=workers
        )
    if points <= 0:
        return ExecutorChoice("local", "every point ran in the first batch")
    if cores < 2:
        return ExecutorChoice(
            "local", "1 core: dask's worker processes cannot run the points faster here"
        )
    if serial_s is None or not math.isfinite(serial_s) or serial_s <= 0:
        return ExecutorChoice("local", "no per-point cost measured to repay dask's start-up")
    share = min(1.0, max(1e-3, float(share)))
    free = max(1.0, share * cores)
    fixed = dask_fixed_cost(cores, cores, share)
    saving = points * serial_s * (1.0 - 1.0 / free)
    numbers = (
        f"{points} more points x {serial_s * 1e3:.0f} ms of per-point Python work, "
        f"{cores} cores at {share:.0%} of a core each (other load): dask would save about "
        f"{saving:.1f} s against its start-up of about {fixed:.1f} s"
    )
    kw = {"fixed_s": fixed, "saving_s": saving, "share": share}
    if saving > MARGIN * fixed:
        return ExecutorChoice("dask", numbers, workers=cores, **kw)
    return ExecutorChoice("local", f"{numbers} (it must save {MARGIN:g} times that)", **kw)
