"""Tests of the PMSM wheel drive: dq model, torque, FOC current control.

References used below:
- Kayaalp (seed), Table 1: p = 22, φ = 0.2 Wb, 852 N.m, 650 rpm.
- DESIGN.md section 2 (documented assumptions): Rs = 0.04 ohm, Ld = Lq = 0.5 mH, V_dc = 600 V.
- Krause et al., Analysis of Electric Machinery (2002), ch. 7: rotor-frame voltage equations,
  torque and the power balance of the amplitude-invariant dq model.
- Harnefors & Nee (1998): PI current control by pole-zero cancellation -> first-order loop.
- Holmes & Lipo (2003): SVPWM linear range V_dc/sqrt(3).
"""

from __future__ import annotations

import re

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rollerrig._validation import ParameterError
from rollerrig.drives.pmsm import (
    max_phase_voltage,
    pi_gains_for_bandwidth,
    pmsm_current_derivatives,
    pmsm_current_reference,
    pmsm_foc_voltages,
    pmsm_magnetic_energy,
    pmsm_torque,
    pmsm_torque_ripple,
)
from rollerrig.rig.parameters import default_rig

P = default_rig().pmsm  # Kayaalp Table 1 plus the rig file's stated assumptions
RPM = 2.0 * np.pi / 60.0
KP, KI = pi_gains_for_bandwidth(P.inductance_q, P.stator_resistance, P.current_loop_bandwidth)
VMAX = max_phase_voltage(P.dc_link_voltage)


def closed_loop_rhs(omega_mech, i_d_ref, i_q_ref, params=P, kp=KP, ki=KI, vmax=VMAX):
    """Current ODE + FOC at constant speed; state (i_d, i_q, I_d, I_q)."""

    def rhs(_t, y):
        i_d, i_q, int_d, int_q = y
        v_d, v_q, dint_d, dint_q = pmsm_foc_voltages(
            i_d,
            i_q,
            i_d_ref,
            i_q_ref,
            int_d,
            int_q,
            omega_mech,
            params.pole_pairs,
            params.inductance_d,
            params.inductance_q,
            params.flux_linkage,
            kp,
            ki,
            vmax,
        )
        did, diq = pmsm_current_derivatives(
            i_d,
            i_q,
            v_d,
            v_q,
            omega_mech,
            params.pole_pairs,
            params.stator_resistance,
            params.inductance_d,
            params.inductance_q,
            params.flux_linkage,
        )
        return [did, diq, dint_d, dint_q]

    return rhs


def voltages_of(sol_y, omega_mech, i_d_ref, i_q_ref):
    i_d, i_q, int_d, int_q = sol_y
    return pmsm_foc_voltages(
        i_d,
        i_q,
        i_d_ref,
        i_q_ref,
        int_d,
        int_q,
        omega_mech,
        P.pole_pairs,
        P.inductance_d,
        P.inductance_q,
        P.flux_linkage,
        KP,
        KI,
        VMAX,
    )


# ---------------------------------------------------------------------------------------------
# Torque and references
# ---------------------------------------------------------------------------------------------
def test_rated_torque_needs_129_A_q_current():
    # Kayaalp Table 1 and eq. 4.25: 852 N.m / (1.5 * 22 * 0.2 Wb) = 129.09 A.
    _, i_q = pmsm_current_reference(852.0, 22, 0.2, 1e3)
    assert i_q == pytest.approx(852.0 / 6.6, rel=1e-14)
    assert pmsm_torque(0.0, i_q, 22, 0.2, 5e-4, 5e-4) == pytest.approx(852.0, rel=1e-14)


def test_reluctance_torque_term():
    # eq. 4.25 with L_d != L_q: 1.5 p [φ i_q + (L_d - L_q) i_d i_q], hand-evaluated.
    t = pmsm_torque(-50.0, 100.0, 4, 0.1, 2e-3, 5e-3)
    assert t == pytest.approx(1.5 * 4 * (0.1 * 100.0 + (-3e-3) * (-50.0) * 100.0), rel=1e-14)


def test_current_reference_is_exact_for_salient_machine_and_clipped():
    i_d, i_q = pmsm_current_reference(np.array([-5e3, 100.0, 5e3]), 4, 0.1, 200.0)
    np.testing.assert_array_equal(i_d, 0.0)
    np.testing.assert_allclose(i_q, [-200.0, 100.0 / 0.6, 200.0], rtol=1e-14)
    assert pmsm_torque(i_d[1], i_q[1], 4, 0.1, 2e-3, 5e-3) == pytest.approx(100.0, rel=1e-14)


