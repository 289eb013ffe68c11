"""Correct the adhesion the rig reports for the rig's own dynamics.

The torque sensor sits between the roller and its motor, so the rig's CoA = T56/(r_r N) misses
the torque that accelerates the roller and the roller's bearing loss. The roller's equation of
motion gives the contact force exactly (Kayaalp eq. 4.5 with consistent signs):

.. math:: F_x r_r = T_{56} + J_5 \\alpha_5 + R_{05}

with α5 the roller's angular acceleration (here the Savitzky-Golay derivative of the measured
roller speed) and R05 = f_g (W_r + N) r_b tanh(ω5/ω_reg) the bearing loss torque.

The rig divides by the air-spring force S it measures, but the wheel hangs on a swinging arm:
the load at the contact is N = S + W_d + κ F_x with κ = σ h/l
(:class:`rollerrig.rig.sections.ArmParameters`). The bearing loss grows with N, so F_x solves

.. math:: F_x (r_r - κ b) = T_{56} + J_5 \\alpha_5 + b (W_r + S + W_d),
          \\qquad b = f_g r_b \\tanh(\\omega_5/\\omega_{reg})

and the corrected CoA is F_x / N. With κ = 0 and W_d = 0 this is the correction above.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._validation import require_finite, require_nonnegative, require_positive
from rollerrig.signal.smoothing import savitzky_golay

__all__ = ["CorrectionTerms", "corrected_adhesion", "correction_terms"]


def corrected_adhesion(
    torque,
    roller_speed,
    normal_load,
    sample_rate: float,
    *,
    roller_radius: float,
    roller_inertia: float,
    bearing_friction: float,
    bearing_radius: float,
    roller_weight: float,
    regularisation_speed: float = 0.05,
    window: int = 51,
    order: int = 4,
    load_transfer: float = 0.0,
    dead_weight: float = 0.0,
):
    """Contact-force CoA from the torque sensor, corrected for roller inertia and bearing loss.

    .. math:: \\mu_{corr} = \\frac{T_{56} + J_5 \\alpha_5 + R_{05}}{r_r N}

    Parameters
    ----------
    torque : array_like
        Roller-shaft torque T56 [N.m] (smoothed or raw: it is smoothed with the same filter).
    roller_speed : array_like
        Roller angular speed ω5 [rad/s].
    normal_load : array_like
        The load the rig measures, the air-spring force S [N].
    sample_rate : float
        [Hz].
    roller_radius : float
        r_r [m].
    roller_inertia : float
        J5 [kg.m^2].
    bearing_friction : float
        f_g [-].
    bearing_radius : float
        Roller bearing friction radius r_b [m].
    roller_weight : float
        W_r [N].
    regularisation_speed : float
        ω_reg of the bearing model [rad/s].
    window, order : int
        Savitzky-Golay window [samples] and order for the torque, speed and acceleration.
    load_transfer : float
        κ = σ h/l of the swinging arm [-] (:attr:`ArmParameters.transfer_ratio
        <rollerrig.rig.sections.ArmParameters.transfer_ratio>`); 0: the contact carries S.
    dead_weight : float
        W_d, weight on the contact outside S [N].

    Returns
    -------
    coa_corrected : ndarray
        [-].
    acceleration : ndarray
        α5 [rad/s²].

    Examples
    --------
    A roller accelerating at 2 rad/s² with no shaft torque: the contact must supply J5·α5.

    >>> t = np.arange(500) / 250.0
    >>> coa, alpha = corrected_adhesion(np.zeros(500), 18.0 + 2.0 * t, np.full(500, 1e4), 250.0,
    ...     roller_radius=0.452, roller_inertia=45.0, bearing_friction=0.0, bearing_radius=0.065,
    ...     roller_weight=5000.0)
    >>> round(float(alpha[250]), 6), round(float(coa[250]), 6)
    (2.0, 0.019912)
    """
    terms = correction_terms(
        torque,
        roller_speed,
        normal_load,
        sample_rate,
        roller_radius=roller_radius,
        roller_inertia=roller_inertia,
        bearing_friction=bearing_friction,
        bearing_radius=bearing_radius,
        roller_weight=roller_weight,
        regularisation_speed=regularisation_speed,
        window=window,
        order=order,
        load_transfer=load_transfer,
        dead_weight=dead_weight,
    )
    return terms.coa, terms.acceleration


@dataclass(frozen=True)
class CorrectionTerms:
    """The terms of the dynamics correction, per sample (:func:`correction_terms`).

    Attributes
    ----------
    torque : ndarray
        T56 smoothed [N.m].
    roller_speed : ndarray
        ω5 smoothed [rad/s].
    acceleration : ndarray
        α5 [rad/s²].
    bearing_torque : ndarray
        R05 [N.m].
    normal_load : ndarray
        The air-spring force S [N] (as given, not smoothed).
    coa : ndarray
        μ_corr = F_x / N_c [-].
    window, order : int
        The Savitzky-Golay window [samples] and order used.
    contact_force : ndarray
        F_x = (T56 + J5 α5 + R05)/r_r [N].
    contact_load : ndarray
        N_c = S + W_d + κ F_x [N], the load at the contact.
    load_transfer, dead_weight : float
        κ [-] and W_d [N] of the swinging arm used.
    """

    torque: np.ndarray
    roller_speed: np.ndarray
    acceleration: np.ndarray
    bearing_torque: np.ndarray
    normal_load: np.ndarray
    coa: np.ndarray
    window: int
    order: int
    contact_force: np.ndarray | None = None
    contact_load: np.ndarray | None = None
    load_transfer: float = 0.0
    dead_weight: float = 0.0


def correction_terms(
    torque,
    roller_speed,
    normal_load,
    sample_rate: float,
    *,
    roller_radius: float,
    roller_inertia: float,
    bearing_friction: float,
    bearing_radius: float,
    roller_weight: float,
    regularisation_speed: float = 0.05,
    window: int = 51,
    order: int = 4,
    load_transfer: float = 0.0,
    dead_weight: float = 0.0,
) -> CorrectionTerms:
    """The smoothed torque and speed, α5, R05 and μ_corr of :func:`corrected_adhesion`.

    Same parameters as :func:`corrected_adhesion`; the terms are what the uncertainty of the
    corrected CoA (:mod:`rollerrig.estimation.uncertainty`) takes its sensitivities at.

    Returns
    -------
    CorrectionTerms

    Examples
    --------
    >>> t = np.arange(500) / 250.0
    >>> terms = correction_terms(np.full(500, 100.0), np.full(500, 20.0), np.full(500, 1e4),
    ...     250.0, roller_radius=0.5, roller_inertia=45.0, bearing_friction=0.007,
    ...     bearing_radius=0.065, roller_weight=5000.0)
    >>> round(float(terms.bearing_torque[0]), 6), round(float(terms.coa[0]), 6)
    (6.825, 0.021365)

    With a swinging arm that adds half the contact force to the load (κ = 0.5), the same
    torque is the same force on a larger load:

    >>> arm = correction_terms(np.full(500, 100.0), np.full(500, 20.0), np.full(500, 1e4),
    ...     250.0, roller_radius=0.5, roller_inertia=45.0, bearing_friction=0.007,
    ...     bearing_radius=0.065, roller_weight=5000.0, load_transfer=0.5)
    >>> round(float(arm.contact_load[0]), 3), round(float(arm.coa[0]), 6)
    (10106.874, 0.021149)
    """
    t56 = require_finite("torque", torque, "N.m")
    w = require_finite("roller_speed", roller_speed, "rad/s")
    n = require_positive("normal_load", normal_load, "N")
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    rr = require_positive("roller_radius", roller_radius, "m", single=True)
    j5 = require_positive("roller_inertia", roller_inertia, "kg.m^2", single=True)
    kappa = require_finite("load_transfer", load_transfer, "1", single=True)
    w_d = require_finite("dead_weight", dead_weight, "N", single=True)
    # A NaN here had made every CoA NaN, a negative weight or friction a CoA of the wrong sign.
    mu_b = require_nonnegative("bearing_friction", bearing_friction, "1", single=True)
    r_b = require_nonnegative("bearing_radius", bearing_radius, "m", single=True)
    w_r = require_nonnegative("roller_weight", roller_weight, "N", single=True)
    w_reg = require_positive("regularisation_speed", regularisation_speed, "rad/s", single=True)
    t56_s = savitzky_golay(t56, window, order)
    w_s = savitzky_golay(w, window, order)
    alpha = savitzky_golay(w, window, order, deriv=1, sample_rate=fs)
    b = mu_b * r_b * np.tanh(w_s / w_reg)
    n = np.broadcast_to(n, t56_s.shape)
    # F_x (r_r − κ b) = T56 + J5 α5 + b (W_r + S + W_d): the bearing loss at the contact's load.
    force = (t56_s + j5 * alpha + b * (w_r + n + w_d)) / (rr - kappa * b)
    contact_load = n + w_d + kappa * force
    bearing = b * (w_r + contact_load)
    coa = force / contact_load
    return CorrectionTerms(
        t56_s, w_s, alpha, bearing, n, coa, int(window), int(order),
        force, contact_load, kappa, w_d,
    )  # fmt: skip
