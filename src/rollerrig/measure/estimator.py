"""A causal estimate of the contact torque F_x r_r from the torque sensor and the roller encoder.

The offline correction (:func:`rollerrig.measure.correction.corrected_adhesion`) takes the
roller's acceleration from a zero-phase Savitzky-Golay derivative: it needs samples on both sides
of each instant. This module estimates the same quantity causally, each output from the samples
up to its own instant, so that it can run online at the DAQ rate: a Kalman filter on the roller
(a disturbance observer for the contact torque).

Model (the roller's equation of motion, DESIGN.md §3; Kayaalp eq. 4.5 with consistent signs)

.. math::
    \\dot\\theta_5 = \\omega_5, \\qquad
    J_5 \\dot\\omega_5 = F_x r_r - T_{56} - R_{05}(\\omega_5, N), \\qquad
    \\dot d = w, \\; d = F_x r_r

- the measured roller-shaft torque T56 is an input, held first-order (linear) between samples,
  with white noise of standard deviation ``torque_noise`` [N.m] that enters as process noise;
- R05 = f_g (W_r + N) r_b tanh(ω/ω_reg) is the bearing loss (Kayaalp eq. 4.14, as
  :mod:`~rollerrig.measure.correction`), an input evaluated with the encoder's backward-difference
  speed (Δcounts·2π/CPR·fs: causal; 0 at the first sample, which has no speed);
- the measurement is the encoder angle θ = counts·2π/CPR with the quantisation noise of a
  uniform rounding error, variance q²/12, q = 2π/CPR [rad];
- the contact torque d is a random walk of spectral density ``process_noise`` [N².m²/s] (the one
  tuning knob: larger follows faster and passes more quantisation noise). An integrated random
  walk (``model="integrated_random_walk"``: d has a slope s, ṡ = w, [N².m²/s³]) is available;
  the random walk is the default on the evidence below.

The model is discretised exactly at the sample interval h (Van Loan's integral in closed form;
the input's first-order hold). The filter starts with the angle of the first sample, an unknown
speed (standard deviation 1000 rad/s) and the contact torque equal to the first torque sample
with the steady-state uncertainty; its gain is the exact time-varying Kalman gain until it is
within 1e-9 (relative) of the steady-state gain of the discrete algebraic Riccati equation, then
the steady-state gain. From there on the filter is a fixed linear recursion: written as
deviations from its quasi-static state and in the Schur basis of its closed-loop matrix, a
triangular set of first-order recursions run by :func:`scipy.signal.lfilter` (an hour at 250 Hz
in about half a second on a shared 2-core machine). The few hundred samples before are a Python
loop shared with :class:`ContactObserver`, which runs the same filter one sample at a time
(about 6 µs a sample; the same numbers to ~1e-10 N.m).

Tuning (evidence, on synthetic recordings other than those the tests assert on). Five twin
runs at 1 kHz, sampled at 250 Hz by :func:`~rollerrig.measure.synthetic.synthetic_recording`
with the default disturbances and seeds 11, 12 and 13 (15 recordings): the bundled
seed-10kmh-wet test and four protocols of two ramp-hold-release cycles (20 km/h 10 kN dry
800 N.m in 2 s; 30 km/h 4.3 kN dry 700 N.m in 1.5 s; 40 km/h 7 kN dry 600 N.m in 4 s; 15 km/h
4.3 kN wet 350 N.m in 2.5 s). RMS error of the CoA against the twin's true contact CoA over all
15 (the rig's raw CoA: 0.0303; the offline correction: 0.0062) and the mean lag:

========================  ======  ======  ======  ======  ======  ======  ======  ======
random walk q [N².m²/s]    1e3     3.2e3   1e4     1.8e4   3.2e4   5.6e4   1e5     3.2e5
RMS error [-]              0.0149  0.0134  0.0123  0.0121  0.0120  0.0124  0.0132  0.0168
lag [ms]                   51      42      35      32      29      26      24      19
========================  ======  ======  ======  ======  ======  ======  ======  ======

The integrated random walk is worse at every setting (best 0.0141 at 1e7 N².m²/s³, lag
25 ms): it follows the ramps without lag but overshoots each sudden release and passes more
quantisation noise. The default is the random walk with q = 3e4 N².m²/s
(:data:`DEFAULT_PROCESS_NOISE`); the best q of each protocol alone lies between 5.6e3 (10 km/h
wet) and 5.6e4 (the fast ramps, 10 kN), within 10 % of the error at the default. The torque
noise (0.3, 1 or 3 N.m) changes none of these errors in the third digit.

Comparison (the bundled seed-30kmh-dry test: 30 km/h, 4.3 kN, three ramps past the adhesion
peak with sudden releases; twin at 1 kHz, :func:`synthetic_recording` at 250 Hz with seed 1 as
the demo writes it; the CoA against the true contact CoA, :func:`estimator_performance`; seeds
2 and 3, and a twin run at 250 Hz, change the RMS errors by at most 0.0001 and the lags by at
most 0.2 ms):

=======================================  ========  =============  ================
CoA                                       lag [ms]  RMS error [-]  largest error [-]
=======================================  ========  =============  ================
rig, T56/(r_r N)                          79.5      0.0383         0.28
offline correction (SG 0.2 s, order 4)    2.4       0.0088         0.11
this estimate, causal, default tuning     29.1      0.0162         0.29
=======================================  ========  =============  ================

(As a contact torque: RMS error 31 N.m, lag 29 ms. The offline correction's 2.4 ms is mostly
half a sample, 2 ms, of the encoder's backward-difference speed.) Two thirds of the causal
estimate's squared error lies in the 0.1 s after each sudden release (1 % of the time), where
the contact torque falls by ~600 N.m within ~12 ms and the encoder shows it only as a change of
curvature of about one count after 10 ms; elsewhere its RMS error is 0.009 (free rolling 0.005:
the quantisation noise passed at this bandwidth; ramps 0.007). A prototype with the roller shaft
and the roller motor's rotor in the model (T56 as a measurement of the shaft's twist, k56, b56
and J6 known, the motor torque a random walk) lowered the RMS error on three of the tuning
recordings only from 0.0135 to 0.0127, so it was not pursued.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy import linalg, signal

from rollerrig._validation import ParameterError
from rollerrig.measure.recording import RecordingError

__all__ = [
    "DEFAULT_PROCESS_NOISE",
    "DEFAULT_TORQUE_NOISE",
    "MODELS",
    "ContactEstimate",
    "ContactObserver",
    "estimate_contact_torque",
    "estimate_from_recording",
    "estimator_performance",
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
:class:`rollerrig.measure.synthetic.DisturbanceModel`)."""