def test_torque_ripple_is_zero_mean_sinusoid():
    t = np.linspace(0.0, 0.1, 1001)[:-1]  # 10 full periods at 100 Hz
    ripple = pmsm_torque_ripple(t, 12.0, 100.0)
    assert abs(ripple.mean()) < 1e-12
    assert ripple.max() == pytest.approx(12.0, rel=1e-12)


# ---------------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------------
def test_max_phase_voltage_svpwm():
    assert max_phase_voltage(600.0) == pytest.approx(600.0 / np.sqrt(3.0), rel=1e-15)
    with pytest.raises(ParameterError, match=r"dc_link_voltage.*\[V\]"):
        max_phase_voltage(-1.0)


def test_pi_gains_pole_zero_cancellation():
    kp, ki = pi_gains_for_bandwidth(5e-4, 0.04, 2.0 * np.pi * 200.0)
    assert kp == pytest.approx(5e-4 * 2.0 * np.pi * 200.0)
    assert ki / kp == pytest.approx(0.04 / 5e-4)  # zero at -R/L cancels the winding pole
    with pytest.raises(ParameterError, match="inductance"):
        pi_gains_for_bandwidth(0.0, 0.04, 100.0)


def test_parameters_validate():
    # The drive's parameters live in the validated rig parameter set.
    with pytest.raises(ParameterError, match=r"pmsm\.stator_resistance"):
        default_rig().with_overrides({"pmsm.stator_resistance": -0.1})


# ---------------------------------------------------------------------------------------------
# Power balance (Krause ch. 7) and the sign of eq. 4.24
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("l_d,l_q", [(5e-4, 5e-4), (3e-4, 8e-4)])
def test_power_balance_identity_at_arbitrary_states(l_d, l_q):
    rng = np.random.default_rng(0)
    n = 200
    i_d, i_q = rng.normal(0, 100, n), rng.normal(0, 100, n)
    v_d, v_q = rng.normal(0, 200, n), rng.normal(0, 200, n)
    omega = rng.uniform(-100, 100, n)
    p, r, phi = 22, 0.04, 0.2
    did, diq = pmsm_current_derivatives(i_d, i_q, v_d, v_q, omega, p, r, l_d, l_q, phi)
    p_in = 1.5 * (v_d * i_d + v_q * i_q)
    copper = 1.5 * r * (i_d**2 + i_q**2)
    mech = pmsm_torque(i_d, i_q, p, phi, l_d, l_q) * omega
    d_energy = 1.5 * (l_d * i_d * did + l_q * i_q * diq)  # d/dt of pmsm_magnetic_energy
    scale = np.abs(p_in) + np.abs(copper) + np.abs(mech) + np.abs(d_energy)
    np.testing.assert_array_less(np.abs(p_in - copper - mech - d_energy) / scale, 1e-13)
    # the energy helper is the function whose derivative was used
    h = 1e-3
    e1 = pmsm_magnetic_energy(i_d + h * did, i_q + h * diq, l_d, l_q)
    e0 = pmsm_magnetic_energy(i_d - h * did, i_q - h * diq, l_d, l_q)
    np.testing.assert_allclose((e1 - e0) / (2 * h), d_energy, rtol=1e-9, atol=1e-9)


def test_seed_sign_of_eq_4_24_violates_energy_balance():
    # With the printed "+ (L_d/L_q) p ω i_d" the balance misses 2 * 1.5 * ω_e * L_d * i_d * i_q.
    i_d, i_q, v_d, v_q, omega = -40.0, 100.0, -50.0, 300.0, 60.0
    p, r, l_d, l_q, phi = 22, 0.04, 5e-4, 5e-4, 0.2
    did, _ = pmsm_current_derivatives(i_d, i_q, v_d, v_q, omega, p, r, l_d, l_q, phi)
    diq_seed = (v_q - r * i_q + l_d * p * omega * i_d - phi * p * omega) / l_q
    p_in = 1.5 * (v_d * i_d + v_q * i_q)
    rest = (
        1.5 * r * (i_d**2 + i_q**2)
        + pmsm_torque(i_d, i_q, p, phi, l_d, l_q) * omega
        + 1.5 * (l_d * i_d * did + l_q * i_q * diq_seed)
    )
    assert p_in - rest == pytest.approx(-3.0 * p * omega * l_d * i_d * i_q, rel=1e-12)
    assert abs(p_in - rest) > 1e3  # W: not a rounding matter


