"""Running a study: batches of points on the compiled backend, in this process or on dask.

Two executors run the same batches (:func:`run_batch`) and give identical results:

``"local"``
    In this process, each batch integrated in parallel by numba's threads (all cores).
``"dask"``
    On ``dask.distributed``: a local cluster of ``workers`` processes (one thread each) by
    default, or any running scheduler (``scheduler="tcp://host:8786"``) for a real cluster.
    Each worker loads the compiled backend once (from the on-disk cache; a worker on another
    machine compiles it there once) and runs batches one after the other.

Every point ends with a status (:data:`rollerrig.studies.store.STATUSES`): a value the rig or
the experiment refuses is ``invalid parameters``, a run the solver cannot finish ``solver
failed``, both with the reason, and the rest of the study goes on. Finished points go to the
store as they arrive (:class:`~rollerrig.studies.store.StudyStore`), so an interrupted study
resumes where it stopped: running it again into the same store computes only the points still
pending.
"""

from __future__ import annotations

import logging
import math
import os
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._optional import require
from rollerrig._validation import ParameterError
from rollerrig.experiment import Protocol, load_protocol
from rollerrig.rig.parameters import RigParameters, default_rig, load_rig
from rollerrig.studies.design import (
    DesignTable,
    design_points,
    parameter_attrs,
    point_setup,
    protocol_groups,
)
from rollerrig.studies.metrics import METRICS, compute_metrics, run_channels
from rollerrig.studies.store import StoreError, StudyStore
from rollerrig.studies.studyfile import StudySpec, load_study

__all__ = [
    "EXECUTORS",
    "Progress",
    "StudyRun",
    "run_batch",
    "run_study",
]

