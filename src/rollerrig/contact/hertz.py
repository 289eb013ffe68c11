"""Exact Hertz theory for the elliptical contact of two convex bodies (wheel and roller or rail).

The contact ellipse is solved with complete elliptic integrals, not with the tabulated Hertz
coefficients m, n: the eccentricity follows from the curvature ratio by a vectorised, bracketed
Newton solve, then the semi-axes, the peak pressure and the mutual approach follow in closed
form.

Geometry and notation (Johnson 1985, §4.2): x is the rolling direction, y the lateral direction,
z the common normal. Both bodies are convex with aligned principal planes, so the gap between
them is ``h = A x² + B y²`` with

    A = ½ (1/R_wx + 1/R_rx),    B = ½ (1/R_wy + 1/R_ry).

A radius of ``np.inf`` is a flat direction (a tangent rail is flat longitudinally:
``roller_radius_x=np.inf``). The semi-axis ``a`` lies along x and ``b`` along y; the major axis
lies in the direction of the *smaller* relative curvature, so ``a > b`` when ``A < B``.

Domain of validity: Hertz treats each body as an elastic half-space and the gap as parabolic,
which needs the contact to be small against the radii of curvature, ``a ≪ R`` (Johnson 1985,
§4.1). :func:`hertz_contact` issues a :class:`~rollerrig._warnings.DomainWarning` when a
semi-axis exceeds :data:`HERTZ_DOMAIN_LIMIT` of the relative radius of curvature in its
direction, ``R'_x = 1/(2A)``, ``R'_y = 1/(2B)``, or of a body's own radius there where that is
smaller (with convex bodies R' is smaller than either radius; a concave body makes it larger).

References
----------
.. [1] H. Hertz, "Über die Berührung fester elastischer Körper", J. reine angew. Math. 92 (1882)
   156-171.
.. [2] K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985), §4.2,
   eqs. (4.39)-(4.41).
.. [3] NIST Digital Library of Mathematical Functions, §19.25(i), eq. 19.25.1 (complete
   elliptic integrals as Carlson symmetric integrals).
.. [4] J. J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer (1990),
   §1.6 (combined elastic constants of two dissimilar bodies).
"""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_in_range,
    require_number,
    require_positive,
)
from rollerrig._warnings import DomainWarning
from rollerrig.contact.elliptic import carlson_rd, complete_elliptic_integrals

__all__ = [
    "HERTZ_DOMAIN_LIMIT",
    "CombinedElasticConstants",
    "HertzContact",
    "combined_elastic_constants",
    "hertz_contact",
]

HERTZ_DOMAIN_LIMIT = 0.1
"""Largest semi-axis over the relative radius of curvature in its direction, a/R' [-], for
which :func:`hertz_contact` is taken to be valid.

Johnson (1985, §4.1) states the half-space condition as ``a ≪ R`` without a number. The errors
of the two approximations it rests on grow with a/R': the parabolic gap ``x²/(2R)`` differs from
the circle by ``(x/R)²/8`` relative at the contact edge, and the surface slope there, ``~a/R``,
is what the half-space solution neglects. At a/R' = 0.1 both stay at the per-cent level; beyond
it the result is an extrapolation. On the bundled rig (R'x = 197 mm) the limit is reached at
about 7 MN.
"""

#: Most iterations of the axis ratio's solve (:func:`_axis_ratio_kernel`): Newton's steps
#: converge in 3-7 from the start below (up to 15 for ratios between 1 + 1e-13 and 1 + 1e-5,
#: where ln ρ is tiny; in one call every element iterates until the slowest has converged); a
#: step that leaves the bracket is a bisection, and 64 halvings of the bracket, at most
#: (2/3)·ln(ρ) wide, reach the spacing of doubles.
_MAX_ITERATIONS = 64
#: Relative step of the forward difference that gives Newton's slope in ln g: its error
#: (about this) only slows the convergence, to a factor of about 1e-8 an iteration.
_SLOPE_STEP = 2.0**-26
#: Up to this many distinct curvature ratios in one call are solved one by one and remembered
#: (:func:`_axis_ratio_of`); more (a sweep over the geometry) are solved together.
_REMEMBERED_RATIOS = 8
_EPS = np.finfo(float).eps


# --------------------------------------------------------------------------------------------
# Kernels (plain numpy arithmetic, no validation)
# --------------------------------------------------------------------------------------------


