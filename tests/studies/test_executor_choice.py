"""executor="auto" (issue 20): the rule, its record, the mixed run, warm dask workers.

The rule's break-even is computed here by hand from its constants (start 4.8 s, warm-up 5.0 s,
close 1.7 s: 11.5 s on a free core) and the formula in
:mod:`rollerrig.studies.executor_choice`: n s (1 - 1/c) > 2 t_fixed.
"""

import json
from typing import ClassVar

import numpy as np
import pytest

from rollerrig.studies import run_study
from rollerrig.studies import runner as runner_module
from rollerrig.studies.executor_choice import (
    ExecutorChoice,
    choose_executor,
    cpu_share,
    dask_fixed_cost,
)
from rollerrig.studies.runner import _local
from rollerrig.studies.studyfile import study_from_toml_string

TINY = """
name = "tiny"
[grid]
"stiffness.roller_shaft" = { values = [43.5, 83.5, 143.5], unit = "kN.m/rad" }
"induction_motor.response_lag_clp" = { values = [2.75, 10000.0] }
[outputs]
metrics = ["release_overshoot", "coa_bias_rms"]
"""


@pytest.mark.parametrize(
    ("points", "kw", "executor"),
    [
        (200, {"cores": 2, "serial_s": 0.038}, "local"),  # a small study: local
        (5000, {"cores": 16, "serial_s": 0.038}, "dask"),  # large, many cores: dask
        (10, {"cores": 1, "scheduler": "tcp://10.0.0.5:8786"}, "dask"),  # scheduler given
        (10, {"cores": 2, "workers": 3}, "dask"),  # workers: a request for dask
        (10**6, {"cores": 1, "serial_s": 0.038}, "local"),  # one core: dask cannot gain
        (5000, {"cores": 2, "serial_s": 0.038, "share": 0.4}, "local"),  # a busy machine
        (5000, {"cores": 16, "serial_s": 0.038, "share": 0.4}, "dask"),  # busy, 6.4 cores free
        (0, {"cores": 16, "serial_s": 0.038}, "local"),  # nothing left after the first batch
        (5000, {"cores": 16}, "local"),  # nothing measured
        (5000, {"cores": 16, "serial_s": float("nan")}, "local"),
    ],
)
def test_the_rule_by_size_cores_load_and_requests(points, kw, executor):
    choice = choose_executor(points, **kw)
    assert choice.executor == executor
    assert choice.reason and "nan" not in choice.reason.lower()


def test_the_break_even_is_where_the_hand_computed_numbers_put_it():
    # 2 cores, 38 ms of Python work a point: 19 ms saved a point against 2 x 11.5 s.
    assert dask_fixed_cost(2, 2) == pytest.approx(11.5)
    assert choose_executor(1210, cores=2, serial_s=0.038).executor == "local"
    assert choose_executor(1211, cores=2, serial_s=0.038).executor == "dask"
    # At half a core each (other load) the start-up doubles and only 1 core is free: local.
    assert dask_fixed_cost(2, 2, share=0.5) == pytest.approx(23.0)
    assert choose_executor(10**7, cores=2, serial_s=0.038, share=0.5).executor == "local"
    # 16 workers warm up at once on 16 cores; 32 on 16 take two rounds of warm-up.
    assert dask_fixed_cost(32, 16) - dask_fixed_cost(16, 16) == pytest.approx(5.0)


def test_the_reason_names_the_numbers_and_the_requests():
    choice = choose_executor(1000, cores=2, serial_s=0.038)
    assert "1000 more points x 38 ms" in choice.reason and "19.0 s" in choice.reason
    assert "11.5 s" in choice.reason and "2 times" in choice.reason
    assert "tcp://h:1" in choose_executor(5, cores=2, scheduler="tcp://h:1").reason
    assert choose_executor(5, cores=2, workers=3).workers == 3


def test_cpu_share_is_cpu_over_wall_within_0_and_1():
    assert cpu_share([0.02, 0.02], [0.05, 0.05]) == pytest.approx(0.4)
    assert cpu_share([0.2], [0.1]) == 1.0  # rounding of two clocks: never above a core
    assert cpu_share([], []) == 1.0 and cpu_share([0.0], [1.0]) > 0


def test_auto_on_a_small_study_runs_here_records_why_and_gives_the_local_numbers(tmp_path):
    spec = study_from_toml_string(TINY)
    seen = []
    auto = run_study(spec, store=tmp_path / "s.zarr", chosen=seen.append)
    assert auto.executor == "local" and seen[0].executor == "local"
    assert auto.reason == "every point ran in the first batch" == seen[0].reason
    assert auto.serial_s > 0 and "solver_load_s" in auto.fixed_cost
    (record,) = json.loads(auto.dataset.attrs["runs"])
    assert record["asked"] == "auto" and record["executor"] == "local"
    assert record["reason"] == auto.reason and record["computed"] == 6
    local = run_study(spec, executor="local").dataset
    for m in ("release_overshoot", "coa_bias_rms"):
        np.testing.assert_array_equal(auto.dataset[m].values, local[m].values)


class _FakeDask:
    """Stands in for the dask executor: runs the batches here and says what it was asked."""

    made: ClassVar[list] = []

    def __init__(self, scheduler, workers):
        self.workers, self.start_s, self.warm_s = workers or 1, 0.5, 0.25
        self.warmed = None
        _FakeDask.made.append(self)

    def warm(self, point, args):
        self.warmed = point

    def run(self, batches, args):
        self.batches = [[i for i, _ in b] for b in batches]
        return _local(batches, args)

    def close(self, *, interrupted=False):
        self.closed = True


