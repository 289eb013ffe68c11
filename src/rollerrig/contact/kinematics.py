"""Creep and slip velocity of the wheel-roller pair from their angular speeds.

The seed's definitions (Kayaalp eqs. 4.21-4.22) divide by the roller's peripheral speed, which is
singular at standstill. Here the denominator is regularised as sqrt(v_r² + v_ε²): the creep is
smooth in both speeds, zero at standstill, finite when the wheel spins on a stopped roller, and
changes sign smoothly at slip reversal. For |v_r| ≫ v_ε it is w/|v_r|, the slip velocity
relative to the roller's speed magnitude: the seed's creep w/v_r when the roller runs forwards
(v_r > 0), and its negative when the roller runs backwards.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_in_range,
    require_positive,
)

__all__ = [
    "DEFAULT_REGULARISATION_SPEED",
    "MAX_PERIPHERAL_SPEED",
    "creep_and_slip_velocity",
    "creep_kernel",
    "kalker_creepage",
    "rig_creep",
]

DEFAULT_REGULARISATION_SPEED = 0.05
"""Speed v_ε below which the creep definition is regularised [m/s] (0.18 km/h).

Far below the rig's test speeds (5-60 km/h = 1.4-16.7 m/s): the relative change of the creep at
5 km/h is (v_ε/v)²/2 ≈ 6e-4.
"""

MAX_PERIPHERAL_SPEED = 3e8
"""Largest peripheral speed |ω·r| (and regularisation speed) :func:`creep_and_slip_velocity`
takes [m/s]: about the speed of light, so no physical wheel or roller comes near it.

