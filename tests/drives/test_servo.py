"""Tests of the speed-controlled servo roller drive (the seed's proposed fix, chapter 5).

References used below:
- Closed loop of a PI speed controller on a rigid inertia J:
  ω/ω* = (kp s + ki)/(J s^2 + kp s + ki) (Ellis, Control System Design Guide, 2012, ch. 6),
  evaluated independently with scipy.signal.
- Its step response for ζ = 1 in closed form (partial fractions, checked here):
  y(t) = 1 - e^{-ω_n t} + ω_n t e^{-ω_n t}; peak 1 + e^{-2} at t = 2/ω_n (13.53 % overshoot).
- Anti-windup by back-calculation: Åström & Hägglund, Advanced PID Control (2006), sec. 3.5.
- Roller inertias J5 = 45, J6 = 6.6 kg.m^2: Kayaalp, section 4.5.1.5.
"""

from __future__ import annotations

import re

import numba
import numpy as np
import pytest
from scipy import signal
from scipy.integrate import solve_ivp

from rollerrig._validation import ParameterError
from rollerrig.drives.induction import lag_derivative
from rollerrig.drives.servo import (
    servo_gains_for_bandwidth,
    servo_speed_torque,
)
from rollerrig.rig.parameters import default_rig

J = 45.0 + 6.6
WN = 2.0 * np.pi * 5.0
KP, KI = servo_gains_for_bandwidth(J, WN, 1.0)
T_LIM = 2.0 * 891.0


def simulate(omega_ref, t_end, *, tau=0.0, load=lambda t: 0.0, limit=T_LIM, windup=False, n=801):
    """Rigid inertia J ω' = T - T_load driven by the servo; state (ω, I[, T_act])."""

    def rhs(t, y):
        omega, integral = y[0], y[1]
        cmd, dint = servo_speed_torque(omega, omega_ref, integral, KP, KI, limit)
        if windup:  # naive PI for comparison: integrate the error regardless of saturation
            dint = omega_ref - omega
        if tau > 0.0:
            torque = y[2]
            return [(torque - load(t)) / J, dint, lag_derivative(cmd, torque, tau)]
        return [(cmd - load(t)) / J, dint]

    y0 = [0.0, 0.0, 0.0] if tau > 0.0 else [0.0, 0.0]
    t = np.linspace(0.0, t_end, n)
    sol = solve_ivp(rhs, (0.0, t_end), y0, t_eval=t, method="LSODA", rtol=1e-10, atol=1e-10)
    assert sol.success
    return sol


def test_gains_pole_placement():
    assert (KP, KI) == pytest.approx((2.0 * WN * J, WN**2 * J), rel=1e-15)
    den = np.array([J, KP, KI]) / J
    poles = np.roots(den)
    np.testing.assert_allclose(poles, [-WN, -WN], rtol=1e-6)  # double pole for ζ = 1
    kp, ki = servo_gains_for_bandwidth(J, WN, 0.5)
    np.testing.assert_allclose(np.abs(np.roots([J, kp, ki])), WN, rtol=1e-12)  # |pole| = ω_n
    with pytest.raises(ParameterError, match=r"inertia.*kg\.m\^2"):
        servo_gains_for_bandwidth(0.0, WN)
    with pytest.raises(ParameterError, match=r"servo_roller_drive\.torque_time_constant"):
        default_rig().with_overrides({"servo_roller_drive.torque_time_constant": -1.0})


def test_closed_form_of_the_zeta_one_step_response():
    t = np.linspace(0.0, 2.0, 401)
    _, y_tf = signal.step(([KP, KI], [J, KP, KI]), T=t)
    closed = 1.0 - np.exp(-WN * t) + WN * t * np.exp(-WN * t)
    np.testing.assert_allclose(y_tf, closed, atol=1e-10)