def _curvature_ratio_of_axis_ratio(axis_ratio):
    """Curvature ratio ρ = B/A ≥ 1 of the ellipse with minor/major axis ratio g = b/a ≤ 1.

    Johnson (1985) eq. (4.39a,b) divided: ``B/A = [E/(1-e²) - K] / [K - E]`` with m = e² = 1 - g².
    Written with Carlson's integrals (DLMF 19.25.1: ``K - E = (m/3) R_D(0, g², 1)`` and
    ``E - g² K = (m g²/3) R_D(0, 1, g²)``) the common factor m cancels, which removes the
    cancellation of ``K - E`` near the circle:

        ρ(g) = R_D(0, 1, g²) / R_D(0, g², 1).
    """
    g2 = np.asarray(axis_ratio * axis_ratio, dtype=float)
    ones = np.ones_like(g2)
    # Both integrals in one call (the solve below evaluates this a few times).
    both = carlson_rd(0.0, np.stack([ones, g2]), np.stack([g2, ones]))
    return both[0] / both[1]


def _axis_ratio_kernel(curvature_ratio):
    """Minor/major semi-axis ratio g ∈ (0, 1] for a curvature ratio ρ = B/A ≥ 1 (vectorised).

    Solves ln ρ(g) = ln ``curvature_ratio`` in u = ln g by Newton's method, the slope by a
    forward difference (both points in one evaluation of Carlson's integrals), from Hamrock
    and Brewe's fit g ≈ ρ^(-0.636) (their κ = 1.0339 (R_y/R_x)^0.636 without the factor, which
    keeps ρ = 1 at g = 1). ρ(g) decreases monotonically from +∞ (g → 0) to 1 (g = 1), and
    g·ρ(g)^(2/3) ≥ 1 for all g, so the root lies in [-(2/3)·ln ρ, 0]; the bracket shrinks with
    each iterate's sign, and a step that would leave it is its midpoint instead. It stops when
    every element's step is within four ulps of max(1, |u|). ρ = 1 (the circle) returns g = 1
    exactly.

    A bisection of 64 steps did this before (until 2026-12-01): 10-20 times as many
    evaluations of the integrals (a new geometry through :func:`hertz_contact` 16-31 ms against
    3-4 ms, paired on this project's 2-core machine), and farther from the root: over 60 ratios
    from 1 to 1e12 at most 2.9e-15 relative against 1.4e-15 (medians 5.4e-16 and 3.5e-16),
    against mpmath's elliptic integrals at 40 digits.

    References: B. J. Hamrock, D. E. Brewe, "Simplified solution for stresses and deformations",
    J. Lubr. Technol. 105 (1983) 171-177 (the starting value).
    """
    log_target = np.log(curvature_ratio)
    lo = -(2.0 / 3.0) * log_target
    hi = np.zeros_like(lo)
    u = np.clip(-0.636 * log_target, lo, hi)
    with np.errstate(invalid="ignore", divide="ignore"):  # NaN ratios stay NaN, done at once
        for _ in range(_MAX_ITERATIONS):
            delta = _SLOPE_STEP * np.maximum(1.0, np.abs(u))
            both = np.log(_curvature_ratio_of_axis_ratio(np.exp(np.stack([u, u - delta]))))
            miss = both[0] - log_target  # > 0: g too small, the root lies above u
            lo = np.where(miss > 0.0, u, lo)
            hi = np.where(miss < 0.0, u, hi)
            new = u - miss * delta / (miss - (both[1] - log_target))
            new = np.where((new > lo) & (new < hi), new, 0.5 * (lo + hi))
            new = np.where(miss == 0.0, u, new)
            step = np.abs(new - u)
            u = new
            if not np.any(step > 4.0 * _EPS * np.maximum(1.0, np.abs(u))):
                break
    return np.exp(u)


@functools.lru_cache(maxsize=256)
def _axis_ratio_of(curvature_ratio: float) -> float:
    """:func:`_axis_ratio_kernel` of one curvature ratio, remembered: the ratio depends only on
    the geometry, which a study or a fit keeps while it varies the load or the rig's other
    parameters (the solve costs 1-3 ms, a thousand of the remembered look-ups)."""
    return float(_axis_ratio_kernel(np.array([curvature_ratio]))[0])


def _axis_ratio(curvature_ratio):
    """:func:`_axis_ratio_kernel` of an array of curvature ratios, each distinct ratio solved
    once (the loads of a contact broadcast the geometry's one ratio to their shape)."""
    distinct, where = np.unique(curvature_ratio, return_inverse=True)
    if distinct.size <= _REMEMBERED_RATIOS:
        solved = np.array([_axis_ratio_of(float(r)) for r in distinct])
    else:
        solved = _axis_ratio_kernel(distinct)
    return solved[where].reshape(np.shape(curvature_ratio))


