"""Tests of the roller AM: Thevenin torque (eq. 4.28) under V/f, linear fit, response lag (4.29).

References used below:
- Kayaalp (seed), Table 2: 55 kW, 50 Hz, 891 N.m, 3x380 V delta, 10 poles; section 4.5.1.8:
  c_lp = 1e4 -> no delay, c_lp = 2.75 -> fitted delay, both at step 1e-4 s.
- Chapman, Electric Machinery Fundamentals (5th ed., 2012), eqs. 6-50 (Thevenin torque),
  6-51 (slip of pull-out torque s_max = R2/sqrt(R_Th^2 + X^2)) and 6-54 (pull-out torque
  3 V^2 / (2 ω_syn (R_Th + sqrt(R_Th^2 + X^2)))).
- Backward Euler for a first-order lag: exact recursion y_n = w u_n + (1 - w) y_{n-1} with
  w = Δt/(τ + Δt) (any numerical analysis text, e.g. Hairer & Wanner, Solving ODEs II, IV.3).
"""

from __future__ import annotations

import inspect
import re
import warnings

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from rollerrig._validation import ParameterError
from rollerrig.drives.induction import (
    TheveninCircuit,
    clp_from_lag_time_constant,
    discrete_lag_filter,
    induction_torque,
    lag_derivative,
    lag_time_constant_from_clp,
    linear_induction_torque,
    linear_slope_from_nameplate,
    thevenin_from_nameplate,
    vf_supply_frequency,
    vf_voltage,
)
from rollerrig.rig.parameters import default_rig

AM = thevenin_from_nameplate()
W_SYNC = 2.0 * np.pi * 50.0 / 5  # Table 2: 50 Hz, 5 pole pairs -> 62.83 rad/s (600 rpm)
W_RATED = 55e3 / 891.0  # P = T ω -> 61.73 rad/s


def torque_at(circuit, omega_rotor, frequency):
    v = vf_voltage(frequency, circuit.voltage, circuit.rated_frequency)
    return induction_torque(
        omega_rotor,
        frequency,
        v,
        circuit.resistance,
        circuit.reactance_th,
        circuit.rotor_resistance,
        circuit.rotor_reactance,
        circuit.rated_frequency,
        circuit.pole_pairs,
    )


def torque_textbook(circuit, slip, frequency=50.0):
    """Eq. 4.28 exactly as printed (with the 1/s), for s != 0, V/f scaling applied."""
    k = frequency / circuit.rated_frequency
    v, x = circuit.voltage * k, circuit.reactance * k
    w_syn = 2.0 * np.pi * frequency / circuit.pole_pairs
    r2s = circuit.rotor_resistance / slip
    return 3.0 / w_syn * v**2 / ((circuit.resistance + r2s) ** 2 + x**2) * r2s


# ---------------------------------------------------------------------------------------------
# Nameplate -> circuit
# ---------------------------------------------------------------------------------------------
def test_rated_point_of_table_2():
    # Source: Kayaalp (seed dissertation), section 4.1.2, Table 2 "Parameters of AM": power
    # 55 kW, frequency 50 Hz, nominal torque 891 Nm, current 133 A, voltage 3x380 V / delta,
    # 10 poles. The bundled rig and the nameplate defaults must be that table ...
    table_2 = {
        "rated_power": 55e3,
        "rated_frequency": 50.0,
        "rated_torque": 891.0,
        "rated_line_voltage": 380.0,
        "connection": "delta",
        "pole_pairs": 10 // 2,
    }
    rig_am = default_rig().induction_motor
    assert {key: getattr(rig_am, key) for key in table_2} == table_2
    assert rig_am.rated_current == 133.0
    defaults = inspect.signature(thevenin_from_nameplate).parameters
    assert {key: defaults[key].default for key in table_2} == table_2
    # ... and the circuit built from it runs where the table puts the motor: synchronous speed
    # 600 rpm (50 Hz, 10 poles), the nameplate torque at P/T = 55 kW / 891 N.m = 589.46 rpm
    # (rated slip 1.756 %), on the stable side of the breakdown point. Tolerance: the rounding
    # of 589.46 rpm and 1.756 %.
    rpm = 60.0 / (2.0 * np.pi)
    assert AM.synchronous_speed() * rpm == pytest.approx(600.0, abs=1e-9)
    w_breakdown = AM.synchronous_speed() * (1.0 - AM.breakdown_slip())
    w_nameplate = brentq(lambda w: AM.torque(w) - 891.0, w_breakdown, AM.synchronous_speed())
    assert w_nameplate * rpm == pytest.approx(589.46, abs=0.01)
    assert 1.0 - w_nameplate / AM.synchronous_speed() == pytest.approx(0.01756, abs=1e-5)


