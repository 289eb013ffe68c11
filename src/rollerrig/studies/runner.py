"""Running a study: batches of points on the compiled backend, in this process or on dask.

Two executors run the same batches (:func:`run_batch`) and give identical results; ``"auto"``
(the default) chooses between them (:mod:`rollerrig.studies.executor_choice`):

``"auto"``
    A given scheduler address or a number of workers means dask. Otherwise the first batch
    runs locally and its per-point cost decides: local, unless the rest of the study is large
    enough that a local cluster's start-up and each worker's solver load are repaid (the rule
    and the numbers behind it in :func:`~rollerrig.studies.executor_choice.choose_executor`).
    The choice and its reason are in :attr:`StudyRun.reason` and the store's ``runs``.
``"local"``
    In this process, each batch integrated in parallel by numba's threads (all cores).
``"dask"``
    On ``dask.distributed``: a local cluster of ``workers`` processes (one thread each) by
    default, or any running scheduler (``scheduler="tcp://host:8786"``) for a real cluster.
    Each worker loads the compiled backend once, when it is warmed up before the first batch
    (from the on-disk cache; a worker on another machine compiles it there once), and keeps it
    for every later batch: a worker runs batches one after the other in the same process.
    The start-up (the cluster, then the warm-up) is timed apart from the points
    (:attr:`StudyRun.fixed_cost`). A scheduler address
    is checked for its form first (:func:`check_scheduler_address`) and must answer within
    :data:`SCHEDULER_TIMEOUT`. After an interruption (Ctrl-C) the cluster shuts down quietly:
    the local workers ignore SIGINT (their nanny ends them) and the library loggers
    (:data:`QUIET_LOGGERS`) are silenced while the client and cluster close.

Every point ends with a status (:data:`rollerrig.studies.store.STATUSES`): a value the rig or
the experiment refuses is ``invalid parameters``, a run the solver cannot finish (or one that
finishes without a value of any metric and without the experiment's releases in its torque)
``solver failed``, both with the reason, and the rest
of the study goes on. Finished points go to the
store as they arrive (:class:`~rollerrig.studies.store.StudyStore`), so an interrupted study
resumes where it stopped: running it again into the same store computes only the points still
pending.
"""

from __future__ import annotations

import contextlib
import ipaddress
import logging
import math
import os
import re
import shutil
import statistics
import tempfile
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._optional import require
from rollerrig._validation import ParameterError, did_you_mean
from rollerrig._warnings import DomainWarning
from rollerrig.experiment import Protocol, load_protocol
from rollerrig.output.names import safe_file_name
from rollerrig.rig.parameters import RigParameters, default_rig, load_rig
from rollerrig.studies.design import (
    DesignTable,
    design_points,
    parameter_attrs,
    point_setup,
    protocol_groups,
)
from rollerrig.studies.executor_choice import (
    ExecutorChoice,
    available_cores,
    choose_executor,
    cpu_share,
)
from rollerrig.studies.metrics import (
    METRICS,
    compute_metrics,
    misses_its_releases,
    require_measurable,
    run_channels,
)
from rollerrig.studies.store import StudyStore, remove_store
from rollerrig.studies.studyfile import StudySpec, load_study
from rollerrig.studies.summary import WARNING_PREFIX

__all__ = [
    "EXECUTORS",
    "QUIET_LOGGERS",
    "SCHEDULER_PROTOCOLS",
    "SCHEDULER_TIMEOUT",
    "Progress",
    "StudyRun",
    "check_scheduler_address",
    "run_batch",
    "run_study",
]

EXECUTORS = ("auto", "local", "dask")
"""The executors a study can run on (``"auto"`` chooses one of the other two)."""
BATCH_BYTES = 256 * 2**20
"""Largest solution a batch holds in memory [bytes] (states of every point at every sample)."""
DASK_BATCH = 32
"""Points per dask task: long enough (a fraction of a second) that scheduling costs little,
short enough that progress moves and the workers share the load evenly."""
SCHEDULER_PROTOCOLS = ("tcp", "tls", "ucx", "ws", "wss", "inproc")
"""Protocols of a dask scheduler address (``tcp://HOST:PORT``; ``HOST:PORT`` means tcp)."""
SCHEDULER_TIMEOUT = 10.0
"""How long to try to reach a given dask scheduler before giving up [s]."""
QUIET_LOGGERS = ("distributed", "tornado", "asyncio")
"""Library loggers silenced while dask shuts down after an interruption (their tracebacks of
cancelled tasks and lost workers say nothing the one-line message does not)."""
_WORKER_SETUP = "rollerrig.studies._dask_worker"
"""Preload of each local dask worker (:mod:`rollerrig.studies._dask_worker`)."""
_HOST_LABEL = re.compile(r"[A-Za-z0-9_]([A-Za-z0-9_-]{0,61}[A-Za-z0-9_])?")


