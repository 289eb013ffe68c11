"""Creep-force laws: Polach (2005) with slip-velocity-dependent friction; Kalker's linear theory.

Only longitudinal creep is modelled (the wheel-roller pair of the rig has no lateral creep or
spin by construction), as in the seed dissertation (Kayaalp, section 4.5.1.2).

The kernels (``_friction_kernel``, ``_polach_force_kernel``) use plain arithmetic and numpy
ufuncs so that the fast solver compiles the very same source with numba.

References
----------
.. [1] O. Polach, "Creep forces in simulations of traction vehicles running on adhesion limit",
   Wear 258 (2005) 992-1000.
.. [2] O. Polach, "A fast wheel-rail forces calculation computer code", Vehicle System Dynamics
   33 (suppl.) (1999) 728-739.
.. [3] J.J. Kalker, "Three-dimensional elastic bodies in rolling contact", Kluwer, 1990.
.. [4] B.T. Kayaalp, "Accuracy improvement of measurements by analyzing dynamic response of a
   tram wheel roller-rig", dissertation, University of Pardubice, eqs. 4.15-4.20.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
)

__all__ = [
    "POLACH_DRY",
    "POLACH_PARAMETER_SETS",
    "POLACH_WET",
    "PolachParameters",
    "adhesion_gradient",
    "adhesion_gradient_kernel",
    "friction_coefficient",
    "friction_kernel",
    "kalker_linear_force",
    "polach_creep_force",
    "polach_force_at_friction_kernel",
    "polach_force_kernel",
    "polach_shape_derivatives",
    "polach_shape_kernel",
]


@dataclass(frozen=True)
class PolachParameters:
    """Parameters of Polach's creep-force model with slip-velocity-dependent friction.

    Parameters
    ----------
    static_friction : float
        Maximum friction coefficient μ0 at zero slip velocity [-].
    limit_ratio : float
        A = μ∞ / μ0, ratio of the friction coefficient at infinite slip velocity to μ0 [-].
    friction_decay : float
        B, coefficient of the exponential friction decrease with slip velocity [s/m].
    k_adhesion : float
        k_A, reduction factor in the area of adhesion [-], 0 < k_A <= 1.
    k_slip : float
        k_S, reduction factor in the area of slip [-], 0 < k_S <= k_A.
    name, source : str
        Label and bibliographic source of the set.

    Raises
    ------
    ParameterError
        If a value is outside its physical range, naming the parameter.

    Examples
    --------
    >>> PolachParameters(0.5, 0.4, 0.6, 0.8, 0.3).k_slip
    0.3
    """

    static_friction: float
    limit_ratio: float
    friction_decay: float
    k_adhesion: float
    k_slip: float
    name: str = "custom"
    source: str = ""

    def __post_init__(self) -> None:
        require_positive("static_friction (mu0)", self.static_friction, "-")
        require_in_range("limit_ratio (A)", self.limit_ratio, 0.0, 1.0, "-", high_inclusive=True)
        require_nonnegative("friction_decay (B)", self.friction_decay, "s/m")
        require_in_range("k_adhesion (kA)", self.k_adhesion, 0.0, 1.0, "-", high_inclusive=True)
        require_in_range("k_slip (kS)", self.k_slip, 0.0, 1.0, "-", high_inclusive=True)
        if self.k_slip > self.k_adhesion:
            raise ParameterError(
                f"k_slip (kS) must not exceed k_adhesion (kA): Polach requires kS <= kA <= 1, "
                f"got kS = {self.k_slip:g} > kA = {self.k_adhesion:g}"
            )

    def as_tuple(self) -> tuple[float, float, float, float, float]:
        """(μ0, A, B, k_A, k_S) in the order the kernels take them."""
        return (
            self.static_friction,
            self.limit_ratio,
            self.friction_decay,
            self.k_adhesion,
            self.k_slip,
        )

    def to_dict(self) -> dict:
        """Plain dictionary, for provenance records."""
        return asdict(self)


POLACH_DRY = PolachParameters(
    static_friction=0.55,
    limit_ratio=0.40,
    friction_decay=0.60,
    k_adhesion=1.00,
    k_slip=0.40,
    name="dry",
    source="Polach (2005), Wear 258, Table 2: dry rail",
)
"""Polach (2005) parameter set for dry rail."""

POLACH_WET = PolachParameters(
    static_friction=0.30,
    limit_ratio=0.40,
    friction_decay=0.20,
    k_adhesion=0.30,
    k_slip=0.10,
    name="wet",
    source="Polach (2005), Wear 258, Table 2: wet rail",
)
"""Polach (2005) parameter set for wet rail."""

POLACH_PARAMETER_SETS: dict[str, PolachParameters] = {"dry": POLACH_DRY, "wet": POLACH_WET}
"""Named Polach parameter sets, by friction condition."""


# --------------------------------------------------------------------------------------------
# Kernels: no validation, plain arithmetic and ufuncs (compiled unchanged by numba).
# --------------------------------------------------------------------------------------------


def _friction_kernel(slip_velocity, mu0, limit_ratio, friction_decay):
    """μ = μ0 [(1 − A) exp(−B |w|) + A] (Kayaalp eq. 4.19; Polach 2005 eq. 8)."""
    return mu0 * (
        (1.0 - limit_ratio) * np.exp(-friction_decay * np.abs(slip_velocity)) + limit_ratio
    )


def _adhesion_gradient_kernel(creep, q_mu, creep_stiffness):
    """ε = ¼ π G a b c11 s / (Q μ) (Polach 2005, eq. 4); ``creep_stiffness`` = G a b c11 [N]."""
    return 0.25 * np.pi * creep_stiffness * creep / q_mu


def _polach_force_kernel(
    creep, slip_velocity, normal_load, creep_stiffness, mu0, limit_ratio, friction_decay, k_a, k_s
):
    """Polach longitudinal creep force [N] (Kayaalp eq. 4.20, with eq. 4.17 corrected).

    ``creep_stiffness`` is Kalker's linear creep coefficient G·a·b·c11 [N]; the gradient of the
    tangential stress is ε = (π/4)·G·a·b·c11·s/(Q·μ) = ¼ G π a b c11 s / (Q μ).
    Both terms are odd in ε, so the signed creep gives the signed force.
    """
    mu = _friction_kernel(slip_velocity, mu0, limit_ratio, friction_decay)
    return _polach_force_at_friction_kernel(creep, normal_load * mu, creep_stiffness, k_a, k_s)


def _polach_force_at_friction_kernel(creep, q_mu, creep_stiffness, k_a, k_s):
    """Polach's creep force [N] for a given Q·μ [N] (the twin has μ already: one exp less)."""
    eps = _adhesion_gradient_kernel(creep, q_mu, creep_stiffness)
    return (2.0 / np.pi) * q_mu * _polach_shape_kernel(eps, k_a, k_s)[0]