def test_circuit_reproduces_rated_torque():
    assert torque_at(AM, W_RATED, 50.0) == pytest.approx(891.0, rel=1e-9)
    assert AM.torque(W_RATED) == pytest.approx(891.0, rel=1e-9)


def test_circuit_reproduces_breakdown_torque_closed_form_and_numerically():
    assert AM.breakdown_torque() == pytest.approx(2.5 * 891.0, rel=1e-9)
    res = minimize_scalar(
        lambda s: -torque_textbook(AM, s),
        bounds=(1e-3, 0.5),
        method="bounded",
        options={"xatol": 1e-12},
    )
    assert -res.fun == pytest.approx(2.5 * 891.0, rel=1e-9)
    assert res.x == pytest.approx(AM.breakdown_slip(), rel=1e-5)
    assert AM.breakdown_slip() > (W_SYNC - W_RATED) / W_SYNC  # rated point on the stable side


def test_default_circuit_numbers_and_assumptions():
    # V_Th = phase voltage of the delta winding, R_Th = assumed stator resistance, X split 50/50
    assert AM.voltage == 380.0
    assert AM.resistance == 0.1
    assert AM.reactance_th == pytest.approx(AM.rotor_reactance, rel=1e-15)
    z = 3 * 380.0**2 / (2 * W_SYNC * 2.5 * 891.0) - 0.1  # Chapman eq. 6-54 solved for |Z|
    assert AM.reactance == pytest.approx(np.sqrt(z**2 - 0.1**2), rel=1e-14)
    assert AM.reactance == pytest.approx(1.44415, rel=1e-5)
    assert AM.rotor_resistance == pytest.approx(0.127307, rel=1e-5)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"connection": "star", "rated_line_voltage": 400.0, "stator_resistance": 0.0},
        {"breakdown_torque_ratio": 1.8, "stator_resistance": 0.2},
        {"breakdown_torque_ratio": 3.2, "stator_reactance_fraction": 0.4},
    ],
)
def test_circuit_reproduces_nameplate_for_other_choices(kwargs):
    c = thevenin_from_nameplate(**kwargs)
    ratio = kwargs.get("breakdown_torque_ratio", 2.5)
    assert c.torque(W_RATED) == pytest.approx(891.0, rel=1e-9)
    assert c.breakdown_torque() == pytest.approx(ratio * 891.0, rel=1e-9)
    if kwargs.get("connection") == "star":
        assert c.voltage == pytest.approx(400.0 / np.sqrt(3.0))


def test_nameplate_validation():
    with pytest.raises(ParameterError, match="connection"):
        thevenin_from_nameplate(connection="zigzag")
    with pytest.raises(ParameterError, match="stator_resistance"):
        thevenin_from_nameplate(stator_resistance=1.0)
    with pytest.raises(ParameterError, match="synchronous"):
        thevenin_from_nameplate(rated_power=60e3)  # 67 rad/s > 62.8 rad/s
    with pytest.raises(ParameterError, match="breakdown_torque_ratio"):
        thevenin_from_nameplate(breakdown_torque_ratio=0.9)
    with pytest.raises(ParameterError, match=r"rotor_resistance.*ohm"):
        TheveninCircuit(380.0, 0.1, 0.7, 0.0, 0.7, 50.0, 5)