def _hertz_kernel(normal_load, curvature_x, curvature_y, effective_modulus):
    """Exact Hertz ellipse for relative curvatures A (along x) and B (along y).

    Returns ``(a, b, p0, delta)``: semi-axis along x and along y [m], peak pressure [Pa] and
    mutual approach [m]. With g = b_minor/a_major, m = e² = 1 - g² and K, E the complete
    elliptic integrals of parameter m (Johnson 1985, eqs. 4.39-4.41):

        a_major³ = 3 Q E / (2π g² (A + B) E*)
        b_minor  = g a_major
        p0       = 3 Q / (2π a b)
        δ        = (A + B) b_minor² K / E
    """
    curvature_small = np.minimum(curvature_x, curvature_y)
    curvature_large = np.maximum(curvature_x, curvature_y)
    g = _axis_ratio(curvature_large / curvature_small)
    g2 = g * g
    # K(m) and E(m) with 1 - m = g² given as such: exact for slender ellipses
    elliptic_k, elliptic_e = complete_elliptic_integrals(g2)
    curvature_sum = curvature_x + curvature_y
    major = np.cbrt(
        3.0 * normal_load * elliptic_e / (2.0 * np.pi * g2 * curvature_sum * effective_modulus)
    )
    minor = g * major
    x_is_major = curvature_x <= curvature_y
    semi_axis_x = np.where(x_is_major, major, minor)
    semi_axis_y = np.where(x_is_major, minor, major)
    peak_pressure = 3.0 * normal_load / (2.0 * np.pi * major * minor)
    approach = curvature_sum * minor * minor * elliptic_k / elliptic_e
    return semi_axis_x, semi_axis_y, peak_pressure, approach


def _effective_modulus_kernel(youngs_modulus_1, poisson_1, youngs_modulus_2, poisson_2):
    """Effective modulus E* [Pa]: 1/E* = (1-ν1²)/E1 + (1-ν2²)/E2 (Johnson 1985, eq. 4.22)."""
    return 1.0 / (
        (1.0 - poisson_1 * poisson_1) / youngs_modulus_1
        + (1.0 - poisson_2 * poisson_2) / youngs_modulus_2
    )


# --------------------------------------------------------------------------------------------
# Public functions
# --------------------------------------------------------------------------------------------


class CombinedElasticConstants(NamedTuple):
    """Combined elastic constants of two bodies in contact.

    Attributes
    ----------
    effective_modulus : float or ndarray
        E* [Pa], with 1/E* = (1-ν1²)/E1 + (1-ν2²)/E2 (Johnson 1985, eq. 4.22).
    shear_modulus : float or ndarray
        Kalker's combined shear modulus G [Pa], with 2/G = 1/G1 + 1/G2 (Kalker 1990, §1.6).
    poisson : float or ndarray
        Kalker's combined Poisson ratio ν [-], with ν/G = ½(ν1/G1 + ν2/G2) (Kalker 1990, §1.6).
    """

    effective_modulus: float | np.ndarray
    shear_modulus: float | np.ndarray
    poisson: float | np.ndarray


