"""The fast backend's batch driver against its single-run driver."""

import time

import numpy as np
import pytest

from rollerrig.rig.assemble import assemble
from rollerrig.rig.model import DriveConfig
from rollerrig.solve import fast
from rollerrig.solve.fast import integrate_batch, integrate_experiment
from rollerrig.solve.simulation import Simulation


def test_batch_equals_single_runs_whatever_the_thread_shares():
    """Variants of unequal cost run one per thread at a time; every variant's states and
    counts are those of its own single run, to the bit."""
    sim = Simulation(experiment="seed-30kmh-dry")
    t = sim.times[::25]
    variants = [
        assemble(sim.inputs.rig.with_overrides({"stiffness.roller_shaft": k}), sim.protocol, d)
        for k, d in ((43.5e3, DriveConfig()), (143.5e3, DriveConfig(roller_lag=0.0)))
    ]
    variants.append(sim.inputs)
    x, stats = integrate_batch(variants, t)
    for inputs, xb, sb in zip(variants, x, stats, strict=True):
        xs, ss = integrate_experiment(inputs, t)
        np.testing.assert_array_equal(xb, xs)
        assert sb == ss


def test_every_driver_releases_the_gil_so_that_the_batch_threads_run_at_once():
    """integrate_batch runs the single drivers in Python threads: held, the GIL would make
    the batch serial (same results, half the speed on 2 cores)."""
    drivers = (fast._integrate, fast._integrate_exp, *fast._dq_drivers())
    assert all(d.targetoptions.get("nogil") for d in drivers)


def test_an_interrupted_batch_starts_no_further_variant(monkeypatch):
    """Ctrl-C (here raised by the first variant) drops the variants not started: only those
    already running finish, instead of the whole batch running on before the error shows."""
    calls = []

    def driver(*args):
        calls.append(None)
        if len(calls) == 1:
            raise KeyboardInterrupt
        time.sleep(0.01)  # a variant's solve
        return 0

    monkeypatch.setattr(fast, "_bound_driver", lambda *args: (driver, 0))
    inputs = Simulation(experiment="seed-30kmh-dry").inputs
    with pytest.raises(KeyboardInterrupt):
        integrate_batch([inputs] * 50, np.array([0.0, 0.01]))
    assert len(calls) < 10


def test_the_etdrk4_driver_leaves_ros34pw2_uncompiled_until_a_segment_needs_it():
    """The ETDRK4 driver hands a segment that needs the fallback back to Python (which runs
    ROS34PW2's driver on it and resumes) instead of calling ROS34PW2 from compiled code, so a
    run that needs no fallback (the default experiment) compiles only ETDRK4's driver: 7-10 s
    less of a first run's compilation, measured with numba's compile events (issue 20). That the
    fallback still runs and resumes: test_etdrk4's macro-slip and stiff-shaft cases."""
    names = fast._integrate_exp.py_func.__code__.co_names
    assert "_exp_segment" in names
    assert "_rig_integrate" not in names


def test_the_step_loop_and_the_model_are_compiled_without_reference_counting():
    """Reference counts taken and given back (atomic operations) in every step and every call
    of the creep law were 12-30 % of the solve's samples (perf, 2026-11-30): the segment's step
    loop and the model's right-hand side are compiled with ``_nrt=False``."""
    from rollerrig.solve import etdrk4
    from rollerrig.solve._compiled import rig_rhs

    _, prepare, segment = etdrk4.bind(fast.RIG, "rig")
    assert segment.targetoptions.get("_nrt") is False
    assert rig_rhs.targetoptions.get("_nrt") is False
    assert prepare.targetoptions.get("_nrt", True) is not False  # it allocates (eigenvalues)


