"""Creep-adhesion curves for a given wheel-roller (or wheel-rail) geometry.

Chains the exact Hertz solution, Kalker's C11 at the contact's a/b and Polach's creep law, with
the slip velocity that goes with each creep at the given rolling speed (w = s·v). Used for the
roller-versus-tangent-rail comparison of the creep curve (the seed compares only contact areas,
section 2.5).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.contact.creep import POLACH_DRY, PolachParameters, _polach_force_kernel
from rollerrig.contact.hertz import HertzContact, combined_elastic_constants, hertz_contact
from rollerrig.contact.kalker import kalker_coefficients

__all__ = ["CreepCurve", "polach_creep_curve"]


def _require_creep_values(creep) -> np.ndarray:
    """The creep of a curve [-]: finite, and at least one value (a curve of none has no
    peak and nothing to plot; an empty array is most likely an empty selection upstream)."""
    s = require_finite("creep", creep, "-")
    if s.size == 0:
        raise ParameterError(
            f"creep must hold at least one value [-] to make a creep curve, got an empty array "
            f"(shape {s.shape})"
        )
    return s


@dataclass(frozen=True)
class CreepCurve:
    """A creep-adhesion curve and the contact it was computed for.

    Attributes
    ----------
    creep : ndarray
        Longitudinal creep s [-].
    slip_velocity : ndarray
        w = s·v [m/s].
    adhesion_coefficient : ndarray
        F/Q [-].
    contact : HertzContact
        Hertz solution at the normal load.
    c11 : float
        Kalker's C11 [-] at the contact's a/b and ν.
    creep_stiffness : float
        Kalker's linear slope G a b C11 [N].
    normal_load : float
        Q [N].
    rolling_speed : float
        v [m/s].
    parameters : PolachParameters
    """

    creep: np.ndarray
    slip_velocity: np.ndarray
    adhesion_coefficient: np.ndarray
    contact: HertzContact
    c11: float
    creep_stiffness: float
    normal_load: float
    rolling_speed: float
    parameters: PolachParameters

    @property
    def peak(self) -> tuple[float, float]:
        """(creep [-], adhesion coefficient [-]) at the maximum of the curve (the first, if
        several; over all elements whatever the creep array's shape)."""
        adhesion = np.ravel(self.adhesion_coefficient)
        k = int(np.argmax(adhesion))
        return float(np.ravel(self.creep)[k]), float(adhesion[k])


def polach_creep_curve(
    creep,
    normal_load,
    rolling_speed,
    wheel_radius_x,
    wheel_radius_y,
    roller_radius_x,
    roller_radius_y,
    parameters: PolachParameters = POLACH_DRY,
    youngs_modulus=210e9,
    poisson=0.3,
) -> CreepCurve:
    """Polach creep-adhesion curve of a wheel on a roller (or on a tangent rail).

    Parameters
    ----------
    creep : array_like
        Longitudinal creep s = w/v [-], w the slip velocity and v ``rolling_speed``: Polach's
        convention, not Kalker's ξ = 2s/(2 + s) (see
        :func:`~rollerrig.contact.laws.law_creep_curve`).
    normal_load : float
        Q [N].
    rolling_speed : float
        Rolling speed v [m/s] (roller peripheral speed, the reference of the creep).
    wheel_radius_x, wheel_radius_y : float
        Wheel rolling radius and transverse profile radius [m].
    roller_radius_x, roller_radius_y : float
        Roller radius (``np.inf`` for a tangent rail) and rail-head transverse radius [m].
    parameters : PolachParameters
        Friction condition.
    youngs_modulus : float
        E of both bodies [Pa].
    poisson : float
        ν of both bodies [-].

    Returns
    -------
    CreepCurve

    Raises
    ------
    ParameterError
        If ``creep`` is empty or not finite, or another value is outside its physical range
        (naming it).

    Examples
    --------
    The default rig (Kayaalp Table 4.5.1.5) at 10 kN and 30 km/h, dry:

    >>> c = polach_creep_curve(np.linspace(0, 0.05, 501), 10e3, 30 / 3.6,
    ...                        0.348, 0.291, 0.452, 1.890)
    >>> s_peak, mu_peak = c.peak
    >>> round(100 * s_peak, 1), round(mu_peak, 3)
    (3.5, 0.455)
    """
    s = _require_creep_values(creep)
    q = require_positive("normal_load", normal_load, "N", single=True)
    v = require_positive("rolling_speed", rolling_speed, "m/s", single=True)
    contact = hertz_contact(
        q,
        wheel_radius_x,
        wheel_radius_y,
        roller_radius_x,
        roller_radius_y,
        youngs_modulus=youngs_modulus,
        poisson=poisson,
    )
    elastic = combined_elastic_constants(youngs_modulus, poisson, youngs_modulus, poisson)
    c11 = float(kalker_coefficients(contact.a_over_b, float(elastic.poisson)).c11)
    stiffness = (
        float(elastic.shear_modulus) * float(contact.semi_axis_x) * float(contact.semi_axis_y) * c11
    )
    w = s * v
    force = _polach_force_kernel(s, w, q, stiffness, *parameters.as_tuple())
    return CreepCurve(
        creep=s,
        slip_velocity=w,
        adhesion_coefficient=force / q,
        contact=contact,
        c11=c11,
        creep_stiffness=stiffness,
        normal_load=q,
        rolling_speed=v,
        parameters=parameters,
    )
