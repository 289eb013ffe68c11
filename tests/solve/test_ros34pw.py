"""ROS34PW2 W-method: tableau vs the published one, order 3 (also with a wrong Jacobian), stiff
problems against scipy's Radau, exact output landing, failure statuses, batch = serial.

References: Rang & Angermann (2005), BIT 45, 761-787 (the method, Table 4.1); Hairer & Wanner,
"Solving ODEs II" (1996), Sec. IV.7 (order conditions, Table 7.1; transformed form eq. 7.25),
IV.10 (Van der Pol and Robertson test problems); Prothero & Robinson (1974), Math. Comp. 28,
145-162 (the stiff test equation).
"""

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rollerrig.solve import ros34pw as rp
from rollerrig.solve._wdriver import fd_jacobian
from rollerrig.solve.ros34pw import (
    FT_EVERY_STEP,
    FT_NONE,
    GAMMA,
    STATUS_BAD_INPUT,
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    invert_w,
    ros34pw2_fixed,
    ros34pw2_integrate,
    ros34pw2_integrate_batch,
    ros34pw2_step,
    stability_function,
)

TABLES = np.zeros((1, 1))

# Untransformed ROS34PW2 coefficients (α_ij, γ_ij, b, b̂) of Rang & Angermann (2005), as listed
# to 17 digits in the public "rabbit" solver (solver/rodas5p.py) - an independent listing of
# the one the module's transformed coefficients come from (ParMooN, TimeDiscRout.C).
_ALPHA = np.zeros((4, 4))
_ALPHA[1, 0] = 8.7173304301691801e-01
_ALPHA[2, 0] = 8.4457060015369423e-01
_ALPHA[2, 1] = -1.1299064236397981e-01
_ALPHA[3, 2] = 1.0
_GAMMA_OFF = np.zeros((4, 4))
_GAMMA_OFF[1, 0] = -8.7173304301691801e-01
_GAMMA_OFF[2, 0] = -9.0338057013044082e-01
_GAMMA_OFF[2, 1] = 5.4180672388095326e-02
_GAMMA_OFF[3, 0] = 2.4212380706095346e-01
_GAMMA_OFF[3, 1] = -1.2232505839045147e00
_GAMMA_OFF[3, 2] = 5.4526025533510214e-01
_B = np.array([2.4212380706095346e-01, -1.2232505839045147e00, 1.5452602553351023e00, GAMMA])
_BHAT = np.array(
    [3.7810903145819369e-01, -9.6042292212423178e-02, 5.0000000000000000e-01, GAMMA / 2.0]
)


@numba.njit
def pendulum(t, x, p, tables, dx):
    """Forced pendulum, non-stiff and non-autonomous (the single steps of the W-method)."""
    dx[0] = x[1]
    dx[1] = -np.sin(x[0]) + p[0] * np.cos(2.0 * t)


PR, VDP, ROBERTSON, PENDULUM, DECAY, CUBIC = 0.0, 1.0, 2.0, 3.0, 4.0, 5.0


@numba.njit
def problem(t, x, p, tables, dx):
    """The test problems of the drivers in one function, p[0] picks (each right-hand side is a
    compilation of its own of every driver it is passed to, 6-9 s of CPU each):

    - PR: Prothero-Robinson x' = λ (x − g) + g', g = sin t + cos 3t (exact solution g), λ = p[1];
    - VDP: Van der Pol x1' = x2, x2' = μ (1 − x1²) x2 − x1, μ = p[1];
    - ROBERTSON: Robertson's chemical kinetics (Hairer & Wanner 1996, Sec. IV.10);
    - PENDULUM: :func:`pendulum` with the forcing amplitude p[1];
    - DECAY: x_i' = −p[1 + i] x_i, NaN from t = p[1 + n] on (inf: never), see :func:`decay`;
    - CUBIC: x' = 3 t², x(t) = t³ from x(0) = 0.
    """
    kind = p[0]
    if kind == PR:
        g = np.sin(t) + np.cos(3.0 * t)
        dg = np.cos(t) - 3.0 * np.sin(3.0 * t)
        dx[0] = p[1] * (x[0] - g) + dg
    elif kind == VDP:
        dx[0] = x[1]
        dx[1] = p[1] * (1.0 - x[0] * x[0]) * x[1] - x[0]
    elif kind == ROBERTSON:
        dx[0] = -0.04 * x[0] + 1e4 * x[1] * x[2]
        dx[2] = 3e7 * x[1] * x[1]
        dx[1] = -dx[0] - dx[2]
    elif kind == PENDULUM:
        dx[0] = x[1]
        dx[1] = -np.sin(x[0]) + p[1] * np.cos(2.0 * t)
    elif kind == DECAY:
        n = x.shape[0]
        for i in range(n):
            dx[i] = -p[1 + i] * x[i] if t < p[1 + n] else np.nan
    else:
        dx[0] = 3.0 * t * t