# ---------------------------------------------------------------------------------------------
# Closed-loop current control at 650 rpm (Table 1 rated speed)
# ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def rated_steady_state():
    omega = 650.0 * RPM
    i_d_ref, i_q_ref = pmsm_current_reference(852.0, P.pole_pairs, P.flux_linkage, P.max_current)
    sol = solve_ivp(
        closed_loop_rhs(omega, i_d_ref, i_q_ref),
        (0.0, 0.25),
        [0.0, 0.0, 0.0, 0.0],
        method="DOP853",
        rtol=1e-11,
        atol=1e-10,
    )
    assert sol.success
    return omega, i_q_ref, sol.y[:, -1]


def test_rated_torque_reached_in_steady_state(rated_steady_state):
    _, i_q_ref, y = rated_steady_state
    i_d, i_q = y[0], y[1]
    assert i_q == pytest.approx(i_q_ref, rel=1e-7)
    assert abs(i_d) < 1e-6
    torque = pmsm_torque(i_d, i_q, P.pole_pairs, P.flux_linkage, P.inductance_d, P.inductance_q)
    assert torque == pytest.approx(1.5 * P.pole_pairs * P.flux_linkage * i_q_ref, rel=1e-7)
    assert torque == pytest.approx(852.0, rel=1e-7)


def test_back_emf_relation_in_steady_state(rated_steady_state):
    # Krause ch. 7, i_d = 0: v_q = R i_q + ω_e φ, v_d = -ω_e L_q i_q.
    omega, _, y = rated_steady_state
    v_d, v_q, _, _ = voltages_of(y, omega, 0.0, y[1])
    omega_e = P.pole_pairs * omega
    assert v_q == pytest.approx(P.stator_resistance * y[1] + omega_e * P.flux_linkage, rel=1e-8)
    assert v_d == pytest.approx(-omega_e * P.inductance_q * y[1], rel=1e-6)
    assert np.hypot(v_d, v_q) < VMAX  # rated point is inside the voltage circle


def test_power_balance_in_steady_state(rated_steady_state):
    omega, i_q_ref, y = rated_steady_state
    v_d, v_q, _, _ = voltages_of(y, omega, 0.0, i_q_ref)
    i_d, i_q = y[0], y[1]
    p_in = 1.5 * (v_d * i_d + v_q * i_q)
    copper = 1.5 * P.stator_resistance * (i_d**2 + i_q**2)
    mech = pmsm_torque(i_d, i_q, P.pole_pairs, P.flux_linkage, 5e-4, 5e-4) * omega
    did, diq = pmsm_current_derivatives(
        i_d, i_q, v_d, v_q, omega, P.pole_pairs, P.stator_resistance, 5e-4, 5e-4, 0.2
    )
    d_energy = 1.5 * 5e-4 * (i_d * did + i_q * diq)
    assert p_in == pytest.approx(copper + mech + d_energy, rel=1e-12)
    assert abs(d_energy) / p_in < 1e-9  # steady: the stored energy no longer changes
    assert p_in == pytest.approx(copper + mech, rel=1e-9)


def test_closed_loop_step_is_first_order_with_time_constant_one_over_bandwidth():
    # Harnefors & Nee (1998): pole-zero cancellation + decoupling -> i_q/i_q* = ω_c/(s + ω_c).
    omega = 650.0 * RPM
    i0, i1 = 40.0, 60.0  # small step: the voltage stays inside the circle
    y0 = [0.0, i0, 0.0, P.stator_resistance * i0 / KI]  # integrator at its steady value
    t = np.linspace(0.0, 8.0 / P.current_loop_bandwidth, 200)
    sol = solve_ivp(
        closed_loop_rhs(omega, 0.0, i1),
        (0.0, t[-1]),
        y0,
        t_eval=t,
        method="DOP853",
        rtol=1e-11,
        atol=1e-10,
    )
    v_d, v_q, _, _ = voltages_of(sol.y, omega, 0.0, i1)
    assert np.all(np.hypot(v_d, v_q) < VMAX)
    expected = i1 + (i0 - i1) * np.exp(-P.current_loop_bandwidth * t)
    np.testing.assert_allclose(sol.y[1], expected, atol=1e-6 * i1)
    np.testing.assert_allclose(sol.y[0], 0.0, atol=1e-7)
    # time constant read off the response, 63.2 % point
    frac = (sol.y[1] - i0) / (i1 - i0)
    tau = np.interp(1.0 - np.exp(-1.0), frac, t)
    assert tau == pytest.approx(1.0 / P.current_loop_bandwidth, rel=1e-3)