@pytest.mark.parametrize(
    ("t0", "t1", "goes"),
    [
        (0.0, 1.0, False),  # a hold at 3 m/s
        (1.0, 2.0, True),  # a ramp down to standstill
        (2.0, 3.0, True),  # a ramp up from it
        (0.5, 3.5, True),  # through standstill at a breakpoint inside (a replayed set point)
        (4.0, 5.0, False),  # a hold at standstill: the V/f supply is off, no such stiffness
        (5.0, 6.0, True),  # from standstill to 0.005 m/s, below STOP_SPEED all along
    ],
)
def test_ramps_to_from_and_through_standstill_go_to_the_fallback(t0, t1, goes):
    from rollerrig.rig import model as m
    from rollerrig.solve.fast import _stops

    tables = np.zeros((m.N_TABLE_ROWS, 7))
    tables[m.TAB_SPEED_T] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    tables[m.TAB_SPEED] = [3.0, 3.0, 0.0, 3.0, 0.0, 0.0, 0.005]
    tables[m.TAB_TORQUE_T] = tables[m.TAB_LOAD_T] = tables[m.TAB_SPEED_T]
    assert bool(_stops(tables, t0, t1)) is goes
    assert bool(_stops.py_func(tables, t0, t1)) is goes  # needs_fallback's


def test_a_run_asked_for_its_first_seconds_integrates_only_that_far_and_gives_the_same_bits():
    """The driver stops at the end of the segment that holds the last output instant: the rows
    it returns are those of the whole run, bit for bit (single call, segment by segment with
    progress, and in a batch), in fewer steps; a warm-up call of 10 ms does not integrate the
    rest of the experiment."""
    sim = Simulation(experiment="seed-30kmh-dry")
    t = sim.times
    whole, stats_whole = integrate_experiment(sim.inputs, t)
    # A batch's variants differ: each must get its own parameters, cut to the same segments.
    stiffer = assemble(
        sim.inputs.rig.with_overrides({"stiffness.roller_shaft": 90e3}), sim.protocol
    )
    stiffer_whole, _ = integrate_experiment(stiffer, t)
    first_end = sim.inputs.segments[0].end
    for k in (1, 3, int(np.searchsorted(t, first_end)) + 1, t.size // 2):
        part, stats = integrate_experiment(sim.inputs, t[:k])
        np.testing.assert_array_equal(part, whole[:k])
        assert stats["accepted_steps"] < stats_whole["accepted_steps"]
        assert t[k - 1] <= stats["t_stop"] < sim.inputs.segments[-1].end
        stepped, _ = integrate_experiment(sim.inputs, t[:k], progress=lambda *_: None)
        np.testing.assert_array_equal(stepped, whole[:k])
        batch, _ = integrate_batch([stiffer, sim.inputs], t[:k])
        np.testing.assert_array_equal(batch[0], stiffer_whole[:k])
        np.testing.assert_array_equal(batch[1], whole[:k])
    assert integrate_experiment(sim.inputs, t[:3])[1]["t_stop"] == first_end


def test_the_reference_integrates_only_as_far_as_its_last_output_instant():
    from rollerrig.solve.reference import integrate_reference

    sim = Simulation(experiment="seed-30kmh-dry")
    t = sim.times
    ends = [s.end for s in sim.inputs.segments]
    two = t[: int(np.searchsorted(t, ends[1], side="right"))]  # the first two segments
    longer, stats_longer = integrate_reference(sim.inputs, two, rtol=1e-6)
    part, stats = integrate_reference(sim.inputs, two[:3], rtol=1e-6)
    np.testing.assert_array_equal(part, longer[:3])
    assert stats["t_stop"] == ends[0] and stats_longer["t_stop"] == ends[1]
    assert stats["rhs_evaluations"] < stats_longer["rhs_evaluations"]


@pytest.mark.parametrize(
    ("t_out", "message"),
    [
        ([0.0, 31.0], r"got t_out\[1\] = 31, after its end"),
        ([0.0, 2.0, 1.0], r"must not go back in time"),
        ([0.0, float("nan")], r"must be finite"),
    ],
)
def test_output_instants_outside_the_experiment_are_refused_by_every_backend(t_out, message):
    """Past the experiment's end the fast driver had returned uninitialised rows with status
    0, and instants out of order the state at the largest of them: now a ParameterError from
    the fast backend, its batch and the reference alike."""
    from rollerrig._validation import ParameterError
    from rollerrig.solve.reference import integrate_reference

    inputs = Simulation(experiment="seed-30kmh-dry").inputs
    for run in (
        lambda: integrate_experiment(inputs, t_out),
        lambda: integrate_batch([inputs], t_out),
        lambda: integrate_reference(inputs, t_out),
    ):
        with pytest.raises(ParameterError, match=message):
            run()