def _polach_shape_kernel(eps, k_a, k_s):
    """Polach's shape ``h(ε)`` [-] and its derivative ``h'(ε)`` [-]: F = (2/π) Q μ h(ε).

    h(ε) = k_A ε/(1 + (k_A ε)²) + arctan(k_S ε) (Polach 2005, eq. 7 with the reduction factors;
    Kayaalp eq. 4.20), h'(ε) = k_A (1 − (k_A ε)²)/(1 + (k_A ε)²)² + k_S/(1 + (k_S ε)²).
    """
    shape, slope, _ = _polach_shape_derivatives(eps, k_a, k_s)
    return shape, slope


def _polach_shape_derivatives(eps, k_a, k_s):
    """Polach's shape ``h(ε)``, ``h'(ε)`` and ``h''(ε)`` [-] (:func:`_polach_shape_kernel`).

    With a = k_A ε and b = k_S ε, h''(ε) = −2 k_A² a (3 − a²)/(1 + a²)³ − 2 k_S² b/(1 + b²)²,
    rational: the second derivative costs no transcendental function (the twin's arm loop
    takes Halley's steps with it). Compiled, the unused h'' of a caller that wants two is
    removed as dead code.
    """
    ka_eps = k_a * eps
    ks_eps = k_s * eps
    inv = 1.0 / (1.0 + ka_eps * ka_eps)
    inv_s = 1.0 / (1.0 + ks_eps * ks_eps)
    shape = ka_eps * inv + np.arctan(ks_eps)
    # (1 − a²)/(1 + a²)² written as (2/(1 + a²) − 1)/(1 + a²): no overflow of a² at large ε;
    # likewise (3 − a²)/(1 + a²) = 4/(1 + a²) − 1.
    slope = k_a * (2.0 * inv - 1.0) * inv + k_s * inv_s
    curvature = -2.0 * k_a * k_a * (ka_eps * inv) * inv * (4.0 * inv - 1.0)
    curvature = curvature - 2.0 * k_s * k_s * (ks_eps * inv_s) * inv_s
    return shape, slope, curvature


