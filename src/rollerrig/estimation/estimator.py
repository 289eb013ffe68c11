"""Model-based estimates of the contact torque F_x r_r from the torque sensor and the encoders.

This module gathers the estimators' public names and states their method and evidence; the
code is split by method: :mod:`~rollerrig.estimation.kalman` (the roller's model, the causal
filter, the online observer), :mod:`~rollerrig.estimation.smoother` (the RTS smoothers, the
chain model, the order lines, the drive noise by maximum likelihood),
:mod:`~rollerrig.estimation.smoother_weights` (the smoother as a linear filter),
:mod:`~rollerrig.estimation.choice` (on a recording, and which smoother to trust) and
:mod:`~rollerrig.estimation.performance` (errors against a truth).

The offline correction (:func:`rollerrig.measure.correction.corrected_adhesion`) takes the
roller's acceleration from a zero-phase Savitzky-Golay derivative: it needs samples on both sides
of each instant. This module estimates the same quantity causally, each output from the samples
up to its own instant, so that it can run online at the DAQ rate: a Kalman filter on the roller
(a disturbance observer for the contact torque, :func:`estimate_contact_torque`,
:class:`ContactObserver`); and offline, from all the samples, with a Rauch-Tung-Striebel
smoother on the roller or on the roller-shaft-rotor-drive chain (:func:`smooth_contact_torque`,
section "The smoother" below).

Model (the roller's equation of motion, Kayaalp eq. 4.5 with consistent signs)

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

=======================  ======  ======  ======  ======  ======  ======  ======  ======
random walk q [N².m²/s]  1e3     3.2e3   1e4     1.8e4   3.2e4   5.6e4   1e5     3.2e5
RMS error [-]            0.0149  0.0134  0.0123  0.0121  0.0120  0.0124  0.0132  0.0168
lag [ms]                 51      42      35      32      29      26      24      19
=======================  ======  ======  ======  ======  ======  ======  ======  ======

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

======================================  ========  =============  =================
CoA                                     lag [ms]  RMS error [-]  largest error [-]
======================================  ========  =============  =================
rig, T56/(r_r N)                        79.5      0.0383         0.28
offline correction (SG 0.2 s, order 4)  2.4       0.0088         0.11
this estimate, causal, default tuning   29.1      0.0162         0.29
======================================  ========  =============  =================

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

  ==============  =======  =======  =======
  q \\ σ_T [N.m]   0.7      1.0      1.5
  ==============  =======  =======  =======
  1e4             0.00134  0.00144  0.00161
  2e4             0.00132  0.00136  0.00149
  3e4             0.00135  0.00134  0.00144
  5e4             0.00146  0.00135  0.00140
  ==============  =======  =======  =======

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

=========================  ==============  ==============  ================
CoA                        seed-30kmh-dry  50 km/h         25 km/h, altered
=========================  ==============  ==============  ================
rig, T56/(r_r N)           0.0383 / 0.28   0.0407 / 0.25   0.0194 / 0.13
offline correction (SG)    0.0088 / 0.11   0.0079 / 0.10   0.0045 / 0.057
causal filter              0.0162 / 0.29   0.0148 / 0.24   0.0076 / 0.13
smoother, roller alone     0.0058 / 0.084  0.0053 / 0.081  0.0029 / 0.043
smoother, chain            0.0031 / 0.064  0.0033 / 0.060  0.0058 / 0.031
smoother, chain and lines  0.0021 / 0.048  0.0023 / 0.045  0.0057 / 0.022
... with the true k56, J6  0.0009 / 0.017
1/8 of the rig's error     0.0048          0.0051          0.0024
=========================  ==============  ==============  ================

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

from rollerrig.estimation.choice import (
    CHAIN_CONSISTENCY,
    chain_reason,
    choose_smoother,
    estimate_from_recording,
    smooth_from_recording,
)
from rollerrig.estimation.kalman import (
    DEFAULT_PROCESS_NOISE,
    DEFAULT_TORQUE_NOISE,
    INITIAL_ACCELERATION_SD,
    MODELS,
    ContactEstimate,
    ContactObserver,
    estimate_contact_torque,
)
from rollerrig.estimation.performance import estimator_performance
from rollerrig.estimation.smoother import (
    DEFAULT_CHAIN_NOISE,
    DEFAULT_CHAIN_TORQUE_NOISE,
    DEFAULT_DRIVE_NOISE,
    DEFAULT_SMOOTHER_NOISE,
    DRIVE_NOISE_RANGE,
    LINE_BLOCK,
    RollerChain,
    smooth_contact_torque,
)
from rollerrig.estimation.smoother_weights import SmootherWeights, smoother_weights

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
