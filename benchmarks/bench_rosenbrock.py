"""Micro-benchmark of the ROS2 W-method on a 21-state roller-rig-like stiff model.

Not part of the test suite. Prints a table: accepted/rejected steps, Jacobians, wall time per
30 s simulation and per step, and the error against a tight scipy Radau reference.

The model mimics the twin's structure and stiffness (it is not the rig model): a 7-body
torsional chain (PMSM stator on a stiff mount damper with a pole near -3.3e4 1/s, PMSM rotor,
wheel disc, tyre, roller, AM rotor, AM stator), PI current control of the PMSM (poles ~ -1e3 1/s),
PI speed control of the wheel following a ramp, AM torque lag and a creep force whose slope at
low speed acts as a damper of order -1e4 1/s. States: 7 angles, 7 speeds, i_d, i_q, two current
integrators, wheel speed integrator, roller speed integrator, AM torque (21).

    python benchmarks/bench_rosenbrock.py
"""

import time

import numba
import numpy as np
from scipy.integrate import solve_ivp

from rollerrig.solve.rosenbrock import (
    FT_EVERY_STEP,
    FT_WITH_JACOBIAN,
    fd_jacobian,
    ros2_fixed,
    ros2_integrate,
)

N = 21
# inertias [kg m^2] of bodies 1..7
J = np.array([0.05, 0.08, 20.0, 5.0, 30.0, 0.1, 0.05])
R_W, R_R = 0.46, 0.5  # wheel and roller radius [m]
Q, MU0, S0 = 4300.0, 0.4, 0.005  # normal load [N], friction, creep scale [-]
V_MIN = 0.5  # creep regularisation speed [m/s]
L_S, R_S, PSI, POLES = 2e-3, 0.05, 0.3, 4  # PMSM [H, ohm, V s, pole pairs]
T_END = 30.0
T_RAMP = 10.0
BREAKS = np.array([0.0, T_RAMP, T_END])
P = np.array(
    [
        1.0e5,  # 0 k mount PMSM stator [N m/rad]
        1650.0,  # 1 b mount PMSM stator [N m s/rad] -> pole ~ -3.3e4 1/s
        5.0e4,  # 2 k shaft rotor-disc
        5.0,  # 3 b shaft
        1.0e6,  # 4 k disc-tyre
        50.0,  # 5 b disc-tyre
        5.0e4,  # 6 k shaft roller-AM
        5.0,  # 7 b shaft
        1.0e5,  # 8 k mount AM stator
        1650.0,  # 9 b mount AM stator
        1000.0,  # 10 current loop bandwidth [rad/s]
        60.0,  # 11 speed P gain [A s/rad]
        300.0,  # 12 speed I gain [A/rad]
        0.005,  # 13 AM torque lag [s]
        400.0,  # 14 AM speed P gain [N m s/rad]
        2000.0,  # 15 AM speed I gain [N m/rad]
        70.0,  # 16 final wheel speed [rad/s]
        0.01,  # 17 target creep [-]
    ]
)


