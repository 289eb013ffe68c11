"""ROS2 W-method integrator against closed forms and independent reference solvers.

References used for pinned numbers and test problems:
- Verwer, Spee, Blom, Hundsdorfer (1999), SIAM J. Sci. Comput. 20, 1456-1480: ROS2 is second
  order for any Jacobian approximation (W-method) and L-stable with the exact Jacobian.
- Prothero & Robinson (1974), Math. Comp. 28, 145-162: x' = λ(x − g(t)) + g'(t), exact x = g.
- Hairer & Wanner (1996), "Solving ODEs II", Sec. IV.1: Van der Pol in the scaled form
  ε y'' − (1 − y²) y' + y = 0 (ε = 1e-6 ⇔ μ = 1000) and Robertson's chemical kinetics.
- Closed forms: matrix exponential (scipy.linalg.expm) for linear systems; ROS2 is exact for
  x' = 2t (its order conditions are those of a second-order quadrature for f(t)).
- Independent reference: scipy.integrate.solve_ivp (Radau IIA, rtol = atol = 1e-10).
"""

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from rollerrig.solve.rosenbrock import (
    FT_NONE,
    GAMMA,
    STATUS_BAD_INPUT,
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    fd_jacobian,
    fd_time_derivative,
    lu_factor,
    lu_solve,
    ros2_fixed,
    ros2_integrate,
    ros2_integrate_batch,
    ros2_step,
)

# One right-hand side for all test problems (selected by p[0]) so that the integrators are
# compiled once per test module.
PR, LINEAR, VDP, ROBERTSON, PROBE, NAN_BEYOND = 0.0, 1.0, 2.0, 3.0, 4.0, 5.0
NO_TABLES = np.zeros((1, 1))


@numba.njit
def model_rhs(t, x, p, tables, dx):
    model = int(p[0])
    if model == 0:  # Prothero-Robinson with g = cos t, λ = p[1]
        dx[0] = p[1] * (x[0] - np.cos(t)) - np.sin(t)
    elif model == 1:  # x' = M x with M = tables
        n = x.shape[0]
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += tables[i, j] * x[j]
            dx[i] = s
    elif model == 2:  # Van der Pol, scaled form, p[1] = 1/ε
        dx[0] = x[1]
        dx[1] = ((1.0 - x[0] * x[0]) * x[1] - x[0]) * p[1]
    elif model == 3:  # Robertson
        dx[0] = -0.04 * x[0] + 1e4 * x[1] * x[2]
        dx[2] = 3e7 * x[1] * x[1]
        dx[1] = -dx[0] - dx[2]
    elif model == 4:  # x' = 2t, counts evaluations exactly at the times in tables[0]
        dx[0] = 2.0 * t
        for k in range(tables.shape[1]):
            if t == tables[0, k]:
                tables[1, k] += 1.0
    else:  # x' = 1 until x reaches p[1], NaN beyond
        dx[0] = 1.0 if x[0] < p[1] else np.nan


def _adaptive(x0, t0, t1, t_out, p, tables, rtol, atol, jac_every=10, h_max=0.0, max_steps=10**6):
    x_out = np.empty((len(t_out), len(x0)))
    res = ros2_integrate(
        model_rhs,
        np.asarray(x0, dtype=float),
        t0,
        t1,
        np.asarray(t_out, dtype=float),
        np.asarray(p, dtype=float),
        tables,
        rtol,
        atol,
        0.0,
        h_max,
        jac_every,
        x_out,
        max_steps,
    )
    return x_out, res


def _fixed(x0, t1, h, p, tables, jac_every=1):
    x_out = np.empty((1, len(x0)))
    res = ros2_fixed(
        model_rhs,
        np.asarray(x0, dtype=float),
        0.0,
        t1,
        h,
        np.array([t1]),
        np.asarray(p, dtype=float),
        tables,
        x_out,
        jac_every,
    )
    assert res[2] == STATUS_OK
    return x_out[0]


def _orders(errors):
    errors = np.asarray(errors)
    return np.log2(errors[:-1] / errors[1:])