# ---------------------------------------------------------------------------------------------
# Torque characteristic
# ---------------------------------------------------------------------------------------------
def test_matches_printed_eq_4_28_away_from_zero_slip():
    slips = np.array([-1.5, -0.3, -0.02, 0.005, 0.0176, 0.2, 1.0, 1.8])
    for f in (10.0, 37.0, 50.0):  # V/f range: V and X scale with f
        w_syn = 2.0 * np.pi * f / 5
        got = torque_at(AM, w_syn * (1.0 - slips), f)
        np.testing.assert_allclose(got, torque_textbook(AM, slips, f), rtol=1e-12)


def test_zero_torque_at_synchronous_speed_and_sign():
    for f in (5.0, 25.0, 50.0):
        w_syn = 2.0 * np.pi * f / 5
        assert torque_at(AM, w_syn, f) == 0.0
        assert torque_at(AM, 1.01 * w_syn, f) < 0.0  # rotor driven faster: generator, brakes
        assert torque_at(AM, 0.99 * w_syn, f) > 0.0
        assert np.isfinite(torque_at(AM, 0.0, f))  # standstill, s = 1
        assert torque_at(AM, -w_syn, f) > 0.0  # plugging, s = 2


def test_odd_under_reversal_of_all_speeds():
    w = np.linspace(-80.0, 80.0, 17)
    args = (AM.resistance, AM.reactance_th, AM.rotor_resistance, AM.rotor_reactance, 50.0, 5)
    forward = induction_torque(w, 40.0, 300.0, *args)
    backward = induction_torque(-w, -40.0, 300.0, *args)
    np.testing.assert_allclose(backward, -forward, rtol=1e-14)