The kernel squares the roller's peripheral speed; beyond about 1.3e154 m/s the square overflows
and the creep came out as 0 (or -0.0) without an error. Refusing speeds above this bound keeps
every intermediate (squares below 1e17) far inside the range of doubles.
"""


def _creep_kernel(wheel_speed, roller_speed, wheel_radius, roller_radius, regularisation_speed):
    """(creep [-], slip velocity [m/s]); see :func:`creep_and_slip_velocity`."""
    v_wheel = wheel_speed * wheel_radius
    v_roller = roller_speed * roller_radius
    slip_velocity = v_wheel - v_roller
    creep = slip_velocity / np.sqrt(
        v_roller * v_roller + regularisation_speed * regularisation_speed
    )
    return creep, slip_velocity


def creep_and_slip_velocity(
    wheel_speed,
    roller_speed,
    wheel_radius,
    roller_radius,
    regularisation_speed=DEFAULT_REGULARISATION_SPEED,
):
    """Longitudinal creep and slip velocity, regularised at standstill.

    .. math::
        w = \\omega_w r_w - \\omega_r r_r, \\qquad
        s = \\frac{w}{\\sqrt{(\\omega_r r_r)^2 + v_\\varepsilon^2}}

    For |ω_r r_r| ≫ v_ε this is s = w/|ω_r r_r|: the slip velocity relative to the magnitude
    of the roller's peripheral speed, with the sign of w. With the roller running forwards
    (ω_r r_r > 0) it is Kayaalp's s = w/(ω_r r_r) (eqs. 4.21-4.22); with both running
    backwards (ω_r r_r < 0) the two differ in sign: a wheel 1 % faster backwards gives
    w < 0 and s = -0.01 here, +0.01 by Kayaalp's definition.

    Parameters
    ----------
    wheel_speed, roller_speed : array_like
        Angular speeds ω_w, ω_r [rad/s], each positive in its own rolling direction.
    wheel_radius, roller_radius : array_like
        Rolling radii r_w, r_r [m].
    regularisation_speed : float, optional
        v_ε [m/s], > 0.

    Returns
    -------
    creep : numpy.ndarray
        s [-], with the sign of w: positive when ω_w r_w > ω_r r_r (in traction when rolling
        forwards, in braking when rolling backwards).
    slip_velocity : numpy.ndarray
        w [m/s].

    Raises
    ------
    ParameterError
        If a speed is not finite, a radius or ``regularisation_speed`` is not > 0, a
        peripheral speed |ω·r| or ``regularisation_speed`` exceeds
        :data:`MAX_PERIPHERAL_SPEED` (3e8 m/s, about the speed of light), or array arguments
        have shapes that do not broadcast together (naming them).

    Examples
    --------
    Wheel 1 % faster than the roller at 30 km/h:

    >>> v = 30 / 3.6
    >>> s, w = creep_and_slip_velocity(1.01 * v / 0.348, v / 0.452, 0.348, 0.452)
    >>> round(float(s), 5), round(float(w), 4)
    (0.01, 0.0833)

    Standstill gives zero creep, not NaN:

    >>> creep_and_slip_velocity(0.0, 0.0, 0.348, 0.452)[0].item()
    0.0
    """
    ww = require_finite("wheel_speed", wheel_speed, "rad/s")
    wr = require_finite("roller_speed", roller_speed, "rad/s")
    rw = require_positive("wheel_radius", wheel_radius, "m")
    rr = require_positive("roller_radius", roller_radius, "m")
    ve = require_positive("regularisation_speed", regularisation_speed, "m/s")
    if ww.ndim or wr.ndim or rw.ndim or rr.ndim or ve.ndim:  # single numbers always broadcast
        require_broadcastable(
            wheel_speed=ww,
            roller_speed=wr,
            wheel_radius=rw,
            roller_radius=rr,
            regularisation_speed=ve,
        )
    limit = MAX_PERIPHERAL_SPEED
    with np.errstate(over="ignore"):  # an overflow is reported as not finite
        v_wheel, v_roller = ww * rw, wr * rr
    for name, v in (
        ("wheel_speed * wheel_radius (the wheel's peripheral speed)", v_wheel),
        ("roller_speed * roller_radius (the roller's peripheral speed)", v_roller),
        ("regularisation_speed", ve),
    ):
        # A plain comparison first (this runs in loops); require_in_range words the error.
        if not (abs(float(v)) <= limit if v.ndim == 0 else bool(np.all(np.abs(v) <= limit))):
            speed = name != "regularisation_speed"  # signed; v_eps is > 0 (checked above)
            low = -limit if speed else 0.0
            require_in_range(name, v, low, limit, "m/s", low_inclusive=speed, high_inclusive=True)
    return _creep_kernel(ww, wr, rw, rr, ve)


# Public name of the compiled kernel, for the twin's right-hand side and the measurement.
creep_kernel = _creep_kernel


def kalker_creepage(creep):
    """Kalker's creepage ξ (mean rolling speed) from the rig's creep s (roller speed).

    .. math:: \\xi = \\frac{w}{(v_w + v_r)/2} = \\frac{2s}{2+s}, \\quad s = \\frac{w}{v_r}

    Parameters
    ----------
    creep : array_like
        s [-] (Kayaalp eq. 4.21), s > −2.

    Returns
    -------
    numpy.ndarray
        ξ [-].

    Examples
    --------
    >>> float(kalker_creepage(0.02))
    0.019801980198019802
    >>> float(rig_creep(kalker_creepage(0.02)))
    0.02
    """
    s = require_finite("creep", creep, "-")
    if np.any(s <= -2.0):
        raise ParameterError("creep s must be above -2 (the wheel would turn backwards)")
    return 2.0 * s / (2.0 + s)


def rig_creep(creepage):
    """The rig's creep s (roller speed, Kayaalp eq. 4.21) from Kalker's creepage ξ.

    .. math:: s = \\frac{2\\xi}{2-\\xi}

    Parameters
    ----------
    creepage : array_like
        ξ [-], |ξ| < 2.

    Returns
    -------
    numpy.ndarray
        s [-].

    Examples
    --------
    >>> round(float(rig_creep(0.1)), 6)
    0.105263
    """
    xi = require_finite("creepage", creepage, "-")
    if np.any(np.abs(xi) >= 2.0):
        raise ParameterError("Kalker's creepage must lie in (-2, 2)")
    return 2.0 * xi / (2.0 - xi)