INITIAL_SPEED_SD = 1e3
"""Prior standard deviation of the roller speed at the first sample [rad/s] (unknown)."""

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
        [1/s], contact torque [N.m/rad] (and its slope [N.m/(s.rad)]).
    settling_samples : int
        Samples filtered with the time-varying gain before the steady-state gain [1].
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
        self.sample_rate = _positive("sample_rate", sample_rate, "Hz")
        self.counts_per_rev = _positive("counts_per_rev", counts_per_rev, "1")
        self.roller_inertia = _positive("roller_inertia", roller_inertia, "kg.m^2")
        self.bearing_friction = _nonnegative("bearing_friction", bearing_friction, "1")
        self.bearing_radius = _nonnegative("bearing_radius", bearing_radius, "m")
        self.roller_weight = _nonnegative("roller_weight", roller_weight, "N")
        self.roller_radius = _positive("roller_radius", roller_radius, "m")
        self.regularisation_speed = _positive("regularisation_speed", regularisation_speed, "rad/s")
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
    m = Uᴴζ the recursion is triangular: from the last component up, each is a first-order
    recursion (:func:`scipy.signal.lfilter`, complex) whose input holds the components
    below it at the previous sample. Run in chunks of :data:`_CHUNK` samples.
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
        m = np.empty((nz, hi - lo), dtype=complex)
        for i in range(nz - 1, -1, -1):
            drive = s1[i] * ddy + s2[i] * du
            for j in range(i + 1, nz):  # T_ij m_j at the previous sample
                drive[0] += T[i, j] * m_last[j]
                drive[1:] += T[i, j] * m[j, :-1]
            m[i], _ = signal.lfilter([1.0], [1.0, -T[i, i]], drive, zi=[T[i, i] * m_last[i]])
        m_last = m[:, -1].copy()
        for row, ref in ((1, ref_speed), (2, ref_torque)):
            out = ref[lo:hi].copy()
            for i in range(nz):  # elementwise: each sample's sum is the same whatever hi is
                out += (U[row, i] * m[i]).real
            z_hist[lo:hi, row] = out


def estimate_from_recording(recording, rig=None, **options) -> ContactEstimate:
    """:func:`estimate_contact_torque` on a recording with a rig's parameters.

    Parameters
    ----------
    recording : Recording
        Needs ``torque``, ``roller_encoder_counts`` and ``normal_load`` or
        ``air_spring_pressure`` (then N = p·A_eff of the rig).
    rig : RigParameters, optional
        Inertia, bearing, geometry and encoder of the rig; default the bundled rig.
    **options
        ``torque_noise``, ``process_noise``, ``model`` of :func:`estimate_contact_torque`.

    Returns
    -------
    ContactEstimate
    """
    from rollerrig.measure.quantities import normal_force_from_pressure
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    if "normal_load" in recording:
        load = recording["normal_load"]
    else:
        recording.require("air_spring_pressure")
        load = normal_force_from_pressure(
            recording["air_spring_pressure"], rig.sensors.air_spring_effective_area
        )
    recording.require("torque", "roller_encoder_counts")
    b = rig.bearing
    return estimate_contact_torque(
        recording["torque"],
        recording["roller_encoder_counts"],
        load,
        recording.sample_rate,
        counts_per_rev=rig.sensors.encoder_counts_per_revolution,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        roller_radius=rig.geometry.roller_radius_x,
        regularisation_speed=b.regularisation_speed,
        **options,
    )


