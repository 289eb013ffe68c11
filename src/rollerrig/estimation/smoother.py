"""The two-sided (Rauch-Tung-Striebel) smoothers of the contact torque: the roller alone or the
roller-shaft-rotor-drive chain (:class:`RollerChain`), the order lines of the torque, the
innovations judged and the drive noise by maximum likelihood.

The method, its tuning and its accuracy: :mod:`rollerrig.estimation.estimator`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import linalg

from rollerrig._validation import ParameterError
from rollerrig.estimation.kalman import (
    _GAIN_TOLERANCE,
    _MAX_SETTLING,
    DEFAULT_TORQUE_NOISE,
    INITIAL_ACCELERATION_SD,
    INITIAL_SPEED_SD,
    ContactEstimate,
    _array,
    _bearing,
    _check_model,
    _inputs,
    _nonnegative,
    _positive,
    _roller_parameters,
    _triangular,
)
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "DEFAULT_CHAIN_NOISE",
    "DEFAULT_CHAIN_TORQUE_NOISE",
    "DEFAULT_DRIVE_NOISE",
    "DEFAULT_SMOOTHER_NOISE",
    "DRIVE_NOISE_RANGE",
    "LINE_BLOCK",
    "RollerChain",
    "smooth_contact_torque",
]


DEFAULT_SMOOTHER_NOISE = {"random_walk": 3e4, "integrated_random_walk": 1e8}
"""Default spectral density of the contact torque's process noise of the smoother on the
roller alone (``chain=None``), by model [N².m²/s] or [N².m²/s³] (module docstring)."""

DEFAULT_CHAIN_NOISE = {"random_walk": 3e4, "integrated_random_walk": 1e9}
"""Default spectral density of the contact torque's process noise of the smoother on the
roller-shaft-rotor chain, by model [N².m²/s] or [N².m²/s³] (module docstring)."""

DEFAULT_DRIVE_NOISE = 1e2
"""Default spectral density of the random walk of the roller drive [N².m²/s]: of κ·ω_s, the
linearised induction motor's torque at standstill, or of the drive torque itself when the drive
is not modelled (module docstring)."""

DEFAULT_CHAIN_TORQUE_NOISE = {"lines": 1.5, "no_lines": 4.0}
"""Default standard deviation of the torque measurement of the chain model [N.m], with and
without the fit of the order lines: the sensor's white noise (1 N.m on the synthetic
recordings) and what the model does not explain (the lines when they are not fitted, the
motor's nonlinearity); chosen on synthetic recordings (module docstring)."""

LINE_BLOCK = 60.0
"""Length of the blocks in which the order lines of the torque are fitted [s]: their amplitude
and phase are taken as constant within a block."""

_SMOOTHER_CHUNK = 1 << 18


@dataclass(frozen=True)
class RollerChain:
    """The rig beyond the roller, for the chain model of :func:`smooth_contact_torque`.

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


def _order_lines(sd: _Smoother, dth, torque, u, angles_orders, fs):
    """Lines cos/sin(order·angle) of the torque channel, their amplitudes by maximum
    likelihood: constant within blocks of :data:`LINE_BLOCK` (as states without process noise
    in the measurement), estimated by weighted least squares on the forward filter's
    innovations, which are linear in the amplitudes (e(a) = e(0) − Σ a_j ψ_j, ψ_j the
    innovations of the line j alone). The samples of the filter's transient are left out."""
    n = torque.size
    cols = [
        f(order * angle)
        for angle, orders in angles_orders
        for order in orders
        for f in (np.cos, np.sin)
    ]
    zero = np.zeros(n)
    W = np.linalg.cholesky(np.linalg.inv(sd.H @ sd.P_prior @ sd.H.T + np.eye(2)))
    e0 = _innovations(sd, dth, torque, u) @ W
    psi = np.array([_innovations(sd, zero, x, zero) @ W for x in cols])  # (m, n − 1, 2)
    block = max(round(LINE_BLOCK * fs), 1)
    starts = list(range(0, n, block))
    if len(starts) > 1 and n - starts[-1] < block // 2:
        starts.pop()  # a short last block joins the one before
    fit = np.zeros(n)
    skip = sd.gains.shape[0] + 1
    for b, lo in enumerate(starts):
        hi = starts[b + 1] if b + 1 < len(starts) else n
        rows = slice(max(lo, skip) - 1, hi - 1)  # innovations of samples lo..hi−1
        if rows.stop - rows.start <= len(cols):
            continue  # too short a block to tell the lines apart
        A = psi[:, rows].reshape(len(cols), -1).T
        coef, *_ = np.linalg.lstsq(A, e0[rows].reshape(-1), rcond=None)
        for a, x in zip(coef, cols, strict=True):
            fit[lo:hi] += a * x[lo:hi]
    return fit


def _orders(name: str, orders) -> tuple[float, ...]:
    try:
        values = tuple(float(o) for o in orders)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be numbers (orders of the rotation) [1]") from None
    for o in values:
        if not (math.isfinite(o) and o > 0.0):
            raise ParameterError(f"{name} must be finite and > 0 [1], got {o!r}")
    return values


def _smoother_noises(model, chain, torque_noise, process_noise, drive_noise, lines=False):
    """The validated model name and noises of the smoother, defaults filled in."""
    model = _check_model(model)
    if chain is not None and not isinstance(chain, RollerChain):
        raise ParameterError(
            f"chain must be a RollerChain (RollerChain.from_rig(rig)) or None, got "
            f"{type(chain).__name__}"
        )
    unit = "N^2.m^2/s" if model == "random_walk" else "N^2.m^2/s^3"
    defaults = DEFAULT_SMOOTHER_NOISE if chain is None else DEFAULT_CHAIN_NOISE
    q = (
        defaults[model]
        if process_noise is None
        else _positive("process_noise", process_noise, unit)
    )
    if chain is None:
        sigma_t = (
            DEFAULT_TORQUE_NOISE
            if torque_noise is None
            else _nonnegative("torque_noise", torque_noise, "N.m")
        )
        return model, q, sigma_t, 0.0
    sigma_t = (
        DEFAULT_CHAIN_TORQUE_NOISE["lines" if lines else "no_lines"]
        if torque_noise is None
        else _positive("torque_noise", torque_noise, "N.m")
    )
    if isinstance(drive_noise, str):
        if drive_noise != "ml":
            raise ParameterError(
                f"drive_noise must be a spectral density [N^2.m^2/s] or 'ml' (maximum "
                f"likelihood), got {drive_noise!r}"
            )
        return model, q, sigma_t, "ml"
    q_drive = (
        DEFAULT_DRIVE_NOISE
        if drive_noise is None
        else _positive("drive_noise", drive_noise, "N^2.m^2/s")
    )
    return model, q, sigma_t, q_drive


def smooth_contact_torque(
    torque,
    roller_counts,
    normal_load,
    sample_rate: float,
    *,
    counts_per_rev: float,
    roller_inertia: float,
    bearing_friction: float,
    bearing_radius: float,
    roller_weight: float,
    roller_radius: float,
    regularisation_speed: float = 0.05,
    torque_noise: float | None = None,
    process_noise: float | None = None,
    model: str = "random_walk",
    chain: RollerChain | None = None,
    drive_noise: float | None = None,
    roller_orders=(),
    wheel_counts=None,
    wheel_orders=(),
) -> ContactEstimate:
    """Offline (two-sided) estimate of the contact torque F_x r_r: a Rauch-Tung-Striebel
    smoother.

    The Kalman filter of :func:`estimate_contact_torque` run forward, then the RTS recursion
    backward (Rauch, Tung and Striebel 1965; Särkkä 2013, section 8.2): each output uses every
    sample of the recording. With ``chain=None`` the model is the causal filter's (the roller
    alone, T56 an input); with a :class:`RollerChain`, the roller, the roller shaft, the
    motor's rotor and the roller drive, with T56 a second measurement (of the shaft's twist):
    the torque sensor then also tells the roller's acceleration, through the shaft's dynamics.
    Order lines of the torque channel (``roller_orders`` of the roller's rotation,
    ``wheel_orders`` of the wheel's; chain only) are estimated by maximum likelihood, constant
    within blocks of :data:`LINE_BLOCK` (weighted least squares on the forward filter's
    innovations), and removed before the smoother runs. See the module docstring for the
    tuning and the accuracy.

    Exact time-varying gains while the filter settles, then the steady-state filter and
    smoother gains, run as triangular recursions by :func:`scipy.signal.lfilter` (an hour at
    250 Hz in seconds).

    Parameters
    ----------
    torque, roller_counts, normal_load, sample_rate, counts_per_rev, roller_inertia,
    bearing_friction, bearing_radius, roller_weight, roller_radius, regularisation_speed
        As :func:`estimate_contact_torque`.
    torque_noise : float, optional
        Standard deviation of the torque sensor [N.m]: a white input noise on the roller alone
        (default :data:`DEFAULT_TORQUE_NOISE`), the torque measurement's noise in the chain
        model, > 0 (default :data:`DEFAULT_CHAIN_TORQUE_NOISE`, ``"lines"`` when orders are
        given).
    process_noise : float, optional
        Spectral density of the contact torque's random walk [N².m²/s] (of its slope for the
        integrated random walk [N².m²/s³]); default :data:`DEFAULT_SMOOTHER_NOISE` (roller
        alone) or :data:`DEFAULT_CHAIN_NOISE` (chain).
    model : str
        ``"random_walk"`` (default) or ``"integrated_random_walk"``.
    chain : RollerChain, optional
        The roller shaft, the rotor and the drive (:meth:`RollerChain.from_rig`); None: the
        roller alone.
    drive_noise : float or "ml", optional
        Spectral density of the drive's random walk [N².m²/s] (chain only); default
        :data:`DEFAULT_DRIVE_NOISE`. ``"ml"``: the one in :data:`DRIVE_NOISE_RANGE` that
        maximises the likelihood of the innovations (a drive the lag model does not describe,
        such as the dq machine under slip compensation, takes 10³–10⁴ times the default and
        the chain then leans on the torque sensor: RMS CoA error 0.0039–0.0043 on such
        recordings, against 0.0093–0.0124 at the default and 0.0044–0.0046 for the roller
        alone; the twin's own recording keeps 0.0022).
    roller_orders : sequence of float
        Orders of the roller's rotation whose lines are fitted and removed from the torque
        (e.g. 1, 2 and the roller motor's pole pairs p, 2p, 3p); default none.
    wheel_counts : array_like, optional
        Cumulative wheel encoder counts [1] (same CPR), for ``wheel_orders``.
    wheel_orders : sequence of float
        Orders of the wheel's rotation to remove (e.g. 1, 2 and the wheel motor's pole pairs).

    Returns
    -------
    ContactEstimate
        With ``contact_torque_variance`` (the smoother's P of the contact torque, per sample
        [N².m²]), ``smoother_gain`` and ``torque_lines`` (the lines removed [N.m]);
        ``settling_samples`` counts the forward filter's time-varying gains.

    Raises
    ------
    RecordingError
        As :func:`estimate_contact_torque` (and for ``wheel_counts``).
    ParameterError
        A parameter out of range (the message names it, its unit and the range).

    Examples
    --------
    A roller accelerating at 2 rad/s² with no shaft torque: the contact supplies J5·α5 = 90 N.m.

    >>> t = np.arange(2500) / 250.0
    >>> counts = np.floor((18.0 * t + t**2) * 10000 / (2 * np.pi))
    >>> est = smooth_contact_torque(np.zeros(t.size), counts, 4300.0, 250.0,
    ...     counts_per_rev=10000, roller_inertia=45.0, bearing_friction=0.0,
    ...     bearing_radius=0.065, roller_weight=5000.0, roller_radius=0.452)
    >>> round(float(np.mean(est.contact_torque)), 0), round(float(est.contact_torque.std()), 0)
    (90.0, 5.0)
    """
    par = _roller_parameters(
        sample_rate,
        counts_per_rev,
        roller_inertia,
        bearing_friction,
        bearing_radius,
        roller_weight,
        roller_radius,
        regularisation_speed,
    )
    r_orders = _orders("roller_orders", roller_orders)
    w_orders = _orders("wheel_orders", wheel_orders)
    model, q, sigma_t, q_drive = _smoother_noises(
        model, chain, torque_noise, process_noise, drive_noise, bool(r_orders or w_orders)
    )
    if chain is None and (r_orders or w_orders):
        raise ParameterError(
            "roller_orders and wheel_orders need chain=RollerChain(...): on the roller alone "
            "a line of the torque sensor cannot be told from the contact torque (T56 is an "
            "input there)"
        )
    t56, c, n_load = _inputs(torque, roller_counts, normal_load)
    n = t56.size
    fs = par["sample_rate"]
    to_rad = 2.0 * math.pi / par["counts_per_rev"]
    angles_orders = []
    if r_orders:
        angles_orders.append(((c - c[0]) * to_rad, r_orders))
    if w_orders:
        if wheel_counts is None:
            raise ParameterError("wheel_orders need wheel_counts (the wheel encoder's counts)")
        wc = _array("wheel_counts", wheel_counts, "1", "cumulative wheel encoder counts")
        if wc.shape != t56.shape:
            raise RecordingError(
                f"wheel_counts has {wc.size} samples and torque {n}: give both on the same "
                "time axis (same length)"
            )
        angles_orders.append(((wc - wc[0]) * to_rad, w_orders))
    dth = np.empty(n)
    dth[0] = 0.0
    dth[1:] = np.diff(c) * to_rad
    speed_enc = dth * fs
    if n > 1:
        speed_enc[0] = speed_enc[1]
    bearing = _bearing(
        n_load,
        speed_enc,
        par["bearing_friction"],
        par["bearing_radius"],
        par["roller_weight"],
        par["regularisation_speed"],
    )

    def filtered(q_drive, lines=None, judge=True):
        sd = _smoother_design(
            model, fs, par["roller_inertia"], par["counts_per_rev"], q, sigma_t, chain, q_drive
        )
        if lines is None:
            lines = np.zeros(n)
            if angles_orders and n > 1:  # chain only: u is the bearing loss
                lines = _order_lines(sd, dth, t56, bearing, angles_orders, fs)
        t_clean = t56 - lines
        u = t_clean + bearing if chain is None else bearing
        Z = _smoother_forward(sd, dth, t_clean, u, _start(sd, t_clean[0], u[0]))
        innovations = _innovation_whiteness(sd, _innovations(sd, dth, t_clean, u, Z), judge)
        return sd, lines, u, Z, innovations

    if q_drive == "ml":
        # The lines hardly depend on the drive noise: fitted once at the default for the
        # search (the likelihood alone at each trial), again at the noise found.
        fixed = filtered(DEFAULT_DRIVE_NOISE, judge=False)[1]
        q_drive = _most_likely_drive_noise(lambda qd: filtered(qd, fixed, judge=False)[-1])
    sd, lines, u, Z, innovations = filtered(q_drive)
    x = _smoother_backward(sd, Z, dth, u) * sd.scale
    contact = x[:, sd.i_d]
    variance = _smoothed_variance(sd, n) * sd.scale[sd.i_d] ** 2
    gain_phys = sd.scale[:, None] * sd.gain / sd.meas_scale[None, :]
    return ContactEstimate(
        contact_torque=contact,
        roller_speed=x[:, sd.i_w],
        roller_acceleration=x @ sd.accel[:-1] + sd.accel[-1] * u,
        coa=contact / (par["roller_radius"] * n_load),
        sample_rate=fs,
        model=model,
        process_noise=q,
        torque_noise=sigma_t,
        gain=gain_phys if gain_phys.shape[1] > 1 else gain_phys[:, 0],
        settling_samples=int(sd.gains.shape[0]),
        contact_torque_variance=variance,
        smoother_gain=(sd.scale[:, None] * sd.C / sd.scale[None, :]),
        torque_lines=lines,
        smoothed=True,
        innovations=innovations,
        drive_noise=q_drive if chain is not None else None,
    )


DRIVE_NOISE_RANGE = (1e1, 1e8)
"""Range of the chain's drive noise [N².m²/s] searched by maximum likelihood
(``drive_noise="ml"``): from a tenth of :data:`DEFAULT_DRIVE_NOISE` to where the drive model
says nothing any more (the drive torque then follows the torque sensor alone)."""


def _most_likely_drive_noise(log_likelihood) -> float:
    """The drive noise [N².m²/s] in :data:`DRIVE_NOISE_RANGE` that maximises the innovations'
    log-likelihood per sample (``log_likelihood(q)`` returns the innovations' dict): a bounded
    scalar search on log10 q to 0.2 decade (the likelihood is smooth and single-peaked in it
    on every recording tried, the twin's own, the dq drive's and the arm's)."""
    from scipy.optimize import minimize_scalar

    lo, hi = (math.log10(v) for v in DRIVE_NOISE_RANGE)
    res = minimize_scalar(
        lambda z: -log_likelihood(10.0**z)["log_likelihood_per_sample"],
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 0.2},
    )
    return float(10.0**res.x)