# --- linear algebra and differences -------------------------------------------------------------


def test_lu_matches_numpy_solve_with_pivoting():
    rng = np.random.default_rng(1)
    a = rng.normal(size=(21, 21))
    a[0, 0] = 0.0  # forces a row exchange
    b = rng.normal(size=21)
    lu = a.copy()
    piv = np.empty(21, dtype=np.int64)
    assert lu_factor(lu, piv) == 0
    z = b.copy()
    lu_solve(lu, piv, z)
    np.testing.assert_allclose(z, np.linalg.solve(a, b), rtol=1e-10)


def test_lu_reports_singular_matrix():
    a = np.array([[1.0, 2.0], [2.0, 4.0]])
    assert lu_factor(a, np.empty(2, dtype=np.int64)) == 2


@numba.njit
def _rig_like_rhs(t, x, p, tables, dx):
    # states of rig magnitudes: angle ~1e3 rad, current ~1e2 A, torque ~1e3 N·m, speed ~0
    dx[0] = np.sin(x[0]) * x[1] + t
    dx[1] = x[1] * x[1] / 100.0 + x[2]
    dx[2] = np.tanh(x[3]) * x[2]
    dx[3] = x[0] * x[3] - 3.3e4 * (x[3] - 1e-3 * np.sin(t))


def test_fd_jacobian_and_time_derivative_match_analytic_at_rig_magnitudes():
    x = np.array([1234.5, 150.0, -800.0, 0.0])
    p = np.zeros(1)
    f0 = np.empty(4)
    t = 2.0
    _rig_like_rhs(t, x, p, NO_TABLES, f0)
    jac = np.empty((4, 4))
    fd_jacobian(_rig_like_rhs, t, x, p, NO_TABLES, f0, jac, np.empty((2, 4)))
    exact = np.array(
        [
            [np.cos(x[0]) * x[1], np.sin(x[0]), 0.0, 0.0],
            [0.0, 2.0 * x[1] / 100.0, 1.0, 0.0],
            [0.0, 0.0, np.tanh(x[3]), x[2] / np.cosh(x[3]) ** 2],
            [x[3], 0.0, 0.0, x[0] - 3.3e4],
        ]
    )
    # forward differences: error ~ √ε · (second derivative · scale) relative to ‖J‖
    np.testing.assert_allclose(jac, exact, atol=1e-6 * np.abs(exact).max())
    ft = np.empty(4)
    fd_time_derivative(_rig_like_rhs, t, x, p, NO_TABLES, f0, ft, np.empty(4), 10.0)
    np.testing.assert_allclose(ft, [1.0, 0.0, 0.0, 33.0 * np.cos(t)], rtol=1e-6, atol=1e-6)


# --- Prothero-Robinson ----------------------------------------------------------------------------


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_prothero_robinson_adaptive_meets_tolerance(rtol):
    x_out, (_, _, _, status) = _adaptive(
        [1.0], 0.0, 1.0, [1.0], [PR, -1e4], NO_TABLES, rtol, 1e-2 * rtol
    )
    assert status == STATUS_OK
    # exact solution cos t (Prothero & Robinson 1974); measured 2.1e-5, 3.0e-7, 1.7e-9
    assert abs(x_out[0, 0] - np.cos(1.0)) < rtol


def test_prothero_robinson_fixed_step_stable_and_second_order_far_beyond_stiffness():
    # h|λ| from 1000 down to 125: no instability, and the error is O(h²) (∂f/∂t included)
    errors = [
        abs(_fixed([1.0], 1.0, h, [PR, -1e4], NO_TABLES)[0] - np.cos(1.0))
        for h in (0.1, 0.05, 0.025, 0.0125)
    ]
    assert errors[0] < 3e-3  # measured 2.1e-3 at h = 0.1 = 1000/|λ|
    assert np.all(np.abs(_orders(errors) - 2.0) < 0.1)


