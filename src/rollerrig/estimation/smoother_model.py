"""The smoothers' state-space model, discretised, with its filter and smoother gains.

The roller alone or the roller-shaft-rotor-drive chain (:class:`RollerChain`), as a continuous
model, discretised exactly (Van Loan), scaled, with its steady-state Kalman and RTS gains and
the exact time-varying gains while the filter settles from its start. The passes that run it
are :mod:`~rollerrig.estimation.smoother_passes`; the smoother itself is
:func:`rollerrig.estimation.smoother.smooth_contact_torque`.
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
    INITIAL_ACCELERATION_SD,
    INITIAL_SPEED_SD,
    _nonnegative,
    _positive,
)

__all__ = ["RollerChain"]


@dataclass(frozen=True)
class RollerChain:
    """The rig beyond the roller, for the chain model of
    :func:`~rollerrig.estimation.smoother.smooth_contact_torque`.

    The roller shaft (k56, b56: the torque sensor measures its torque) between the roller and
    the rotor of the roller motor (J6), and the roller drive's air-gap torque T_a on the rotor
    (motoring positive): an open-loop V/f induction motor linearised about synchronous speed
    and lagged, τ Ṫ_a = κ (ω_s − ω6) − T_a (Kayaalp eq. 4.28 near zero slip, where the slope
    κ does not depend on the V/f frequency; eq. 4.29 as a continuous lag), with κ ω_s a random
    walk (it absorbs the curvature of the torque-slip characteristic and any change of the
    speed command); or, with ``drive_slope=None``, T_a itself a random walk (any drive). The
    stator's mount (k70, b70) is taken as rigid.

    Parameters
    ----------
    shaft_stiffness : float
        k56 [N.m/rad], > 0.
    shaft_damping : float
        b56 [N.m.s/rad], >= 0.
    rotor_inertia : float
        J6 [kg.m^2], > 0.
    drive_slope : float or None
        κ, slope of the drive torque against the rotor speed near synchronous speed
        [N.m.s/rad], > 0; None: the drive torque is an unknown random walk.
    drive_lag : float
        τ, time constant of the drive's response lag [s], > 0 (unused when ``drive_slope`` is
        None).

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> chain = RollerChain.from_rig(default_rig())
    >>> chain.shaft_stiffness, chain.rotor_inertia, round(chain.drive_lag, 4)
    (43500.0, 6.6, 0.3635)
    """

    shaft_stiffness: float
    shaft_damping: float
    rotor_inertia: float
    drive_slope: float | None
    drive_lag: float = 1.0

    def __post_init__(self) -> None:
        for name, unit, check in (
            ("shaft_stiffness", "N.m/rad", _positive),
            ("shaft_damping", "N.m.s/rad", _nonnegative),
            ("rotor_inertia", "kg.m^2", _positive),
            ("drive_lag", "s", _positive),
        ):
            object.__setattr__(self, name, check(name, getattr(self, name), unit))
        if self.drive_slope is not None:
            object.__setattr__(
                self, "drive_slope", _positive("drive_slope", self.drive_slope, "N.m.s/rad")
            )

    @classmethod
    def from_rig(cls, rig, drive: str = "induction") -> RollerChain:
        """The chain of a rig: k56, b56, J6, and the induction motor's slope and lag.

        Parameters
        ----------
        rig : RigParameters
            The rig (``stiffness.roller_shaft``, ``damping.roller_shaft``,
            ``inertia.am_rotor``, ``induction_motor``).
        drive : {"induction", "unknown"}
            ``"induction"``: κ is the small-slip slope of the Thevenin circuit the twin uses
            (:func:`rollerrig.drives.induction.thevenin_from_nameplate`) and τ the lag of
            ``response_lag_clp`` (:func:`~rollerrig.drives.induction.lag_time_constant_from_clp`);
            ``"unknown"``: the drive torque is a random walk (a servo drive, or a drive whose
            model is in doubt).

        Returns
        -------
        RollerChain
        """
        from rollerrig.drives.induction import lag_time_constant_from_clp

        if drive not in ("induction", "unknown"):
            raise ParameterError(f"drive must be 'induction' or 'unknown', got {drive!r}")
        am = rig.induction_motor
        slope = None
        if drive == "induction":
            slope = float(am.circuit().small_slip_slope())
        return cls(
            shaft_stiffness=rig.stiffness.roller_shaft,
            shaft_damping=rig.damping.roller_shaft,
            rotor_inertia=rig.inertia.am_rotor,
            drive_slope=slope,
            drive_lag=float(
                lag_time_constant_from_clp(am.response_lag_clp, am.response_lag_reference_step)
            ),
        )


@dataclass(frozen=True)
class _Smoother:
    """The discretised model, its steady-state filter and smoother, and the exact start.

    States z = x / scale (x physical, z of order one per quantisation step of the angle);
    measurements y_s = y / meas_scale (unit variance). State 0 is the roller angle, taken in
    the recursions as the deviation from the measured angle (bounded over hours).
    """

    h: float
    scale: np.ndarray
    meas_scale: np.ndarray
    F: np.ndarray
    G0: np.ndarray
    G1: np.ndarray
    H: np.ndarray
    accel: np.ndarray  # α5 = accel[:-1] @ x + accel[-1] * u (physical)
    i_d: int
    i_w: int
    x0_of: tuple  # (state index, coefficient of T56_0, of u_0) of the start
    gain: np.ndarray  # (n, p) steady state, per scaled measurement
    Phi: np.ndarray
    C: np.ndarray
    P_post: np.ndarray
    P_prior: np.ndarray
    P_smooth: np.ndarray
    P0: np.ndarray
    gains: np.ndarray  # (M, n, p): samples 1..M
    P_post_t: np.ndarray  # (M + 1, n, n): samples 0..M
    C_t: np.ndarray  # (M + 1, n, n): samples 0..M
    P_prior_t: np.ndarray  # (M + 2, n, n): samples 0..M+1 (0 unused)


def _van_loan(A, B, L, Qc, h):
    """Exact discretisation: x1 = F x0 + G0 u0 + G1 u1 (input linear between samples),
    Q = ∫ e^{Aτ} L Qc Lᵀ e^{Aᵀτ} dτ (Van Loan 1978), and the zero-order-held input vector."""
    n = A.shape[0]
    M = np.zeros((n + 2, n + 2))
    M[:n, :n] = A * h
    M[:n, n] = B * h
    M[n, n + 1] = 1.0
    E = linalg.expm(M)
    F, g_hold, g_ramp = E[:n, :n], E[:n, n], E[:n, n + 1]
    V = np.zeros((2 * n, 2 * n))
    V[:n, :n] = -A * h
    V[:n, n:] = L @ Qc @ L.T * h
    V[n:, n:] = A.T * h
    EV = linalg.expm(V)
    Q = EV[n:, n:].T @ EV[:n, n:]
    return F, g_hold - g_ramp, g_ramp, 0.5 * (Q + Q.T), g_hold


def _chain_model(model, inertia, chain, q, q_drive, sigma_t):
    """Continuous model: A, B (input u), L, Qc, H, the torque-noise input vector's use,
    measurement noise, state names and the acceleration row.

    Roller alone: x = [θ, ω, d(, s)], u = T56 + R05, the torque noise a held white input.
    Chain: x = [θ, ω5, φ, ω6, d(, s), T_a(, m)], φ = θ5 − θ6, u = R05, y = [θ, T56]
    with T56 = k56 φ + b56 (ω5 − ω6).
    """
    integrated = model == "integrated_random_walk"
    J = inertia
    if chain is None:
        names = ["theta", "omega", "d"] + (["slope"] if integrated else [])
    else:
        names = ["theta", "omega", "phi", "omega6", "d"] + (["slope"] if integrated else [])
        names += ["torque_a"] + (["m"] if chain.drive_slope is not None else [])
    n = len(names)
    ix = {name: i for i, name in enumerate(names)}
    A = np.zeros((n, n))
    B = np.zeros(n)
    A[0, 1] = 1.0
    A[1, ix["d"]] = 1.0 / J
    B[1] = -1.0 / J
    if integrated:
        A[ix["d"], ix["slope"]] = 1.0
    noise_in = [ix["slope" if integrated else "d"]]
    qs = [q]
    if chain is None:
        H = np.zeros((1, n))
        H[0, 0] = 1.0
        meas_var = None
    else:
        k, b, J6 = chain.shaft_stiffness, chain.shaft_damping, chain.rotor_inertia
        # T56 = k φ + b (ω5 − ω6): −T56/J on the roller, +T56/J6 on the rotor.
        t56 = np.zeros(n)
        t56[[ix["phi"], 1, ix["omega6"]]] = [k, b, -b]
        A[1] -= t56 / J
        A[ix["phi"], 1], A[ix["phi"], ix["omega6"]] = 1.0, -1.0
        A[ix["omega6"]] += t56 / J6
        A[ix["omega6"], ix["torque_a"]] = 1.0 / J6
        if chain.drive_slope is None:
            noise_in.append(ix["torque_a"])
        else:
            tau, kappa = chain.drive_lag, chain.drive_slope
            A[ix["torque_a"], ix["torque_a"]] = -1.0 / tau
            A[ix["torque_a"], ix["omega6"]] = -kappa / tau
            A[ix["torque_a"], ix["m"]] = 1.0 / tau
            noise_in.append(ix["m"])
        qs.append(q_drive)
        H = np.zeros((2, n))
        H[0, 0] = 1.0
        H[1] = t56
        meas_var = sigma_t**2
    L = np.zeros((n, len(noise_in)))
    L[noise_in, range(len(noise_in))] = 1.0
    return A, B, L, np.diag(qs), H, meas_var, names


@lru_cache(maxsize=32)
def _smoother_design(
    model: str,
    sample_rate: float,
    inertia: float,
    cpr: float,
    q: float,
    sigma_t: float,
    chain: RollerChain | None,
    q_drive: float,
) -> _Smoother:
    h = 1.0 / sample_rate
    A, B, L, Qc, H, meas_var, names = _chain_model(model, inertia, chain, q, q_drive, sigma_t)
    n, p = A.shape[0], H.shape[0]
    F, G0, G1, Q, g_hold = _van_loan(A, B, L, Qc, h)
    r_angle = (2.0 * math.pi / cpr) ** 2 / 12.0
    if meas_var is None:  # the torque noise enters with the input (held over the step)
        Q = Q + sigma_t**2 * np.outer(g_hold, g_hold)
        meas_scale = np.array([math.sqrt(r_angle)])
    else:
        meas_scale = np.array([math.sqrt(r_angle), math.sqrt(meas_var)])
    # Scales: an angle quantum per sample, per sample², as a torque on the roller.
    s_angle = math.sqrt(r_angle)
    unit = {
        "theta": s_angle,
        "omega": s_angle / h,
        "omega6": s_angle / h,
        "d": inertia * s_angle / h**2,
        "slope": inertia * s_angle / h**3,
        "torque_a": inertia * s_angle / h**2,
        "m": inertia * s_angle / h**2,
    }
    if chain is not None:
        unit["phi"] = unit["d"] / chain.shaft_stiffness
    scale = np.array([unit[name] for name in names])
    Si = 1.0 / scale
    Fz = Si[:, None] * F * scale[None, :]
    G0z, G1z = Si * G0, Si * G1
    Qz = Si[:, None] * Q * Si[None, :]
    Hz = H * scale[None, :] / meas_scale[:, None]
    try:
        P_prior = linalg.solve_discrete_are(Fz.T, Hz.T, Qz, np.eye(p))
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ParameterError(
            f"the smoother has no steady state for process_noise {q:g}, torque_noise "
            f"{sigma_t:g} and drive_noise {q_drive:g} at {sample_rate:g} Hz ({exc}); choose "
            "noises within a few decades of the defaults"
        ) from None
    P_prior = 0.5 * (P_prior + P_prior.T)
    S = Hz @ P_prior @ Hz.T + np.eye(p)
    K = np.linalg.solve(S, Hz @ P_prior).T
    eye = np.eye(n)
    IKH = eye - K @ Hz
    P_post = IKH @ P_prior @ IKH.T + K @ K.T
    Phi = IKH @ Fz
    C = np.linalg.solve(P_prior, Fz @ P_post).T  # P_post Fᵀ P_prior⁻¹ (both symmetric)
    P_smooth = linalg.solve_discrete_lyapunov(C, P_post - C @ P_prior @ C.T, method="bilinear")
    # Start: the angle known to the quantisation, the speed unknown (the rotor's with it, and
    # the drive's κ ω_s), the rest as in the steady state.
    P0 = P_post.copy()
    P0[0, :] = 0.0
    P0[:, 0] = 0.0
    P0[0, 0] = 1.0
    v = np.zeros(n)
    v[1] = INITIAL_SPEED_SD / unit["omega"]
    if "omega6" in names:
        v[names.index("omega6")] = v[1]
    if "m" in names:
        v[names.index("m")] = INITIAL_SPEED_SD * chain.drive_slope / unit["m"]
    if chain is None:  # as the causal filter: the speed independent of the rest
        P0[1, :] = 0.0
        P0[:, 1] = 0.0
    # ... and an unknown acceleration: d = T56 + R05 + J5 α, T_a = J6 α − T56 (and κ ω_s).
    a = np.zeros(n)
    a[names.index("d")] = INITIAL_ACCELERATION_SD * inertia / unit["d"]
    if chain is not None:
        a[names.index("torque_a")] = INITIAL_ACCELERATION_SD * chain.rotor_inertia / unit["d"]
        if "m" in names:
            a[names.index("m")] = a[names.index("torque_a")]
    P0 = P0 + np.outer(v, v) + np.outer(a, a)
    # The exact filter until its gain is the steady state's (relative to the largest entry of
    # each column: the chain's gains have entries near zero).
    gains, posts, priors, Cs = [], [P0], [np.zeros((n, n))], []
    P = P0
    tol = _GAIN_TOLERANCE * np.max(np.abs(K), axis=0)
    for _ in range(_MAX_SETTLING):
        Pp = Fz @ P @ Fz.T + Qz
        priors.append(Pp)
        Cs.append(np.linalg.solve(Pp, Fz @ P).T)
        Kk = np.linalg.solve(Hz @ Pp @ Hz.T + np.eye(p), Hz @ Pp).T
        if np.all(np.abs(Kk - K) <= tol):
            break
        IKHk = eye - Kk @ Hz
        P = IKHk @ Pp @ IKHk.T + Kk @ Kk.T  # Joseph form
        gains.append(Kk)
        posts.append(P)
    # The state at the start from the first samples: x_i = a T56_0 + b u_0.
    if chain is None:
        x0_of = ((names.index("d"), 0.0, 1.0),)
    else:
        k56 = chain.shaft_stiffness
        x0_of = [
            (names.index("phi"), 1.0 / k56, 0.0),
            (names.index("d"), 1.0, 1.0),
            (names.index("torque_a"), -1.0, 0.0),
        ]
        if "m" in names:
            x0_of.append((names.index("m"), -1.0, 0.0))  # κ ω_s = T_a + κ ω6, ω6 taken as 0
        x0_of = tuple(x0_of)
    accel = np.append(A[1], B[1])
    arrays = {
        "scale": scale,
        "meas_scale": meas_scale,
        "F": Fz,
        "G0": G0z,
        "G1": G1z,
        "H": Hz,
        "accel": accel,
        "gain": K,
        "Phi": Phi,
        "C": C,
        "P_post": P_post,
        "P_prior": P_prior,
        "P_smooth": P_smooth,
        "P0": P0,
        "gains": np.array(gains).reshape(-1, n, p),
        "P_post_t": np.array(posts),
        "C_t": np.array(Cs),
        "P_prior_t": np.array(priors),
    }
    for arr in arrays.values():
        arr.setflags(write=False)
    return _Smoother(h=h, i_d=names.index("d"), i_w=1, x0_of=x0_of, **arrays)