_MIN_INNOVATIONS = 30  # steady-state innovations below which none are judged


def _innovation_whiteness(sd: _Smoother, e: np.ndarray, judge: bool = True) -> dict:
    """The innovations' log-likelihood per sample (Gaussian, steady-state covariance
    S = H P⁻ Hᵀ + R in the scaled measurements) and, per measurement (``angle``, ``torque``),
    the whiteness (:func:`rollerrig.fit.whiteness.whiteness`) and ``variance`` of each
    innovation divided by its predicted standard deviation: for the right model, white with
    unit variance (the consistency test of Bar-Shalom, Li and Kirubarajan 2001, §5.4). The
    filter's transient is left out; empty (a likelihood of 0) below
    :data:`_MIN_INNOVATIONS` samples after it."""
    from rollerrig.fit.whiteness import whiteness

    skip = sd.gains.shape[0]
    if e.shape[0] - skip < _MIN_INNOVATIONS:
        return {"log_likelihood_per_sample": 0.0}  # too short to judge
    e = e[skip:]
    sd_pred = np.sqrt(np.diag(sd.H @ sd.P_prior @ sd.H.T) + 1.0)
    S = sd.H @ sd.P_prior @ sd.H.T + np.eye(e.shape[1])
    out = {
        "log_likelihood_per_sample": float(
            -0.5 * np.mean(np.sum(e * np.linalg.solve(S, e.T).T, axis=1))
            - 0.5 * np.log(np.linalg.det(S))
        )
    }
    if not judge:  # the likelihood alone (the drive noise's search)
        return out
    for j, name in enumerate(("angle", "torque")[: e.shape[1]]):
        x = e[:, j] / sd_pred[j]
        w = whiteness(x)
        w["variance"] = float(np.mean(x**2))
        out[name] = w
    return out