def test_prothero_robinson_without_time_derivative_is_first_order_but_stable():
    # Plain W-method (f_t column dropped): still stable and convergent, but stiff order 1.
    errors = []
    for h in (0.1, 0.05, 0.025):
        x_out = np.empty((1, 1))
        res = ros2_fixed(
            model_rhs,
            np.array([1.0]),
            0.0,
            1.0,
            h,
            np.array([1.0]),
            np.array([PR, -1e4]),
            NO_TABLES,
            x_out,
            1,
            FT_NONE,
        )
        assert res[2] == STATUS_OK
        errors.append(abs(x_out[0, 0] - np.cos(1.0)))
    assert max(errors) < 0.1
    assert np.all(np.abs(_orders(errors) - 1.0) < 0.1)


# --- linear stiff system vs the matrix exponential ----------------------------------------------

# Hairer & Wanner (1996), Sec. IV.1-type stiff linear system: eigenvalues -1 and -1000.
A_STIFF = np.array([[-2.0, 1.0], [998.0, -999.0]])
X0_LIN = np.array([1.0, 2.0])


@pytest.mark.parametrize("tol", [1e-3, 1e-5, 1e-7])
def test_linear_stiff_adaptive_error_follows_tolerance(tol):
    t_out = np.linspace(0.1, 1.0, 10)
    exact = np.array([expm(A_STIFF * t) @ X0_LIN for t in t_out])
    x_out, (_, _, _, status) = _adaptive(X0_LIN, 0.0, 1.0, t_out, [LINEAR], A_STIFF, tol, tol)
    assert status == STATUS_OK
    rel = np.max(np.abs(x_out - exact) / np.abs(exact))
    assert rel < 5.0 * tol  # measured 1.6, 2.4, 2.4 × tol
    assert rel > 0.01 * tol  # the tolerance is actually used, not overshot by decades


@pytest.mark.parametrize("jac_every", [1, 10**9])
def test_linear_stiff_fixed_step_is_second_order(jac_every):
    exact = expm(A_STIFF) @ X0_LIN
    hs = [0.1, 0.05, 0.025, 0.0125, 0.00625]
    errors = [
        np.max(np.abs(_fixed(X0_LIN, 1.0, h, [LINEAR], A_STIFF, jac_every) - exact)) for h in hs
    ]
    orders = _orders(errors)
    assert np.all(orders > 1.75)  # measured 1.81, 1.90, 1.95, 1.97
    assert abs(orders[-1] - 2.0) < 0.05


def test_w_method_is_second_order_with_a_perturbed_jacobian():
    # W-method property (Verwer et al. 1999): order 2 for any W; here W = I − γh(A + E).
    a = np.array([[-2.0, 1.0], [8.0, -9.0]])  # eigenvalues -1, -10
    e = np.array([[0.7, -0.4], [-2.5, 3.0]])  # ~30 % perturbation
    exact = expm(a) @ X0_LIN
    p = np.array([LINEAR])
    ft = np.zeros(2)
    work = np.empty((3, 2))
    errors = {}
    for name, w_mat in (("exact", a), ("perturbed", a + e), ("explicit", 0.0 * a)):
        errs = []
        for m in (10, 20, 40, 80, 160, 320):
            h = 1.0 / m
            lu = np.eye(2) - GAMMA * h * w_mat
            piv = np.empty(2, dtype=np.int64)
            assert lu_factor(lu, piv) == 0
            x = X0_LIN.copy()
            f0 = np.empty(2)
            x_new = np.empty(2)
            err = np.empty(2)
            for i in range(m):
                model_rhs(i * h, x, p, a, f0)
                ros2_step(
                    model_rhs, i * h, h, (i + 1) * h, x, f0, ft, h, p, a, lu, piv, x_new, err, work
                )
                x[:] = x_new
            errs.append(np.max(np.abs(x - exact)))
        errors[name] = errs
        # measured last orders: exact 1.98, perturbed 1.95, explicit (W = I) 2.01
        assert abs(_orders(errs)[-1] - 2.0) < 0.1
    assert errors["perturbed"][-1] < 1e-3


