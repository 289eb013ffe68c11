"""The rig with the dq V/f roller drive in the compiled backend (rig.model_dq, roller drive
"induction_dq") against the python-level coupled twin it ports
(:class:`rollerrig.rig.drive_dynamics.DqTwin`, scipy Radau)."""

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.rig import dq_twin, model_dq
from rollerrig.rig import drive_dynamics as dd
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.fast import integrate_experiment
from rollerrig.solve.simulation import Simulation

SPEED = 30 / 3.6  # [m/s]
LOAD = 4.3e3  # [N]
# A short release test: 300 N.m wheel torque ramped in 0.1 s from 0.2 s, released at 0.6 s
# in 20 ms.
TORQUE_TIME = [0.0, 0.2, 0.3, 0.6, 0.62, 1.2]
TORQUE = [0.0, 0.0, 300.0, 300.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def rig():
    return default_rig()


def _inputs(rig, torque_time=None, torque=None, wheel="ideal_torque"):
    proto = dq_twin._protocol(SPEED, LOAD, "dry", torque_time, torque)
    inputs = assemble(rig, proto, m.DriveConfig(wheel=wheel, roller="induction_dq"))
    for seg in inputs.segments:  # DqTwin runs without the inverter's torque ripple
        seg.params[m.P_RIPPLE_AMP] = 0.0
    return inputs


def test_layout_and_parameters_follow_the_rig_then_the_drive(rig):
    inputs = _inputs(rig)
    p = inputs.segments[0].params
    drive = dd.default_dq_drive(rig)
    assert p.size == model_dq.N_DQ_PARAMS == m.N_PARAMS + 5 + 13
    np.testing.assert_array_equal(p[model_dq.P_MACHINE : model_dq.P_VF], drive.machine.as_array())
    np.testing.assert_array_equal(p[model_dq.P_VF :], drive.control.as_array())
    assert inputs.initial_state.size == model_dq.N_DQ_STATES == 29
    assert model_dq.STATE_NAMES[model_dq.X_PSI] == "am_psi_s_d"
    assert m.N_STATES == 22  # the default twin keeps its state


def test_initial_state_is_the_dq_twins_steady_free_rolling_and_is_steady(rig):
    inputs = _inputs(rig)
    twin = dd.DqTwin.at(rig, SPEED, LOAD, wheel="ideal_torque")
    x0 = inputs.initial_state
    np.testing.assert_allclose(x0, twin.steady_free_rolling(), rtol=1e-9, atol=1e-9)
    dx = np.empty_like(x0)
    model_dq.rig_dq_rhs(0.0, x0, inputs.segments[0].params, inputs.tables, dx)
    # accelerations [rad/s^2], flux [V] and filter rates at rest: zero to the steady state's
    # solver tolerance (drive_steady_state: scaled residuals < 1e-11)
    assert np.max(np.abs(dx[m.X_OMEGA : m.X_OMEGA + 7])) < 1e-6
    assert np.max(np.abs(dx[model_dq.X_PSI :])) < 1e-6


def test_steady_free_rolling_stays_steady_in_the_fast_backend(rig):
    inputs = _inputs(rig)  # 1 s of free rolling
    t = np.linspace(0.0, 1.0, 101)
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0
    x0 = inputs.initial_state
    drift = np.abs(x - x0)
    assert np.max(drift[:, m.X_OMEGA : m.X_OMEGA + 7]) < 1e-6  # [rad/s]
    assert np.max(drift[:, model_dq.X_PSI : model_dq.X_PSI + 4]) < 1e-7  # [Wb]
    torque = model_dq.air_gap_torque(x.T, inputs.segments[0].params)
    assert np.max(np.abs(torque - torque[0])) < 1e-3  # [N.m]


def test_release_test_agrees_with_the_scipy_dq_twin(rig):
    inputs = _inputs(rig, TORQUE_TIME, TORQUE)
    twin = dd.DqTwin.at(
        rig, SPEED, LOAD, wheel="ideal_torque", torque_time=TORQUE_TIME, torque_request=TORQUE
    )
    t = np.linspace(0.0, 1.2, 301)
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0
    ref = twin.simulate(1.2, t_eval=t, rtol=1e-9, atol=1e-10).y_full.T
    # The fast backend at its defaults (FAST_DEFAULTS: ETDRK4, 1.6 ms) against Radau at rtol
    # 1e-9. Measured: T56 5.8e-3 N.m, fluxes 9.0e-7 Wb, speeds 4.6e-3 rad/s (the PMSM rotor on
    # the wheel shaft), 7.7e-5 rad/s (wheel tyre to AM), the current filters 1.9e-4 A (of about
    # 100 A); ROS34PW2 (method="ros34pw2"): 2.4e-3 N.m, 2.0e-7 Wb, 2.2e-3 and 3.3e-5 rad/s,
    # 2.2e-6 A. Bounds: about 5-10x the larger. The slip filter is left out: without slip
    # compensation it feeds nothing, and DqTwin holds it (an inactive state).
    d = np.max(np.abs(x - ref), axis=0)
    assert np.max(d[m.X_OMEGA : m.X_OMEGA + 7]) < 0.02  # [rad/s]
    assert np.max(d[m.X_OMEGA + 3 : m.X_OMEGA + 7]) < 5e-4  # [rad/s]
    assert np.max(d[model_dq.X_PSI : model_dq.X_PSI + 4]) < 5e-6  # [Wb], of about 1 Wb
    assert np.max(d[model_dq.X_CTRL : model_dq.X_CTRL + 2]) < 2e-3  # [A]
    p = inputs.segments[0].params
    t56 = p[m.P_K56] * (x[:, 4] - x[:, 5]) + p[m.P_B56] * (x[:, 11] - x[:, 12])
    t56_ref = p[m.P_K56] * (ref[:, 4] - ref[:, 5]) + p[m.P_B56] * (ref[:, 11] - ref[:, 12])
    assert np.ptp(t56_ref) > 400.0  # the release moves T56 by hundreds of N.m
    assert np.max(np.abs(t56 - t56_ref)) < 0.03  # [N.m]
    torque = model_dq.air_gap_torque(x.T, p)
    torque_ref = model_dq.air_gap_torque(ref.T, p)
    assert np.max(np.abs(torque - torque_ref)) < 0.01  # [N.m]


def test_simulation_dataset_has_the_machine_torque_and_fluxes(rig):
    proto = dq_twin._protocol(SPEED, LOAD, "dry", TORQUE_TIME, TORQUE)
    ds = Simulation(rig, proto, m.DriveConfig(roller="induction_dq"), output_rate=250.0).run()
    for name in ("am_psi_s_d", "am_psi_s_q", "am_psi_r_d", "am_psi_r_q"):
        assert ds[name].attrs["units"] == "Wb"
    p = assemble(rig, proto, m.DriveConfig(roller="induction_dq")).segments[0].params
    x = np.zeros((ds.time.size, model_dq.N_DQ_STATES))
    for k, name in enumerate(("am_psi_s_d", "am_psi_s_q", "am_psi_r_d", "am_psi_r_q")):
        x[:, model_dq.X_PSI + k] = ds[name].values
    np.testing.assert_allclose(
        ds.roller_drive_torque.values, model_dq.air_gap_torque(x.T, p), rtol=1e-12, atol=1e-9
    )
    np.testing.assert_array_equal(ds.roller_drive_torque_target, ds.roller_drive_torque)
    assert ds.attrs["roller_drive"] == "induction_dq"


@pytest.mark.slow
def test_reference_backend_runs_the_dq_drive(rig):
    proto = dq_twin._protocol(SPEED, LOAD, "dry", TORQUE_TIME, TORQUE)
    drives = m.DriveConfig(roller="induction_dq")
    fast = Simulation(rig, proto, drives, output_rate=250.0).run()
    ref = Simulation(rig, proto, drives, solver="reference", output_rate=250.0, rtol=1e-7).run()
    assert float(np.max(np.abs(fast.t56 - ref.t56))) < 0.5  # [N.m]


def test_a_protocol_starting_at_rest_is_refused_with_a_hint(rig):
    drive = dd.default_dq_drive(rig)
    inputs = _inputs(rig)
    tables = inputs.tables.copy()
    tables[m.TAB_SPEED] = 0.0
    from rollerrig.rig.assemble import dq_steady_free_rolling_state

    with pytest.raises(ParameterError, match="speed set point > 0"):
        dq_steady_free_rolling_state(inputs.segments[0].params, tables, drive)