# ------------------------------------------------------------------ performance


def estimator_performance(
    estimate, truth_contact_torque, sample_rate: float, *, max_lag: float = 0.5, unit="N.m"
) -> dict:
    """Lag and errors of an estimate against the truth.

    Parameters
    ----------
    estimate : ContactEstimate or array_like, shape (n,)
        The estimate (its ``contact_torque`` for a :class:`ContactEstimate`); any signal on
        the truth's samples works (a CoA with ``unit="-"``).
    truth_contact_torque : array_like, shape (n,)
        The true signal at the same instants [unit].
    sample_rate : float
        [Hz], > 0.
    max_lag : float
        Largest lag searched, either sign [s], > 0.
    unit : str
        Unit of the signals, for the keys (default N.m).

    Returns
    -------
    dict
        ``"lag [s]"``: where the correlation coefficient of the estimate and the shifted truth
        over their overlap peaks (parabolic interpolation between samples; > 0: the estimate
        comes later; None with ``"lag_note"`` when a signal has no variation);
        ``"rms_error [unit]"``, ``"max_abs_error [unit]"``, ``"bias [unit]"`` (mean of
        estimate − truth); ``"samples"``.

    Examples
    --------
    >>> t = np.arange(2000) / 250.0
    >>> truth = np.sin(2 * np.pi * 0.5 * t)
    >>> late = np.sin(2 * np.pi * 0.5 * (t - 0.02))
    >>> round(estimator_performance(late, truth, 250.0, unit="-")["lag [s]"], 3)
    0.02
    """
    est = estimate.contact_torque if isinstance(estimate, ContactEstimate) else estimate
    x = _array("estimate", est, unit, "the estimate")
    y = _array("truth_contact_torque", truth_contact_torque, unit, "the truth")
    if x.ndim == 0 or x.shape != y.shape:
        raise RecordingError(
            f"estimate ({x.size} samples) and truth ({y.size} samples) must be arrays on the "
            "same instants (same length)"
        )
    if x.size < 3:
        raise RecordingError(f"the performance needs at least 3 samples, got {x.size}")
    fs = _positive("sample_rate", sample_rate, "Hz")
    lag_max = _positive("max_lag", max_lag, "s")
    err = x - y
    out: dict = {
        "lag [s]": None,
        f"rms_error [{unit}]": float(np.sqrt(np.mean(err**2))),
        f"max_abs_error [{unit}]": float(np.max(np.abs(err))),
        f"bias [{unit}]": float(np.mean(err)),
        "samples": int(x.size),
    }
    xc, yc = x - x.mean(), y - y.mean()
    if not (np.any(xc) and np.any(yc)):
        out["lag_note"] = "a signal has no variation: no lag can be measured"
        return out
    m = max(1, min(round(lag_max * fs), x.size - 3))
    c = _lagged_correlation(xc, yc, m)
    i = int(np.argmax(c))
    frac = 0.0
    if 0 < i < c.size - 1:
        den = c[i - 1] - 2.0 * c[i] + c[i + 1]
        if den < 0.0:
            frac = 0.5 * (c[i - 1] - c[i + 1]) / den
    out["lag [s]"] = float((i - m + frac) / fs)
    if i in (0, c.size - 1):
        out["lag_note"] = f"the correlation peaks at the edge of the search (±{lag_max:g} s)"
    return out


def _lagged_correlation(x: np.ndarray, y: np.ndarray, m: int) -> np.ndarray:
    """Pearson correlation of x[i] with y[i − l] over their overlap, for l = −m..m.

    The products by FFT (:func:`scipy.signal.correlate`), the overlap's sums by cumulative
    sums: O(n log n) for all lags. A lag's overlap has n − |l| samples, so the coefficient
    is not biased towards short lags the way a zero-padded correlation is.
    """
    n = x.size
    full = signal.correlate(x, y, mode="full", method="fft")
    lags = np.arange(-m, m + 1)
    sxy = full[n - 1 - m : n + m]

    def sums(v):
        c1 = np.concatenate([[0.0], np.cumsum(v)])
        c2 = np.concatenate([[0.0], np.cumsum(v * v)])
        return c1, c2

    cx, cxx = sums(x)
    cy, cyy = sums(y)
    pos = np.maximum(lags, 0)
    neg = np.maximum(-lags, 0)
    # x[i] for i in [pos, n − neg), y[j] for j in [neg, n − pos).
    count = n - np.abs(lags)
    sx, sxx = cx[n - neg] - cx[pos], cxx[n - neg] - cxx[pos]
    sy, syy = cy[n - pos] - cy[neg], cyy[n - pos] - cyy[neg]
    cov = sxy - sx * sy / count
    var = np.maximum(sxx - sx * sx / count, 0.0) * np.maximum(syy - sy * sy / count, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(var > 0.0, cov / np.sqrt(var), 0.0)
    return r