def combined_elastic_constants(
    youngs_modulus_1, poisson_1, youngs_modulus_2, poisson_2
) -> CombinedElasticConstants:
    """Effective modulus E*, combined shear modulus G and combined Poisson ratio ν of two bodies.

    Parameters
    ----------
    youngs_modulus_1, youngs_modulus_2 : array_like
        Young's moduli E1, E2 of the two bodies [Pa], > 0.
    poisson_1, poisson_2 : array_like
        Poisson ratios ν1, ν2 of the two bodies [-], in [0, 0.5].

    Returns
    -------
    CombinedElasticConstants
        ``(effective_modulus, shear_modulus, poisson)``:
        1/E* = (1-ν1²)/E1 + (1-ν2²)/E2 (Johnson 1985, eq. 4.22);
        2/G = 1/G1 + 1/G2 and ν/G = ½(ν1/G1 + ν2/G2) with G_i = E_i / (2(1+ν_i))
        (Kalker 1990, §1.6). Identical bodies give E* = E/(2(1-ν²)), G = G1 and ν = ν1.

    Raises
    ------
    ParameterError
        If a modulus is not > 0 or a Poisson ratio is outside [0, 0.5].

    Examples
    --------
    >>> c = combined_elastic_constants(210e9, 0.3, 210e9, 0.3)
    >>> round(float(c.effective_modulus) / 1e9, 3), round(float(c.shear_modulus) / 1e9, 3)
    (115.385, 80.769)
    >>> round(float(c.poisson), 12)
    0.3
    """
    e1 = require_positive("youngs_modulus_1", youngs_modulus_1, "Pa")
    e2 = require_positive("youngs_modulus_2", youngs_modulus_2, "Pa")
    nu1 = require_in_range(
        "poisson_1", poisson_1, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True
    )
    nu2 = require_in_range(
        "poisson_2", poisson_2, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True
    )
    e_star = _effective_modulus_kernel(e1, nu1, e2, nu2)
    g1 = e1 / (2.0 * (1.0 + nu1))
    g2 = e2 / (2.0 * (1.0 + nu2))
    shear = 2.0 / (1.0 / g1 + 1.0 / g2)
    nu = shear * 0.5 * (nu1 / g1 + nu2 / g2)
    return CombinedElasticConstants(_out(e_star), _out(shear), _out(nu))


@dataclass(frozen=True)
class HertzContact:
    """Result of :func:`hertz_contact`; every field has the broadcast shape of the inputs.

    Attributes
    ----------
    semi_axis_x : float or ndarray
        Semi-axis a of the contact ellipse along the rolling direction x [m].
    semi_axis_y : float or ndarray
        Semi-axis b of the contact ellipse along the lateral direction y [m].
    area : float or ndarray
        Contact area π a b [m²].
    peak_pressure : float or ndarray
        Maximum contact pressure p0 = 3Q / (2π a b) [Pa].
    approach : float or ndarray
        Mutual approach δ of distant points of the two bodies [m].
    a_over_b : float or ndarray
        Ellipse axis ratio a/b [-] (> 1 when the ellipse is long in the rolling direction).
    """

    semi_axis_x: float | np.ndarray
    semi_axis_y: float | np.ndarray
    area: float | np.ndarray
    peak_pressure: float | np.ndarray
    approach: float | np.ndarray
    a_over_b: float | np.ndarray


