"""The slope reduction k of the modified FASTSIM (Spiryagin, Polach & Cole 2013): L_eff = L/k.

The modified FASTSIM divides the flexibilities of the simplified theory by a factor that falls
with Polach's gradient of the tangential stress, so that the creep force's initial slope falls
with the creepage (CONTACT's ``K0_MF, ALFAMF, BETAMF``); :func:`rollerrig.contact.fastsim.fastsim`
applies it.

References
----------
.. [1] M. Spiryagin, O. Polach, C. Cole, "Creep force modelling for rail traction vehicles
   based on the Fastsim algorithm", Vehicle System Dynamics 51 (2013) 1765-1783.
.. [2] E.A.H. Vollebregt, *User guide for CONTACT*, Vtech CMCC (github.com/eve70a/CONTACT,
   Apache-2.0), subroutine ``fastsim_params``.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import (
    require_in_range,
    require_nonnegative,
)
from rollerrig.contact.flexibilities import _checked_contact
from rollerrig.contact.kalker import kalker_coefficients

__all__ = ["slope_reduction"]


def _total_creepage(xi, eta, phi, a):
    """Spiryagin's total creepage: ν_φ = η + φ a, unless |η + φ a| < |η| (CONTACT)."""
    nu_phi = eta + phi * a
    nu_phi = np.where(np.abs(nu_phi) < np.abs(eta), eta, nu_phi)
    return np.sqrt(xi**2 + nu_phi**2)


def _slope_reduction_kernel(a, b, g, c11, normal_load, friction, total_creep, k0, alpha_inf, beta):
    eps = g * np.pi * a * b * k0 * c11 * total_creep / (4.0 * friction * normal_load)
    return k0 * (alpha_inf + (1.0 - alpha_inf) / (1.0 + beta * eps))


def slope_reduction(
    semi_axis_x,
    semi_axis_y,
    shear_modulus,
    poisson,
    normal_load,
    friction,
    long_creep,
    lat_creep=0.0,
    spin=0.0,
    *,
    k0=1.0,
    alpha_inf=1.0,
    beta=0.0,
):
    """Slope reduction factor k of the modified FASTSIM (L_eff = L/k).

    .. math::
        k = k_0\\left(\\alpha_\\infty + \\frac{1-\\alpha_\\infty}{1+\\beta\\varepsilon}\\right),
        \\quad \\varepsilon = \\frac{G \\pi a b\\, k_0 C_{11}\\, \\nu_{tot}}{4 \\mu N},
        \\quad \\nu_{tot} = \\sqrt{\\xi^2 + \\nu_\\varphi^2},\\; \\nu_\\varphi = \\eta + \\varphi a

    Spiryagin, Polach & Cole (2013), eqs. (11)-(13); CONTACT user guide, eq. (k_modif_fs), and
    subroutine ``fastsim_params`` (which keeps ν_φ = η where |η + φa| < |η|). ε is Polach's
    gradient of the tangential stress (package: :func:`~rollerrig.contact.adhesion_gradient`)
    times k0.

    Parameters
    ----------
    semi_axis_x, semi_axis_y : float
        a, b [m].
    shear_modulus : float
        G [Pa].
    poisson : float
        ν [-].
    normal_load : float
        N [N].
    friction : array_like
        μ [-].
    long_creep, lat_creep : array_like
        ξ, η [-].
    spin : array_like
        φ [1/m].
    k0 : float
        Initial reduction factor, 0 < k0 <= 1.
    alpha_inf : float
        k_∞/k0, in [0, 1].
    beta : float
        Rate of the reduction's change, >= 0.

    Returns
    -------
    numpy.ndarray
        k [-], one per case.

    Examples
    --------
    >>> float(slope_reduction(6e-3, 12e-3, 82e9, 0.28, 1e5, 0.36, 0.0, k0=0.54,
    ...                       alpha_inf=0.02, beta=0.62))
    0.54
    """
    a, b, g, nu, n, mu, xi, eta, phi = _checked_contact(
        semi_axis_x, semi_axis_y, shear_modulus, poisson, normal_load, friction,
        long_creep, lat_creep, spin,
    )  # fmt: skip
    k0, alpha_inf, beta = _check_modification(k0, alpha_inf, beta)
    c11 = float(kalker_coefficients(a / b, nu).c11)
    total = _total_creepage(xi, eta, phi, a)
    return _slope_reduction_kernel(a, b, g, c11, n, mu, total, k0, alpha_inf, beta)


def _check_modification(k0, alpha_inf, beta):
    k0 = require_in_range("k0", k0, 0.0, 1.0, "-", high_inclusive=True, single=True)
    alpha_inf = require_in_range(
        "alpha_inf", alpha_inf, 0.0, 1.0, "-", low_inclusive=True, high_inclusive=True, single=True
    )
    beta = require_nonnegative("beta", beta, "-", single=True)
    return k0, alpha_inf, beta
