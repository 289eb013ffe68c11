"""The steady-state filter recursion run fast: in the Schur form of its closed-loop matrix,
where it is triangular and each component a first-order recursion (:func:`scipy.signal.lfilter`),
run in chunks over long recordings.

The causal filter (:func:`rollerrig.estimation.kalman.estimate_contact_torque`) runs its tail
after the gain has settled with :func:`_tail`; the smoother's passes
(:mod:`rollerrig.estimation.smoother_passes`) use :func:`_triangular`.
"""

from __future__ import annotations

import numpy as np
from scipy import linalg, signal

from rollerrig.estimation.kalman_design import _Design

__all__: list[str] = []

_CHUNK = 1 << 20


def _schur_recursion(d: _Design):
    """The steady-state recursion of the deviations ζ (see :func:`_tail`) in Schur form.

    Returns (T, U, Uᴴ g1, Uᴴ g2) with Φ = U T Uᴴ, T upper triangular and U unitary: a
    well-conditioned basis however close the closed-loop poles lie (the eigenvectors of Φ are
    nearly parallel at high sample rates).
    """
    nz = d.F.shape[0]
    eye = np.eye(nz)
    IKH = eye - np.outer(d.gain, eye[0])
    Phi = IKH @ d.F
    T, U = linalg.schur(Phi, output="complex")
    g1 = -Phi @ eye[1]  # per Δ²y [rad]
    g2 = -d.scale[2] * (Phi @ eye[2]) - IKH @ d.Ga  # per Δu [N.m]
    Uh = U.conj().T
    return T, U, Uh @ g1, Uh @ g2


def _tail(d: _Design, z_hist: np.ndarray, start: int, dy: np.ndarray, u: np.ndarray) -> None:
    """Fill ``z_hist[start:]`` (speed and contact torque) by the steady-state recursion.

    z_k = Φ z_{k−1} + (K − e₁) Δy_k + (I − K H)(Ga u_{k−1} + Gb u_k), Φ = (I − K H) F, taken
    as deviations from the quasi-static reference r_k = (0, Δy_k, h²u_k/J(, 0)), the filter's
    exact steady state for a constant speed and torque: ζ = z − r obeys
    ζ_k = Φ ζ_{k−1} − Φ Δr_k − (I − K H) Ga Δu_k, driven only by the second difference of the
    angle and the torque increments (no large constant part cancels). In the Schur basis
    m = Uᴴζ the recursion is triangular (:func:`_triangular`). Run in chunks of :data:`_CHUNK`
    samples.
    """
    T, U, s1, s2 = _schur_recursion(d)
    nz = T.shape[0]
    tau = d.scale[2]
    ref_speed, ref_torque = dy, tau * u
    zeta = z_hist[start - 1].astype(complex)
    zeta[1] -= ref_speed[start - 1]
    zeta[2] -= ref_torque[start - 1]
    m_last = U.conj().T @ zeta  # the modal state at the sample before the chunk
    for lo in range(start, u.size, _CHUNK):
        hi = min(lo + _CHUNK, u.size)
        ddy = dy[lo:hi] - dy[lo - 1 : hi - 1]
        du = u[lo:hi] - u[lo - 1 : hi - 1]
        m = _triangular(T, m_last, s1[:, None] * ddy + s2[:, None] * du)
        m_last = m[:, -1].copy()
        for row, ref in ((1, ref_speed), (2, ref_torque)):
            out = ref[lo:hi].copy()
            for i in range(nz):  # elementwise: each sample's sum is the same whatever hi is
                out += (U[row, i] * m[i]).real
            z_hist[lo:hi, row] = out


def _triangular(T: np.ndarray, m_last: np.ndarray, drive: np.ndarray) -> np.ndarray:
    """Run m_k = T m_{k−1} + drive[:, k] over the columns of ``drive`` (T upper triangular).

    From the last component up, each is a first-order recursion
    (:func:`scipy.signal.lfilter`, complex) whose input holds the components below it at the
    previous sample; ``m_last`` is the state before the first column.
    """
    nz = T.shape[0]
    m = np.empty(drive.shape, dtype=complex)
    for i in range(nz - 1, -1, -1):
        d = drive[i].astype(complex)
        for j in range(i + 1, nz):  # T_ij m_j at the previous sample
            d[0] += T[i, j] * m_last[j]
            d[1:] += T[i, j] * m[j, :-1]
        m[i], _ = signal.lfilter([1.0], [1.0, -T[i, i]], d, zi=[T[i, i] * m_last[i]])
    return m