# --- nonlinear stiff references -----------------------------------------------------------------

VDP_EPS = 1e-6  # μ = 1000 in the scaled form


def _vdp_reference(t_out):
    def f(t, y):
        return [y[1], ((1.0 - y[0] ** 2) * y[1] - y[0]) / VDP_EPS]

    def jac(t, y):
        return [[0.0, 1.0], [(-2.0 * y[0] * y[1] - 1.0) / VDP_EPS, (1.0 - y[0] ** 2) / VDP_EPS]]

    sol = solve_ivp(
        f,
        (0.0, t_out[-1]),
        [2.0, -0.66],
        method="Radau",
        rtol=1e-10,
        atol=1e-10,
        t_eval=t_out,
        jac=jac,
    )
    assert sol.success
    return sol.y.T


def test_van_der_pol_mu_1000_matches_radau():
    t_out = np.linspace(0.0, 2.0, 21)  # more than one relaxation period incl. two jumps
    ref = _vdp_reference(t_out)
    x_out, (_, _, _, status) = _adaptive(
        [2.0, -0.66], 0.0, 2.0, t_out, [VDP, 1.0 / VDP_EPS], NO_TABLES, 1e-6, 1e-6
    )
    assert status == STATUS_OK
    rel = np.abs(x_out - ref) / np.abs(ref)
    assert rel[:, 0].max() < 1e-4  # measured 1.3e-5
    assert rel[:, 1].max() < 1e-3  # measured 1.5e-4 (y' right before the jump at t = 0.8)


def test_stale_jacobian_keeps_second_order_on_van_der_pol():
    # Mildly stiff Van der Pol (ε = 0.1): the Jacobian of t = 0 reused for the whole run.
    eps = 0.1

    def f(t, y):
        return [y[1], ((1.0 - y[0] ** 2) * y[1] - y[0]) / eps]

    ref = solve_ivp(f, (0.0, 0.5), [2.0, -0.66], method="Radau", rtol=1e-12, atol=1e-12).y[:, -1]
    for jac_every in (1, 10**9):
        errs = [
            np.max(
                np.abs(_fixed([2.0, -0.66], 0.5, h, [VDP, 1.0 / eps], NO_TABLES, jac_every) - ref)
            )
            for h in (0.01, 0.005, 0.0025, 0.00125)
        ]
        assert abs(_orders(errs)[-1] - 2.0) < 0.15


def test_robertson_matches_radau():
    def f(t, y):
        return [
            -0.04 * y[0] + 1e4 * y[1] * y[2],
            0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] ** 2,
            3e7 * y[1] ** 2,
        ]

    t_out = np.array([0.4, 4.0, 40.0])
    ref = solve_ivp(
        f,
        (0.0, 40.0),
        [1.0, 0.0, 0.0],
        method="Radau",
        rtol=1e-10,
        atol=[1e-12, 1e-16, 1e-12],
        t_eval=t_out,
    ).y.T
    # Hairer & Wanner (1996), Sec. IV.1: y(40) ≈ (0.7158, 9.185e-6, 0.2842)
    np.testing.assert_allclose(ref[-1], [0.7158, 9.185e-6, 0.2842], rtol=2e-4)
    x_out, (_, _, _, status) = _adaptive(
        [1.0, 0.0, 0.0],
        0.0,
        40.0,
        t_out,
        [ROBERTSON],
        NO_TABLES,
        1e-6,
        np.array([1e-8, 1e-12, 1e-8]),
    )
    assert status == STATUS_OK
    assert np.max(np.abs(x_out - ref) / ref) < 1e-5  # measured 1.1e-6
    np.testing.assert_allclose(x_out.sum(axis=1), 1.0, rtol=1e-12)  # mass conservation


# --- output times, failures, batches ------------------------------------------------------------