EXECUTORS = ("local", "dask")
"""The executors a study can run on."""
BATCH_BYTES = 256 * 2**20
"""Largest solution a batch holds in memory [bytes] (states of every point at every sample)."""
DASK_BATCH = 32
"""Points per dask task: long enough (a fraction of a second) that scheduling costs little,
short enough that progress moves and the workers share the load evenly."""


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
    workers : int
        Processes (dask) or numba threads (local) that ran the points.
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
        Largest step [s]; default :data:`rollerrig.solve.fast.SWEEP_H_MAX`.
    threads : int, optional
        numba threads to use here (a dask worker uses 1); default: numba's setting.

    Returns
    -------
    list of (index, status, reason, metrics)
        One per point, in the order given.
    """
    from rollerrig.rig.assemble import assemble
    from rollerrig.solve.fast import SWEEP_H_MAX, failure_reason, integrate_batch
    from rollerrig.solve.simulation import output_times

    if threads is not None:
        import numba

        numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
    rows: dict[int, tuple] = {}
    ready, inputs = [], []
    point_protocol = None
    for index, values in points:
        try:
            r, p, d = point_setup(rig, protocol, values)
            inp = assemble(r, p, d)
        except ParameterError as exc:
            rows[index] = (index, "invalid parameters", _one_line(exc), {})
            continue
        point_protocol = p
        ready.append(index)
        inputs.append(inp)
    if inputs:
        t = output_times(point_protocol.duration, output_rate)
        x, stats = integrate_batch(inputs, t, h_max=h_max or SWEEP_H_MAX)
        for index, inp, xi, st in zip(ready, inputs, x, stats, strict=True):
            if st["status"] != 0:
                reason = f"the fast solver failed {failure_reason(st['status'], st['t_stop'])}"
                rows[index] = (index, "solver failed", _one_line(reason), {})
                continue
            try:
                values = compute_metrics(run_channels(inp, t, xi), point_protocol, metrics)
            except Exception as exc:  # a study records a broken point and goes on
                reason = f"measuring the run failed: {type(exc).__name__}: {exc}"
                rows[index] = (index, "solver failed", _one_line(reason), {})
                continue
            rows[index] = (index, "ok", "", values)
    return [rows[index] for index, _ in points]


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


def _open_store(path: Path, spec: StudySpec, table: DesignTable, restart: bool) -> StudyStore:
    from rollerrig.output.provenance import provenance

    if path.exists() and restart:
        if not (path / "zarr.json").is_file():
            raise StoreError(f"{path}: exists and is not a study store; not removing it")
        shutil.rmtree(path)
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


def _ensure_compiled() -> None:
    """Compile the batch driver here, once, before workers start: they then load it from the
    cache instead of each compiling it at the same time."""
    from rollerrig.solve.fast import integrate_batch, is_compiled

    if is_compiled(batch=True):
        return
    from rollerrig.rig.assemble import assemble

    inp = assemble(default_rig(), load_protocol("release-test"))
    integrate_batch([inp], np.array([0.0, 0.01]))


def _local(batches, args) -> Iterator[list]:
    for batch in batches:
        yield run_batch(*args[:2], batch, *args[2:])


class _DaskExecutor:
    """A dask client on a local cluster or on a given scheduler; closed on exit."""

    def __init__(self, scheduler: str | None, workers: int | None):
        distributed = require("distributed", purpose="running a study on dask")
        self.distributed = distributed
        self.cluster = None
        if scheduler:
            try:
                self.client = distributed.Client(scheduler, timeout="20s")
            except OSError as exc:
                raise ParameterError(
                    f"--scheduler {scheduler}: cannot reach the dask scheduler ({exc}); start "
                    "it (dask scheduler) or leave --scheduler out for a local cluster"
                ) from None
        else:
            try:
                self.cluster = distributed.LocalCluster(
                    n_workers=workers or os.cpu_count() or 1,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=logging.ERROR,
                )
            except RuntimeError as exc:
                raise ParameterError(
                    f"the local dask workers did not start ({exc}). In a Python script, run "
                    'the study under `if __name__ == "__main__":` (dask starts each worker '
                    'process by importing the script), or use executor="local"'
                ) from None
            self.client = distributed.Client(self.cluster)
        self.workers = len(self.client.scheduler_info().get("workers", {})) or (workers or 1)

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
            for f in futures:
                f.cancel()

    def close(self) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def run_study(
    study: str | os.PathLike | StudySpec,
    *,
    rig: RigParameters | str | os.PathLike | None = None,
    store: str | os.PathLike | None = None,
    executor: str = "dask",
    scheduler: str | None = None,
    workers: int | None = None,
    batch_size: int | None = None,
    restart: bool = False,
    progress: Callable[[Progress], None] | None = None,
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
        Default: a temporary store, removed after it is read.
    executor : {"dask", "local"}
        Where the points run (see the module docstring).
    scheduler : str, optional
        Address of a running dask scheduler (``executor="dask"``); default: a local cluster.
    workers : int, optional
        Worker processes of the local cluster; default: the machine's cores.
    batch_size : int, optional
        Points per batch; default: 32 per dask task, 8 per numba thread locally.
    restart : bool
        Remove an existing store first and compute every point again.
    progress : callable, optional
        Called with a :class:`Progress` after every batch.

    Returns
    -------
    StudyRun

    Raises
    ------
    StudyFileError, RigFileError, ProtocolError, StoreError
        A bad study, rig or experiment, or a store of another study, before anything runs.
    """
    spec = study if isinstance(study, StudySpec) else load_study(study)
    if executor not in EXECUTORS:
        raise ParameterError(f"executor must be one of {list(EXECUTORS)}, got {executor!r}")
    if workers is not None and not (isinstance(workers, int) and workers >= 1):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    if batch_size is not None and not (isinstance(batch_size, int) and batch_size >= 1):
        raise ParameterError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    if rig is None:
        rig = load_rig(spec.rig) if spec.rig else default_rig()
    elif not isinstance(rig, RigParameters):
        rig = load_rig(rig)
    protocol = load_protocol(spec.experiment)
    table = design_points(spec)

    temporary = store is None
    path = (
        Path(tempfile.mkdtemp(prefix="rollerrig-study-")) / f"{spec.name}.zarr"
        if temporary
        else Path(store)
    )
    start = time.perf_counter()
    try:
        st = _open_store(path, spec, table, restart)
        pending = st.pending()
        skipped = len(table) - pending.size
        failed = int(np.isin(st.status(), ("solver failed", "invalid parameters")).sum())
        done = skipped
        args = (rig, protocol, spec.metrics, spec.output_rate, spec.h_max)
        limit = _batch_limit(protocol, spec.output_rate)
        runner = None
        workers_used = 1
        try:
            if pending.size:
                _ensure_compiled()
                if executor == "dask":
                    runner = _DaskExecutor(scheduler, workers)
                    workers_used = runner.workers
                    size = min(batch_size or DASK_BATCH, limit)
                    results = runner.run(_batches(table, pending, size), args)
                else:
                    import numba

                    workers_used = numba.get_num_threads()
                    size = min(batch_size or 8 * workers_used, limit)
                    results = _local(_batches(table, pending, size), args)
                if progress is not None:
                    progress(Progress(done, len(table), failed, skipped, 0.0))
                for rows in results:
                    st.record(rows)
                    done += len(rows)
                    failed += sum(r[1] != "ok" for r in rows)
                    if progress is not None:
                        elapsed = time.perf_counter() - start
                        progress(Progress(done, len(table), failed, skipped, elapsed))
        finally:
            st.flush()
            if runner is not None:
                runner.close()
        wall = time.perf_counter() - start
        ds = st.dataset()
        status = np.asarray(ds.status.values, dtype=str)
        counts = {s: int((status == s).sum()) for s in np.unique(status)}
        return StudyRun(
            spec,
            None if temporary else path,
            ds,
            int(pending.size),
            int(skipped),
            wall,
            executor,
            workers_used,
            counts,
        )
    finally:
        if temporary:  # the dataset is in memory already (numpy arrays read from the store)
            shutil.rmtree(path.parent, ignore_errors=True)