def hertz_contact(
    normal_load,
    wheel_radius_x,
    wheel_radius_y,
    roller_radius_x,
    roller_radius_y,
    youngs_modulus=210e9,
    poisson=0.3,
    youngs_modulus_2=None,
    poisson_2=None,
) -> HertzContact:
    """Exact Hertz contact ellipse between a wheel and a roller (or rail), both convex.

    With A = ½(1/R_wx + 1/R_rx) and B = ½(1/R_wy + 1/R_ry), the axis ratio g = b_minor/a_major
    solves (Johnson 1985, eqs. 4.39a,b divided)

        max(A, B) / min(A, B) = [E(m)/(1-m) - K(m)] / [K(m) - E(m)],    m = e² = 1 - g²,

    found by a bracketed Newton solve in ln g (evaluated through Carlson's R_D, DLMF 19.25.1, so
    that it is exact also near the circle and for slender ellipses); then (Johnson 1985,
    eqs. 4.39-4.41)

        a_major³ = 3 Q E(m) / (2π g² (A + B) E*),    b_minor = g a_major,
        p0 = 3 Q / (2π a b),    δ = (A + B) b_minor² K(m) / E(m).

    The major axis lies along the direction of the smaller relative curvature. A = B gives the
    circle, a = b = (3 Q R / (4 E*))^(1/3) with 1/R = 2A. All arguments broadcast.

    Parameters
    ----------
    normal_load : array_like
        Normal load Q [N], > 0.
    wheel_radius_x : array_like
        Wheel rolling radius R_wx, in the rolling plane [m], > 0 (``np.inf`` allowed: flat;
        < 0 for a concave surface, the inside of a ring).
    wheel_radius_y : array_like
        Wheel transverse profile radius R_wy [m], > 0 convex, < 0 concave (a hollow-worn
        tread; the combined curvature must stay > 0), ``np.inf`` a cylindrical tread.
    roller_radius_x : array_like
        Roller radius R_rx in the rolling plane [m], > 0; ``np.inf`` for a tangent rail; < 0
        for the inside of a ring (a wheel running inside a drum).
    roller_radius_y : array_like
        Roller (or rail head) transverse profile radius R_ry [m], > 0 convex, < 0 concave,
        ``np.inf`` flat.
    youngs_modulus : array_like, optional
        Young's modulus E of the wheel [Pa], > 0. Default 210e9.
    poisson : array_like, optional
        Poisson ratio ν of the wheel [-], in [0, 0.5]. Default 0.3.
    youngs_modulus_2 : array_like, optional
        Young's modulus of the roller [Pa]; defaults to ``youngs_modulus``.
    poisson_2 : array_like, optional
        Poisson ratio of the roller [-]; defaults to ``poisson``.

    Returns
    -------
    HertzContact
        Semi-axes a (x) and b (y) [m], area [m²], peak pressure [Pa], approach [m], a/b [-].

    Raises
    ------
    ParameterError
        If an argument is True/False or text (numpy would read True as 1, "1e4" as 1e4), a
        load or modulus is not > 0, a radius is 0 or NaN, a Poisson ratio lies outside
        [0, 0.5], both radii of one direction are infinite (then the contact is a line or a
        plane, not an ellipse), a direction's combined curvature is not > 0 (a concave radius
        that the convex one does not exceed in curvature), or array arguments have shapes that
        do not broadcast together (naming them).

    Warns
    -----
    DomainWarning
        If a semi-axis exceeds :data:`HERTZ_DOMAIN_LIMIT` (0.1) of the relative radius of
        curvature in its direction (the half-space assumption, Johnson 1985, §4.1); the
        result is then returned as computed.

    References
    ----------
    Hertz (1882); Johnson, *Contact Mechanics* (1985), §4.2, eqs. (4.39)-(4.41);
    DLMF §19.25(i).

    Examples
    --------
    The seed's section 2.5 tangent-rail case (Kayaalp, §2.5): wheel 350 mm, lateral radii
    300/400 mm, 20 kN, E = 210 GPa, ν = 0.3.

    >>> c = hertz_contact(20e3, 0.35, 0.30, np.inf, 0.40)
    >>> round(float(c.semi_axis_x) * 1e3, 3), round(float(c.semi_axis_y) * 1e3, 3)
    (3.991, 2.482)
    >>> round(float(c.area) * 1e6, 2)
    31.12

    Two equal steel spheres of radius 10 mm under 100 N (circle, a = (3QR/(4E*))^(1/3), R = 5 mm):

    >>> s = hertz_contact(100.0, 0.01, 0.01, 0.01, 0.01)
    >>> bool(np.isclose(s.semi_axis_x, (3 * 100.0 * 0.005 / (4 * 210e9 / 1.82)) ** (1 / 3)))
    True
    """
    load = require_positive("normal_load", normal_load, "N")
    r_wx = _require_radius("wheel_radius_x", wheel_radius_x)
    r_wy = _require_radius("wheel_radius_y", wheel_radius_y)
    r_rx = _require_radius("roller_radius_x", roller_radius_x)
    r_ry = _require_radius("roller_radius_y", roller_radius_y)
    e1 = require_positive("youngs_modulus", youngs_modulus, "Pa")
    nu1 = require_in_range(
        "poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True
    )
    e2 = e1
    if youngs_modulus_2 is not None:
        e2 = require_positive("youngs_modulus_2", youngs_modulus_2, "Pa")
    nu2 = nu1
    if poisson_2 is not None:
        nu2 = require_in_range(
            "poisson_2", poisson_2, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True
        )
    # Broadcast under the names the caller gave (an omitted second body is the first's).
    named = dict(
        normal_load=load,
        wheel_radius_x=r_wx,
        wheel_radius_y=r_wy,
        roller_radius_x=r_rx,
        roller_radius_y=r_ry,
        youngs_modulus=e1,
        poisson=nu1,
    )
    if youngs_modulus_2 is not None:
        named["youngs_modulus_2"] = e2
    if poisson_2 is not None:
        named["poisson_2"] = nu2
    load, r_wx, r_wy, r_rx, r_ry, e1, nu1, *second = require_broadcastable(**named)
    e2 = second.pop(0) if youngs_modulus_2 is not None else e1
    nu2 = second.pop(0) if poisson_2 is not None else nu1

    if np.any(np.isinf(r_wx) & np.isinf(r_rx)):
        raise ParameterError(
            "wheel_radius_x and roller_radius_x must not both be infinite [m]: "
            "two flat directions make a line contact, not a Hertz ellipse"
        )
    if np.any(np.isinf(r_wy) & np.isinf(r_ry)):
        raise ParameterError(
            "wheel_radius_y and roller_radius_y must not both be infinite [m]: "
            "two flat directions make a line contact, not a Hertz ellipse"
        )

    curvature_x = 0.5 * (1.0 / r_wx + 1.0 / r_rx)
    curvature_y = 0.5 * (1.0 / r_wy + 1.0 / r_ry)
    for direction, curvature, names in (
        ("x", curvature_x, ("wheel_radius_x", "roller_radius_x")),
        ("y", curvature_y, ("wheel_radius_y", "roller_radius_y")),
    ):
        if np.any(curvature <= 0.0):
            k = np.unravel_index(int(np.argmin(curvature)), np.shape(curvature))
            raise ParameterError(
                f"{names[0]} and {names[1]} curve the bodies apart by no more than they curve "
                f"them together in {direction} (combined curvature {float(curvature[k]):.4g} "
                "1/m, must be > 0): a concave (negative) radius must exceed in size a convex "
                "one it meets (a flat one cannot hold it); conforming bodies make no Hertz "
                "ellipse"
            )
    e_star = _effective_modulus_kernel(e1, nu1, e2, nu2)
    a, b, p0, delta = _hertz_kernel(load, curvature_x, curvature_y, e_star)
    _warn_outside_half_space(
        load,
        a,
        b,
        _smallest_radius(curvature_x, r_wx, r_rx),
        _smallest_radius(curvature_y, r_wy, r_ry),
    )
    return HertzContact(
        semi_axis_x=_out(a),
        semi_axis_y=_out(b),
        area=_out(np.pi * a * b),
        peak_pressure=_out(p0),
        approach=_out(delta),
        a_over_b=_out(a / b),
    )


