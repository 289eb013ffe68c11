"""The estimate of the contact torque, as every estimator returns it: the causal Kalman filter
(:mod:`rollerrig.estimation.kalman`) and the smoothers (:mod:`rollerrig.estimation.smoother`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["ContactEstimate"]


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
        One of :data:`~rollerrig.estimation.estimator_parameters.MODELS`.
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
        Samples filtered with the time-varying gain before the steady-state gain [-].
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
