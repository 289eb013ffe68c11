"""The flexibilities L1, L2, L3 of Kalker's simplified theory: Kalker's, and CONTACT's blend.

The simplified theory (:mod:`rollerrig.contact.fastsim`) replaces the elastic half-space by
independent springs, u = L·p, with one flexibility L1, L2, L3 for longitudinal, lateral and spin
creepage. Kalker's values (Kalker 1982, VSD 11, eq. 8; CONTACT ``simpflex``) make the theory
reproduce Kalker's linear theory at vanishing creepage; CONTACT blends them towards one
flexibility as the creepage grows (Vollebregt & Voltr 2023).

References
----------
.. [1] J.J. Kalker, "A fast algorithm for the simplified theory of rolling contact", Vehicle
   System Dynamics 11 (1982) 1-13.
.. [2] E.A.H. Vollebregt, P. Voltr, "Improved accuracy for FASTSIM using one or three
   flexibility values", Vehicle System Dynamics 61 (2023) 309-317 (CONTACT's blending).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._validation import (
    require_broadcastable,
    require_finite,
    require_in_range,
    require_positive,
)
from rollerrig.contact.kalker import kalker_coefficients

__all__ = ["Flexibilities", "blended_flexibilities", "kalker_flexibilities"]


@dataclass(frozen=True)
class Flexibilities:
    """Flexibilities of the simplified theory L1, L2, L3 [m³/N] (arrays broadcast over cases)."""

    l1: np.ndarray
    l2: np.ndarray
    l3: np.ndarray


def _kalker_flex(a, b, g, c11, c22, c23):
    c = np.sqrt(a * b)
    return (
        8.0 * a / (3.0 * g * c11),
        8.0 * a / (3.0 * g * c22),
        np.pi * a * a / (4.0 * g * c * c23),
    )


def kalker_flexibilities(semi_axis_x, semi_axis_y, shear_modulus, poisson) -> Flexibilities:
    """Kalker's three flexibilities of the simplified theory for a Hertzian ellipse.

    .. math:: L_1 = \\frac{8a}{3 G C_{11}}, \\quad L_2 = \\frac{8a}{3 G C_{22}}, \\quad
              L_3 = \\frac{\\pi a^2}{4 G c\\, C_{23}}, \\quad c = \\sqrt{ab}

    Kalker (1982), VSD 11, eq. (8); Kalker (1990) §3.2; CONTACT subroutine ``simpflex``
    (``flx(3) = π a √(a/b) / (4 C23 G)``, the same expression). They make the simplified theory
    reproduce Kalker's linear theory at vanishing creepage.

    Parameters
    ----------
    semi_axis_x, semi_axis_y : array_like
        Semi-axes a (rolling direction) and b [m].
    shear_modulus : array_like
        Combined shear modulus G [Pa].
    poisson : array_like
        Combined Poisson's ratio ν [-], in [0, 0.5].

    Returns
    -------
    Flexibilities
        L1, L2, L3 [m³/N].

    Examples
    --------
    >>> f = kalker_flexibilities(8e-3, 4e-3, 82e9, 0.28)
    >>> round(float(f.l1) * 1e14, 3)  # m³/N
    5.0
    """
    a = require_positive("semi_axis_x", semi_axis_x, "m")
    b = require_positive("semi_axis_y", semi_axis_y, "m")
    g = require_positive("shear_modulus", shear_modulus, "Pa")
    nu = require_in_range(
        "poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True
    )
    # numpy's own "operands could not be broadcast together" named none of them
    a, b, g, nu = require_broadcastable(semi_axis_x=a, semi_axis_y=b, shear_modulus=g, poisson=nu)
    k = kalker_coefficients(a / b, nu)
    return Flexibilities(*(np.asarray(v) for v in _kalker_flex(a, b, g, k.c11, k.c22, k.c23)))


def _blend(a, b, g, nu, normal_load, friction, xi, eta, phi):
    """CONTACT's blending of L1, L2, L3 towards one flexibility at larger creepage."""
    k = kalker_coefficients(a / b, nu)
    l1, l2, l3 = _kalker_flex(a, b, g, k.c11, k.c22, k.c23)
    cc2 = a * b
    ch_xi = friction * normal_load / (cc2 * g * k.c11)
    ch_eta = friction * normal_load / (cc2 * g * k.c22)
    f3 = 8.0 * a / 3.0
    f4 = np.pi * a * a / 4.0
    spin = phi * f4 / f3
    numer = xi**2 + eta**2 + spin**2
    denom = xi**2 / l1 + eta**2 / l2 + spin**2 / l3
    l_cross = np.where(denom > 0.0, numer / np.where(denom > 0.0, denom, 1.0), l1)
    f_crp = np.maximum(1e-10, np.sqrt((xi**2 + eta**2) / (ch_xi**2 + ch_eta**2)))
    w = np.clip(f_crp / 3.0, 0.0, 1.0)
    return (
        (1.0 - w) * l1 + w * l_cross,
        (1.0 - w) * l2 + w * l_cross,
        (1.0 - w) * l3 + w * l_cross,
    )


