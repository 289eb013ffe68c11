"""The passes of a designed smoother over a recording: the forward Kalman filter, the backward
Rauch-Tung-Striebel recursion, the smoothed variance of the contact torque, the start and the
innovations.

Each runs the exact time-varying gains while the filter settles and the steady-state gains
after, as triangular recursions in Schur form, in chunks. The model and its gains:
:mod:`~rollerrig.estimation.smoother_model`.
"""

from __future__ import annotations

import numpy as np
from scipy import linalg

from rollerrig.estimation.estimator_parameters import _GAIN_TOLERANCE
from rollerrig.estimation.schur_recursion import _triangular
from rollerrig.estimation.smoother_model import _Smoother

__all__: list[str] = []

_SMOOTHER_CHUNK = 1 << 18


def _smoother_forward(sd: _Smoother, dth, y_torque, u, z0, exact: bool = True):
    """Filtered states z̃_{k|k} (rows; the angle as θ̂ − θ_k), the exact gains then the steady
    recursion (Schur form, :func:`_triangular`, in chunks); ``exact=False``: steady gains
    from the first sample on."""
    n, nz = u.size, sd.F.shape[0]
    p = sd.H.shape[0]
    Z = np.empty((n, nz))
    Z[0] = z0
    ys = np.zeros(p)
    n_loop = min(n, sd.gains.shape[0] + 1) if exact else 1
    z = z0.copy()
    for k in range(1, n_loop):
        zp = sd.F @ z + sd.G0 * u[k - 1] + sd.G1 * u[k]
        zp[0] -= dth[k] / sd.scale[0]
        if p == 2:
            ys[1] = y_torque[k] / sd.meas_scale[1]
        z = zp + sd.gains[k - 1] @ (ys - sd.H @ zp)
        Z[k] = z
    if n > n_loop:
        eye = np.eye(nz)
        IKH = eye - sd.gain @ sd.H
        cols = [IKH @ sd.G0, IKH @ sd.G1, -IKH[:, 0] / sd.scale[0]]
        if p == 2:
            cols.append(sd.gain[:, 1] / sd.meas_scale[1])
        T, U = linalg.schur(sd.Phi, output="complex")
        Uh = U.conj().T
        W = Uh @ np.array(cols).T  # modal input matrix
        m_last = Uh @ Z[n_loop - 1]
        for lo in range(n_loop, n, _SMOOTHER_CHUNK):
            hi = min(lo + _SMOOTHER_CHUNK, n)
            inputs = [u[lo - 1 : hi - 1], u[lo:hi], dth[lo:hi]]
            if p == 2:
                inputs.append(y_torque[lo:hi])
            m = _triangular(T, m_last, W @ np.array(inputs))
            m_last = m[:, -1].copy()
            Z[lo:hi] = (U @ m).real.T
    return Z


def _smoother_backward(sd: _Smoother, Z, dth, u, exact: bool = True):
    """RTS: z̃s_k = z̃_k + C_k (z̃s_{k+1} − z̃⁻_{k+1}); the steady gain from the end down to
    the filter's transient (Schur form, reversed, in chunks), then the exact gains
    (``exact=False``: the steady gain down to the first sample)."""
    n = Z.shape[0]
    M = sd.gains.shape[0]
    Zs = np.empty_like(Z)
    Zs[-1] = Z[-1]

    def prior(rows):  # z̃⁻_{k+1} from z̃_k for the k in rows
        zp = Z[rows] @ sd.F.T + np.outer(u[rows], sd.G0) + np.outer(u[rows + 1], sd.G1)
        zp[:, 0] -= dth[rows + 1] / sd.scale[0]
        return zp

    k_exact = min(M, n - 2) if exact else -1  # samples 0..k_exact use the exact gains
    if n - 2 > k_exact:
        T, U = linalg.schur(sd.C, output="complex")
        Uh = U.conj().T
        m_last = Uh @ Zs[-1]
        for hi in range(n - 2, k_exact, -_SMOOTHER_CHUNK):  # rows hi, hi-1, ..., lo
            lo = max(hi - _SMOOTHER_CHUNK + 1, k_exact + 1)
            rows = np.arange(hi, lo - 1, -1)
            b = Z[rows] - prior(rows) @ sd.C.T
            m = _triangular(T, m_last, Uh @ b.T)
            m_last = m[:, -1].copy()
            Zs[rows] = (U @ m).real.T
    for k in range(k_exact, -1, -1):
        zp = prior(np.array([k]))[0]
        Zs[k] = Z[k] + sd.C_t[k] @ (Zs[k + 1] - zp)
    return Zs


def _smoothed_variance(sd: _Smoother, n: int) -> np.ndarray:
    """P^s_k of the contact torque in scaled units: the backward recursion of the covariance
    from the end until it reaches the steady state, then constant, then the exact start."""
    M = sd.gains.shape[0]
    i = sd.i_d
    out = np.empty(n)
    Ps = sd.P_post if n - 1 > M else sd.P_post_t[n - 1]
    out[-1] = Ps[i, i]
    k = n - 2
    target = sd.P_smooth[i, i]
    while k > M:
        Ps = sd.P_post + sd.C @ (Ps - sd.P_prior) @ sd.C.T
        out[k] = Ps[i, i]
        k -= 1
        if abs(Ps[i, i] - target) <= _GAIN_TOLERANCE * target:
            out[M + 1 : k + 1] = target
            Ps = sd.P_smooth
            k = M
            break
    for j in range(k, -1, -1):
        Ps = sd.P_post_t[j] + sd.C_t[j] @ (Ps - sd.P_prior_t[j + 1]) @ sd.C_t[j].T
        out[j] = Ps[i, i]
    return out


def _start(sd: _Smoother, torque0: float, u0: float) -> np.ndarray:
    """The scaled state at the first sample from its torque and input."""
    z0 = np.zeros(sd.F.shape[0])
    for i, a, b in sd.x0_of:
        z0[i] = (a * torque0 + b * u0) / sd.scale[i]
    return z0


def _innovations(sd: _Smoother, dth, y_torque, u, Z=None):
    """The forward filter's innovations of the angle (and the torque, chain), in the scaled
    measurements (unit measurement noise), at samples 1..n−1 (rows); ``Z`` the filtered
    states when already run."""
    if Z is None:
        Z = _smoother_forward(sd, dth, y_torque, u, _start(sd, y_torque[0], u[0]))
    zp = Z[:-1] @ sd.F.T + np.outer(u[:-1], sd.G0) + np.outer(u[1:], sd.G1)
    zp[:, 0] -= dth[1:] / sd.scale[0]
    e = -(zp @ sd.H.T)
    if e.shape[1] == 2:
        e[:, 1] += y_torque[1:] / sd.meas_scale[1]
    return e