def test_voltage_limit_and_bounded_integrators_when_unreachable():
    # 900 rpm: back-EMF ω_e φ = 414.7 V > V_dc/sqrt(3) = 346.4 V, so i_d* = 0 cannot be held.
    omega = 900.0 * RPM
    assert P.pole_pairs * omega * P.flux_linkage > VMAX
    _, i_q_ref = pmsm_current_reference(852.0, P.pole_pairs, P.flux_linkage, P.max_current)
    t = np.linspace(0.0, 0.5, 2001)
    sol = solve_ivp(
        closed_loop_rhs(omega, 0.0, i_q_ref),
        (0.0, t[-1]),
        [0.0, 0.0, 0.0, 0.0],
        t_eval=t,
        method="LSODA",
        rtol=1e-9,
        atol=1e-9,
    )
    assert sol.success
    v_d, v_q, dint_d, dint_q = voltages_of(sol.y, omega, 0.0, i_q_ref)
    assert np.all(np.hypot(v_d, v_q) <= VMAX * (1.0 + 1e-12))
    # integrators settle (no wind-up): k_i I stays of the order of the voltage limit
    assert np.max(np.abs(KI * sol.y[2:])) < 2.0 * VMAX
    assert abs(dint_d[-1]) < 1e-6 and abs(dint_q[-1]) < 1e-6
    # and the request is indeed not met
    assert abs(sol.y[1, -1] - i_q_ref) > 1.0
    # the currents stay bounded too
    assert np.max(np.abs(sol.y[:2])) < 10 * P.max_current


# ---------------------------------------------------------------------------------------------
# Kernels compile under numba
# ---------------------------------------------------------------------------------------------
KERNEL_CASES = [
    (pmsm_current_derivatives, (3.0, 100.0, -40.0, 310.0, 68.0, 22, 0.04, 3e-4, 5e-4, 0.2)),
    (pmsm_torque, (-5.0, 100.0, 22, 0.2, 3e-4, 5e-4)),
    (pmsm_current_reference, (900.0, 22, 0.2, 120.0)),
    (
        pmsm_foc_voltages,
        (1.0, 90.0, 0.0, 129.0, 0.1, 0.3, 68.0, 22, 5e-4, 5e-4, 0.2, 0.63, 50.0, 346.4),
    ),
    (
        pmsm_foc_voltages,
        (1.0, 90.0, 0.0, 129.0, 0.1, 0.3, 99.0, 22, 5e-4, 5e-4, 0.2, 0.63, 50.0, 346.4),
    ),
    (pmsm_magnetic_energy, (3.0, 100.0, 3e-4, 5e-4)),
    (pmsm_torque_ripple, (0.013, 5.0, 300.0)),
]


@pytest.mark.parametrize("kernel,args", KERNEL_CASES)
def test_kernels_compile_with_numba(kernel, args):
    expected = kernel(*args)
    got = numba.njit(kernel)(*args)
    np.testing.assert_allclose(np.asarray(got, float), np.asarray(expected, float), rtol=1e-14)


def test_foc_kernel_elementwise_on_arrays():
    args = list(KERNEL_CASES[3][1])
    speeds = np.array([10.0, 68.0, 99.0, 150.0])
    args[6] = speeds
    vec = pmsm_foc_voltages(*args)
    for k, w in enumerate(speeds):
        args[6] = w
        scalar = pmsm_foc_voltages(*args)
        np.testing.assert_allclose([v[k] for v in vec], scalar, rtol=1e-15)


def test_pi_gains_beyond_float_range_are_refused():
    """L = 1e300 H at 1e300 rad/s returned kp = inf silently."""
    with pytest.raises(
        ParameterError,
        match=re.escape("inductance = 1e+300 H and resistance = 0.04 ohm at bandwidth = 1e+300"),
    ):
        pi_gains_for_bandwidth(1e300, 0.04, 1e300)
