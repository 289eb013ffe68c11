"""FaStrip: strip theory with FASTSIM's slip directions (Sichani, Enblom & Berg 2016).

Kalker's strip theory (1967) solves every strip y = const of the contact ellipse as a 2D Carter
problem: adhesion at the leading edge, slip at the trailing edge, and a slip zone whose length
2d is the same on every strip for pure creepage. It is exact for a/b → 0. FaStrip (Sichani et
al. 2016) replaces the strip theory's creepage constants by Kalker's C11, C22, C23, so that the
initial slope is that of the linear theory for any a/b, and takes the direction of the traction
in the slip zone from FASTSIM.

Non-dimensional creepages (Sichani et al. 2016, eqs. 14-16; CONTACT ``original_fastrip``),
with p0 = 3N/(2πab) (scaled so that the grid carries N exactly, see :func:`fastrip`), c = √(ab):

.. math::
    \\xi' = \\frac{4(1-\\nu) G C_{11}\\, \\xi}{2\\mu p_0 \\pi^2},\\quad
    \\eta' = \\frac{4(1-\\nu) G C_{22}\\, \\eta}{2\\mu p_0 \\pi^2},\\quad
    \\varphi' = \\frac{3 G c\\, C_{23}\\, \\varphi}{2\\mu p_0 \\pi}.

Half the slip-zone length on strip y (eq. 20):

.. math:: d(y) = \\frac{\\sqrt{\\eta'^2 + (1-\\varphi'^2)(\\xi' - \\varphi' y/a)^2}
          + \\eta'\\varphi'}{1-\\varphi'^2}\\;\\frac{a}{1-\\nu},

full sliding of the strip where d < 0, d ≥ a(y) or |φ'| ≥ 1 (CONTACT's "full sliding
correction", ``M = 7``). In the adhesion zone x > 2d - a(y) (eqs. 21-22):

.. math::
    p_x = \\frac{\\mu p_0}{a}\\kappa\\left(\\sqrt{a_y^2-x^2} - \\sqrt{(a_y-d)^2-(x-d)^2}\\right),
    \\quad
    p_y = \\frac{\\mu p_0}{a}\\left(\\lambda\\sqrt{a_y^2-x^2}
          - (\\lambda-\\varphi')\\sqrt{(a_y-d)^2-(x-d)^2}\\right),

κ, λ the direction cosines of (ξ' - φ'y/a, η' + φ'd/a). In the slip zone p = μ p_n (Hertzian
p_n) along the direction of FASTSIM's traction there (three flexibilities, parabolic bound; one
flexibility on strips whose leading element slips, as in CONTACT).

Signs as in :mod:`rollerrig.contact.fastsim` (forces with the sign of the creepage).

Modified FaStrip: the slope reduction of the modified FASTSIM (Spiryagin, Polach & Cole 2013;
:mod:`rollerrig.contact.slope_reduction`) applies here as there, the flexibilities divided by k:
FASTSIM's slip directions use L/k, and the strip theory's non-dimensional creepages ξ', η', φ'
(each proportional to the creep stiffness) are multiplied by k. With k0 = α∞ = 1 (the defaults)
this is FaStrip as published. It carries a measured reduction of the initial slope with the
strip theory's saturation shape, which follows Kalker's exact theory closer than FASTSIM's
(on the rig's roller and rail: 0.75 % against 2.5 % in the ratio of the two curves).

References
----------
.. [1] M. Sichani, R. Enblom, M. Berg, "An alternative to FASTSIM for tangential solution of
   the wheel-rail contact", Vehicle System Dynamics 54 (2016) 748-764.
.. [2] J.J. Kalker, *On the rolling contact of two elastic bodies in the presence of dry
   friction*, thesis, TH Delft (1967) (strip theory).
.. [3] E.A.H. Vollebregt, CONTACT, subroutine ``original_fastrip`` of ``m_solvpt.f90``
   (github.com/eve70a/CONTACT, Apache-2.0).
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import require_flag, require_in_range, require_positive
from rollerrig.contact.ellipse_grid import _checked_grid
from rollerrig.contact.fastsim import (
    FastsimGrid,
    Flexibilities,
    TangentialResult,
    TractionField,
    _cases,
    _fastsim_kernel,
    _kalker_flex,
    _pressure_shape,
)
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.slope_reduction import (
    _check_modification,
    _slope_reduction_kernel,
    _total_creepage,
)

__all__ = ["fastrip"]


def _arc_integral(centre, radius, lo, hi):
    """∫ √(r² - (x - c)²) dx over [lo, hi] ∩ [c - r, c + r] (0 where empty or r <= 0)."""
    r = np.maximum(radius, 0.0)
    u_lo = np.clip(lo - centre, -r, r)
    u_hi = np.clip(hi - centre, -r, r)

    def prim(u):
        # √(r² - u²) as √((r - u)(r + u)) and the angle as arctan2(u, √(r² - u²)): both terms
        # then round alike at an end u ≈ ±r, where each alone moves as √(r - |u|) and their
        # sum as (r - |u|)^1.5 (with r * r - u * u and arcsin(u/r) a strip's integral had
        # been off by 1e-8 where its last element's end rounded inside the ellipse).
        root = np.sqrt(np.maximum(0.0, (r - u) * (r + u)))
        return 0.5 * (u * root + r * r * np.arctan2(u, root))

    return np.where(hi > lo, np.maximum(0.0, prim(u_hi) - prim(u_lo)), 0.0)


def _carried_peak_pressure(grid: FastsimGrid, a: float, b: float, n: float) -> float:
    """Peak pressure p0 [Pa] of the Hertzian pressure that the grid's elements carry N with.

    The tractions are integrated exactly along each strip but summed over the strips by the
    midpoint rule (on CONTACT's grid over the elements whose centre lies in the ellipse), so
    Hertz's p0 = 3N/(2πab) put more than N into the grid: 1 + 5.6e-4 on the default 30 x 30
    strips, 1 + 5.0e-3 on 10 x 10, and a fully sliding contact carried as much more than μN
    (a review, 2026-12-03). As FASTSIM's pressures (``_pressure_shape`` of
    :mod:`rollerrig.contact.ellipse_grid`), p0 is scaled so that the elements carry N exactly.
    """
    a_y = a * np.sqrt(np.maximum(0.0, 1.0 - grid.y**2))[:, None]
    x = grid.x * a
    half = 0.5 * grid.width * a
    along = _arc_integral(0.0, a_y, x - half, x + half)  # ∫ √(a_y² - x²) dx per element [m²]
    strip_width = b * grid.area / grid.width  # [m]
    per_unit_p0 = np.sum(np.where(grid.inside, along * strip_width, 0.0)) / a  # N per Pa of p0
    return n / float(per_unit_p0)


def _longitudinal_on_strips(xi, mu, k, a, b, n, g, nu, c11, p0, grid, flex) -> TangentialResult:
    """FaStrip's forces for pure longitudinal creepage on a strip grid, strip by strip in
    closed form (the traction integrated over each strip's length).

    With η = φ = 0 the slip direction is that of ξ and Carter's traction on strip y integrates
    to (μ p0/a) sign(ξ) (π/2) (a_y² - max(0, a_y - d)²): the half-disc of the contact pressure
    less the adhesion zone's half-disc of radius a_y - d. The general path integrates the same
    tractions element by element (exactly in x) over elements that tile each strip, so both give
    the same forces (tested to 1e-8 of μN); this one skips the (cases x ny x nx) arrays, about 30x
    faster on the default grid.
    """
    xi_p = 4.0 * (1.0 - nu) * g * c11 * xi * k / (2.0 * mu * p0 * np.pi**2)
    d = np.abs(xi_p)[:, None] * a / (1.0 - nu)  # (M, 1)
    a_y = (a * np.sqrt(np.maximum(0.0, 1.0 - grid.y**2)))[None, :]  # (1, ny)
    per_strip = 0.5 * np.pi * (a_y**2 - np.maximum(0.0, a_y - d) ** 2)  # ∫ Carter dx / (μp0/a)
    strip_width = b * grid.area[:, 0] / grid.width[:, 0]  # 2b/ny
    fx = (mu * p0 / a) * np.sign(xi) * (per_strip @ strip_width)
    mz = -(mu * p0 / a) * np.sign(xi) * (per_strip @ (strip_width * grid.y * b))
    return TangentialResult(
        fx=fx,
        fy=np.zeros_like(fx),
        mz=mz,
        friction=mu,
        k_eff=np.asarray(k, dtype=float),
        flexibilities=Flexibilities(*(np.asarray(v) for v in flex)),
        tractions=None,
    )


def fastrip(
    long_creep,
    lat_creep=0.0,
    spin=0.0,
    *,
    semi_axis_x,
    semi_axis_y,
    normal_load,
    shear_modulus,
    poisson,
    friction,
    grid: FastsimGrid | None = None,
    tractions: bool = False,
    k0=1.0,
    alpha_inf=1.0,
    beta=0.0,
) -> TangentialResult:
    """Creep forces by FaStrip (Sichani, Enblom & Berg 2016) on a Hertzian ellipse.

    Parameters
    ----------
    long_creep, lat_creep : array_like
        ξ, η [-].
    spin : array_like
        φ [1/m].
    semi_axis_x, semi_axis_y : float
        a (rolling direction), b [m].
    normal_load : float
        N [N].
    shear_modulus : float
        G [Pa].
    poisson : float
        ν [-], in [0, 0.5).
    friction : array_like
        μ [-] per case.
    grid : FastsimGrid, optional
        Default ``fastsim_grid(30, 30)`` (strips).
    tractions : bool
        Also return the traction distributions.
    k0, alpha_inf, beta : float
        The modified FASTSIM's slope reduction parameters (Spiryagin et al. 2013), applied to
        the strip theory as the module docstring says; the defaults give FaStrip.

    Returns
    -------
    TangentialResult
        Forces [N], moment [N m]; ``k_eff`` the slope reduction k per case [-] (1 without).

    Raises
    ------
    ParameterError
        For a non-physical input, naming it, or for creepages and ``friction`` whose shapes do
        not broadcast together (naming them and their shapes).

    Notes
    -----
    The normal pressure is Hertz's, its p0 scaled so that the grid's elements carry N exactly
    (the tractions are integrated exactly along each strip, but the strips are summed by the
    midpoint rule): a fully sliding contact carries μN, and the initial slope is unchanged.

    Three conventions differ from CONTACT's FaStrip (``original_fastrip`` of ``m_solvpt.f90``,
    ``M = 7``; compared with a Python port of it):

    * The grid. CONTACT's rectangular grid puts a full step of traction on each strip's first
      element, the default strips grid half a step, and a strip whose leading element slips
      takes FASTSIM's slip directions with one flexibility. On the spin case of CONTACT's
      ``fastsim.inp`` (a = 8 mm, b = 4 mm, N = 82 kN, G = 82 GPa, ν = 0.28, μ = 0.3,
      η = -6.25e-4, φ = 0.625 1/m) the leading element slips on 93 % of CONTACT's strips and
      on 29 % of ours, and CONTACT gives F_y = 0.645-0.649 μN (120-220 elements a side)
      against our 0.678 μN (100 x 100 strips). On ``fastsim_grid(n, n, kind="contact")`` ours
      follows CONTACT's within 0.4 % at n = 220 (2 % at n = 44).
    * The traction bound of the slip directions. For a/b < 1 CONTACT raises FASTSIM's
      parabolic bound by the factor 1 + (1 - a/b)^4 (its "heuristic compensation of normal
      force"); it is left out here. On the same case with a/b = 0.5 (a = 6.304 mm,
      b = 12.61 mm) CONTACT gives F_y = 0.2583 μN and ours 0.2515 μN (120 x 120 contact
      grid); at the rig's a/b ≈ 0.85 the factor is 1.0005.
    * The friction coefficient. CONTACT's FaStrip (ξ', η', φ' and the bound) and its blending
      of FASTSIM's flexibilities take the static coefficient of its friction law; here
      ``friction`` is the case's, μ(w) of the slip velocity where
      :func:`~rollerrig.contact.laws.creep_force` passes it. With Coulomb friction the two
      agree.

    Examples
    --------
    Pure longitudinal creepage: the slope at zero is Kalker's G a b C11 (C11 = 5.2037 here):

    >>> r = fastrip(1e-6, semi_axis_x=8e-3, semi_axis_y=4e-3, normal_load=82e3,
    ...             shear_modulus=82e9, poisson=0.28, friction=0.3)
    >>> round(float(r.fx[0]) / (82e9 * 8e-3 * 4e-3 * 1e-6), 1)
    5.2

    With the slope reduction, the initial slope is k0 times that (k → k0 as ξ → 0):

    >>> m = fastrip(1e-6, semi_axis_x=8e-3, semi_axis_y=4e-3, normal_load=82e3,
    ...             shear_modulus=82e9, poisson=0.28, friction=0.3, k0=0.6, alpha_inf=0.1,
    ...             beta=0.3)
    >>> round(float(m.fx[0] / r.fx[0]), 4)
    0.6
    """
    a = require_positive("semi_axis_x", semi_axis_x, "m", single=True)
    b = require_positive("semi_axis_y", semi_axis_y, "m", single=True)
    n = require_positive("normal_load", normal_load, "N", single=True)
    g = require_positive("shear_modulus", shear_modulus, "Pa", single=True)
    nu = require_in_range("poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, single=True)
    k0, alpha_inf, beta = _check_modification(k0, alpha_inf, beta)
    _, xi, eta, phi, mu = _cases(long_creep, lat_creep, spin, friction)
    grid = _checked_grid(grid)
    tractions = require_flag("tractions", tractions)
    return _fastrip(xi, eta, phi, mu, a, b, n, g, nu, k0, alpha_inf, beta, grid, tractions)


# Creepages beyond about 1e154 overflow intermediates to inf (ξ'², the FASTSIM step, d): the
# contact then slides fully and the forces are right (μN along the creepage); an overflow that
# did matter ends as inf/inf or 0 * inf, which numpy still reports as "invalid".
@np.errstate(over="ignore")
def _fastrip(xi, eta, phi, mu, a, b, n, g, nu, k0, alpha_inf, beta, grid, tractions):
    """:func:`fastrip` of validated, flattened cases."""
    col = (slice(None), None)
    kc = kalker_coefficients(a / b, nu)
    l1, l2, l3 = _kalker_flex(a, b, g, kc.c11, kc.c22, kc.c23)
    if k0 == 1.0 and alpha_inf == 1.0:
        k = np.ones_like(xi)
    else:  # L_eff = L/k, as the modified FASTSIM (slope_reduction)
        total = _total_creepage(xi, eta, phi, a)
        k = _slope_reduction_kernel(a, b, g, kc.c11, n, mu, total, k0, alpha_inf, beta)
        l1, l2, l3 = (np.asarray(v, float) / k for v in (l1, l2, l3))
    # Hertz's p0 = 3N/(2πab), scaled so that the grid carries N exactly: full sliding gives μN.
    # The strip theory's creepages ξ', η', φ' take the same p0, so the initial slope (where
    # the tractions are proportional to p0 times ξ' ∝ 1/p0) does not depend on the scaling.
    p0 = _carried_peak_pressure(grid, a, b, n)
    c = np.sqrt(a * b)

    if not (tractions or np.any(eta) or np.any(phi)) and grid.kind == "strips":
        return _longitudinal_on_strips(xi, mu, k, a, b, n, g, nu, kc.c11, p0, grid, (l1, l2, l3))

    if not (np.any(eta) or np.any(phi)):
        # Pure longitudinal creepage: the slip direction is that of the creepage.
        ux = np.broadcast_to(np.sign(xi)[:, None, None], (xi.size, *grid.size))
        uy = np.zeros_like(ux)
    else:
        # Slip directions from FASTSIM: three flexibilities, and one (CONTACT original_fastrip).
        parab = _pressure_shape(grid, "parabolic", a, b)
        ones = np.ones_like(xi)
        mu_n = (mu * n)[col]
        _, _, _, f3 = _fastsim_kernel(
            grid,
            a,
            b,
            xi[col],
            eta[col],
            phi[col],
            (ones / l1)[col],
            (ones / l2)[col],
            (ones / l3)[col],
            parab,
            mu_n,
            True,
        )
        denom = np.sqrt(np.maximum(1e-20, xi**2 + eta**2 + a * b * phi**2))
        l_one = (np.abs(xi) * l1 + np.abs(eta) * l2 + c * np.abs(phi) * l3) / denom
        l_one = np.where(l_one > 0.0, l_one, l1)
        _, _, _, f1 = _fastsim_kernel(
            grid,
            a,
            b,
            xi[col],
            eta[col],
            phi[col],
            (1 / l_one)[col],
            (1 / l_one)[col],
            (1 / l_one)[col],
            parab,
            mu_n,
            True,
        )
        first = np.argmax(grid.inside, axis=1)  # leading interior element of each strip
        rows = np.arange(grid.size[0])
        lead_slips = (f3[2][:, rows, first] == 2)[:, :, None]  # (M, ny, 1)
        dir_x = np.where(lead_slips, f1[0], f3[0])
        dir_y = np.where(lead_slips, f1[1], f3[1])
        mag = np.hypot(dir_x, dir_y)
        safe = np.where(mag > 0.0, mag, 1.0)
        ux = np.where(mag > 0.0, dir_x / safe, np.sign(xi)[:, None, None])
        uy = np.where(mag > 0.0, dir_y / safe, 0.0)

    # Strip theory.
    scale = 2.0 * mu * p0 * np.pi**2 / k  # the creep stiffness times k (L/k)
    xi_p = 4.0 * (1.0 - nu) * g * kc.c11 * xi / scale
    eta_p = 4.0 * (1.0 - nu) * g * kc.c22 * eta / scale
    phi_p = 3.0 * g * c * kc.c23 * phi * k / (2.0 * mu * p0 * np.pi)
    y = grid.y * b  # (ny,)
    a_y = a * np.sqrt(np.maximum(0.0, 1.0 - (grid.y) ** 2))  # strip half-length
    xp, ep, fp = xi_p[col], eta_p[col], phi_p[col]
    lon = xp - fp * y[None, :] / a  # (M, ny)
    one_m = 1.0 - fp * fp
    sliding = np.abs(fp) >= 1.0 - 1e-6
    with np.errstate(invalid="ignore", divide="ignore"):
        d = (np.sqrt(ep * ep + one_m * lon * lon) + ep * fp) / np.where(sliding, 1.0, one_m)
    d = d * a / (1.0 - nu)
    d = np.where(sliding | ~np.isfinite(d) | (d < 0.0), 2.0 * a_y[None, :] + a, d)
    lat = ep + fp * d / a
    norm = np.sqrt(np.maximum(1e-40, lon * lon + lat * lat))
    kappa, lam = lon / norm, lat / norm
    lam_p = lam - fp

    # Element averages, integrated exactly in x (the Carter tractions have square-root edges
    # that a midpoint rule resolves poorly at small creepage): adhesion on [x_b, a_y], slip on
    # [-a_y, x_b], x_b = 2d - a_y.
    x = grid.x * a  # (ny, nx)
    half = 0.5 * grid.width * a
    lo, hi = (x - half)[None], (x + half)[None]
    ay = a_y[:, None][None]  # (1, ny, 1)
    dd = d[:, :, None]  # (M, ny, 1)
    x_b = np.minimum(2.0 * dd - ay, ay)
    a_lo = np.maximum(lo, x_b)
    cnt_adh = _arc_integral(0.0, ay, a_lo, hi)
    adh_adh = _arc_integral(dd, ay - dd, a_lo, hi)
    cnt_slip = _arc_integral(0.0, ay, lo, np.minimum(hi, x_b))
    width = (2.0 * half)[None]
    muc = (mu * p0 / a)[:, None, None]
    inside = grid.inside[None]
    px = muc * (kappa[:, :, None] * (cnt_adh - adh_adh) + ux * cnt_slip) / width
    py = muc * (lam[:, :, None] * cnt_adh - lam_p[:, :, None] * adh_adh + uy * cnt_slip) / width
    px = np.where(inside, px, 0.0)
    py = np.where(inside, py, 0.0)
    adhesion = inside & (x[None] > x_b)
    # The element averages of μ times the pressure that carries N: what a sliding element holds.
    hertz = np.where(inside, muc * _arc_integral(0.0, ay, lo, hi) / width, 0.0)

    w = grid.area * (a * b)
    fx = np.einsum("mjk,jk->m", px, w)
    fy = np.einsum("mjk,jk->m", py, w)
    mz = np.einsum("mjk,jk->m", py, x * w) - np.einsum("mjk,jk->m", px, y[:, None] * w)
    field = None
    if tractions:
        state = np.where(adhesion, 1, np.where(np.broadcast_to(inside, px.shape), 2, 0))
        field = TractionField(
            x=x,
            y=np.broadcast_to(y[:, None], grid.size).copy(),
            px=px,
            py=py,
            bound=hertz,
            state=state.astype(np.int8),
        )
    return TangentialResult(
        fx=fx,
        fy=fy,
        mz=mz,
        friction=mu,
        k_eff=np.asarray(k, dtype=float),
        flexibilities=Flexibilities(np.asarray(l1), np.asarray(l2), np.asarray(l3)),
        tractions=field,
    )