@numba.njit(cache=True)
def rig_like_rhs(t, x, p, tables, dx):
    th = x[0:7]
    om = x[7:14]
    i_d, i_q, z_d, z_q, z_w, z_r, t_am = x[14], x[15], x[16], x[17], x[18], x[19], x[20]
    # protocol: wheel speed ramp, then hold; roller follows at the target creep
    w_ref = 1.0 + (p[16] - 1.0) * min(t / T_RAMP, 1.0)
    # PMSM: speed PI -> i_q reference, current PI (bandwidth p[10]) with back-EMF
    iq_ref = p[11] * (w_ref - om[1]) + z_w
    w_e = POLES * (om[1] - om[0])
    kp_i, ki_i = L_S * p[10], R_S * p[10]
    u_d = kp_i * (0.0 - i_d) + z_d - w_e * L_S * i_q
    u_q = kp_i * (iq_ref - i_q) + z_q + w_e * (L_S * i_d + PSI)
    dx[14] = (u_d - R_S * i_d + w_e * L_S * i_q) / L_S
    dx[15] = (u_q - R_S * i_q - w_e * (L_S * i_d + PSI)) / L_S
    dx[16] = ki_i * (0.0 - i_d)
    dx[17] = ki_i * (iq_ref - i_q)
    dx[18] = p[12] * (w_ref - om[1])
    t_e = 1.5 * POLES * PSI * i_q
    # creep force (arctan law, regularised at low speed)
    v_r = om[4] * R_R
    s = (om[3] * R_W - v_r) / np.sqrt(v_r * v_r + V_MIN * V_MIN)
    f_x = Q * MU0 * 2.0 / np.pi * np.arctan(s / S0 * np.pi / 2.0)
    # AM: speed PI on the roller -> torque command -> first-order lag
    wr_ref = om[3] * R_W / (R_R * (1.0 + p[17]))
    t_ref = p[14] * (om[4] - wr_ref) + z_r
    dx[19] = p[15] * (om[4] - wr_ref)
    dx[20] = (t_ref - t_am) / p[13]
    # torsional chain, T_ij = k (th_i - th_j) + b (om_i - om_j)
    t_01 = p[0] * (0.0 - th[0]) + p[1] * (0.0 - om[0])
    t_23 = p[2] * (th[1] - th[2]) + p[3] * (om[1] - om[2])
    t_34 = p[4] * (th[2] - th[3]) + p[5] * (om[2] - om[3])
    t_56 = p[6] * (th[4] - th[5]) + p[7] * (om[4] - om[5])
    t_70 = p[8] * (th[6] - 0.0) + p[9] * (om[6] - 0.0)
    acc0 = t_01 - t_e
    acc1 = t_e - t_23
    acc2 = t_23 - t_34
    acc3 = t_34 - f_x * R_W
    acc4 = f_x * R_R - t_56
    acc5 = t_56 - t_am
    acc6 = t_am - t_70
    for k in range(7):
        dx[k] = om[k]
    dx[7] = acc0 / J[0]
    dx[8] = acc1 / J[1]
    dx[9] = acc2 / J[2]
    dx[10] = acc3 / J[3]
    dx[11] = acc4 / J[4]
    dx[12] = acc5 / J[5]
    dx[13] = acc6 / J[6]


def initial_state():
    """At rest in angle, rolling at 1 rad/s wheel speed with 1 % creep, stators still."""
    x = np.zeros(N)
    x[8:11] = 1.0
    x[11:13] = R_W / (R_R * 1.01)
    return x


@numba.njit
def simulate(x0, t_out, p, tables, rtol, atol, h_max, jac_every, time_derivative, x_out):
    """Segment-by-segment driver (outputs strictly inside or at the end of each segment)."""
    x = x0.copy()
    totals = np.zeros(4, dtype=np.int64)
    for s in range(BREAKS.shape[0] - 1):
        t0, t1 = BREAKS[s], BREAKS[s + 1]
        lo = np.searchsorted(t_out, t0, side="left")
        hi = np.searchsorted(t_out, t1, side="right")
        seg_out = t_out[lo:hi]
        seg_x = np.empty((seg_out.shape[0] + 1, x.shape[0]))
        seg_t = np.empty(seg_out.shape[0] + 1)
        seg_t[:-1] = seg_out
        seg_t[-1] = t1
        n_steps, n_rej, n_jac, status = ros2_integrate(
            rig_like_rhs,
            x,
            t0,
            t1,
            seg_t,
            p,
            tables,
            rtol,
            atol,
            0.0,
            h_max,
            jac_every,
            seg_x,
            1_000_000,
            time_derivative,
        )
        x_out[lo:hi] = seg_x[:-1]
        x = seg_x[-1].copy()
        totals[0] += n_steps
        totals[1] += n_rej
        totals[2] += n_jac
        totals[3] = max(totals[3], status)
        if status != 0:
            break
    return totals


def reference(t_out):
    tables = np.zeros((1, 1))
    dx = np.empty(N)

    jac = np.empty((N, N))
    work = np.empty((2, N))

    def f(t, y):
        rig_like_rhs(t, y, P, tables, dx)
        return dx.copy()

    def jacobian(t, y):
        f0 = f(t, y)
        fd_jacobian(rig_like_rhs, t, y, P, tables, f0, jac, work)
        return jac.copy()

    ys = []
    x = initial_state()
    for s in range(len(BREAKS) - 1):
        t0, t1 = BREAKS[s], BREAKS[s + 1]
        last = s == len(BREAKS) - 2
        mask = (t_out >= t0) & ((t_out < t1) | last)
        t_eval = np.unique(np.r_[t_out[mask], t1])
        sol = solve_ivp(
            f, (t0, t1), x, method="Radau", rtol=1e-9, atol=1e-9, t_eval=t_eval, jac=jacobian
        )
        ys.append(sol.y.T[: mask.sum()])
        x = sol.y[:, -1]
    return np.vstack(ys)


