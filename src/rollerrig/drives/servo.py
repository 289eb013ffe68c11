"""Speed-controlled servo (PMSM) roller drive: the improvement Kayaalp proposes.

Kayaalp concludes (chapter 5) that the open-loop V/f asynchronous motor's response delay causes
the oscillation seen after torque changes, and proposes replacing it by a servo motor or a
speed-controlled PMSM. This module models that drive as a PI speed controller with torque
saturation and anti-windup, followed by a torque actuator that is a first-order lag with time
constant ``torque_time_constant`` (integrate it with
:func:`rollerrig.drives.induction.lag_derivative`; the current loop of a PMSM closed with
:func:`rollerrig.drives.pmsm.pi_gains_for_bandwidth` is such a lag with τ = 1/ω_c).

Kernel (compiles under ``numba.njit``; the name is a contract with the coupled model):
:func:`servo_speed_torque`. Validated: :func:`servo_gains_for_bandwidth`. The drive's
parameters live in the rig parameter set, ``RigParameters.servo_roller_drive``.

References
----------
Kayaalp (dissertation, the seed), chapter 5 (proposed improvements, refs. [123, 124]).
K. J. Åström, T. Hägglund, *Advanced PID Control*, ISA, 2006, sections 3.5 (back-calculation
anti-windup) and 6 (PI design by pole placement).
G. Ellis, *Control System Design Guide*, 4th ed., Butterworth-Heinemann, 2012, ch. 6 (PI
velocity loop on a rigid inertia).
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig._validation import ParameterError, require_positive

__all__ = [
    "servo_gains_for_bandwidth",
    "servo_speed_torque",
]


def servo_speed_torque(omega, omega_ref, integral, kp, ki, torque_limit):
    r"""PI speed controller with torque saturation and back-calculation anti-windup.

    .. math::

        u = k_p e + k_i I, \quad e = \omega^* - \omega, \qquad
        T_{cmd} = \operatorname{clip}(u, -T_{lim}, T_{lim}), \qquad
        \frac{dI}{dt} = e + \frac{T_{cmd} - u}{k_p}.

    The back-calculation term (Åström & Hägglund 2006, sec. 3.5) uses the tracking time constant
    T_t = k_p/k_i, the integral time. Without saturation dI/dt = e; in saturation the integrator
    settles at k_i I = ±T_lim instead of winding up.

    Parameters
    ----------
    omega : float or array_like
        Measured speed ω [rad/s].
    omega_ref : float or array_like
        Speed reference ω* [rad/s].
    integral : float or array_like
        Integrator state I = ∫(ω* − ω) dt [rad].
    kp : float
        Proportional gain [N.m.s/rad], > 0.
    ki : float
        Integral gain [N.m/rad].
    torque_limit : float
        Torque limit T_lim > 0 [N.m].

    Returns
    -------
    torque_cmd : float or ndarray
        Torque command, motoring positive [N.m].
    dintegral_dt : float or ndarray
        Derivative of the integrator state [rad/s].

    Examples
    --------
    >>> t, di = servo_speed_torque(60.0, 61.0, 0.0, 500.0, 1e4, 5000.0)
    >>> float(t), float(di)
    (500.0, 1.0)
    """
    error = omega_ref - omega
    unsaturated = kp * error + ki * integral
    torque_cmd = np.minimum(np.maximum(unsaturated, -torque_limit), torque_limit)
    dintegral_dt = error + (torque_cmd - unsaturated) / kp
    return torque_cmd, dintegral_dt


def servo_gains_for_bandwidth(inertia, bandwidth, damping_ratio=1.0):
    r"""PI speed gains placing the closed-loop poles of a rigid inertia.

    With :math:`J\dot\omega = T` and :math:`T = k_p e + k_i\int e\,dt` the closed loop is

    .. math::

        \frac{\omega}{\omega^*} = \frac{k_p s + k_i}{J s^2 + k_p s + k_i}
        = \frac{2\zeta\omega_n s + \omega_n^2}{s^2 + 2\zeta\omega_n s + \omega_n^2}

    for :math:`k_p = 2\zeta\omega_n J`, :math:`k_i = \omega_n^2 J`. The zero at
    :math:`-\omega_n/(2\zeta)` adds overshoot to the pure second-order response (about 13.5 %
    at ζ = 1). A torque-actuator lag τ is neglected by this design; keep τ ω_n << 1.

    Parameters
    ----------
    inertia : float
        Total inertia driven by the servo J [kg.m^2].
    bandwidth : float
        Natural frequency ω_n [rad/s].
    damping_ratio : float, optional
        Damping ratio ζ [-].

    Returns
    -------
    kp : float
        Proportional gain [N.m.s/rad].
    ki : float
        Integral gain [N.m/rad].

    Examples
    --------
    >>> servo_gains_for_bandwidth(50.0, 10.0)
    (1000.0, 5000.0)
    """
    inertia = require_positive("inertia", inertia, "kg.m^2", single=True)
    bandwidth = require_positive("bandwidth", bandwidth, "rad/s", single=True)
    damping_ratio = require_positive("damping_ratio", damping_ratio, "-", single=True)
    # bandwidth * bandwidth, not bandwidth**2: a float power raises OverflowError past 1e308.
    kp, ki = 2.0 * damping_ratio * bandwidth * inertia, bandwidth * bandwidth * inertia
    if not (math.isfinite(kp) and math.isfinite(ki)):
        raise ParameterError(
            f"inertia = {inertia:g} kg.m^2 at bandwidth = {bandwidth:g} rad/s gives gains "
            "beyond the float range; check their units"
        )
    return kp, ki