# --------------------------------------------------------------------------------------------
# Public, validated functions.
# --------------------------------------------------------------------------------------------


def _creep_stiffness(semi_axis_x, semi_axis_y, c11, shear_modulus, **validated):
    """Kalker's linear creep stiffness G a b c11 [N] from validated inputs.

    ``validated`` are the caller's other (already validated) arrays by their public names,
    listed before the contact's: all must broadcast together, else the error names them.
    """
    a = require_positive("semi_axis_x", semi_axis_x, "m")
    b = require_positive("semi_axis_y", semi_axis_y, "m")
    c = require_positive("c11", c11, "-")
    g = require_positive("shear_modulus", shear_modulus, "Pa")
    require_broadcastable(**validated, semi_axis_x=a, semi_axis_y=b, c11=c, shear_modulus=g)
    return g * a * b * c


def friction_coefficient(slip_velocity, parameters: PolachParameters = POLACH_DRY):
    """Slip-velocity-dependent friction coefficient.

    .. math:: \\mu = \\mu_0 \\left[(1 - A)\\, e^{-B |w|} + A\\right]

    Kayaalp eq. 4.19; Polach (2005) eq. 8.

    Parameters
    ----------
    slip_velocity : array_like
        Slip (creep) velocity w [m/s]; its sign is irrelevant.
    parameters : PolachParameters
        μ0 [-], A [-], B [s/m].

    Returns
    -------
    numpy.ndarray
        Friction coefficient μ [-], between A·μ0 and μ0.

    Examples
    --------
    >>> float(friction_coefficient(0.0))
    0.55
    """
    w = require_finite("slip_velocity", slip_velocity, "m/s")
    p = parameters
    return _friction_kernel(w, p.static_friction, p.limit_ratio, p.friction_decay)


def adhesion_gradient(creep, normal_load, friction, semi_axis_x, semi_axis_y, c11, shear_modulus):
    """Gradient of the tangential stress in the area of adhesion, ε (Polach's ε).

    .. math:: \\varepsilon = \\frac{1}{4}\\,\\frac{G \\pi a b c_{11}}{Q \\mu}\\, s

    Kayaalp eq. 4.17 prints the contact shear stiffness C where the shear modulus G belongs:
    with Polach's C = 3 G c11 / (8 a) (from Kalker's linear theory) eq. 4.16,
    ε = (2/3) C π a² b s / (Q μ), reduces to the expression above (Polach 2005, eq. 4).

    Parameters
    ----------
    creep : array_like
        Longitudinal creep s [-].
    normal_load : array_like
        Wheel load Q [N], > 0.
    friction : array_like
        Friction coefficient μ [-], > 0.
    semi_axis_x, semi_axis_y : array_like
        Contact ellipse semi-axes a (rolling direction) and b (lateral) [m].
    c11 : array_like
        Kalker's longitudinal creep coefficient [-].
    shear_modulus : array_like
        Combined shear modulus G [Pa].

    Returns
    -------
    numpy.ndarray
        ε [-].

    Examples
    --------
    >>> round(float(adhesion_gradient(1e-3, 1e4, 0.5, 5e-3, 4e-3, 4.0, 8.1e10)), 3)
    1.018
    """
    s = require_finite("creep", creep, "-")
    q = require_positive("normal_load", normal_load, "N")
    mu = require_positive("friction", friction, "-")
    stiffness = _creep_stiffness(
        semi_axis_x, semi_axis_y, c11, shear_modulus, creep=s, normal_load=q, friction=mu
    )
    return _adhesion_gradient_kernel(s, q * mu, stiffness)