def decay(*rates, nan_from=np.inf):
    """p of :func:`problem`'s decay x_i' = −rates_i x_i, NaN from t = ``nan_from`` on."""
    return np.array([DECAY, *rates, nan_from])


NEVER_NAN = decay(1.0)  # decay rate 1/s, never NaN


def _transformed():
    gam = _GAMMA_OFF + GAMMA * np.eye(4)
    gi = np.linalg.inv(gam)
    return _ALPHA @ gi, np.diag(1.0 / np.diag(gam)) - gi, _B @ gi, _BHAT @ gi


def test_transformed_coefficients_match_the_published_tableau():
    a, c, m, mhat = _transformed()
    mod = rp
    a_mod = [[mod._A21], [mod._A31, mod._A32], [mod._A41, mod._A42, mod._A43]]
    c_mod = [[mod._C21], [mod._C31, mod._C32], [mod._C41, mod._C42, mod._C43]]
    for i in range(1, 4):
        np.testing.assert_allclose(a[i, :i], a_mod[i - 1], rtol=1e-11)
        np.testing.assert_allclose(c[i, :i], c_mod[i - 1], rtol=1e-11)
    np.testing.assert_allclose(m, [mod._M1, mod._M2, mod._M3, mod._M4], rtol=1e-11)
    np.testing.assert_allclose(m - mhat, [mod._E1, mod._E2, mod._E3, mod._E4], atol=1e-11)
    np.testing.assert_allclose(_ALPHA.sum(axis=1), [0.0, mod._ALPHA2, mod._ALPHA3, 1.0], rtol=1e-11)
    np.testing.assert_allclose(
        (_GAMMA_OFF + GAMMA * np.eye(4)).sum(axis=1),
        [GAMMA, mod._GAMMA2, mod._GAMMA3, 0.0],
        atol=1e-11,
    )
    # γ makes the method L-stable: root of 6γ³ − 18γ² + 9γ − 1 (Rang & Angermann 2005, Sec. 4).
    assert abs(6 * GAMMA**3 - 18 * GAMMA**2 + 9 * GAMMA - 1) < 1e-15


def _module_tableau():
    """(α_ij, γ_ij + γ δ_ij, b, b̂) recovered from the module's transformed coefficients."""
    a = np.zeros((4, 4))
    c = np.zeros((4, 4))
    a[1, 0] = rp._A21
    a[2, :2] = rp._A31, rp._A32
    a[3, :3] = rp._A41, rp._A42, rp._A43
    c[1, 0] = rp._C21
    c[2, :2] = rp._C31, rp._C32
    c[3, :3] = rp._C41, rp._C42, rp._C43
    gam = np.linalg.inv(np.eye(4) / GAMMA - c)
    m = np.array([rp._M1, rp._M2, rp._M3, rp._M4])
    mhat = m - np.array([rp._E1, rp._E2, rp._E3, rp._E4])
    return a @ gam, gam, m @ gam, mhat @ gam