@dataclass(frozen=True)
class Progress:
    """Where a running study stands: ``done`` of ``total`` points (``skipped`` of them were
    already in the store), ``failed`` (solver failed or invalid), ``elapsed`` [s] and the
    ``rate`` of this run [points/s]."""

    done: int
    total: int
    failed: int
    skipped: int
    elapsed: float

    @property
    def rate(self) -> float:
        """Points computed by this run per second [1/s]."""
        return (self.done - self.skipped) / self.elapsed if self.elapsed > 0 else 0.0


@dataclass
class StudyRun:
    """The outcome of :func:`run_study`.

    Attributes
    ----------
    spec : StudySpec
    store : Path or None
        The store's folder (None when it was a temporary one).
    dataset : xarray.Dataset
        Every point with its status, reason and metrics (:func:`~rollerrig.studies.store.
        open_study`).
    computed : int
        Points this run computed; ``skipped``: points already in the store (a resumed study).
    wall_time : float
        Of this run [s], workers' start included.
    executor : str
        ``"local"`` or ``"dask"``: where the points ran (``"auto"`` resolved).
    workers : int
        Processes (dask) or threads (local) that ran the points.
    reason : str
        Why this executor (one line; for ``"auto"``, with the numbers the choice rests on).
    fixed_cost : dict of str to float
        The start-up of this run, apart from the points [s]: ``solver_load_s`` (the compiled
        solver loaded in this process), and on dask ``cluster_start_s`` (the local cluster
        started, or the scheduler reached), ``worker_warm_up_s`` (every worker's import of
        rollerrig and load of the compiled solver, in parallel) and ``cluster_close_s``.
    serial_s : float or None
        Per-point Python work measured on the first batch under ``"auto"`` [s] (median).
    counts : dict of str to int
        Points per status.
    damaged : int
        Points of a resumed store whose results were missing (lost chunk files,
        ``damaged_files``) and that this run computed again.
    """

    spec: StudySpec
    store: Path | None
    dataset: Any
    computed: int
    skipped: int
    wall_time: float
    executor: str
    workers: int
    counts: dict[str, int] = field(default_factory=dict)
    damaged: int = 0
    damaged_files: tuple[str, ...] = ()
    reason: str = ""
    fixed_cost: dict[str, float] = field(default_factory=dict)
    serial_s: float | None = None

    @property
    def rate(self) -> float:
        """Points computed per second of this run's wall time [1/s]."""
        return self.computed / self.wall_time if self.wall_time > 0 else 0.0


# --------------------------------------------------------------------------------------------
# One batch (runs on a worker)
# --------------------------------------------------------------------------------------------


