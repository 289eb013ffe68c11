"""The fast backend's drivers of the model with the dq roller drive ("induction_dq"):
chosen by the inputs, per-model tolerances, batches."""

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.rig import drive_dynamics as dd
from rollerrig.rig import model as m
from rollerrig.rig import model_dq
from rollerrig.rig.assemble import assemble
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.fast import (
    default_tolerances,
    dq_tolerances,
    integrate_batch,
    integrate_experiment,
)

TORQUE_TIME = [0.0, 0.1, 0.2, 0.4, 0.42, 0.8]
TORQUE = [0.0, 0.0, 300.0, 300.0, 0.0, 0.0]


def _inputs(rig, roller="induction_dq"):
    proto = dd._protocol(30 / 3.6, 4.3e3, "dry", TORQUE_TIME, TORQUE)
    return assemble(rig, proto, m.DriveConfig(roller=roller))


def test_dq_tolerances_extend_the_rigs_by_the_drive_states():
    rt, at = dq_tolerances(1e-5)
    rt0, at0 = default_tolerances(1e-5)
    assert rt.size == at.size == model_dq.N_DQ_STATES
    np.testing.assert_array_equal(rt[: m.N_STATES], rt0)
    np.testing.assert_array_equal(at[: m.N_STATES], at0)
    assert np.all(at[m.N_STATES :] > 0.0)


def test_progress_segments_give_the_same_result_as_one_call():
    inputs = _inputs(default_rig())
    t = np.linspace(0.0, 0.8, 201)
    x, stats = integrate_experiment(inputs, t)
    seen = []
    x2, stats2 = integrate_experiment(inputs, t, progress=lambda a, b: seen.append(a))
    assert x.shape == (t.size, model_dq.N_DQ_STATES)
    assert stats["status"] == stats2["status"] == 0
    np.testing.assert_allclose(x2, x, rtol=0, atol=1e-9)
    assert seen[-1] == pytest.approx(0.8)


def test_a_batch_mixing_models_is_refused():
    rig = default_rig()
    with pytest.raises(ParameterError, match="induction_dq"):
        integrate_batch([_inputs(rig), _inputs(rig, "induction")], np.linspace(0.0, 0.8, 5))


@pytest.mark.slow
def test_a_dq_batch_equals_the_single_runs():
    rig = default_rig()
    stiff = rig.with_overrides({"stiffness.roller_shaft": 2 * rig.stiffness.roller_shaft})
    variants = [_inputs(rig), _inputs(stiff)]
    t = np.linspace(0.0, 0.8, 201)
    xb, stats = integrate_batch(variants, t)
    assert [s["status"] for s in stats] == [0, 0]
    for i, inputs in enumerate(variants):
        x, _ = integrate_experiment(inputs, t)
        np.testing.assert_allclose(xb[i], x, rtol=0, atol=1e-12)