def test_finite_without_warnings_at_zero_frequency():
    args = (AM.resistance, AM.reactance_th, AM.rotor_resistance, AM.rotor_reactance, 50.0, 5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert induction_torque(0.0, 0.0, 0.0, *args) == 0.0
        assert induction_torque(0.0, 0.0, 5.0, *args) == 0.0  # boost voltage, no slip
        t = induction_torque(np.array([-1.0, 1e-9, 1.0]), 1e-12, 5.0, *args)
    assert np.all(np.isfinite(t))
    # DC braking: a boost voltage at f = 0 brakes a turning rotor
    assert t[2] < 0.0 < t[0]


def test_breakdown_torque_nearly_constant_under_vf_for_small_stator_resistance():
    # Chapman sec. 6.9: with R_Th -> 0 and V, X ∝ f the pull-out torque does not depend on f.
    for r_th, tol in ((0.0, 1e-9), (1e-3, 2e-2)):
        c = thevenin_from_nameplate(stator_resistance=r_th)
        peaks = []
        for f in (10.0, 25.0, 50.0):
            w_syn = 2.0 * np.pi * f / 5
            res = minimize_scalar(
                lambda w, f=f, c=c: -torque_at(c, w, f),
                bounds=(0.5 * w_syn, w_syn),
                method="bounded",
                options={"xatol": 1e-10},
            )
            peaks.append(-res.fun)
        np.testing.assert_allclose(peaks, c.breakdown_torque(), rtol=tol)
    # with the default R_Th = 0.1 ohm it drops at low frequency (why V/f drives use a boost)
    assert torque_at(AM, 0.9 * 2 * np.pi * 10 / 5, 10.0) < torque_at(AM, 0.9 * W_SYNC, 50.0)


def test_vf_law():
    np.testing.assert_allclose(
        vf_voltage(np.array([0.0, 25.0, 50.0, 80.0, -25.0]), 380.0, 50.0),
        [0.0, 190.0, 380.0, 380.0, 190.0],
    )
    assert vf_voltage(0.0, 380.0, 50.0, 20.0) == pytest.approx(20.0)
    assert vf_voltage(25.0, 380.0, 50.0, 20.0) == pytest.approx(200.0)
    # 600 rpm roller target -> 50 Hz on the 10-pole AM
    assert vf_supply_frequency(600.0 * 2 * np.pi / 60, 5) == pytest.approx(50.0, rel=1e-15)


def test_open_loop_speed_droops_with_load():
    target = 30.0  # rad/s
    f = vf_supply_frequency(target, AM.pole_pairs)
    # braking load of 500 N.m (the contact drives the roller): speed settles above target
    w_brake = brentq(lambda w: torque_at(AM, w, f) + 500.0, target, 1.2 * target)
    w_motor = brentq(lambda w: torque_at(AM, w, f) - 500.0, 0.8 * target, target)
    assert w_motor < target < w_brake


# ---------------------------------------------------------------------------------------------
# Linear characteristic (Fig. 45)
# ---------------------------------------------------------------------------------------------
def test_linear_slope_is_the_secant_through_the_rated_point():
    k = linear_slope_from_nameplate()
    assert k == pytest.approx(891.0 / (W_SYNC - W_RATED), rel=1e-14)
    assert linear_induction_torque(W_RATED, W_SYNC, k) == pytest.approx(AM.torque(W_RATED))


def test_linear_slope_versus_thevenin_tangent_at_zero_slip():
    h = 1e-6
    tangent = (torque_at(AM, W_SYNC - h, 50.0) - torque_at(AM, W_SYNC + h, 50.0)) / (2 * h)
    assert tangent == pytest.approx(AM.small_slip_slope(), rel=1e-8)
    s = (W_SYNC - W_RATED) / W_SYNC
    factor = ((AM.resistance * s + AM.rotor_resistance) ** 2 + (AM.reactance * s) ** 2) / (
        AM.rotor_resistance**2
    )
    assert tangent / linear_slope_from_nameplate() == pytest.approx(factor, rel=1e-8)
    assert 1.0 < factor < 1.1  # the rated point is in the nearly linear range


# ---------------------------------------------------------------------------------------------
# Response lag, eq. 4.29
# ---------------------------------------------------------------------------------------------
def test_lag_mapping_numbers():
    assert lag_time_constant_from_clp(1e4) == 0.0  # Kayaalp: "zero response delay"
    assert lag_time_constant_from_clp(2.75) == pytest.approx(1 / 2.75 - 1e-4, rel=1e-14)
    assert lag_time_constant_from_clp(2.75) == pytest.approx(0.3635, abs=1e-4)
    for c in (2.75, 10.0, 1e3, 1e4):
        tau = lag_time_constant_from_clp(c)
        assert clp_from_lag_time_constant(tau) == pytest.approx(c, rel=1e-12)
    with pytest.raises(ParameterError, match="c_lp"):
        lag_time_constant_from_clp(2e4)  # weight 2 > 1: the filter would be unstable


def test_seed_filter_is_backward_euler_of_the_continuous_lag():
    c, dt = 2.75, 1e-4
    tau = lag_time_constant_from_clp(c, dt)
    rng = np.random.default_rng(1)
    u = rng.normal(0.0, 100.0, 500)
    seed = discrete_lag_filter(u, c, dt, initial=3.0)
    y_prev, be = 3.0, []
    for un in u:  # backward Euler: y_n = y_{n-1} + dt * lag_derivative(u_n, y_n, tau)
        y = (y_prev + dt / tau * un) / (1.0 + dt / tau)
        assert y - y_prev == pytest.approx(dt * lag_derivative(un, y, tau), rel=1e-9, abs=1e-12)
        be.append(y)
        y_prev = y
    np.testing.assert_allclose(seed, be, rtol=1e-12, atol=1e-12)


def test_seed_filter_step_response_against_exact_continuous_solution():
    c, dt = 2.75, 1e-4
    tau = lag_time_constant_from_clp(c, dt)
    n = int(3.0 / dt)
    y = discrete_lag_filter(np.ones(n), c, dt)
    t = dt * np.arange(1, n + 1)
    exact = 1.0 - np.exp(-t / tau)
    # backward-Euler global error on a step: max_n |(1+h)^-n - e^-nh| <= h/(2e) (1 + O(h)),
    # h = dt/tau = 2.75e-4 -> about 5.1e-5
    bound = dt / tau / (2.0 * np.e) * 1.01
    err = np.max(np.abs(y - exact))
    assert err < bound
    assert err > 0.9 * bound / 1.01  # and the bound is tight: the 1e-4 step matters that much
    # and the continuous lag integrated accurately gives the exact solution
    sol = solve_ivp(
        lambda _t, z: [lag_derivative(1.0, z[0], tau)], (0, 3.0), [0.0], rtol=1e-10, atol=1e-12
    )
    assert sol.y[0, -1] == pytest.approx(1.0 - np.exp(-3.0 / tau), rel=1e-8)


def test_no_lag_filter_passes_input_through():
    u = np.array([0.0, 5.0, -3.0, 7.0])
    np.testing.assert_array_equal(discrete_lag_filter(u, 1e4, 1e-4), u)


# ---------------------------------------------------------------------------------------------
# numba
# ---------------------------------------------------------------------------------------------
KERNEL_CASES = [
    (induction_torque, (61.0, 50.0, 380.0, 0.1, 0.72, 0.127, 0.72, 50.0, 5)),
    (induction_torque, (64.0, 50.0, 380.0, 0.1, 0.72, 0.127, 0.72, 50.0, 5)),
    (induction_torque, (0.0, 0.0, 0.0, 0.1, 0.72, 0.127, 0.72, 50.0, 5)),
    (vf_voltage, (31.0, 380.0, 50.0, 10.0)),
    (vf_voltage, (61.0, 380.0, 50.0)),
    (vf_supply_frequency, (40.0, 5)),
    (linear_induction_torque, (61.0, 62.8, 807.5)),
    (lag_derivative, (100.0, 20.0, 0.36)),
]


@pytest.mark.parametrize("kernel,args", KERNEL_CASES)
def test_kernels_compile_with_numba(kernel, args):
    expected = kernel(*args)
    got = numba.njit(kernel)(*args)
    np.testing.assert_allclose(np.asarray(got, float), np.asarray(expected, float), rtol=1e-14)


def test_delta_resistance_is_three_times_the_equivalent_star():
    # A delta of impedances Z is a star of Z/3 (Kennelly 1899): the rig's delta machine with
    # R_s = 0.085 ohm per delta phase at 380 V line and the star machine with 0.085/3 ohm per
    # star phase at the same line voltage have the same torque curve (eq. 4.28), and the
    # dq machine of either has the same equivalent-star R_s.
    from rollerrig.drives.induction_dq import inverse_gamma_from_nameplate
    from rollerrig.rig.parameters import default_rig

    am = default_rig().induction_motor
    assert am.connection == "delta" and am.stator_resistance == pytest.approx(0.085)
    assert am.equivalent_star_stator_resistance == pytest.approx(0.085 / 3.0, rel=1e-15)
    # 1.7 % of the base impedance U_line/(I_line/√3) = 380/(133/√3) = 4.949 ohm
    assert am.stator_resistance_per_unit == pytest.approx(0.085 / (380.0 / (133.0 / np.sqrt(3))))
    delta = thevenin_from_nameplate(stator_resistance=0.085, connection="delta")
    star = thevenin_from_nameplate(stator_resistance=0.085 / 3.0, connection="star")
    w = np.linspace(0.5, 1.2, 15) * delta.synchronous_speed()
    np.testing.assert_allclose(star.torque(w), delta.torque(w), rtol=1e-10)
    assert star.rotor_resistance == pytest.approx(delta.rotor_resistance / 3.0, rel=1e-12)
    m_delta = inverse_gamma_from_nameplate(stator_resistance=0.085, connection="delta")
    m_star = inverse_gamma_from_nameplate(stator_resistance=0.085 / 3.0, connection="star")
    assert m_delta.stator_resistance == pytest.approx(m_star.stator_resistance, rel=1e-15)
    assert m_delta.rotor_resistance == pytest.approx(m_star.rotor_resistance, rel=1e-9)


# --------------------------------------------------------------------------------------------
# Bad input at the boundary (probe of the public functions)
# --------------------------------------------------------------------------------------------
_CIRCUIT = dict(
    voltage=380.0,
    resistance=0.1,
    reactance_th=0.72,
    rotor_resistance=0.13,
    rotor_reactance=0.72,
    rated_frequency=50.0,
)


@pytest.mark.parametrize("pole_pairs", [2.5, True, "5", 0, -2])
def test_circuit_refuses_pole_pairs_that_are_not_a_count(pole_pairs):
    """2.5 pole pairs gave a wrong synchronous speed silently; "5" failed later in torque()."""
    got = repr(pole_pairs)
    with pytest.raises(
        ParameterError, match=re.escape(f"pole_pairs must be a whole number >= 1 [-], got {got}")
    ):
        TheveninCircuit(**_CIRCUIT, pole_pairs=pole_pairs)


def test_circuit_stores_numbers_and_refuses_text_or_arrays():
    c = TheveninCircuit(**_CIRCUIT, pole_pairs=5.0)
    assert type(c.pole_pairs) is int and type(c.voltage) is float
    with pytest.raises(ParameterError, match=re.escape("voltage must be a number [V], got '380'")):
        TheveninCircuit(**{**_CIRCUIT, "voltage": "380"}, pole_pairs=5)
    with pytest.raises(
        ParameterError, match=re.escape("voltage must be a single number [V], got shape (2,)")
    ):
        TheveninCircuit(**{**_CIRCUIT, "voltage": [380.0, 400.0]}, pole_pairs=5)


@pytest.mark.parametrize("func", [thevenin_from_nameplate, linear_slope_from_nameplate])
def test_nameplate_refuses_fractional_pole_pairs(func):
    """pole_pairs=2.5 (or True) gave a circuit, and a slope, for a machine that cannot exist."""
    with pytest.raises(
        ParameterError, match=re.escape("pole_pairs must be a whole number >= 1 [-], got 2.5")
    ):
        func(pole_pairs=2.5)
    with pytest.raises(ParameterError, match=re.escape("got True")):
        func(pole_pairs=True)


def test_nameplate_voltage_beyond_float_range_is_a_parameter_error():
    """1e200 V overflowed in v_th**2: a bare OverflowError."""
    with pytest.raises(
        ParameterError,
        match=re.escape("rated_line_voltage = 1e+200 V with rated_torque = 891 N.m gives"),
    ):
        thevenin_from_nameplate(rated_line_voltage=1e200)


def test_circuit_torque_names_mismatched_speed_and_frequency():
    with pytest.raises(
        ParameterError,
        match=re.escape("omega_rotor (shape (3,)) and supply_frequency (shape (2,)) must have"),
    ):
        AM.torque([60.0, 61.0, 62.0], [50.0, 50.0])


def test_discrete_lag_filter_refuses_a_2d_series():
    """A (2, 2) array was raveled into one series of four samples, rows run on."""
    with pytest.raises(
        ParameterError,
        match=re.escape("torque_target must be a 1-D series of samples [N.m], got shape (2, 2)"),
    ):
        discrete_lag_filter([[1.0, 2.0], [3.0, 4.0]], 1e3)


def test_a_scalar_parameter_given_an_array_is_named():
    # float() of the array had raised a bare TypeError ("only 0-dimensional arrays ...").
    import re

    from rollerrig._validation import ParameterError
    from rollerrig.drives.induction import discrete_lag_filter

    with pytest.raises(ParameterError, match=re.escape(
        "c_lp must be a single number [1/s], got an array of shape (2,)"
    )):  # fmt: skip
        discrete_lag_filter([1.0, 1.0], [5000.0, 1.0])