def run_batch(
    rig: RigParameters,
    protocol: Protocol,
    points: Sequence[tuple[int, dict[str, Any]]],
    metrics: Sequence[str],
    output_rate: float,
    h_max: float | None = None,
    threads: int | None = None,
    timing: dict | None = None,
) -> list[tuple[int, str, str, dict[str, float]]]:
    """Simulate and measure points that share one experiment; never raises for a bad point.

    Parameters
    ----------
    rig : RigParameters
        The base rig.
    protocol : Protocol
        The base experiment (a point's load, speed and friction change it).
    points : sequence of (int, dict)
        ``(index, values)`` of each point (:meth:`DesignTable.point`); all must give the same
        load, speed and friction.
    metrics : sequence of str
        Names in :data:`~rollerrig.studies.metrics.METRICS`.
    output_rate : float
        Sampling of the results [Hz].
    h_max : float, optional
        A cap of the solver's step [s]; default none: the sweeps' settings
        (:func:`rollerrig.solve.fast.sweep_settings`).
    threads : int, optional
        Threads to use here (a dask worker uses 1); default: numba's setting
        (``numba.get_num_threads()``), which :func:`rollerrig.solve.fast.integrate_batch` follows.
    timing : dict, optional
        Filled with ``serial_s`` (per point: its setup and measuring, the Python work of one
        core [s]), ``serial_cpu_s`` (the CPU time of this thread in that work [s]: below
        ``serial_s`` when other processes share the core) and ``integrate_s`` (the batch's
        integration [s]).

    Returns
    -------
    list of (index, status, reason, metrics)
        One per point, in the order given. A point that ran ``ok`` has as its reason the
        domain warnings its setup gave (``"warning: ..."``: a shaft too stiff to resolve, a
        torque beyond the drive), else ``""``; they are issued again here, for a console.
    """
    from rollerrig.rig.assemble import assemble
    from rollerrig.solve.fast import failure_reason, integrate_batch, sweep_settings
    from rollerrig.solve.simulation import output_times

    if threads is not None:
        import numba

        numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
    rows: dict[int, tuple] = {}
    warned: dict[int, str] = {}
    serial: dict[int, float] = {}
    cpu: dict[int, float] = {}
    ready, inputs = [], []
    point_protocol = None
    for index, values in points:
        started, cpu_started = time.perf_counter(), time.thread_time()
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", DomainWarning)
                r, p, d = point_setup(rig, protocol, values)
                inp = assemble(r, p, d)
        except ParameterError as exc:
            rows[index] = (index, "invalid parameters", _one_line(exc), {})
            continue
        finally:
            serial[index] = time.perf_counter() - started
            cpu[index] = time.thread_time() - cpu_started
        warned[index] = _warned(caught)
        point_protocol = p
        ready.append(index)
        inputs.append(inp)
    integrate_s = 0.0
    if inputs:
        t = output_times(point_protocol.duration, output_rate)
        started = time.perf_counter()
        x, stats = integrate_batch(inputs, t, **sweep_settings(h_max or None))
        integrate_s = time.perf_counter() - started
        for index, inp, xi, st in zip(ready, inputs, x, stats, strict=True):
            started, cpu_started = time.perf_counter(), time.thread_time()
            if st["status"] != 0:
                reason = f"the fast solver failed {failure_reason(st['status'], st['t_stop'])}"
                rows[index] = (index, "solver failed", _one_line(reason), {})
                continue
            try:
                run = run_channels(inp, t, xi)
                values = compute_metrics(run, point_protocol, metrics)
                # only a run without any metric is looked at again (not on every sweep point)
                missed = not any(math.isfinite(v) for v in values.values()) and (
                    misses_its_releases(run, point_protocol)
                )
            except Exception as exc:  # a study records a broken point and goes on
                reason = f"measuring the run failed: {type(exc).__name__}: {exc}"
                rows[index] = (index, "solver failed", _one_line(reason), {})
                continue
            finally:
                serial[index] += time.perf_counter() - started
                cpu[index] += time.thread_time() - cpu_started
            rows[index] = _measured(index, values, missed, warned.get(index, ""))
    if timing is not None:
        timing["serial_s"] = [serial[index] for index, _ in points]
        timing["serial_cpu_s"] = [cpu[index] for index, _ in points]
        timing["integrate_s"] = integrate_s
    return [rows[index] for index, _ in points]


def _warned(caught) -> str:
    """The domain warnings of a point's setup as its reason (``"warning: ..."``, each once),
    every caught warning issued again (a console prints it; nothing is swallowed)."""
    texts: list[str] = []
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        text = _one_line(w.message)
        if issubclass(w.category, DomainWarning) and text not in texts:
            texts.append(text)
    return "; ".join(f"{WARNING_PREFIX}{t}" for t in texts)


def _measured(
    index: int, values: dict[str, float], missed: bool, warned: str = ""
) -> tuple[int, str, str, dict[str, float]]:
    """The row of a point whose run finished: ``ok``, unless ``missed``: no metric has a value
    and the run does not show the experiment
    (:func:`~rollerrig.studies.metrics.misses_its_releases`).

    A value the twin cannot resolve in floating point (a roller-shaft stiffness of 1e300
    N.m/rad makes the shaft's torque a rounding error, and no release shows in it) let the
    solver finish: marked ``ok`` it was a blank row that looked like a success, its reason
    only in the JSON; it is ``solver failed`` with each metric's ``nan_meaning``. A metric
    undefined on a run that does show the experiment (a settling time past the end of the
    rest) leaves the point ``ok``: that is a result, and ``study run`` notes it.
    """
    if not missed or not values:
        return (index, "ok", warned, values)
    by_meaning: dict[str, list[str]] = {}
    for name in values:
        by_meaning.setdefault(METRICS[name].nan_meaning, []).append(name)
    why = "; ".join(f"{', '.join(names)}: {meaning}" for meaning, names in by_meaning.items())
    reason = (
        f"the run gave no value of any metric ({why}) and shows no release from a positive "
        "force although the experiment has one; the solver finished, but its result does not "
        "show the experiment: check this point's values (a stiffness, gain or inertia far "
        "from the rig's, a value near zero)"
    )
    if warned:  # what the point's setup already said of its values
        reason = f"{reason}; {warned}"
    return (index, "solver failed", _one_line(reason), values)