@pytest.mark.parametrize("source", ["published", "module"])
def test_classical_order_conditions(source):
    """Hairer & Wanner (1996), Table IV.7.1, with β_ij = α_ij + γ_ij: order 3 for b, 2 for b̂.

    The 17-digit published listing satisfies them to ~1e-12, the module's 21-digit transformed
    coefficients to rounding.
    """
    if source == "published":
        alpha_m, gam, b, bhat = _ALPHA, _GAMMA_OFF + GAMMA * np.eye(4), _B, _BHAT
        tol = 1e-11
    else:
        alpha_m, gam, b, bhat = _module_tableau()
        tol = 5e-15
    beta_m = alpha_m + gam - GAMMA * np.eye(4)
    alpha = alpha_m.sum(axis=1)
    beta = beta_m.sum(axis=1)
    g = GAMMA
    for w, order in ((b, 3), (bhat, 2)):
        assert abs(w.sum() - 1.0) < tol
        assert abs(w @ beta - (0.5 - g)) < tol
        if order == 3:
            assert abs(w @ alpha**2 - 1.0 / 3.0) < tol
            assert abs(w @ beta_m @ beta - (1.0 / 6.0 - g + g * g)) < tol
    # Σ b_i γ_i = 0: ∂f/∂t enters a step only at O(h⁴)
    assert abs(b @ gam.sum(axis=1)) < tol
    # the embedded solution is not third order
    assert abs(bhat @ alpha**2 - 1.0 / 3.0) > 0.05
    # Stiffly accurate: b_j = α_4j + γ_4j (the last stage is the solution).
    np.testing.assert_allclose(b, beta_m[3] + np.eye(4)[3] * GAMMA, atol=tol)


def test_stability_function():
    z_left = -np.logspace(-3, 14, 400)
    np.testing.assert_allclose(stability_function(z_left[:5]), np.exp(z_left[:5]), rtol=1e-9)
    assert abs(stability_function(-1e14)) < 1e-10  # L-stable, R(∞) = 0
    iy = 1j * np.logspace(-3, 8, 400)
    assert np.abs(stability_function(iy)).max() <= 1.0 + 1e-12  # A-stable
    # A W built for h_w is reused for h with h_w/h in [1/1.1, 1.1]: still A-stable on the
    # negative real axis and the imaginary axis, |R(∞)| ≤ 0.19; no longer for h_w/h = 0.6.
    for ratio in (1 / rp._LU_REUSE_RATIO, 0.9, 1.1, rp._LU_REUSE_RATIO):
        assert np.abs(stability_function(z_left, ratio)).max() <= 1.0
        assert np.abs(stability_function(iy, ratio)).max() <= 1.0 + 1e-9
        assert abs(stability_function(-1e14, ratio)) < 0.19
    assert abs(stability_function(-1e14, 0.6)) > 1.0