def _smallest_radius(curvature, r1, r2):
    """The radius [m] a semi-axis is held against in one direction: the relative radius
    R' = 1/(2 (1/R1 + 1/R2)/2), or a body's own radius where that is smaller (a concave body
    makes R' larger than either: the contact's size must stay small against both bodies,
    Johnson 1985, §4.1)."""
    return np.minimum(0.5 / curvature, np.minimum(np.abs(r1), np.abs(r2)))


def _warn_outside_half_space(load, a, b, radius_x, radius_y) -> None:
    """:class:`DomainWarning` naming the worst case where a/R_x or b/R_y > the limit, R the
    radius of :func:`_smallest_radius` in that direction."""
    ratio_x = a / radius_x
    ratio_y = b / radius_y
    ratio = np.maximum(ratio_x, ratio_y)
    outside = ratio > HERTZ_DOMAIN_LIMIT
    if not np.any(outside):
        return
    k = np.unravel_index(np.argmax(ratio), ratio.shape)
    if ratio_x[k] >= ratio_y[k]:
        axis, semi, rel, direction = "a", a[k], radius_x[k], "x"
    else:
        axis, semi, rel, direction = "b", b[k], radius_y[k], "y"
    where = "" if ratio.ndim == 0 else f" (worst of {int(np.sum(outside))} such cases)"
    warnings.warn(
        f"Hertz contact outside its domain: at normal load N = {float(load[k]):.4g} N the "
        f"semi-axis {axis} = {1e3 * float(semi):.4g} mm is {float(ratio[k]):.3g} of the radius "
        f"of curvature R{direction} = {1e3 * float(rel):.4g} mm{where} (the relative one, or a "
        f"body's own where smaller); the half-space assumption of Hertz theory needs "
        f"a/R <= {HERTZ_DOMAIN_LIMIT:g} "
        "(Johnson 1985, §4.1), so the contact size, pressure and approach are extrapolated",
        DomainWarning,
        stacklevel=3,
    )


def _require_radius(name: str, value) -> np.ndarray:
    """A radius of curvature [m]: > 0 convex, < 0 concave, ``np.inf`` allowed (flat); 0 and NaN
    rejected (the combined curvature is checked by the caller)."""
    arr = require_number(name, value, "m")
    bad = np.isnan(arr) | (arr == 0.0)
    if np.any(bad):
        shown = arr[bad].ravel()[:6]
        got = f"{float(shown[0]):g}" if arr.ndim == 0 else np.array2string(shown, precision=4)
        raise ParameterError(
            f"{name} must be a nonzero radius [m] (> 0 convex, < 0 concave, np.inf for a flat "
            f"direction), got {got}"
        )
    return arr


def _out(arr):
    """0-d arrays become numpy scalars; arrays are returned as they are."""
    arr = np.asarray(arr)
    return arr[()] if arr.ndim == 0 else arr
