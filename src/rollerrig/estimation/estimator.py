"""Model-based estimates of the contact torque F_x r_r from the torque sensor and the encoders.

The offline correction (:func:`rollerrig.measure.correction.corrected_adhesion`) takes the
roller's acceleration from a zero-phase Savitzky-Golay derivative: it needs samples on both sides
of each instant. This module estimates the same quantity causally, each output from the samples
up to its own instant, so that it can run online at the DAQ rate: a Kalman filter on the roller
(a disturbance observer for the contact torque, :func:`estimate_contact_torque`,
:class:`ContactObserver`); and offline, from all the samples, with a Rauch-Tung-Striebel
smoother on the roller or on the roller-shaft-rotor-drive chain (:func:`smooth_contact_torque`,
section "The smoother" below).

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
runs at 1 kHz, sampled at 250 Hz by :func:`~rollerrig.recordings.synthetic.synthetic_recording`
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
recordings only from 0.0135 to 0.0127, so it was not pursued for the causal filter (the
smoother's chain below, with the induction motor's model and the order lines, does better).

The smoother
------------
:func:`smooth_contact_torque`: the Kalman filter forward, then the Rauch-Tung-Striebel recursion
backward (Rauch, Tung and Striebel 1965; Särkkä, *Bayesian Filtering and Smoothing*, 2013,
§8.2), x_k|n = x_k|k + C (x_k+1|n − x_k+1|k), C = P_k|k Fᵀ P_k+1|k⁻¹. Two models:

- **the roller alone** (``chain=None``): the causal filter's model above;
- **the chain** (``chain=`` :class:`RollerChain`): x = [θ5, ω5, φ, ω6, d, T_a, κω_s],

  .. math::
      J_5 \\dot\\omega_5 = d - T_{56} - R_{05}, \\quad J_6 \\dot\\omega_6 = T_{56} + T_a,
      \\quad \\dot\\varphi = \\omega_5 - \\omega_6, \\quad
      T_{56} = k_{56}\\varphi + b_{56}(\\omega_5 - \\omega_6),

  τ Ṫ_a = κ (ω_s − ω6) − T_a (the open-loop V/f induction motor near synchronous speed, with
  the lag of Kayaalp eq. 4.29), d and κ ω_s random walks, and T56 a *measurement* (noise σ_T)
  beside the encoder angle: the torque sensor then tells the roller's acceleration through the
  shaft's dynamics, where the encoder alone sees a sudden release only as a change of
  curvature of about a count. The lines of the torque channel at orders of the roller's and the
  wheel's rotation (``roller_orders``, ``wheel_orders``) are estimated by maximum likelihood
  (constant amplitudes within blocks of :data:`LINE_BLOCK`: a weighted least-squares fit of
  the forward filter's innovations, which are linear in the amplitudes) and removed first.

Steady state: the filter's gain from the discrete algebraic Riccati equation, the smoother's
C from it (C is similar to the filter's closed-loop matrix, so the backward recursion is
stable) and the smoothed covariance from the Stein equation P = P⁺ + C (P − P⁻) Cᵀ. The exact
time-varying gains while the filter settles (a few hundred samples), then both recursions in
the Schur basis by :func:`scipy.signal.lfilter`, the backward one on reversed chunks: an hour
at 250 Hz in about 0.5 s (roller), 0.8 s (chain), 7 s (chain with 16 line columns) on a shared
2-core machine. The start: the first sample's angle, an unknown speed (1000 rad/s) and an
unknown acceleration (10 rad/s², :data:`INITIAL_ACCELERATION_SD`). Per sample, the model's
variance of the contact torque is ``contact_torque_variance`` (P_k|n); :func:`smoother_weights`
gives the steady-state smoother as a linear filter on the torque, angle and bearing-loss
samples (the variance from white torque noise and uniform quantisation alone:
:meth:`SmootherWeights.noise_variance`).

Tuning (evidence on synthetic recordings other than those the tests assert on). The 15
recordings of the causal filter's tuning, remade: the bundled seed-10kmh-wet test and four
protocols of two ramp-hold(0.5 s)-release-hold(4 s) cycles after 2 s of free rolling (20 km/h
10 kN dry 800 N.m in 2 s; 30 km/h 4.3 kN dry 700 N.m in 1.5 s; 40 km/h 7 kN dry 600 N.m in
4 s; 15 km/h 4.3 kN wet 350 N.m in 2.5 s), twin at 1 kHz, :func:`synthetic_recording` at
250 Hz with seeds 11, 12, 13. RMS error of the CoA against the twin's contact CoA over the 15
(each recording weighted equally): rig 0.0292, offline correction (SG 0.2 s, order 4) 0.0060,
causal filter 0.0116.

- Roller alone, random walk q [N².m²/s] = 1e4, 2e4, **3e4**, 5e4, 1e5: 0.00437, 0.00422,
  **0.00419**, 0.00426, 0.00468 (the causal filter's optimum too); the integrated random walk
  1e6, 1e7, 1e8, 1e9 [N².m²/s³]: 0.00545, 0.00475, 0.00429, 0.00475. Order lines cannot be
  fitted here (T56 is an input: a line is indistinguishable from the contact torque).
- Chain (the default rig's k56, b56, J6, κ, τ), with the lines at roller orders 1, 2, 5, 10,
  15 and wheel orders 1, 2, 22, drive noise 1e2 N².m²/s:

  ===================  ========  ========  ========
  q \\ σ_T [N.m]         0.7       1.0       1.5
  ===================  ========  ========  ========
  1e4                  0.00134   0.00144   0.00161
  2e4                  0.00132   0.00136   0.00149
  3e4                  0.00135   0.00134   0.00144
  5e4                  0.00146   0.00135   0.00140
  ===================  ========  ========  ========

  (1e5: 0.00148 at 1.0, 0.00148 at 2.0; 1e6: 0.0023 to 0.0032.) Drive noise 30, 100, 300,
  1000: 0.00146, 0.00144, 0.00144, 0.00145. Roller orders alone: 0.00208. No lines:
  0.00280 (σ_T = 4.0; 4.0-4.5 was best without them). The integrated random walk 1e8, 1e9,
  1e10: 0.00169, 0.00143, 0.00162. The drive torque as a random walk in place of the motor's
  model (``RollerChain.from_rig(rig, "unknown")``): 0.0046, worse than the roller alone.
- Defaults: q = 3e4 (:data:`DEFAULT_SMOOTHER_NOISE`, :data:`DEFAULT_CHAIN_NOISE`), drive
  noise 1e2 (:data:`DEFAULT_DRIVE_NOISE`), σ_T = 1.5 N.m with the lines and 4.0 without
  (:data:`DEFAULT_CHAIN_TORQUE_NOISE`): 1.0 is 7 % better here, but it is exactly the synthetic
  sensor's white noise; 1.5 leaves room for lines that drift off their orders (an induction
  motor's supply line lies above its rotor order by the slip).

Comparison (RMS / largest error of the CoA against the twin's contact CoA; seed-30kmh-dry as
the demo makes it, seeds 1, 2 and 3 giving the same numbers to ±0.0001; two recordings not
used for tuning: 50 km/h 6 kN dry 750 N.m in 1 s, seeds 21 and 22, and 25 km/h 12 kN dry
850 N.m in 2.5 s made with k56 = 60 kN.m/rad, J6 = 8 kg.m², b56 = 3 N.m.s/rad, which the
estimates are not told, seeds 31 and 32):

=============================  ===============  ===============  ===============
CoA                             seed-30kmh-dry   50 km/h          25 km/h, altered
=============================  ===============  ===============  ===============
rig, T56/(r_r N)                0.0383 / 0.28    0.0407 / 0.25    0.0194 / 0.13
offline correction (SG)         0.0088 / 0.11    0.0079 / 0.10    0.0045 / 0.057
causal filter                   0.0162 / 0.29    0.0148 / 0.24    0.0076 / 0.13
smoother, roller alone          0.0058 / 0.084   0.0053 / 0.081   0.0029 / 0.043
smoother, chain                 0.0031 / 0.064   0.0033 / 0.060   0.0058 / 0.031
smoother, chain and lines       0.0021 / 0.048   0.0023 / 0.045   0.0057 / 0.022
... with the true k56, J6                                         0.0009 / 0.017
1/8 of the rig's error          0.0048           0.0051           0.0024
=============================  ===============  ===============  ===============

The smoothers have no lag (|lag| < 0.6 ms). The chain model needs the roller shaft's mode,
√(k56 (1/J5 + 1/J6))/2π, to a few per cent: on seed-30kmh-dry with the lines, k56 +5 % / −5 %
gives 0.0042 / 0.0043, ±10 % 0.0072 / 0.0084, J6 +10 % 0.0068; κ +20 %, τ +20 % and b56 ×3
change nothing in the second digit, J5 ±5 % gives 0.0029 / 0.0028. So: the chain with a
calibrated rig (``rollerrig calibrate --free stiffness.roller_shaft,inertia.am_rotor``), the
roller alone otherwise. The model's variance is honest for the roller alone (errors/σ: RMS
0.94-1.3, 94-98 % within 1.96 σ on these recordings), conservative for the chain with the right
parameters (RMS 0.26-0.74, > 99 %), and far too small with the wrong ones (3.7, 59 %).
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
    "CHAIN_CONSISTENCY",
    "DEFAULT_CHAIN_NOISE",
    "DEFAULT_CHAIN_TORQUE_NOISE",
    "DEFAULT_DRIVE_NOISE",
    "DEFAULT_PROCESS_NOISE",
    "DEFAULT_SMOOTHER_NOISE",
    "DEFAULT_TORQUE_NOISE",
    "DRIVE_NOISE_RANGE",
    "INITIAL_ACCELERATION_SD",
    "LINE_BLOCK",
    "MODELS",
    "ContactEstimate",
    "ContactObserver",
    "RollerChain",
    "SmootherWeights",
    "chain_reason",
    "choose_smoother",
    "estimate_contact_torque",
    "estimate_from_recording",
    "estimator_performance",
    "smooth_contact_torque",
    "smooth_from_recording",
    "smoother_weights",
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


# ------------------------------------------------------------------ the smoother


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


@dataclass(frozen=True)
class SmootherWeights:
    """The steady-state smoother as a linear filter: the contact torque at sample k is
    Σ_j torque[j] T56_{k−j} + angle[j] θ_{k−j} + bearing[j] R05_{k−j}, j over ``lags``.

    Attributes
    ----------
    lags : numpy.ndarray
        j [samples] (negative: later samples).
    torque : numpy.ndarray
        Weights of the torque samples [N.m/N.m].
    angle : numpy.ndarray
        Weights of the encoder angle samples θ = counts·2π/CPR [N.m/rad] (they sum to zero).
    bearing : numpy.ndarray
        Weights of the bearing-loss samples [N.m/N.m].
    """

    lags: np.ndarray
    torque: np.ndarray
    angle: np.ndarray
    bearing: np.ndarray

    def noise_variance(self, torque_sd: float, counts_per_rev: float) -> float:
        """Variance of the estimate from white torque noise and uniform quantisation [N².m²].

        Parameters
        ----------
        torque_sd : float
            Standard deviation of the torque sensor's white noise [N.m].
        counts_per_rev : float
            Encoder counts per revolution [1] (quantisation variance (2π/CPR)²/12).
        """
        q = 2.0 * math.pi / counts_per_rev
        return float(torque_sd**2 * np.sum(self.torque**2) + q * q / 12.0 * np.sum(self.angle**2))


def smoother_weights(
    sample_rate: float,
    *,
    counts_per_rev: float,
    roller_inertia: float,
    torque_noise: float | None = None,
    process_noise: float | None = None,
    model: str = "random_walk",
    chain: RollerChain | None = None,
    drive_noise: float | None = None,
    lines: bool = False,
    tolerance: float = 1e-9,
) -> SmootherWeights:
    """The weights of the steady-state smoother of :func:`smooth_contact_torque` (away from the
    ends of a recording, and without the order lines' fit, itself a linear projection).

    Parameters
    ----------
    sample_rate, counts_per_rev, roller_inertia, torque_noise, process_noise, model, chain,
    drive_noise
        As :func:`smooth_contact_torque`.
    lines : bool
        Take the default torque noise of a chain smoother that fits order lines.
    tolerance : float
        The weights are cut where the filters' slowest pole has decayed to this [-].

    Returns
    -------
    SmootherWeights

    Examples
    --------
    The weights keep a constant torque and read J5·α5 off a parabola of the angle
    (Σ_j w_j j² h²/2 = J5), and the encoder's quantisation with 1 N.m of torque noise leaves
    about 5 N.m of noise on the roller alone:

    >>> w = smoother_weights(250.0, counts_per_rev=10000, roller_inertia=45.0)
    >>> round(float(w.torque.sum()), 6), round(float(np.sum(w.angle * w.lags**2) / 2 / 250**2), 3)
    (1.0, 45.0)
    >>> round(w.noise_variance(1.0, 10000) ** 0.5, 1)
    4.9
    """
    fs = _positive("sample_rate", sample_rate, "Hz")
    cpr = _positive("counts_per_rev", counts_per_rev, "1")
    inertia = _positive("roller_inertia", roller_inertia, "kg.m^2")
    tol = _positive("tolerance", tolerance, "1")
    model, q, sigma_t, q_drive = _smoother_noises(
        model, chain, torque_noise, process_noise, drive_noise, lines
    )
    if q_drive == "ml":
        raise ParameterError(
            "smoother_weights needs a drive_noise value [N^2.m^2/s]: 'ml' is fitted to a "
            "recording (take ContactEstimate.drive_noise of smooth_contact_torque)"
        )
    sd = _smoother_design(model, fs, inertia, cpr, q, sigma_t, chain, q_drive)
    slowest = float(np.max(np.abs(np.linalg.eigvals(sd.Phi))))
    half = int(min(math.ceil(math.log(min(tol, 0.5)) / math.log(slowest)), _MAX_SETTLING))
    size = 2 * half + 1
    zero, nz = np.zeros(size), sd.F.shape[0]

    def response(dth, y_torque, u):
        Z = _smoother_forward(sd, dth, y_torque, u, np.zeros(nz), exact=False)
        Zs = _smoother_backward(sd, Z, dth, u, exact=False)
        return Zs[::-1, sd.i_d] * sd.scale[sd.i_d]  # output k − j for the impulse at j = half

    impulse = np.zeros(size)
    impulse[half] = 1.0
    steps = np.zeros(size)
    steps[half], steps[half + 1] = 1.0, -1.0  # Δθ of θ_j = δ_j,half
    angle = response(steps, zero, zero)
    bearing = response(zero, zero, impulse)
    torque = bearing if chain is None else response(zero, impulse, zero)
    return SmootherWeights(np.arange(half, -half - 1, -1), torque, angle, bearing)


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
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    load = _recording_load(recording, rig)
    recording.require("torque", "roller_encoder_counts")
    b = rig.bearing
    estimate = estimate_contact_torque(
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
    return _on_contact_load(estimate, load, rig)


CHAIN_CONSISTENCY = 1.25
"""With ``chain="auto"`` the chain smoother is used only when the variance of its angle
innovations, each over its predicted standard deviation, is at most this multiple of the
roller-alone smoother's [1]: the encoder angle is the measurement both models predict, and a
chain that does not fit the recording predicts it worse (the dq drive under the lag model's
default drive noise: 200 to 900 times; with the drive noise by maximum likelihood the chain
fits the twin's own, the dq drive's and the arm's recordings at 0.9–1.0 times). The test does
not see a wrong shaft mode (k56 ±10 % changes the ratio by under 5 % while it doubles the
chain's error): that needs the calibration (``shaft_calibrated``)."""


def smooth_from_recording(
    recording,
    rig=None,
    *,
    chain: str | None = "auto",
    lines: bool = True,
    shaft_calibrated: bool = False,
    **options,
) -> ContactEstimate:
    """:func:`smooth_contact_torque` on a recording with a rig's parameters.

    Parameters
    ----------
    recording : Recording
        Needs ``torque``, ``roller_encoder_counts`` and ``normal_load`` or
        ``air_spring_pressure`` (then N = p·A_eff of the rig); ``wheel_encoder_counts`` for
        the wheel's lines.
    rig : RigParameters, optional
        Default the bundled rig. The chain model needs its roller shaft and motor rotor
        accurate (module docstring): a calibrated rig.
    chain : {"auto", "induction", "unknown", None}
        The drive of :meth:`RollerChain.from_rig`, or None for the roller alone. ``"auto"``
        (default): the chain with the lag model of the drive linearised
        (``"induction"``) and its drive noise by maximum likelihood, used when its angle
        innovations are consistent (:data:`CHAIN_CONSISTENCY`) and ``shaft_calibrated``,
        else the roller alone; the estimate's ``choice`` says which and why.
    lines : bool
        With a chain, remove the lines at orders 1, 2, p, 2p, 3p of the roller (p: the roller
        motor's pole pairs) and 1, 2, p_PMSM of the wheel (when the wheel encoder is recorded).
    shaft_calibrated : bool
        Whether the rig's k56 and J6 come from a calibration whose residuals show no
        structure, to a few per cent (``chain="auto"`` only): the chain needs the shaft's
        mode √(k56 (1/J5 + 1/J6))/2π that well (k56 ±10 % doubles its error, module
        docstring), and its innovations cannot tell.
    **options
        ``torque_noise``, ``process_noise``, ``model``, ``drive_noise`` of
        :func:`smooth_contact_torque`.

    Returns
    -------
    ContactEstimate
    """
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    if chain == "auto":
        return _chain_or_roller(recording, rig, lines, shaft_calibrated, options)
    load = _recording_load(recording, rig)
    recording.require("torque", "roller_encoder_counts")
    b = rig.bearing
    extra: dict = {}
    if chain is not None:
        extra["chain"] = RollerChain.from_rig(rig, drive=chain)
        if lines:
            p = rig.induction_motor.pole_pairs
            extra["roller_orders"] = (1, 2, p, 2 * p, 3 * p)
            if "wheel_encoder_counts" in recording:
                extra["wheel_counts"] = recording["wheel_encoder_counts"]
                extra["wheel_orders"] = (1, 2, rig.pmsm.pole_pairs)
    estimate = smooth_contact_torque(
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
        **extra,
        **options,
    )
    return _on_contact_load(estimate, load, rig)


def _chain_or_roller(
    recording, rig, lines: bool, shaft_calibrated: bool, options: dict
) -> ContactEstimate:
    """``chain="auto"`` of :func:`smooth_from_recording` (:func:`choose_smoother`)."""
    roller_options = {k: v for k, v in options.items() if k != "drive_noise"}
    alone = smooth_from_recording(recording, rig, chain=None, **roller_options)
    chained: ContactEstimate | str | None = None
    if shaft_calibrated:
        try:
            chained = smooth_from_recording(
                recording, rig, chain="induction", lines=lines, **{"drive_noise": "ml", **options}
            )
        except ParameterError as exc:  # a rig the chain cannot take
            chained = str(exc)
    return choose_smoother(alone, chained, shaft_calibrated)


def choose_smoother(
    alone: ContactEstimate,
    chained,
    shaft_calibrated: bool,
    not_calibrated: str = "they are not calibrated",
) -> ContactEstimate:
    """The smoother to trust: the chain where k56 and J6 are calibrated and its angle
    innovations are consistent (:data:`CHAIN_CONSISTENCY`), else the roller alone; the
    returned estimate's ``choice`` says which and why.

    Parameters
    ----------
    alone : ContactEstimate
        The roller-alone smoother's estimate.
    chained : ContactEstimate, str or None
        The chain smoother's estimate (drive noise by maximum likelihood), or why it could
        not be made, or None (not made).
    shaft_calibrated : bool
        As :func:`smooth_from_recording`.
    not_calibrated : str
        Why k56 and J6 are not known well enough, for the reason (when not
        ``shaft_calibrated``).

    Returns
    -------
    ContactEstimate
        ``alone`` or ``chained`` with ``choice`` set.
    """
    import dataclasses

    if not shaft_calibrated:
        why = (
            "roller alone: the chain needs k56 and J6 to a few per cent (k56 ±10 % doubles its "
            f"error) and {not_calibrated} (rollerrig calibrate --free "
            "stiffness.roller_shaft,inertia.am_rotor)"
        )
        return dataclasses.replace(alone, choice=why)
    if not isinstance(chained, ContactEstimate):
        why = f"roller alone: the chain could not be made ({chained or 'not asked for'})"
        return dataclasses.replace(alone, choice=why)
    if "angle" not in (chained.innovations or {}) or "angle" not in (alone.innovations or {}):
        why = "roller alone: the recording is too short to test the chain's innovations"
        return dataclasses.replace(alone, choice=why)
    v_chain = chained.innovations["angle"]["variance"]
    v_alone = alone.innovations["angle"]["variance"]
    ratio = v_chain / v_alone
    numbers = (
        f"variance of the angle innovations over their prediction: chain {v_chain:.3g}, "
        f"roller alone {v_alone:.3g}"
    )
    if ratio > CHAIN_CONSISTENCY:
        why = (
            f"roller alone: the chain predicts the encoder angle {ratio:.3g} times worse than "
            f"the roller alone (limit {CHAIN_CONSISTENCY:g}: its shaft, rotor or drive do not "
            f"fit this recording); {numbers}"
        )
        return dataclasses.replace(alone, choice=why)
    return dataclasses.replace(chained, choice=chain_reason(chained, numbers))


def chain_reason(chained: ContactEstimate, numbers: str = "") -> str:
    """Why the chain's estimate can be used, with what its drive noise says of the drive
    model (a noise far above :data:`DEFAULT_DRIVE_NOISE`: the recording's drive is not the lag
    model and the chain leans on the torque sensor)."""
    tail = f"; {numbers}" if numbers else ""
    if chained.drive_noise is None:
        return f"chain{tail}"
    ratio = chained.drive_noise / DEFAULT_DRIVE_NOISE
    drive = (
        "the lag model of the drive holds"
        if ratio <= 100.0
        else f"{ratio:.3g} times the default: the recording's drive is not the lag model, "
        "the chain leans on the torque sensor"
    )
    return (
        f"chain (roller shaft and rotor, the drive's lag model linearised, its noise "
        f"{chained.drive_noise:.3g} N^2.m^2/s by maximum likelihood: {drive}){tail}"
    )


def _on_contact_load(estimate: ContactEstimate, air_spring_force, rig) -> ContactEstimate:
    """The estimate with its CoA on the contact's load N = S + W_d + κ F_x (the swinging arm,
    :class:`rollerrig.rig.sections.ArmParameters`) instead of the air-spring force S.

    The filters take the bearing loss at S: the arm's share κ F_x changes R05 by f_g r_b κ F_x
    (about 0.1 N.m at the dry peak on the default rig), well inside their noise.
    """
    import dataclasses

    force = estimate.contact_torque / rig.geometry.roller_radius_x
    load = rig.arm.contact_load(np.asarray(air_spring_force, dtype=float), force)
    return dataclasses.replace(estimate, coa=force / load)


def _recording_load(recording, rig):
    """The normal load of a recording: its ``normal_load``, else p·A_eff of the rig [N]."""
    from rollerrig.measure.quantities import normal_force_from_pressure

    if "normal_load" in recording:
        return recording["normal_load"]
    recording.require("air_spring_pressure")
    return normal_force_from_pressure(
        recording["air_spring_pressure"], rig.sensors.air_spring_effective_area
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