def _one_line(message) -> str:
    return " ".join(str(message).split())


# --------------------------------------------------------------------------------------------
# The study
# --------------------------------------------------------------------------------------------


def _store_parameters(table: DesignTable, spec: StudySpec) -> dict:
    labels = {a.key: a.label for a in spec.axes}
    labels.update({d.key: d.label for d in (spec.sample.parameters if spec.sample else ())})
    out = {}
    for key in table.keys:
        column = table.columns[key]
        attrs = parameter_attrs(key, labels.get(key, ""))
        if any(isinstance(v, str) for v in column):
            values = np.array(["" if v is None else v for v in column], dtype=str)
            if any(v is None for v in column):
                attrs["empty_meaning"] = "the case keeps the base value"
        else:
            values = np.array([np.nan if v is None else v for v in column], dtype=float)
            if any(v is None for v in column):
                attrs["nan_meaning"] = "the case keeps the base value"
        out[key] = (values, attrs)
    return out


def _solver_text(h_max: float | None) -> str:
    """What integrated the points, for the store's attributes (:func:`run_batch`)."""
    from rollerrig.solve.fast import CURRENTS_EXACT_ABOVE, SWEEP_EXP_STEP

    step = SWEEP_EXP_STEP if h_max is None else min(SWEEP_EXP_STEP, h_max)
    cap = " (capped by the study's h_max)" if step < SWEEP_EXP_STEP else ""
    currents = (
        ", the PMSM's currents taken exactly below its voltage limit (a segment at the limit "
        "integrated at a single run's settings)"
        if step > CURRENTS_EXACT_ABOVE
        else ""
    )
    return (
        "the fast backend (ETDRK4) with the sweeps' settings "
        f"(rollerrig.solve.fast.sweep_settings): a step of {step * 1e3:g} ms{cap} (0.4 ms with "
        f"the ideal speed source){currents}; for a sweep's 0.1 N.m of T56, measured within "
        "0.083 N.m against Radau at rtol 1e-10 on the benchmark's sweep of the roller shaft's "
        "stiffness and the motor's lag and within 0.094 N.m against rtol 1e-9 on 4.3 kN pulses, "
        "but 0.233 N.m at 20 kN, 10 km/h and 1 400 N.m (rollerrig.solve.fast.SWEEP_EXP_STEP)"
    )


