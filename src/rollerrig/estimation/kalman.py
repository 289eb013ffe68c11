"""The roller's model and the causal Kalman filter of the contact torque (online, one sample at a
time), and what the smoothers share: the estimate's type, the validated parameters, the Schur-
form recursions.

The method, its tuning and its accuracy: :mod:`rollerrig.estimation.estimator`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy import linalg, signal

from rollerrig._validation import ParameterError
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "DEFAULT_PROCESS_NOISE",
    "DEFAULT_TORQUE_NOISE",
    "INITIAL_ACCELERATION_SD",
    "INITIAL_SPEED_SD",
    "MODELS",
    "ContactEstimate",
    "ContactObserver",
    "estimate_contact_torque",
]


MODELS = ("random_walk", "integrated_random_walk")
"""Process models of the contact torque: a random walk (default) or an integrated one."""

DEFAULT_PROCESS_NOISE = {"random_walk": 3e4, "integrated_random_walk": 1e7}
"""Default spectral density of the contact torque's process noise by model: random walk
[N².m²/s] (d increments of variance q·h per step h), integrated random walk [N².m²/s³]
(on the slope). Chosen on synthetic recordings (module docstring)."""

DEFAULT_TORQUE_NOISE = 1.0
"""Default standard deviation of the white noise of the torque sensor [N.m]: 0.03 % of the
default rig's 3000 N.m range, a strain-gauge torque flange's noise floor (the noise of
:class:`rollerrig.recordings.synthetic.DisturbanceModel`)."""

INITIAL_SPEED_SD = 1e3
"""Prior standard deviation of the roller speed at the first sample [rad/s] (unknown)."""

INITIAL_ACCELERATION_SD = 10.0
"""Prior standard deviation of the roller's acceleration at the first sample, for the smoother
[rad/s²] (a recording may start in a transient; the causal filter starts from the steady
state's uncertainty of the contact torque instead)."""

_GAIN_TOLERANCE = 1e-9
_MAX_SETTLING = 200_000
_CHUNK = 1 << 20


@dataclass(frozen=True)
class ContactEstimate:
    """The causal estimate of the contact torque, sample by sample.

    Attributes
    ----------
    contact_torque : numpy.ndarray
        F_x r_r [N.m] at each sample, from the samples up to it.
    roller_speed : numpy.ndarray
        ω5 [rad/s] (0 at the first sample: no speed information yet).
    roller_acceleration : numpy.ndarray
        α5 = (F_x r_r − T56 − R05)/J5 [rad/s²].
    coa : numpy.ndarray
        F_x r_r/(r_r N) [-].
    sample_rate : float
        [Hz].
    model : str
        One of :data:`MODELS`.
    process_noise : float
        Spectral density used [N².m²/s] (random walk) or [N².m²/s³] (integrated).
    torque_noise : float
        Torque-sensor noise used [N.m].
    gain : numpy.ndarray
        Steady-state Kalman gain per radian of angle innovation: angle [rad/rad], speed
        [1/s], contact torque [N.m/rad] (and its slope [N.m/(s.rad)]). For the smoother's
        chain model, shape (states, 2): per radian of angle and per N.m of torque innovation,
        the states in the order [θ5, ω5, φ, ω6, d(, slope), T_a(, κ ω_s)].
    settling_samples : int
        Samples filtered with the time-varying gain before the steady-state gain [1].
    contact_torque_variance : numpy.ndarray or None
        The smoother's variance of the contact torque at each sample [N².m²] (the model's
        P_k|n; None for the causal estimate). Of the CoA: divide by (r_r N)².
    smoother_gain : numpy.ndarray or None
        The smoother's steady-state gain C = P⁺ Fᵀ (P⁻)⁻¹ in physical units, rows and columns
        in the model's state order ([θ, ω, d(, slope)] on the roller alone; the chain's as for
        ``gain``); None for the causal estimate.
    torque_lines : numpy.ndarray or None
        The order lines removed from the torque before the smoother ran [N.m] (zeros when none
        were asked for; None for the causal estimate).
    smoothed : bool
        True for :func:`smooth_contact_torque`, False for the causal estimate.
    innovations : dict or None
        The smoother's forward-filter innovations judged: their log-likelihood per sample and,
        per measurement, whiteness and variance over the prediction (for the right model
        white with unit variance); None for the causal estimate.
    drive_noise : float or None
        The chain's drive noise used [N².m²/s] (the maximum-likelihood one with
        ``drive_noise="ml"``); None on the roller alone.
    choice : str or None
        Why this smoother is the one to trust (:func:`choose_smoother`); None when not chosen.
    """

    contact_torque: np.ndarray
    roller_speed: np.ndarray
    roller_acceleration: np.ndarray
    coa: np.ndarray
    sample_rate: float
    model: str
    process_noise: float
    torque_noise: float
    gain: np.ndarray = field(repr=False)
    settling_samples: int
    contact_torque_variance: np.ndarray | None = field(default=None, repr=False)
    smoother_gain: np.ndarray | None = field(default=None, repr=False)
    torque_lines: np.ndarray | None = field(default=None, repr=False)
    smoothed: bool = False
    innovations: dict | None = field(default=None, repr=False)
    drive_noise: float | None = None
    choice: str | None = None

    @property
    def settling_time(self) -> float:
        """Time of the time-varying gain [s]."""
        return self.settling_samples / self.sample_rate


# ------------------------------------------------------------------ model and gains


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


def _check_model(model: str) -> str:
    if model not in MODELS:
        raise ParameterError(f"model must be one of {MODELS}, got {model!r}")
    return model


def _positive(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number [{unit}], got {value!r}") from None
    if not (math.isfinite(v) and v > 0.0):
        raise ParameterError(f"{name} must be finite and > 0 [{unit}], got {value!r}")
    return v


def _nonnegative(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number [{unit}], got {value!r}") from None
    if not (math.isfinite(v) and v >= 0.0):
        raise ParameterError(f"{name} must be finite and >= 0 [{unit}], got {value!r}")
    return v


def _roller_parameters(
    sample_rate,
    counts_per_rev,
    roller_inertia,
    bearing_friction,
    bearing_radius,
    roller_weight,
    roller_radius,
    regularisation_speed,
) -> dict:
    """The validated rate, encoder, roller and bearing parameters, by name, in SI units."""
    return {
        "sample_rate": _positive("sample_rate", sample_rate, "Hz"),
        "counts_per_rev": _positive("counts_per_rev", counts_per_rev, "1"),
        "roller_inertia": _positive("roller_inertia", roller_inertia, "kg.m^2"),
        "bearing_friction": _nonnegative("bearing_friction", bearing_friction, "1"),
        "bearing_radius": _nonnegative("bearing_radius", bearing_radius, "m"),
        "roller_weight": _nonnegative("roller_weight", roller_weight, "N"),
        "roller_radius": _positive("roller_radius", roller_radius, "m"),
        "regularisation_speed": _positive("regularisation_speed", regularisation_speed, "rad/s"),
    }


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


# ------------------------------------------------------------------ the recursion


def _step(d: _Design, z: np.ndarray, K: np.ndarray, dy: float, u_prev: float, u: float):
    """One filter step in scaled states relative to the measured angle.

    ``z[0]`` is θ̂ − y (the posterior angle minus the measured one), so that only the count
    increment ``dy`` [rad] enters and the states stay bounded over hours.
    """
    zp = d.F @ z + d.Ga * u_prev + d.Gb * u
    e = dy - zp[0]
    z = zp + K * e
    z[0] -= dy
    return z


def _bearing(load, speed, friction, radius, weight, w_reg):
    return friction * radius * (weight + load) * np.tanh(speed / w_reg)


class ContactObserver:
    """The causal contact-torque estimator, one sample at a time (the filter of
    :func:`estimate_contact_torque`, same parameters, same numbers to rounding).

    Parameters
    ----------
    sample_rate : float
        DAQ rate [Hz], > 0; samples are taken as uniformly spaced.
    counts_per_rev, roller_inertia, bearing_friction, bearing_radius, roller_weight,
    roller_radius, regularisation_speed, torque_noise, process_noise, model
        As :func:`estimate_contact_torque`.

    Examples
    --------
    A roller at 20 rad/s, no torque, no bearing loss: the contact torque stays at zero.

    >>> obs = ContactObserver(250.0, counts_per_rev=10000, roller_inertia=45.0,
    ...     bearing_friction=0.0, bearing_radius=0.065, roller_weight=5000.0,
    ...     roller_radius=0.452)
    >>> for k in range(500):
    ...     _ = obs.update(0.0, np.floor(20.0 * k / 250.0 * 10000 / (2 * np.pi)), 4300.0)
    >>> abs(obs.contact_torque) < 20.0, round(obs.roller_speed, 1)
    (True, 20.0)
    """

    def __init__(
        self,
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
    ) -> None:
        self.model = _check_model(model)
        for name, value in _roller_parameters(
            sample_rate,
            counts_per_rev,
            roller_inertia,
            bearing_friction,
            bearing_radius,
            roller_weight,
            roller_radius,
            regularisation_speed,
        ).items():
            setattr(self, name, value)
        self.torque_noise = (
            DEFAULT_TORQUE_NOISE
            if torque_noise is None
            else _nonnegative("torque_noise", torque_noise, "N.m")
        )
        unit = "N^2.m^2/s" if model == "random_walk" else "N^2.m^2/s^3"
        self.process_noise = (
            DEFAULT_PROCESS_NOISE[model]
            if process_noise is None
            else _positive("process_noise", process_noise, unit)
        )
        self._design = _design(
            self.model,
            self.sample_rate,
            self.roller_inertia,
            self.counts_per_rev,
            self.process_noise,
            self.torque_noise,
        )
        self.reset()

    @property
    def gain(self) -> np.ndarray:
        """Steady-state Kalman gain in physical units (see :class:`ContactEstimate`)."""
        d = self._design
        return d.gain / d.scale

    @property
    def settling_samples(self) -> int:
        """Samples filtered with the time-varying gain [1]."""
        return int(self._design.gains.shape[0])

    def reset(self) -> None:
        """Forget every sample: the next :meth:`update` is a first sample."""
        self.samples = 0
        self._z = np.zeros(self._design.F.shape[0])
        self._counts = 0.0
        self._u = 0.0
        self.contact_torque = math.nan
        self.roller_speed = math.nan
        self.roller_acceleration = math.nan
        self.coa = math.nan

    def _input(self, torque: float, speed: float, load: float) -> float:
        return torque + float(
            _bearing(
                load,
                speed,
                self.bearing_friction,
                self.bearing_radius,
                self.roller_weight,
                self.regularisation_speed,
            )
        )

    def update(self, torque: float, counts: float, load: float) -> float:
        """Take one sample; return the contact torque F_x r_r [N.m] at it.

        Parameters
        ----------
        torque : float
            Measured roller-shaft torque T56 [N.m].
        counts : float
            Cumulative roller encoder count [1].
        load : float
            Normal load N [N], > 0.

        Returns
        -------
        float
            F_x r_r [N.m]; also in :attr:`contact_torque`, with :attr:`roller_speed`
            [rad/s], :attr:`roller_acceleration` [rad/s²] and :attr:`coa` [-].
        """
        values = []
        for name, value, unit in (
            ("torque", torque, "N.m"),
            ("counts", counts, "1"),
            ("load", load, "N"),
        ):
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise RecordingError(
                    f"sample {self.samples}: {name} must be a number [{unit}], got {value!r}"
                ) from None
            if not math.isfinite(v):
                raise RecordingError(
                    f"sample {self.samples}: {name} is {v} [{unit}]; the estimator needs finite "
                    "samples: fill or cut the gap first (read_recording(..., lenient=True))"
                )
            values.append(v)
        t56, c, n = values
        if n <= 0.0:
            raise RecordingError(
                f"sample {self.samples}: load must be > 0 [N] (CoA = F_x r_r/(r_r N)), got {n!r}"
            )
        d = self._design
        scale = 2.0 * math.pi / self.counts_per_rev
        if self.samples == 0:
            u = self._input(t56, 0.0, n)
            z = np.zeros(d.F.shape[0])
            z[2] = u * d.h * d.h / d.inertia
        else:
            dy = (c - self._counts) * scale
            u = self._input(t56, dy * self.sample_rate, n)
            k = self.samples - 1
            K = d.gains[k] if k < d.gains.shape[0] else d.gain
            z = _step(d, self._z, K, dy, self._u, u)
        self._z, self._counts, self._u = z, c, u
        self.samples += 1
        self.contact_torque = float(z[2] / d.scale[2])
        self.roller_speed = float(z[1] / d.scale[1])
        self.roller_acceleration = (self.contact_torque - u) / d.inertia
        self.coa = self.contact_torque / (self.roller_radius * n)
        return self.contact_torque


# ------------------------------------------------------------------ batch


def _array(name: str, value, unit: str, what: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise RecordingError(f"{name} must be numbers [{unit}] ({what})") from None
    if arr.ndim > 1:
        raise RecordingError(f"{name} must be 1-D [{unit}] ({what}), got shape {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise RecordingError(
            f"{name} has {bad.size} NaN/inf sample(s), the first at index {bad[0]} [{unit}] "
            f"({what}); the estimator needs finite samples: fill or cut the gaps first "
            "(read_recording(..., lenient=True) interpolates short ones)"
        )
    return arr


def _inputs(torque, roller_counts, normal_load):
    """The validated sample arrays (T56, counts, load per sample) of the batch functions."""
    t56 = _array("torque", torque, "N.m", "roller-shaft torque T56")
    c = _array("roller_counts", roller_counts, "1", "cumulative roller encoder counts")
    n_load = _array("normal_load", normal_load, "N", "normal load")
    if t56.ndim == 0:
        raise RecordingError("torque must be an array of samples [N.m], got a single number")
    n = t56.size
    if n == 0:
        raise RecordingError("torque has no samples: the estimator needs at least one")
    if c.shape != t56.shape:
        raise RecordingError(
            f"roller_counts has {c.size} samples and torque {n}: give both on the same "
            "time axis (same length)"
        )
    if n_load.ndim == 0:
        n_load = np.full(n, float(n_load))
    elif n_load.shape != t56.shape:
        raise RecordingError(
            f"normal_load has {n_load.size} samples and torque {n}: give one load per sample "
            "or a single number"
        )
    if np.any(n_load <= 0.0):
        i = int(np.flatnonzero(n_load <= 0.0)[0])
        raise RecordingError(
            f"normal_load must be > 0 [N] at every sample (CoA = F_x r_r/(r_r N)); sample {i} "
            f"is {n_load[i]:g} N: cut the unloaded part first"
        )
    return t56, c, n_load


def estimate_contact_torque(
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
) -> ContactEstimate:
    """Causal Kalman estimate of the contact torque F_x r_r, its CoA and the roller speed.

    .. math:: J_5 \\dot\\omega_5 = F_x r_r - T_{56} - R_{05}, \\quad
              \\theta_5 = \\mathrm{counts}\\,2\\pi/\\mathrm{CPR}

    Each output uses only the samples up to its own instant (see the module docstring for the
    model, the tuning and its accuracy against the offline correction). O(n): a short Python
    loop while the gain settles, then :func:`scipy.signal.lfilter`.

    Parameters
    ----------
    torque : array_like, shape (n,)
        Measured roller-shaft torque T56 [N.m].
    roller_counts : array_like, shape (n,)
        Cumulative roller encoder counts [1].
    normal_load : array_like, shape (n,) or float
        Normal load N [N], > 0.
    sample_rate : float
        [Hz], > 0; the samples are taken as uniformly spaced.
    counts_per_rev : float
        Encoder counts per revolution after quadrature decoding [1].
    roller_inertia : float
        J5 [kg.m^2].
    bearing_friction : float
        f_g [-].
    bearing_radius : float
        Roller bearing friction radius r_b [m].
    roller_weight : float
        W_r [N].
    roller_radius : float
        r_r [m] (for the CoA).
    regularisation_speed : float
        ω_reg of the bearing model [rad/s].
    torque_noise : float, optional
        Standard deviation of the torque sensor's white noise [N.m]; default
        :data:`DEFAULT_TORQUE_NOISE`.
    process_noise : float, optional
        Spectral density of the contact torque's random walk [N².m²/s] (of its slope for the
        integrated random walk [N².m²/s³]); default :data:`DEFAULT_PROCESS_NOISE` of the model.
    model : str
        ``"random_walk"`` (default) or ``"integrated_random_walk"``.

    Returns
    -------
    ContactEstimate

    Raises
    ------
    RecordingError
        Arrays of different lengths, empty, not 1-D, with NaN/inf, or a load not > 0.
    ParameterError
        A parameter out of range (the message names it, its unit and the range).

    Examples
    --------
    A roller accelerating at 2 rad/s² with no shaft torque: the contact supplies J5·α5 = 90 N.m.

    >>> t = np.arange(2500) / 250.0
    >>> counts = np.floor((18.0 * t + t**2) * 10000 / (2 * np.pi))
    >>> est = estimate_contact_torque(np.zeros(t.size), counts, 4300.0, 250.0,
    ...     counts_per_rev=10000, roller_inertia=45.0, bearing_friction=0.0,
    ...     bearing_radius=0.065, roller_weight=5000.0, roller_radius=0.452)
    >>> round(float(np.mean(est.contact_torque[1250:])), 0)
    90.0
    """
    observer = ContactObserver(
        sample_rate,
        counts_per_rev=counts_per_rev,
        roller_inertia=roller_inertia,
        bearing_friction=bearing_friction,
        bearing_radius=bearing_radius,
        roller_weight=roller_weight,
        roller_radius=roller_radius,
        regularisation_speed=regularisation_speed,
        torque_noise=torque_noise,
        process_noise=process_noise,
        model=model,
    )
    t56, c, n_load = _inputs(torque, roller_counts, normal_load)
    n = t56.size
    d = observer._design
    fs = observer.sample_rate
    dy = np.empty(n)
    dy[0] = 0.0
    dy[1:] = np.diff(c) * (2.0 * math.pi / observer.counts_per_rev)
    speed_enc = dy * fs  # backward difference; 0 at the first sample
    u = t56 + _bearing(
        n_load,
        speed_enc,
        observer.bearing_friction,
        observer.bearing_radius,
        observer.roller_weight,
        observer.regularisation_speed,
    )

    nz = d.F.shape[0]
    z_hist = np.empty((n, nz))
    # The loop while the gain varies; the steady-state recursion from there on.
    n_loop = min(n, d.gains.shape[0] + 1)
    for k in range(n_loop):
        observer.update(t56[k], c[k], n_load[k])
        z_hist[k] = observer._z
    if n > n_loop:
        _tail(d, z_hist, n_loop, dy, u)
    contact = z_hist[:, 2] / d.scale[2]
    speed = z_hist[:, 1] / d.scale[1]
    return ContactEstimate(
        contact_torque=contact,
        roller_speed=speed,
        roller_acceleration=(contact - u) / d.inertia,
        coa=contact / (observer.roller_radius * n_load),
        sample_rate=fs,
        model=observer.model,
        process_noise=observer.process_noise,
        torque_noise=observer.torque_noise,
        gain=observer.gain,
        settling_samples=observer.settling_samples,
    )


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