def test_step_response_matches_transfer_function_and_overshoot():
    step = 0.5  # rad/s: small enough that kp * step stays below the torque limit
    assert KP * step < T_LIM
    sol = simulate(step, 1.0)
    _, y_tf = signal.step(([KP, KI], [J, KP, KI]), T=sol.t)
    np.testing.assert_allclose(sol.y[0], step * y_tf, atol=1e-7 * step)
    overshoot = sol.y[0].max() / step - 1.0
    assert overshoot == pytest.approx(np.exp(-2.0), rel=1e-4)  # 13.53 %
    assert sol.t[np.argmax(sol.y[0])] == pytest.approx(2.0 / WN, abs=2 * (sol.t[1] - sol.t[0]))
    # settling: within 2 % after the closed-form time (y - 1 = (ω_n t - 1) e^{-ω_n t})
    settle = sol.t[np.nonzero(np.abs(sol.y[0] / step - 1.0) > 0.02)[0][-1]]
    t_closed = sol.t[np.nonzero(np.abs((WN * sol.t - 1) * np.exp(-WN * sol.t)) > 0.02)[0][-1]]
    assert settle == pytest.approx(t_closed, abs=2 * (sol.t[1] - sol.t[0]))


def test_step_response_with_torque_actuator_lag():
    tau, step = 5e-3, 0.5
    sol = simulate(step, 1.0, tau=tau)
    _, y_tf = signal.step(([KP, KI], [J * tau, J, KP, KI]), T=sol.t)
    np.testing.assert_allclose(sol.y[0], step * y_tf, atol=1e-7 * step)
    assert sol.y[0].max() / step - 1.0 > np.exp(-2.0)  # the lag adds overshoot


def test_load_torque_step_is_rejected_with_zero_steady_state_error():
    step, load = 0.5, 600.0

    def load_fn(t):
        return load if t >= 1.0 else 0.0

    sol = simulate(step, 3.0, load=load_fn, n=3001)
    after = sol.t > 1.0
    assert np.max(step - sol.y[0][after]) > 0.01  # the load does pull the speed down
    assert sol.y[0, -1] == pytest.approx(step, abs=1e-6)  # integral action removes the error
    assert KI * sol.y[1, -1] == pytest.approx(load, rel=1e-6)  # integrator carries the load
    # peak dip: disturbance transfer -s/(J s^2 + kp s + ki); for ζ = 1 the dip is
    # load/(J ω_n) * max(x e^{-x}) = load/(J ω_n e)
    dip = np.max(step - sol.y[0][after])
    assert dip == pytest.approx(load / (J * WN * np.e), rel=1e-3)


def test_anti_windup_keeps_integrator_bounded_and_limits_overshoot():
    big = 20.0  # rad/s: needs kp * 20 = 65 kN.m, far over the 1.8 kN.m limit
    sol = simulate(big, 4.0, n=4001)
    cmd, _ = servo_speed_torque(sol.y[0], big, sol.y[1], KP, KI, T_LIM)
    assert np.all(np.abs(cmd) <= T_LIM)
    assert np.max(np.abs(KI * sol.y[1])) <= T_LIM * (1.0 + 1e-6)
    assert sol.y[0, -1] == pytest.approx(big, abs=1e-4)
    naive = simulate(big, 4.0, windup=True, n=4001)
    over_aw = sol.y[0].max() - big
    over_naive = naive.y[0].max() - big
    assert over_naive > 5.0 * max(over_aw, 1e-3)
    assert np.max(np.abs(naive.y[1])) > 10.0 * np.max(np.abs(sol.y[1]))


@pytest.mark.parametrize(
    "args",
    [
        (10.0, 10.5, 0.01, KP, KI, T_LIM),
        (10.0, 30.0, 0.01, KP, KI, T_LIM),
        (30.0, 10.0, -0.5, KP, KI, T_LIM),
    ],
)
def test_kernel_compiles_with_numba(args):
    expected = servo_speed_torque(*args)
    got = numba.njit(servo_speed_torque)(*args)
    np.testing.assert_allclose(got, expected, rtol=1e-14)


def test_kernel_elementwise_and_back_calculation():
    omega = np.array([10.0, 10.0, 30.0])
    cmd, dint = servo_speed_torque(omega, 10.5, 0.0, KP, KI, T_LIM)
    np.testing.assert_allclose(cmd, [KP * 0.5, KP * 0.5, -T_LIM])
    assert dint[0] == 0.5  # unsaturated: plain integral of the error
    assert dint[2] == pytest.approx(-19.5 + (-T_LIM - KP * -19.5) / KP)


def test_servo_gains_beyond_float_range_are_a_parameter_error():
    """bandwidth**2 overflowed: a bare OverflowError."""
    with pytest.raises(
        ParameterError,
        match=re.escape("inertia = 1e+300 kg.m^2 at bandwidth = 1e+300 rad/s gives gains beyond"),
    ):
        servo_gains_for_bandwidth(1e300, 1e300)