def _pendulum_reference(t1):
    sol = solve_ivp(
        lambda t, x: [x[1], -np.sin(x[0]) + 0.3 * np.cos(2.0 * t)],
        (0.0, t1),
        [1.0, 0.0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-13,
    )
    return sol.y[:, -1]


def _observed_orders(errors):
    e = np.asarray(errors)
    return np.log2(e[:-1] / e[1:])


@pytest.mark.parametrize("jac_every", [1, 10**9])
def test_order_three_fixed_step(jac_every):
    """Exact Jacobian every step (Rosenbrock) and the Jacobian of t = 0 throughout (W)."""
    t1 = 2.0
    ref = _pendulum_reference(t1)
    p = np.array([PENDULUM, 0.3])
    errors = []
    for n in (10, 20, 40, 80):
        x_out = np.empty((1, 2))
        n_steps, _, status = ros34pw2_fixed(
            problem, np.array([1.0, 0.0]), 0.0, t1, t1 / n, np.array([t1]), p, TABLES, x_out,
            jac_every,
        )  # fmt: skip
        assert status == STATUS_OK and n_steps == n
        errors.append(np.abs(x_out[0] - ref).max())
    orders = _observed_orders(errors)
    assert np.all((orders > 2.7) & (orders < 3.4)), (errors, orders)


def _run_steps_with_matrix(a_matrix, n, t1, ft_scale):
    """n fixed steps of ros34pw2_step with W = I − γ h A for an arbitrary A."""
    p = np.array([0.3])
    x = np.array([1.0, 0.0])
    h = t1 / n
    winv_t = np.empty((2, 2))
    assert invert_w(a_matrix, GAMMA * h, winv_t, np.empty((2, 2))) == 0
    f0 = np.empty(2)
    x_new = np.empty(2)
    err = np.empty(2)
    work = np.empty((6, 2))
    ft = np.array([0.0, -0.6]) * ft_scale
    for k in range(n):
        t = k * h
        pendulum(t, x, p, TABLES, f0)
        t_new = t1 if k == n - 1 else (k + 1) * h
        ros34pw2_step(pendulum, t, h, t_new, x, f0, ft, h, p, TABLES, winv_t, x_new, err, work)
        x[:] = x_new
    return x


@pytest.mark.parametrize(
    "a_matrix, ft_scale",
    [
        (np.array([[0.0, 1.0], [-0.54, 0.0]]), 1.0),  # ≈ exact Jacobian at t = 0
        (np.array([[0.7, -0.4], [1.3, 2.0]]), 0.3),  # an unrelated matrix
        (np.zeros((2, 2)), 0.0),  # A = 0: the explicit Runge-Kutta method (α, b)
    ],
)
def test_order_three_for_any_matrix(a_matrix, ft_scale):
    """W-property (Rang & Angermann 2005, Sec. 3): order 3 whatever A and f_t are."""
    t1 = 2.0
    ref = _pendulum_reference(t1)
    errors = [
        np.abs(_run_steps_with_matrix(a_matrix, n, t1, ft_scale) - ref).max()
        for n in (20, 40, 80, 160)
    ]
    orders = _observed_orders(errors)
    assert np.all((orders > 2.7) & (orders < 3.4)), (errors, orders)


def test_step_error_estimate_is_second_order():
    """The embedded solution is of order 2: the local error estimate scales like h³."""
    p = np.array([0.3])
    x = np.array([1.0, 0.0])
    f0 = np.empty(2)
    pendulum(0.0, x, p, TABLES, f0)
    jac = np.empty((2, 2))
    fd_jacobian(pendulum, 0.0, x, p, TABLES, f0, jac, np.empty((2, 2)))
    est = []
    for h in (0.1, 0.05, 0.025):
        winv_t = np.empty((2, 2))
        invert_w(jac, GAMMA * h, winv_t, np.empty((2, 2)))
        x_new = np.empty(2)
        err = np.empty(2)
        ros34pw2_step(
            pendulum, 0.0, h, h, x, f0, np.zeros(2), h, p, TABLES, winv_t, x_new, err,
            np.empty((6, 2)),
        )  # fmt: skip
        est.append(np.abs(err).max())
    orders = _observed_orders(est)
    assert np.all((orders > 2.7) & (orders < 3.3)), (est, orders)


def test_adaptive_error_is_proportional_to_tolerance():
    t1 = 2.0
    ref = _pendulum_reference(t1)
    errors = []
    for tol in (1e-6, 1e-8, 1e-10):
        x_out = np.empty((1, 2))
        res = ros34pw2_integrate(
            problem, np.array([1.0, 0.0]), 0.0, t1, np.array([t1]), np.array([PENDULUM, 0.3]),
            TABLES, tol, tol, 0.0, 0.0, 10, x_out,
        )  # fmt: skip
        assert res[3] == STATUS_OK
        errors.append(np.abs(x_out[0] - ref).max())
    # Tolerance proportionality: the global error follows the tolerance within a factor 30.
    for tol, e in zip((1e-6, 1e-8, 1e-10), errors, strict=True):
        assert tol / 30 < e < 30 * tol, errors


@pytest.mark.parametrize("lam, fixed_bound", [(-1e4, 2e-6), (-1e8, 2e-10)])
def test_prothero_robinson_stiff(lam, fixed_bound):
    """Stiffly accurate and L-stable: large steps (h |λ| up to 1e7) follow g(t) closely.

    The ∂f/∂t terms enter a W-method only at O(h⁴) per step (Σ b_i γ_i = 0, needed for order 3
    with any f_t), so both treatments give the same accuracy here.
    """
    t1 = 2.0
    g1 = np.sin(t1) + np.cos(3.0 * t1)
    p = np.array([PR, lam])
    x_out = np.empty((1, 1))
    res = ros34pw2_integrate(
        problem, np.array([1.0]), 0.0, t1, np.array([t1]), p, TABLES, 1e-6, 1e-8,
        0.0, 0.0, 10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_OK
    assert abs(x_out[0, 0] - g1) < 1e-5
    assert res[0] < 300  # the step follows the smooth g, not the 1/|λ| time scale
    # Fixed large steps h = 0.1 s (h λ = 0.1 λ), stale Jacobian: no blow-up, error O(h/λ).
    for mode in (FT_NONE, FT_EVERY_STEP):
        n_steps, _, status = ros34pw2_fixed(
            problem, np.array([1.0]), 0.0, t1, 0.1, np.array([t1]), p, TABLES, x_out,
            10**9, mode,
        )  # fmt: skip
        assert status == STATUS_OK and n_steps == 20
        assert abs(x_out[0, 0] - g1) < fixed_bound


def _radau(fun, x0, t1, t_eval, atol):
    sol = solve_ivp(
        fun, (0.0, t1), x0, method="Radau", rtol=1e-10, atol=atol, t_eval=t_eval, dense_output=False
    )
    assert sol.success
    return sol.y.T


def test_van_der_pol_mu_1000_against_radau():
    mu = 1000.0
    t1 = 3000.0  # almost two relaxation periods, (3 − 2 ln 2) μ ≈ 1614 each
    t_out = np.linspace(0.0, t1, 31)
    x0 = np.array([2.0, 0.0])
    ref = _radau(lambda t, x: [x[1], mu * (1.0 - x[0] ** 2) * x[1] - x[0]], x0, t1, t_out, 1e-10)
    x_out = np.empty((t_out.size, 2))
    res = ros34pw2_integrate(
        problem,
        x0,
        0.0,
        t1,
        t_out,
        np.array([VDP, mu]),
        TABLES,
        1e-8,
        1e-8,
        0.0,
        0.0,
        10,
        x_out,
    )
    assert res[3] == STATUS_OK
    # Outputs away from the fast jumps (|x1| far from 1 ... the slow branch) agree to 1e-5
    # relative; all outputs, including those close to a jump, to 2e-3 of the solution scale.
    assert np.abs(x_out[:, 0] - ref[:, 0]).max() < 1e-4
    assert np.abs(x_out[:, 1] - ref[:, 1]).max() < 1e-4 * max(1.0, np.abs(ref[:, 1]).max())


def test_robertson_against_radau():
    t_out = np.array([1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6])
    x0 = np.array([1.0, 0.0, 0.0])

    def fun(t, x):
        return [
            -0.04 * x[0] + 1e4 * x[1] * x[2],
            0.04 * x[0] - 1e4 * x[1] * x[2] - 3e7 * x[1] ** 2,
            3e7 * x[1] ** 2,
        ]

    atol = np.array([1e-12, 1e-16, 1e-12])
    ref = _radau(fun, x0, t_out[-1], t_out, atol)
    x_out = np.empty((t_out.size, 3))
    # rtol per state too: the specialisation test_per_state_tolerances_and_h_max compiles
    res = ros34pw2_integrate(
        problem, x0, 0.0, t_out[-1], t_out, np.array([ROBERTSON, 0.0]), TABLES, np.full(3, 1e-8),
        atol * 100, 0.0, 0.0, 10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_OK
    assert np.all(np.abs(x_out - ref) <= 1e-5 * np.abs(ref) + 1e3 * atol)
    # mass conservation x1 + x2 + x3 = 1 (linear invariant, kept to rounding by any RK/W)
    np.testing.assert_allclose(x_out.sum(axis=1), 1.0, atol=1e-12)


def test_lands_exactly_on_output_times():
    rates = np.array([1.0, 3.0])
    t_out = np.array([0.0, 0.0, 0.013, 0.5, 0.5, 0.77, 1.9, 2.0])
    x_out = np.empty((t_out.size, 2))
    res = ros34pw2_integrate(
        problem, np.ones(2), 0.0, 2.0, t_out, decay(*rates), TABLES, 1e-10, 1e-12, 0.0, 0.0, 100,
        x_out,
    )  # fmt: skip
    assert res[3] == STATUS_OK
    exact = np.exp(-np.outer(t_out, rates))
    np.testing.assert_allclose(x_out, exact, rtol=2e-9)
    np.testing.assert_array_equal(x_out[0], [1.0, 1.0])
    np.testing.assert_array_equal(x_out[3], x_out[4])
    # a tiny output interval next to a large one does not break the step-size sequence
    t_out2 = np.array([1.0, 1.0 + 1e-12, 2.0])
    x_out2 = np.empty((3, 2))
    res = ros34pw2_integrate(
        problem, np.ones(2), 0.0, 2.0, t_out2, decay(*rates), TABLES, 1e-10, 1e-12, 0.0, 0.0,
        100, x_out2,
    )  # fmt: skip
    assert res[3] == STATUS_OK
    np.testing.assert_allclose(x_out2, np.exp(-np.outer(t_out2, rates)), rtol=2e-9)


def test_per_state_tolerances_and_h_max():
    rates = np.array([1.0, 3.0])
    x_out = np.empty((1, 2))
    n_steps, _, n_jac, status = ros34pw2_integrate(
        problem, np.ones(2), 0.0, 2.0, np.array([2.0]), decay(*rates), TABLES,
        np.array([1e-6, 1e-9]), np.array([1e-9, 1e-12]), 0.0, 0.01, 7, x_out,
    )  # fmt: skip
    assert status == STATUS_OK
    assert n_steps >= 200  # h_max = 0.01 s over 2 s
    assert n_jac >= n_steps // 7
    np.testing.assert_allclose(x_out[0], np.exp(-2.0 * rates), rtol=1e-7)


def test_nonfinite_right_hand_side_fails_cleanly():
    t_out = np.array([0.25, 0.5, 1.0, 2.0])
    x_out = np.empty((4, 1))
    res = ros34pw2_integrate(
        problem, np.ones(1), 0.0, 2.0, t_out, decay(1.0, nan_from=0.7), TABLES, 1e-6, 1e-8, 0.0,
        0.0, 10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_NONFINITE
    np.testing.assert_allclose(x_out[:2, 0], np.exp(-t_out[:2]), rtol=1e-5)
    assert np.isnan(x_out[2:]).all()
    # NaN already at t0
    res = ros34pw2_integrate(
        problem, np.ones(1), 0.0, 2.0, t_out, decay(1.0, nan_from=-1.0), TABLES, 1e-6, 1e-8, 0.0,
        0.0, 10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_NONFINITE and np.isnan(x_out).all()
    # NaN initial state
    res = ros34pw2_integrate(
        problem, np.array([np.nan]), 0.0, 2.0, t_out, NEVER_NAN, TABLES, 1e-6, 1e-8, 0.0, 0.0,
        10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_NONFINITE


def test_bad_input_and_step_cap():
    x_out = np.empty((1, 1))
    res = ros34pw2_integrate(
        problem, np.ones(1), 1.0, 0.0, np.array([0.5]), NEVER_NAN, TABLES, 1e-6, 1e-8, 0.0,
        0.0, 10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_BAD_INPUT and np.isnan(x_out).all()
    res = ros34pw2_integrate(
        problem, np.ones(1), 0.0, 1.0, np.array([1.5]), NEVER_NAN, TABLES, 1e-6, 1e-8, 0.0,
        0.0, 10, x_out,
    )  # fmt: skip
    assert res[3] == STATUS_BAD_INPUT
    res = ros34pw2_integrate(
        problem, np.ones(1), 0.0, 1.0, np.array([1.0]), NEVER_NAN, TABLES, 1e-6, 1e-8, 0.0,
        1e-3, 10, x_out, 50,
    )  # fmt: skip
    assert res[3] == STATUS_MAX_STEPS and res[0] + res[1] == 50 and np.isnan(x_out).all()


def test_invert_w_against_numpy():
    rng = np.random.default_rng(7)
    jac = rng.standard_normal((20, 20)) * np.logspace(0, 4, 20)  # stiff-ish, badly scaled
    winv_t = np.empty((20, 20))
    assert invert_w(jac, 0.01, winv_t, np.empty((20, 20))) == 0
    w = np.eye(20) - 0.01 * jac
    np.testing.assert_allclose(winv_t.T, np.linalg.inv(w), rtol=1e-10, atol=1e-12)
    # singular and non-finite W are reported, not inverted
    assert invert_w(np.eye(3), 1.0, np.empty((3, 3)), np.empty((3, 3))) == 1
    bad = np.eye(3)
    bad[1, 1] = np.nan
    assert invert_w(bad, 1.0, np.empty((3, 3)), np.empty((3, 3))) != 0


def test_batch_equals_serial():
    x0 = np.array([[1.0, 0.0], [0.5, 0.2], [2.0, -1.0]])
    params = np.array([[PENDULUM, 0.3], [PENDULUM, 0.0], [PENDULUM, 1.0]])
    t_out = np.linspace(0.0, 3.0, 7)
    batch_out = np.empty((3, t_out.size, 2))
    stats = ros34pw2_integrate_batch(
        problem, x0, 0.0, 3.0, t_out, params, TABLES, 1e-7, 1e-9, 0.0, 0.0, 5, batch_out
    )
    for b in range(3):
        x_out = np.empty((t_out.size, 2))
        res = ros34pw2_integrate(
            problem, x0[b], 0.0, 3.0, t_out, params[b], TABLES, 1e-7, 1e-9, 0.0, 0.0, 5, x_out
        )
        assert tuple(stats[b]) == res
        np.testing.assert_array_equal(batch_out[b], x_out)


def test_dense_output_is_exact_for_a_cubic_and_takes_fewer_steps():
    """Hermite dense output (Hairer, Nørsett & Wanner 1993, eq. II.6.7) reproduces cubics
    exactly; on a fine output grid it takes the steps the tolerance asks for, not one per
    output interval."""
    t_out = np.linspace(0.0, 2.0, 401)
    x_out = np.empty((t_out.size, 1))
    # x(t) = t³: the step and the interpolant are both exact
    args = (np.zeros(1), 0.0, 2.0, t_out, np.array([CUBIC]), TABLES, 1.0, 1.0, 0.5, 0.5, 10)
    res = ros34pw2_integrate(problem, *args, x_out, dense=True)
    assert res[3] == STATUS_OK
    np.testing.assert_allclose(x_out[:, 0], t_out**3, rtol=1e-12, atol=1e-13)
    assert res[0] <= 10  # h_max 0.5 s over 2 s, not 400 steps
    landed = np.empty_like(x_out)
    res_landed = ros34pw2_integrate(problem, *args, landed)
    assert res_landed[0] >= 400
    np.testing.assert_allclose(x_out, landed, rtol=1e-12, atol=1e-13)


def test_dense_output_keeps_the_order_on_a_decay():
    """Interpolated outputs of exp(-t) are as accurate as landed ones (third order)."""
    rates = np.array([1.0, 3.0])
    t_out = np.linspace(0.0, 2.0, 801)
    errors = []
    for h in (0.04, 0.02):
        x_out = np.empty((t_out.size, 2))
        res = ros34pw2_integrate(
            problem, np.ones(2), 0.0, 2.0, t_out, decay(*rates), TABLES, 1.0, 1.0, h, h, 1, x_out,
            dense=True,
        )  # fmt: skip
        assert res[3] == STATUS_OK
        errors.append(np.max(np.abs(x_out - np.exp(-np.outer(t_out, rates)))))
    assert 6.0 < errors[0] / errors[1] < 11.0  # 2^3 = 8