def error(x_out, ref):
    """Max error of the drive-train speeds, i_q and AM torque relative to each signal's range.

    The stator speeds (mount vibration, ~1e-2 rad/s) are left out: their error relative to
    their own tiny range is governed by atol, not by the quantities the twin reports.
    """
    idx = np.r_[8:13, 15, 20]
    scale = np.abs(ref[:, idx]).max(axis=0)
    return float(np.max(np.abs(x_out[:, idx] - ref[:, idx]) / scale))


def main():
    tables = np.zeros((1, 1))
    x0 = initial_state()
    t_ref_out = np.linspace(0.0, T_END, 301)
    t0 = time.perf_counter()
    ref = reference(t_ref_out)
    print(f"scipy Radau reference (rtol=atol=1e-9): {time.perf_counter() - t0:.1f} s")
    rows = []
    for rate in (10.0, 1000.0):
        t_out = np.linspace(0.0, T_END, int(T_END * rate) + 1)
        sub = np.rint(t_ref_out * rate).astype(np.int64)  # rows of t_out at the reference times
        assert np.allclose(t_out[sub], t_ref_out, rtol=0.0, atol=1e-12)
        for rtol, jac_every, mode in (
            (1e-3, 20, FT_EVERY_STEP),
            (1e-4, 20, FT_EVERY_STEP),
            (1e-4, 20, FT_WITH_JACOBIAN),
            (1e-4, 5, FT_EVERY_STEP),
            (1e-5, 20, FT_EVERY_STEP),
        ):
            x_out = np.empty((len(t_out), N))
            args = (x0, t_out, P, tables, rtol, 1e-6, 0.0, jac_every, mode, x_out)
            simulate(*args)  # compile / warm
            reps = 5
            t0 = time.perf_counter()
            for _ in range(reps):
                tot = simulate(*args)
            el = (time.perf_counter() - t0) / reps
            err = error(x_out[sub], ref)
            rows.append((rate, rtol, jac_every, mode, *tot, el * 1e3, el / tot[0] * 1e6, err))
    print(
        f"{'out Hz':>7} {'rtol':>6} {'jac':>4} {'ft':>3} {'steps':>7} {'rej':>5} {'njac':>5} "
        f"{'st':>3} {'ms/30s':>8} {'us/step':>8} {'max err':>9}"
    )
    for r in rows:
        print(
            f"{r[0]:7.0f} {r[1]:6.0e} {r[2]:4d} {r[3]:3d} {r[4]:7d} {r[5]:5d} {r[6]:5d} {r[7]:3d} "
            f"{r[8]:8.2f} {r[9]:8.2f} {r[10]:9.2e}"
        )
    # fixed-step cost per step (identical cost per run)
    t_out = np.linspace(0.0, T_END, 31)
    x_out = np.empty((len(t_out), N))
    for h in (1e-3, 2e-4):
        ros2_fixed(rig_like_rhs, x0, 0.0, T_RAMP, h, t_out[:11], P, tables, x_out[:11], 20)
        t0 = time.perf_counter()
        n_steps, n_jac, status = ros2_fixed(
            rig_like_rhs, x0, 0.0, T_RAMP, h, t_out[:11], P, tables, x_out[:11], 20
        )
        el = time.perf_counter() - t0
        print(
            f"fixed h={h:g}: {n_steps} steps, {n_jac} Jacobians, status {status}, "
            f"{el * 1e3:.2f} ms, {el / n_steps * 1e6:.2f} us/step"
        )
    # raw cost of the building blocks
    dx = np.empty(N)
    rig_like_rhs(0.0, x0, P, tables, dx)
    t0 = time.perf_counter()
    for _ in range(10000):
        rig_like_rhs(0.1, x0, P, tables, dx)
    el = (time.perf_counter() - t0) / 1e4
    print(f"one rhs call from Python (incl. dispatch): {el * 1e6:.2f} us")


if __name__ == "__main__":
    main()