def test_output_times_are_hit_exactly():
    t_out = np.array([0.0, 0.1, 0.1, 0.3, 1.0 / 3.0, 0.7, 2.0])
    tables = np.vstack([t_out, np.zeros_like(t_out)])
    x_out, (_, _, _, status) = _adaptive([0.0], 0.0, 2.0, t_out, [PROBE], tables, 1e-3, 1e-3)
    assert status == STATUS_OK
    # the right-hand side saw every requested time bit for bit (t = 0 only at the start)
    assert np.all(tables[1, 1:] >= 1.0)
    # ROS2 is exact for x' = 2t, so the stored states are the step end states at t_out
    np.testing.assert_allclose(x_out[:, 0], t_out**2, rtol=1e-13, atol=1e-15)

    tables[1] = 0.0
    x_fix = np.empty((len(t_out), 1))
    res = ros2_fixed(
        model_rhs, np.array([0.0]), 0.0, 2.0, 0.07, t_out, np.array([PROBE]), tables, x_fix, 5
    )
    assert res[2] == STATUS_OK
    assert np.all(tables[1, 1:] >= 1.0)
    np.testing.assert_allclose(x_fix[:, 0], t_out**2, rtol=1e-13, atol=1e-15)


def test_nonfinite_rhs_returns_failure_status_instead_of_hanging():
    t_out = np.array([1.0, 2.0, 3.0])
    x_out, (n_steps, n_rej, _, status) = _adaptive(
        [0.0], 0.0, 3.0, t_out, [NAN_BEYOND, 1.5], NO_TABLES, 1e-6, 1e-8
    )
    assert status == STATUS_NONFINITE
    assert n_steps + n_rej < 10_000
    assert abs(x_out[0, 0] - 1.0) < 1e-12
    assert np.all(np.isnan(x_out[1:]))
    # NaN already at the start
    x_out, (_, _, _, status) = _adaptive(
        [2.0], 0.0, 3.0, t_out, [NAN_BEYOND, 1.5], NO_TABLES, 1e-6, 1e-8
    )
    assert status == STATUS_NONFINITE and np.all(np.isnan(x_out))
    # fixed step
    x_fix = np.empty((3, 1))
    res = ros2_fixed(
        model_rhs,
        np.array([0.0]),
        0.0,
        3.0,
        0.3,
        t_out,
        np.array([NAN_BEYOND, 1.5]),
        NO_TABLES,
        x_fix,
        1,
    )
    assert res[2] == STATUS_NONFINITE and np.all(np.isnan(x_fix[1:]))


def test_step_cap_and_bad_input_status():
    _, (n_steps, n_rej, _, status) = _adaptive(
        [1.0], 0.0, 1.0, [1.0], [PR, -1e4], NO_TABLES, 1e-8, 1e-10, 10, 0.0, max_steps=50
    )
    assert status == STATUS_MAX_STEPS and n_steps + n_rej == 50
    x_out, (_, _, _, status) = _adaptive([1.0], 0.0, 1.0, [1.5], [PR, -1e4], NO_TABLES, 1e-6, 1e-8)
    assert status == STATUS_BAD_INPUT and np.all(np.isnan(x_out))


def test_batch_equals_serial():
    inv_eps = np.array([10.0, 1e2, 1e3, 1e4, 1e5, 1e6])
    P = np.column_stack([np.full_like(inv_eps, VDP), inv_eps])
    X0 = np.column_stack([np.linspace(1.5, 2.0, len(inv_eps)), np.full_like(inv_eps, -0.6)])
    t_out = np.linspace(0.0, 1.0, 11)
    X_out = np.empty((len(inv_eps), len(t_out), 2))
    stats = ros2_integrate_batch(
        model_rhs, X0, 0.0, 1.0, t_out, P, NO_TABLES, 1e-6, 1e-6, 0.0, 0.0, 10, X_out
    )
    for b in range(len(inv_eps)):
        x_out, res = _adaptive(X0[b], 0.0, 1.0, t_out, P[b], NO_TABLES, 1e-6, 1e-6)
        assert tuple(stats[b]) == res
        np.testing.assert_allclose(X_out[b], x_out, rtol=1e-13, atol=1e-13)
    assert np.all(stats[:, 3] == STATUS_OK)
