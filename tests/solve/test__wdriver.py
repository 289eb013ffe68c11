"""Forward-difference Jacobian and time derivative of the W-method drivers against closed forms.

The right-hand side has states of the rig's magnitudes (angle ~1e3 rad, current ~1e2 A, torque
~1e3 N·m, speed ~0), where a fixed absolute increment would drown in rounding; the analytic
derivatives are written out below. Forward differences with the increment √ε·max(|x|, 1)
(Dennis & Schnabel 1996, Sec. 5.4) have an error of order √ε relative to ‖J‖.
"""

import numba
import numpy as np

from rollerrig.solve._wdriver import fd_jacobian, fd_time_derivative

NO_TABLES = np.zeros((1, 1))


@numba.njit
def _rig_like_rhs(t, x, p, tables, dx):
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


def test_time_derivative_never_steps_past_the_segment_end():
    # 3 t² has ∂f/∂t = 6 t; at t = t_end the forward increment would cross the breakpoint,
    # so it is taken backwards (the value then differs by O(√ε), not by a jump).
    @numba.njit
    def cubic(t, x, p, tables, dx):
        dx[0] = 3.0 * t * t if t <= 2.0 else np.nan

    ft = np.empty(1)
    fd_time_derivative(
        cubic, 2.0, np.zeros(1), np.zeros(1), NO_TABLES, np.array([12.0]), ft, np.empty(1), 2.0
    )
    assert abs(ft[0] - 12.0) < 1e-5