def blended_flexibilities(
    semi_axis_x,
    semi_axis_y,
    shear_modulus,
    poisson,
    normal_load,
    friction,
    long_creep,
    lat_creep=0.0,
    spin=0.0,
) -> Flexibilities:
    """Kalker's flexibilities blended towards one flexibility as the creepage grows (CONTACT).

    CONTACT's FASTSIM (``M = 3``) blends, with weight w = min(1, f/3),
    f = √((ξ²+η²)/(ξ_c²+η_c²)), ξ_c = μN/(ab G C11), η_c = μN/(ab G C22), each L_i towards

    .. math:: L_\\times = \\frac{\\xi^2 + \\eta^2 + (\\varphi f_4/f_3)^2}
              {\\xi^2/L_1 + \\eta^2/L_2 + (\\varphi f_4/f_3)^2/L_3},
              \\quad f_3 = 8a/3,\\; f_4 = \\pi a^2/4

    (Vollebregt & Voltr 2023; CONTACT ``simpflex``). At small creepage they are Kalker's.

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
        μ [-] (CONTACT uses the static coefficient).
    long_creep, lat_creep : array_like
        ξ, η [-].
    spin : array_like
        φ [1/m].

    Returns
    -------
    Flexibilities
        Arrays over the cases [m³/N].

    Examples
    --------
    >>> f = blended_flexibilities(8e-3, 4e-3, 82e9, 0.28, 82e3, 0.3, 0.0, -6.25e-4, 0.625)
    >>> round(float(f.l1) * 1e14, 3)  # CONTACT fastsim.ref_out prints 0.4937E-04 mm^3/N
    4.937
    """
    a, b, g, nu, n, mu, xi, eta, phi = _checked_contact(
        semi_axis_x, semi_axis_y, shear_modulus, poisson, normal_load, friction,
        long_creep, lat_creep, spin,
    )  # fmt: skip
    return Flexibilities(*(np.asarray(v) for v in _blend(a, b, g, nu, n, mu, xi, eta, phi)))


def _checked_contact(
    semi_axis_x, semi_axis_y, shear_modulus, poisson, normal_load, friction, long_creep,
    lat_creep, spin,
):  # fmt: skip
    """The contact's inputs checked and in SI: a, b [m], G [Pa], ν [-], N [N] as floats; μ [-],
    ξ, η [-], φ [1/m] as arrays (one per case). Shared by the flexibilities and the modified
    FASTSIM's slope reduction."""
    a = require_positive("semi_axis_x", semi_axis_x, "m", single=True)
    b = require_positive("semi_axis_y", semi_axis_y, "m", single=True)
    g = require_positive("shear_modulus", shear_modulus, "Pa", single=True)
    nu = require_in_range(
        "poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True, single=True
    )
    n = require_positive("normal_load", normal_load, "N", single=True)
    mu = require_positive("friction", friction, "-")
    xi = require_finite("long_creep", long_creep, "-")
    eta = require_finite("lat_creep", lat_creep, "-")
    phi = require_finite("spin", spin, "1/m")
    # one case per element: shapes that do not broadcast named (numpy's error names none)
    mu, xi, eta, phi = require_broadcastable(friction=mu, long_creep=xi, lat_creep=eta, spin=phi)
    return a, b, g, nu, n, mu, xi, eta, phi