def _open_store(path: Path, spec: StudySpec, table: DesignTable, restart: bool) -> StudyStore:
    from rollerrig.output.provenance import provenance

    if restart:
        remove_store(path, study=spec.name)  # only a study store of this study
    if path.exists():
        return StudyStore.open(path, study_sha256=spec.sha256)
    attrs = {
        "study": spec.name,
        "study_description": spec.description,
        "study_origin": spec.origin,
        "study_sha256": spec.sha256,
        "study_text": spec.text,
        "experiment": spec.experiment,
        "output_rate_hz": spec.output_rate,
        "solver": _solver_text(spec.h_max),
        "provenance": provenance(study=spec.name, study_sha256=spec.sha256),
        **table.attrs,
    }
    metrics = {
        name: {"units": m.units, "long_name": m.long_name, "nan_meaning": m.nan_meaning}
        for name, m in METRICS.items()
        if name in spec.metrics
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    return StudyStore.create(
        path,
        attrs=attrs,
        parameters=_store_parameters(table, spec),
        labels=table.labels,
        metrics=metrics,
    )


def _batches(table: DesignTable, pending: np.ndarray, size: int) -> list[list[tuple[int, dict]]]:
    batches = []
    for group in protocol_groups(table, pending):
        for start in range(0, group.size, size):
            batches.append([(int(i), table.point(int(i))) for i in group[start : start + size]])
    return batches


def _batch_limit(protocol: Protocol, output_rate: float) -> int:
    from rollerrig.rig.model_dq import N_DQ_STATES  # the largest state vector of the models

    per_point = (math.floor(protocol.duration * output_rate) + 1) * N_DQ_STATES * 8
    return max(1, BATCH_BYTES // per_point)


def _ensure_compiled(load: bool = True) -> float:
    """Compile the fast driver here, once, before workers start (they then load it from the
    cache instead of each compiling it at the same time); with ``load``, also load it into
    this process. The seconds this took (about 0 when this process holds it already)."""
    from rollerrig.rig.assemble import assemble
    from rollerrig.solve.fast import integrate_batch, is_compiled

    if not load and is_compiled():
        return 0.0
    started = time.perf_counter()
    inp = assemble(default_rig(), load_protocol("release-test"))
    integrate_batch([inp], np.array([0.0, 0.01]))
    return time.perf_counter() - started


def _warm_worker(*args) -> float:
    """A dask worker's warm-up: :func:`run_batch` of one point (rollerrig imported, the
    compiled solver loaded, the metrics' imports done; the point is computed again later);
    the seconds it took."""
    started = time.perf_counter()
    run_batch(*args)
    return time.perf_counter() - started


def _local(batches, args) -> Iterator[list]:
    for batch in batches:
        yield run_batch(*args[:2], batch, *args[2:])


def check_scheduler_address(address: str, option: str = "--scheduler") -> str:
    """``address`` if it has the form of a dask scheduler address, else a ParameterError
    naming ``option``.

    Accepted: ``tcp://HOST:PORT`` (or ``HOST:PORT``), ``tls://``, ``ucx://``, ``ws://``,
    ``wss://`` likewise, and ``inproc://NAME``; HOST a host name, an IPv4 address or an IPv6
    address in brackets; PORT 1 to 65535. Whether a scheduler answers there is found when the
    study connects (:data:`SCHEDULER_TIMEOUT`).

    Examples
    --------
    >>> check_scheduler_address("tcp://10.0.0.5:8786"), check_scheduler_address("[::1]:8786")
    ('tcp://10.0.0.5:8786', '[::1]:8786')
    >>> check_scheduler_address("999.1.1.1:99999")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: --scheduler '999.1.1.1:99999': not a dask scheduler ...
    """
    form = (
        "not a dask scheduler address; give tcp://HOST:PORT (or HOST:PORT; tls://, ucx://, "
        "ws://, wss:// likewise, or inproc://NAME) with PORT in 1-65535"
    )

    def refuse(why: str = "") -> ParameterError:
        return ParameterError(f"{option} {address!r}: {form}{why}")

    if not isinstance(address, str) or not address or len(address) > 300:
        raise refuse()
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme not in SCHEDULER_PROTOCOLS:
        raise refuse(f" (unknown protocol {scheme!r})")
    if scheme == "inproc":
        if not rest or any(c.isspace() for c in rest):
            raise refuse()
        return address
    host, colon, port = rest.rpartition(":")
    if not colon or not host:
        raise refuse(" (no host and port)")
    if not port.isdigit() or not 1 <= int(port) <= 65535:
        raise refuse(f" (port {port!r})")
    if host.startswith("[") and host.endswith("]"):
        try:
            ipaddress.IPv6Address(host[1:-1])
        except ValueError:
            raise refuse(f" (host {host!r})") from None
        return address
    if re.fullmatch(r"[0-9.]+", host):
        try:
            ipaddress.IPv4Address(host)
        except ValueError:
            raise refuse(f" (host {host!r} is not an IPv4 address)") from None
        return address
    labels = host.split(".")
    if len(host) > 253 or not all(_HOST_LABEL.fullmatch(label) for label in labels):
        raise refuse(f" (host {host!r})")
    return address


@contextlib.contextmanager
def _quiet_libraries() -> Iterator[None]:
    """Silence :data:`QUIET_LOGGERS` for the block (levels restored after it)."""
    loggers = [logging.getLogger(name) for name in QUIET_LOGGERS]
    levels = [lg.level for lg in loggers]
    for lg in loggers:
        lg.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for lg, level in zip(loggers, levels, strict=True):
            lg.setLevel(level)


class _DaskExecutor:
    """A dask client on a local cluster or on a given scheduler; closed on exit."""

    def __init__(self, scheduler: str | None, workers: int | None):
        distributed = require("distributed", purpose="running a study on dask")
        self.distributed = distributed
        self.cluster = None
        started = time.perf_counter()
        if scheduler:
            check_scheduler_address(scheduler)
            try:
                with _quiet_libraries():
                    self.client = distributed.Client(scheduler, timeout=SCHEDULER_TIMEOUT)
            except (OSError, ValueError, TypeError) as exc:
                raise ParameterError(
                    f"--scheduler {scheduler!r}: cannot reach the dask scheduler at that address "
                    f"within {SCHEDULER_TIMEOUT:g} s ({_one_line(exc)}); start it (dask "
                    "scheduler), check the address, or leave --scheduler out for a local cluster"
                ) from None
        else:
            try:
                self.cluster = distributed.LocalCluster(
                    n_workers=workers or available_cores(),
                    threads_per_worker=1,
                    processes=True,
                    # No dashboard, and the scheduler's HTTP server (its health routes, which
                    # distributed starts even without one) on a free port: at its default
                    # 8787 a second study running at once warned "Port 8787 is already in use".
                    dashboard_address=":0",
                    scheduler_kwargs={"dashboard": False},
                    silence_logs=logging.ERROR,
                    preload=[_WORKER_SETUP],
                )
            except RuntimeError as exc:
                raise ParameterError(
                    f"the local dask workers did not start ({exc}). In a Python script, run "
                    'the study under `if __name__ == "__main__":` (dask starts each worker '
                    'process by importing the script), or use executor="local"'
                ) from None
            try:
                self.client = distributed.Client(self.cluster)
            except BaseException:  # an interruption while connecting: close the workers
                with _quiet_libraries():
                    self.cluster.close()
                raise
        try:
            self.workers = len(self.client.scheduler_info().get("workers", {})) or (workers or 1)
        except BaseException:
            self.close(interrupted=True)
            raise
        self.start_s = time.perf_counter() - started
        self.warm_s = 0.0

    def warm(self, point: tuple[int, dict], args) -> None:
        """Warm every worker up now (:func:`_warm_worker`, one task pinned to each), so that
        the first batches do not pay the solver's load and the start-up is timed apart."""
        rig, protocol, metrics, rate, h_max = args
        started = time.perf_counter()
        one = (rig, protocol, [point], metrics, rate, h_max, 1)
        futures = [
            self.client.submit(
                _warm_worker, *one, workers=[address], allow_other_workers=False, pure=False
            )
            for address in self.client.scheduler_info().get("workers", {})
        ]
        try:
            self.distributed.wait(futures)
        finally:
            self._cancel(futures)
        self.warm_s = time.perf_counter() - started

    def run(self, batches, args) -> Iterator[list]:
        rig, protocol, metrics, rate, h_max = args
        rig_f, protocol_f = self.client.scatter([rig, protocol], broadcast=True)
        futures = [
            self.client.submit(
                run_batch, rig_f, protocol_f, batch, metrics, rate, h_max, 1, pure=False
            )
            for batch in batches
        ]
        try:
            for future in self.distributed.as_completed(futures):
                yield future.result()
        finally:
            self._cancel(futures)

    def _cancel(self, futures) -> None:
        """Cancel ``futures`` in one message (not a round trip each). A client that lost its
        scheduler (or a second Ctrl-C) must not replace the error being raised, nor keep the
        cluster from being closed: the cancellation is then left to the close."""
        with contextlib.suppress(Exception), _quiet_libraries():
            self.client.cancel(futures)

    def close(self, *, interrupted: bool = False) -> None:
        """Close the client and the local cluster; after an interruption, quietly (the
        libraries log the cancelled tasks and the lost workers as errors)."""
        with _quiet_libraries() if interrupted else contextlib.nullcontext():
            self.client.close()
            if self.cluster is not None:
                self.cluster.close()


def _close_timed(runner, interrupted: bool, fixed_cost: dict) -> None:
    """Close the dask executor; its time goes to ``fixed_cost["cluster_close_s"]``."""
    closing = time.perf_counter()
    runner.close(interrupted=interrupted)
    fixed_cost["cluster_close_s"] = time.perf_counter() - closing


def run_study(
    study: str | os.PathLike | StudySpec,
    *,
    rig: RigParameters | str | os.PathLike | None = None,
    store: str | os.PathLike | None = None,
    executor: str = "auto",
    scheduler: str | None = None,
    workers: int | None = None,
    batch_size: int | None = None,
    restart: bool = False,
    progress: Callable[[Progress], None] | None = None,
    chosen: Callable[[ExecutorChoice], None] | None = None,
) -> StudyRun:
    """Run a study (or resume it) and return every point with its status and metrics.

    Parameters
    ----------
    study : str, path or StudySpec
        A bundled study name (:func:`~rollerrig.studies.studyfile.bundled_studies`), a study
        file, or a parsed study.
    rig : RigParameters or path, optional
        The base rig; default: the study's ``rig`` entry, else the bundled default rig.
    store : path, optional
        The store's folder (``<study>.zarr``); an existing store of the same study is resumed.
        A store this call created is removed when the run ends, by an error or an interruption,
        before any point is in it. Default: a temporary store, removed after it is read.
    executor : {"auto", "local", "dask"}
        Where the points run (see the module docstring); ``"auto"``: dask when ``scheduler``
        or ``workers`` is given or the study repays a local cluster's start-up, else local.
    scheduler : str, optional
        Address of a running dask scheduler (dask); default: a local cluster.
    workers : int, optional
        Worker processes of the local dask cluster (under ``"auto"``, a request for dask);
        default: the cores this process may use (``os.sched_getaffinity``).
    batch_size : int, optional
        Points per batch; default: 32 per dask task, 8 per numba thread locally.
    restart : bool
        Remove an existing store first and compute every point again.
    progress : callable, optional
        Called with a :class:`Progress` after every batch.
    chosen : callable, optional
        Called with the :class:`~rollerrig.studies.executor_choice.ExecutorChoice` once the
        executor is known (under ``"auto"``, after the first batch).

    Returns
    -------
    StudyRun

    Raises
    ------
    StudyFileError, RigFileError, ProtocolError, StoreError
        A bad study, rig or experiment, or a store of another study, before anything runs.

    Examples
    --------
    >>> run = run_study("lag")  # doctest: +SKIP
    >>> run.executor, run.reason  # doctest: +SKIP
    ('local', 'every point ran in the first batch')
    """
    if not isinstance(study, StudySpec | str | os.PathLike):  # had raised a TypeError
        raise ParameterError(
            f"study must be a bundled study's name, a study file or a StudySpec, got "
            f"{type(study).__name__}"
        )
    spec = study if isinstance(study, StudySpec) else load_study(study)
    if executor not in EXECUTORS:
        raise ParameterError(
            f"executor must be one of {list(EXECUTORS)}, got {executor!r}"
            + did_you_mean(str(executor), EXECUTORS)
        )
    if scheduler is not None:
        check_scheduler_address(scheduler)
    # bool is an int: workers=True had been taken as one worker
    if workers is not None and not (
        isinstance(workers, int) and not isinstance(workers, bool) and workers >= 1
    ):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    if batch_size is not None and not (
        isinstance(batch_size, int) and not isinstance(batch_size, bool) and batch_size >= 1
    ):
        raise ParameterError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    if rig is None:
        rig = load_rig(spec.rig) if spec.rig else default_rig()
    elif not isinstance(rig, RigParameters):
        rig = load_rig(rig)
    protocol = load_protocol(spec.experiment)
    require_measurable(protocol, spec.metrics)  # before any point runs
    table = design_points(spec)

    temporary = store is None
    path = (
        Path(tempfile.mkdtemp(prefix="rollerrig-study-")) / safe_file_name(f"{spec.name}.zarr")
        if temporary
        else Path(store)
    )
    start = time.perf_counter()
    existed = os.path.lexists(path)
    created = False  # whether the store at path is this run's (set once it is)
    recorded = 0  # points this run wrote into the store
    try:
        st = _open_store(path, spec, table, restart)
        created = not temporary and (restart or not existed)
        damaged_files = st.missing
        damaged = st.reset_damaged()  # marked pending in the store: computed again below
        pending = st.pending()
        skipped = len(table) - pending.size
        failed = int(np.isin(st.status(), ("solver failed", "invalid parameters")).sum())
        done = skipped
        args = (rig, protocol, spec.metrics, spec.output_rate, spec.h_max)
        limit = _batch_limit(protocol, spec.output_rate)
        runner = None
        workers_used = 1
        choice = ExecutorChoice(
            "local" if executor == "auto" else executor,
            "nothing to compute: every point was in the store",
        )
        fixed_cost: dict[str, float] = {}
        serial_s = None

        def record(rows) -> None:
            nonlocal done, failed, recorded
            st.record(rows)
            recorded += len(rows)
            done += len(rows)
            failed += sum(r[1] != "ok" for r in rows)
            if progress is not None:
                elapsed = time.perf_counter() - start
                progress(Progress(done, len(table), failed, skipped, elapsed))

        interrupted = True  # until the points are all in: any exception ends the run early
        results: Iterator[list] = iter(())
        try:
            if pending.size:
                asks_dask = bool(scheduler or workers)
                load = executor == "local" or (executor == "auto" and not asks_dask)
                fixed_cost["solver_load_s"] = _ensure_compiled(load=load)
                if progress is not None:
                    progress(Progress(done, len(table), failed, skipped, 0.0))
                import numba

                threads = numba.get_num_threads()
                local_size = min(batch_size or 8 * threads, limit)
                if executor == "auto" and asks_dask:
                    choice = choose_executor(
                        pending.size, cores=available_cores(), scheduler=scheduler,
                        workers=workers,
                    )  # fmt: skip
                elif executor == "auto":
                    first = _batches(table, pending, local_size)[0]
                    timing: dict = {}
                    record(run_batch(*args[:2], first, *args[2:], timing=timing))
                    pending = np.setdiff1d(pending, [i for i, _ in first])
                    serial_s = statistics.median(timing["serial_s"])
                    share = cpu_share(timing["serial_cpu_s"], timing["serial_s"])
                    choice = choose_executor(
                        pending.size, cores=available_cores(), serial_s=serial_s, share=share
                    )
                else:
                    why = f"executor={executor!r} asked for"
                    choice = ExecutorChoice(executor, why, workers=workers)
                if chosen is not None:
                    chosen(choice)
                if not pending.size:
                    workers_used = threads
                elif choice.executor == "dask":
                    runner = _DaskExecutor(scheduler, workers or choice.workers)
                    fixed_cost["cluster_start_s"] = runner.start_s
                    workers_used = runner.workers
                    size = min(batch_size or DASK_BATCH, limit)
                    batches = _batches(table, pending, size)
                    runner.warm(batches[0][0], args)
                    fixed_cost["worker_warm_up_s"] = runner.warm_s
                    results = runner.run(batches, args)
                else:
                    workers_used = threads
                    results = _local(_batches(table, pending, local_size), args)
                for rows in results:
                    record(rows)
            interrupted = False
        finally:
            # Each step runs even when one before it raised (ExitStack: last pushed, first
            # run): flush the store; close the results generator, which an interruption in
            # record() leaves suspended, so that it cancels the dask futures while the client
            # is open (not when collected after the event loop closed); close the cluster.
            with contextlib.ExitStack() as cleanup:
                if runner is not None:
                    cleanup.callback(_close_timed, runner, interrupted, fixed_cost)
                cleanup.callback(getattr(results, "close", lambda: None))
                cleanup.callback(st.flush)
        wall = time.perf_counter() - start
        computed = len(table) - skipped
        if computed:
            st.note_run(
                {
                    "executor": choice.executor,
                    "asked": executor,
                    "reason": choice.reason,
                    "workers": workers_used,
                    "computed": computed,
                    "wall_time_s": wall,
                    "fixed_cost_s": fixed_cost,
                    "serial_s_per_point": serial_s,
                    "cpu_share": choice.share,
                    "cores": available_cores(),
                }
            )
        ds = st.dataset()
        status = np.asarray(ds.status.values, dtype=str)
        counts = {s: int((status == s).sum()) for s in np.unique(status)}
        return StudyRun(
            spec,
            None if temporary else path,
            ds,
            computed,
            int(skipped),
            wall,
            choice.executor,
            workers_used,
            counts,
            damaged,
            damaged_files,
            choice.reason,
            fixed_cost,
            serial_s,
        )
    except BaseException:
        # A run that ends before its first point (a scheduler nobody listens at, Ctrl-C while
        # the solver loads) leaves no store it created: an empty one had stayed in --out.
        if created and not recorded:
            shutil.rmtree(path, ignore_errors=True)
        raise
    finally:
        if temporary:  # the dataset is in memory already (numpy arrays read from the store)
            shutil.rmtree(path.parent, ignore_errors=True)