@pytest.fixture
def fake_dask(monkeypatch):
    _FakeDask.made = []
    monkeypatch.setattr(runner_module, "_DaskExecutor", _FakeDask)
    return _FakeDask.made


def test_auto_moves_the_rest_to_dask_after_the_first_batch_when_the_rule_says(
    monkeypatch, fake_dask
):
    seen = []

    def rule(points, **kw):
        seen.append((points, kw))
        return ExecutorChoice("dask", "the test's rule", workers=2)

    monkeypatch.setattr(runner_module, "choose_executor", rule)
    spec = study_from_toml_string(TINY)
    run = run_study(spec, batch_size=2)
    ((points, kw),), (made,) = seen, fake_dask
    assert points == 4 and kw["serial_s"] > 0 and 0 < kw["share"] <= 1  # 2 ran here first
    assert sorted(i for b in made.batches for i in b) == [2, 3, 4, 5] and made.closed
    assert made.warmed[0] == 2 and made.workers == 2  # warmed on a point it then runs
    assert run.executor == "dask" and run.reason == "the test's rule"
    assert run.fixed_cost["cluster_start_s"] == 0.5 and run.fixed_cost["worker_warm_up_s"] == 0.25
    local = run_study(spec, executor="local").dataset
    np.testing.assert_array_equal(run.dataset.release_overshoot.values,
                                  local.release_overshoot.values)  # fmt: skip
    assert list(run.dataset.status.values) == ["ok"] * 6


def test_workers_under_auto_are_a_request_for_dask_with_no_local_batch(fake_dask):
    run = run_study(study_from_toml_string(TINY), workers=3)
    (made,) = fake_dask
    assert run.executor == "dask" and made.workers == 3 and run.serial_s is None
    assert sorted(i for b in made.batches for i in b) == list(range(6))
    assert run.reason == "3 workers asked for: a local dask cluster"


@pytest.mark.slow  # ~15 s: a local dask cluster of one worker starts
def test_a_dask_worker_loads_the_solver_once_when_warmed_and_keeps_it(tmp_path):
    import os

    from rollerrig import default_rig, load_protocol
    from rollerrig.studies.design import design_points

    spec = study_from_toml_string(TINY)
    table = design_points(spec)
    points = [(i, table.point(i)) for i in range(6)]
    args = (default_rig(), load_protocol(spec.experiment), spec.metrics, spec.output_rate,
            spec.h_max)  # fmt: skip

    def state():
        from rollerrig.solve.fast import _integrate_exp

        return os.getpid(), len(_integrate_exp.overloads)

    # A second study's cluster holds distributed's default HTTP port: this one must not warn
    # (it did, "Port 8787 is already in use", when two studies ran at once).
    import socket
    import warnings

    taken = socket.socket()
    try:
        taken.bind(("127.0.0.1", 8787))
        taken.listen()
    except OSError:  # something already listens there: the condition holds anyway
        pass
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("error", message=".*already in use")
            ex = runner_module._DaskExecutor(None, 1)
    finally:
        taken.close()
    try:
        before = ex.client.run(state)
        ex.warm(points[0], args)
        warmed = ex.client.run(state)
        rows = [r for batch in ex.run([points[:3], points[3:]], args) for r in batch]
        after = ex.client.run(state)
    finally:
        ex.close()
    assert [n for _, n in before.values()] == [0]  # nothing loaded before the warm-up
    assert [n for _, n in warmed.values()] == [1]  # the compiled driver, once
    assert after == warmed  # the same process, the same driver after two batches
    assert ex.start_s > 0 and ex.warm_s > 0
    assert sorted(r[0] for r in rows) == list(range(6)) and {r[1] for r in rows} == {"ok"}


class _InterruptedDask(_FakeDask):
    """A dask executor whose results generator says when its cleanup runs; the cleanup can
    fail, as a client that lost its scheduler does."""

    log: ClassVar[list] = []
    cleanup_fails: ClassVar[bool] = False

    def run(self, batches, args):
        try:
            yield from _local(batches, args)
        finally:
            _InterruptedDask.log.append("cancelled")
            if _InterruptedDask.cleanup_fails:
                raise RuntimeError("the client is closed")

    def close(self, *, interrupted=False):
        _InterruptedDask.log.append(("closed", interrupted))


@pytest.mark.parametrize("cleanup_fails", [False, True])
def test_ctrl_c_while_recording_cancels_before_closing_the_cluster(monkeypatch, cleanup_fails):
    """Ctrl-C while a batch is being recorded leaves the results generator suspended: its
    cleanup (cancelling the futures) must run before the client closes, not when it is
    collected after (the CI's traceback), and the cluster closes even if that cleanup fails."""
    _InterruptedDask.log, _InterruptedDask.cleanup_fails = [], cleanup_fails
    monkeypatch.setattr(runner_module, "_DaskExecutor", _InterruptedDask)
    calls = []

    def progress(p):
        calls.append(p)
        if p.done >= 2:  # after the first batch is recorded
            raise KeyboardInterrupt

    with pytest.raises(RuntimeError if cleanup_fails else KeyboardInterrupt):
        run_study(study_from_toml_string(TINY), workers=2, batch_size=2, progress=progress)
    assert _InterruptedDask.log == ["cancelled", ("closed", True)]