def polach_creep_force(
    creep,
    slip_velocity,
    normal_load,
    semi_axis_x,
    semi_axis_y,
    c11,
    shear_modulus,
    parameters: PolachParameters = POLACH_DRY,
):
    """Longitudinal creep force by Polach's model with slip-velocity-dependent friction.

    .. math::
        F = \\frac{2 Q \\mu}{\\pi}\\left(\\frac{k_A \\varepsilon}{1 + (k_A \\varepsilon)^2}
            + \\arctan(k_S \\varepsilon)\\right), \\quad k_S \\le k_A \\le 1

    Kayaalp eq. 4.20 (Polach 2005, eq. 12), with ε from :func:`adhesion_gradient` and μ(w) from
    :func:`friction_coefficient`. For k_A = k_S = 1 and small creep it reduces to Kalker's
    linear theory F = G a b c11 s; for large creep it saturates at Q μ(w).

    Parameters
    ----------
    creep : array_like
        Longitudinal creep s [-]; positive in traction (wheel faster than roller).
    slip_velocity : array_like
        Slip velocity w [m/s] (only |w| enters the friction law).
    normal_load : array_like
        Wheel load Q [N].
    semi_axis_x, semi_axis_y : array_like
        Contact ellipse semi-axes a, b [m].
    c11 : array_like
        Kalker's coefficient C11 [-] at the contact's a/b and ν.
    shear_modulus : array_like
        Combined shear modulus G [Pa].
    parameters : PolachParameters
        μ0, A, B, k_A, k_S.

    Returns
    -------
    numpy.ndarray
        Creep force F [N], with the sign of the creep: on the wheel it opposes its rotation in
        traction, on the roller it drives it.

    Raises
    ------
    ParameterError
        If a value is outside its physical range, or array arguments have shapes that do not
        broadcast together (naming them).

    Examples
    --------
    Dry rail, 4.3 kN, 30 km/h, 1 % creep:

    >>> f = polach_creep_force(0.01, 0.01 * 8.33, 4300.0, 3.4e-3, 2.7e-3, 3.9, 8.08e10)
    >>> round(float(f / 4300.0), 3)
    0.484
    """
    s = require_finite("creep", creep, "-")
    w = require_finite("slip_velocity", slip_velocity, "m/s")
    q = require_positive("normal_load", normal_load, "N")
    stiffness = _creep_stiffness(
        semi_axis_x, semi_axis_y, c11, shear_modulus, creep=s, slip_velocity=w, normal_load=q
    )
    # Beyond |k_A ε| ≈ 1.3e154 (a creep of 1e151 in the example above) (k_A ε)² overflows to
    # inf and k_A ε/(1 + (k_A ε)²) is 0, as it should be (the force is μQ): harmless. Where ε
    # itself overflows (creep * G a b c11 beyond 1.8e308) the result is NaN, and numpy still
    # says so ("invalid value").
    with np.errstate(over="ignore"):
        return _polach_force_kernel(s, w, q, stiffness, *parameters.as_tuple())


def kalker_linear_force(creep, semi_axis_x, semi_axis_y, c11, shear_modulus):
    """Longitudinal creep force by Kalker's linear theory, unbounded by friction.

    .. math:: F_x = G\\, a\\, b\\, c_{11}\\, s

    Kalker (1990), linear theory; valid for small creep only (no saturation).

    Parameters
    ----------
    creep : array_like
        Longitudinal creep s [-].
    semi_axis_x, semi_axis_y : array_like
        Contact ellipse semi-axes a, b [m].
    c11 : array_like
        Kalker's coefficient C11 [-].
    shear_modulus : array_like
        Combined shear modulus G [Pa].

    Returns
    -------
    numpy.ndarray
        F_x [N].

    Examples
    --------
    >>> float(kalker_linear_force(1e-3, 5e-3, 4e-3, 4.0, 8e10))
    6400.0
    """
    s = require_finite("creep", creep, "-")
    return _creep_stiffness(semi_axis_x, semi_axis_y, c11, shear_modulus, creep=s) * s


# Public names of the compiled kernels, for the twin's right-hand side and the fits.
polach_force_kernel = _polach_force_kernel
polach_force_at_friction_kernel = _polach_force_at_friction_kernel
polach_shape_kernel = _polach_shape_kernel
polach_shape_derivatives = _polach_shape_derivatives
friction_kernel = _friction_kernel
adhesion_gradient_kernel = _adhesion_gradient_kernel
