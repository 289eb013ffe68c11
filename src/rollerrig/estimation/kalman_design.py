"""The causal Kalman filter's design: the roller's model (angle, speed, contact torque as a random
walk or an integrated one) discretised exactly, in scaled states, with its steady-state gain from
the discrete algebraic Riccati equation and the time-varying gains until they settle.

Used by :class:`rollerrig.estimation.kalman.ContactObserver`; cached per parameter set.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import linalg

from rollerrig._validation import ParameterError
from rollerrig.estimation.estimator_parameters import (
    _GAIN_TOLERANCE,
    _MAX_SETTLING,
    INITIAL_SPEED_SD,
)

__all__: list[str] = []


@dataclass(frozen=True)
class _Design:
    """The discretised filter in scaled states z = S x (all in radians of angle).

    x = [θ, ω, d(, s)], S = diag(1, h, h²/J(, h³/J)); F, Ga, Gb, Q in z; gains in z.
    """

    h: float
    inertia: float
    scale: np.ndarray
    F: np.ndarray
    Ga: np.ndarray
    Gb: np.ndarray
    Q: np.ndarray
    R: float
    gains: np.ndarray  # (M, n): time-varying gains for samples 1..M
    gain: np.ndarray  # steady state
    P0: np.ndarray


def _discretise(model: str, q: float, sigma_t: float):
    """F, Ga, Gb, Q of the scaled model (z = [θ, hω, h²d/J(, h³s/J)]), time in steps h.

    Exact for the continuous model: Van Loan's integral of the white process noise in closed
    form; the input torque held linearly between samples (u_{k-1} → u_k); the torque noise as
    a zero-order-held white input. Q is in rad² (the scaled states); ``q`` must already be
    expressed per the scaled states: q·h⁵/J² for the random walk, q·h⁷/J² for the integrated.
    """
    if model == "random_walk":
        F = np.array([[1.0, 1.0, 0.5], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]])
        Q = q * np.array(
            [[1 / 20, 1 / 8, 1 / 6], [1 / 8, 1 / 3, 1 / 2], [1 / 6, 1 / 2, 1.0]]
        )  # ∫ e^{Aτ} L Lᵀ e^{Aᵀτ} dτ with τ in units of h
        Ga = np.array([-1 / 3, -1 / 2, 0.0])
        Gb = np.array([-1 / 6, -1 / 2, 0.0])
        g = np.array([0.5, 1.0, 0.0])
    else:
        F = np.array(
            [
                [1.0, 1.0, 0.5, 1 / 6],
                [0.0, 1.0, 1.0, 0.5],
                [0.0, 0.0, 1.0, 1.0],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
        Q = q * np.array(
            [
                [1 / 252, 1 / 72, 1 / 30, 1 / 24],
                [1 / 72, 1 / 20, 1 / 8, 1 / 6],
                [1 / 30, 1 / 8, 1 / 3, 1 / 2],
                [1 / 24, 1 / 6, 1 / 2, 1.0],
            ]
        )
        Ga = np.array([-1 / 3, -1 / 2, 0.0, 0.0])
        Gb = np.array([-1 / 6, -1 / 2, 0.0, 0.0])
        g = np.array([0.5, 1.0, 0.0, 0.0])
    Q = Q + sigma_t**2 * np.outer(g, g)
    return F, Ga, Gb, Q


@lru_cache(maxsize=32)
def _design(
    model: str, sample_rate: float, inertia: float, cpr: float, q: float, sigma_t: float
) -> _Design:
    h = 1.0 / sample_rate
    n = 3 if model == "random_walk" else 4
    scale = np.array([1.0, h, h * h / inertia, h**3 / inertia][:n])
    # Scaled units: torque [N.m] -> h²/J rad; the process noise accordingly.
    torque_to_rad = h * h / inertia
    q_scaled = q * torque_to_rad**2 * (h if n == 3 else h**3)
    F, Ga, Gb, Q = _discretise(model, q_scaled, sigma_t * torque_to_rad)
    Ga, Gb = Ga * torque_to_rad, Gb * torque_to_rad  # per N.m of input torque
    R = (2.0 * math.pi / cpr) ** 2 / 12.0
    H = np.zeros((1, n))
    H[0, 0] = 1.0
    # Steady state: prior covariance from the DARE (normalised by R), gain, posterior.
    try:
        P_prior = R * linalg.solve_discrete_are(F.T, H.T, Q / R, np.eye(1))
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ParameterError(
            f"the Kalman filter has no steady state for process_noise {q:g} and torque_noise "
            f"{sigma_t:g} at {sample_rate:g} Hz ({exc}); choose a process_noise within a few "
            "decades of the default"
        ) from None
    gain = P_prior[:, 0] / (P_prior[0, 0] + R)
    P_post = P_prior - np.outer(gain, P_prior[0, :])
    # Start: angle known to the quantisation, speed unknown, d (and s) as in the steady state.
    P0 = P_post.copy()
    P0[:2, :] = 0.0
    P0[:, :2] = 0.0
    P0[0, 0] = R
    P0[1, 1] = (INITIAL_SPEED_SD * h) ** 2
    gains = []
    P = P0
    eye = np.eye(n)
    tol = _GAIN_TOLERANCE * np.abs(gain)
    for _ in range(_MAX_SETTLING):
        Pp = F @ P @ F.T + Q
        K = Pp[:, 0] / (Pp[0, 0] + R)
        IKH = eye - np.outer(K, H[0])
        P = IKH @ Pp @ IKH.T + R * np.outer(K, K)  # Joseph form
        if np.all(np.abs(K - gain) <= tol):
            break
        gains.append(K)
    gains_arr = np.array(gains).reshape(-1, n)
    for arr in (F, Ga, Gb, Q, scale, gain, P0, gains_arr):
        arr.setflags(write=False)
    return _Design(h, inertia, scale, F, Ga, Gb, Q, R, gains_arr, gain, P0)
