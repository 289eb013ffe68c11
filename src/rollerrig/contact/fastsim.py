"""Kalker's FASTSIM and the modified FASTSIM with falling initial slope, on a Hertzian ellipse.

The simplified theory (Kalker 1973, 1982) replaces the elastic half-space by independent springs:
the tangential surface displacement is u = L·p, with one flexibility L1, L2, L3 for
longitudinal, lateral and spin creepage. In steady rolling the displacement of a surface
particle grows, from the leading edge, with the rigid slip, and the traction is held within the
traction bound g = μ·p_n. FASTSIM integrates that along each strip y = const of the contact
ellipse (Kalker 1982, VSD 11, eqs. 12-16):

.. math::
    p_x \\leftarrow p_x + h\\,k\\left(\\frac{\\xi}{L_1} - \\frac{\\varphi y}{L_3}\\right), \\quad
    p_y \\leftarrow p_y + h\\,k\\left(\\frac{\\eta}{L_2} + \\frac{\\varphi x}{L_3}\\right), \\quad
    |p| \\le \\mu p_n,

with step h in the rolling direction and k = 1 (Kalker's FASTSIM) or the slope reduction of the
modified FASTSIM (Spiryagin, Polach & Cole 2013, as in CONTACT's user guide eq. for
``K0_MF, ALFAMF, BETAMF``):

.. math::
    k = k_0\\left(\\alpha_\\infty + \\frac{1-\\alpha_\\infty}{1+\\beta\\,\\varepsilon}\\right),
    \\quad \\varepsilon = \\frac{G\\,\\pi a b\\,k_0\\,C_{11}\\,\\nu_{tot}}{4\\,\\mu N}.

Flexibilities (Kalker 1982; CONTACT ``simpflex``): L1 = 8a/(3 G C11), L2 = 8a/(3 G C22),
L3 = π a²/(4 G c C23), c = √(ab); with them the initial slope of FASTSIM equals Kalker's
linear theory, F_x = G a b C11 ξ (the test suite checks it).

Sign convention (the package's): forces have the sign of the creepage, F_x ≈ +G a b C11 ξ at
small creepage; CONTACT reports the traction on body 1, with the opposite sign. Spin φ [1/m] is
positive as in Kalker/CONTACT: rigid slip w = (ξ - φ y, η + φ x), x along the rolling
direction, leading edge at +x. The total moment is M_z = ∫ (x p_y - y p_x) dA.

Two discretisations:

* ``"strips"`` (default): ``ny`` strips of equal width, each cut into ``nx`` equal elements
  between its own leading and trailing edge; the traction is evaluated at element centres
  (first step half an element), the spin term at the middle of each step. The adhesion part is
  integrated exactly in x, midpoint in y.
* ``"contact"``: CONTACT's grid, ``mx × my`` rectangular elements over the potential contact
  [-scale·a, scale·a] × [-scale·b, scale·b], an element inside where the parabolic (or
  elliptic) bound is positive, step dq = dx, spin at x + dq/6 (CONTACT ``set_tang_rhs``).
  Used to compare with CONTACT at equal discretisation.

References
----------
.. [1] J.J. Kalker, "A fast algorithm for the simplified theory of rolling contact", Vehicle
   System Dynamics 11 (1982) 1-13.
.. [2] J.J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer (1990).
.. [3] M. Spiryagin, O. Polach, C. Cole, "Creep force modelling for rail traction vehicles
   based on the Fastsim algorithm", Vehicle System Dynamics 51 (2013) 1765-1783.
.. [4] E.A.H. Vollebregt, P. Voltr, "Improved accuracy for FASTSIM using one or three
   flexibility values", Vehicle System Dynamics 61 (2023) 309-317 (CONTACT's blending).
.. [5] E.A.H. Vollebregt, *User guide for CONTACT*, Vtech CMCC, section "Flexibilities of the
   simplified theory" and example ``fastsim.inp`` (github.com/eve70a/CONTACT, Apache-2.0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
)
from rollerrig.contact.kalker import kalker_coefficients

__all__ = [
    "FastsimGrid",
    "Flexibilities",
    "TangentialResult",
    "TractionField",
    "blended_flexibilities",
    "fastsim",
    "fastsim_grid",
    "kalker_flexibilities",
    "slope_reduction",
]

_BOUNDS = ("parabolic", "elliptic")


@dataclass(frozen=True)
class Flexibilities:
    """Flexibilities of the simplified theory L1, L2, L3 [m³/N] (arrays broadcast over cases)."""

    l1: np.ndarray
    l2: np.ndarray
    l3: np.ndarray


@dataclass(frozen=True)
class FastsimGrid:
    """A discretisation of the unit ellipse (x/a, y/b), reusable for every a, b.

    All arrays are normalised: x by a, y by b, areas by a·b. Rows are strips y = const; columns
    are processed from the leading edge (+x) to the trailing edge.

    Attributes
    ----------
    kind : str
        ``"strips"`` or ``"contact"``.
    x : ndarray, shape (ny, nx)
        Element centres x/a.
    y : ndarray, shape (ny,)
        Strip centres y/b.
    step : ndarray, shape (ny, nx)
        Step h/a from the previous evaluation point to this one.
    x_spin : ndarray, shape (ny, nx)
        Where the spin's rigid slip is evaluated for this step, x/a.
    area : ndarray, shape (ny, nx)
        Element area / (a b).
    inside : ndarray of bool, shape (ny, nx)
        Element in the contact.
    shape : ndarray, shape (ny, nx)
        1 - x²/a² - y²/b², clipped at 0, at the element centres.
    width : ndarray, shape (ny, nx)
        Element length along x / a.
    """

    kind: str
    x: np.ndarray
    y: np.ndarray
    step: np.ndarray
    x_spin: np.ndarray
    area: np.ndarray
    inside: np.ndarray
    shape: np.ndarray
    width: np.ndarray
    extent: tuple[float, float] = field(default=(1.0, 1.0))

    @property
    def size(self) -> tuple[int, int]:
        """(ny, nx)."""
        return self.x.shape


@dataclass(frozen=True)
class TractionField:
    """Surface tractions of each case on the grid (for plots of adhesion and slip zones).

    Attributes
    ----------
    x, y : ndarray, shape (ny, nx)
        Element centres [m] (x along rolling, leading edge at +x).
    px, py : ndarray, shape (n_cases, ny, nx)
        Tangential tractions [Pa], with the package's sign (that of the creepage).
    bound : ndarray, shape (n_cases, ny, nx)
        Traction bound μ p_n [Pa].
    state : ndarray of int8, shape (n_cases, ny, nx)
        0 outside the contact, 1 adhesion, 2 slip.
    """

    x: np.ndarray
    y: np.ndarray
    px: np.ndarray
    py: np.ndarray
    bound: np.ndarray
    state: np.ndarray

    @property
    def slip_fraction(self) -> np.ndarray:
        """Fraction of the contact's elements in slip, per case [-]."""
        inside = self.state > 0
        return (self.state == 2).sum(axis=(1, 2)) / np.maximum(inside.sum(axis=(1, 2)), 1)


@dataclass(frozen=True)
class TangentialResult:
    """Total tangential forces of a creep law for one or more cases.

    Attributes
    ----------
    fx, fy : ndarray, shape (n_cases,)
        Creep forces [N] (sign of the creepage).
    mz : ndarray, shape (n_cases,)
        Spin moment ∫(x p_y - y p_x) dA [N m].
    friction : ndarray, shape (n_cases,)
        μ used in each case [-].
    k_eff : ndarray, shape (n_cases,)
        Slope reduction factor k (1 for Kalker's FASTSIM) [-].
    flexibilities : Flexibilities
        L1, L2, L3 [m³/N] used (before division by k).
    tractions : TractionField or None
        Only when asked for.
    """

    fx: np.ndarray
    fy: np.ndarray
    mz: np.ndarray
    friction: np.ndarray
    k_eff: np.ndarray
    flexibilities: Flexibilities
    tractions: TractionField | None = None


# --------------------------------------------------------------------------------------------
# Flexibilities
# --------------------------------------------------------------------------------------------


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
    a = float(require_positive("semi_axis_x", semi_axis_x, "m"))
    b = float(require_positive("semi_axis_y", semi_axis_y, "m"))
    g = float(require_positive("shear_modulus", shear_modulus, "Pa"))
    nu = float(
        require_in_range("poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True)
    )
    n = float(require_positive("normal_load", normal_load, "N"))
    mu = require_positive("friction", friction, "-")
    xi = require_finite("long_creep", long_creep, "-")
    eta = require_finite("lat_creep", lat_creep, "-")
    phi = require_finite("spin", spin, "1/m")
    return Flexibilities(*(np.asarray(v) for v in _blend(a, b, g, nu, n, mu, xi, eta, phi)))


# --------------------------------------------------------------------------------------------
# Slope reduction of the modified FASTSIM
# --------------------------------------------------------------------------------------------


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
    a = float(require_positive("semi_axis_x", semi_axis_x, "m"))
    b = float(require_positive("semi_axis_y", semi_axis_y, "m"))
    g = float(require_positive("shear_modulus", shear_modulus, "Pa"))
    nu = float(
        require_in_range("poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True)
    )
    n = float(require_positive("normal_load", normal_load, "N"))
    mu = require_positive("friction", friction, "-")
    xi = require_finite("long_creep", long_creep, "-")
    eta = require_finite("lat_creep", lat_creep, "-")
    phi = require_finite("spin", spin, "1/m")
    k0, alpha_inf, beta = _check_modification(k0, alpha_inf, beta)
    c11 = float(kalker_coefficients(a / b, nu).c11)
    total = _total_creepage(xi, eta, phi, a)
    return _slope_reduction_kernel(a, b, g, c11, n, mu, total, k0, alpha_inf, beta)


def _check_modification(k0, alpha_inf, beta):
    k0 = float(require_in_range("k0", k0, 0.0, 1.0, "-", high_inclusive=True))
    alpha_inf = float(
        require_in_range(
            "alpha_inf", alpha_inf, 0.0, 1.0, "-", low_inclusive=True, high_inclusive=True
        )
    )
    beta = float(require_nonnegative("beta", beta, "-"))
    return k0, alpha_inf, beta


# --------------------------------------------------------------------------------------------
# Grids
# --------------------------------------------------------------------------------------------


def fastsim_grid(
    nx: int = 30, ny: int = 30, kind: str = "strips", scale: float = 1.1
) -> FastsimGrid:
    """A FASTSIM discretisation of the unit ellipse.

    Parameters
    ----------
    nx, ny : int
        Elements per strip (``"strips"``) or grid columns (``"contact"``: CONTACT's MX), and
        strips (MY).
    kind : {"strips", "contact"}
        Kalker-type strips (each strip cut into ``nx`` equal elements, default), or CONTACT's
        rectangular potential-contact grid (for comparison at equal discretisation).
    scale : float
        Potential contact half-size / semi-axis for ``"contact"`` (CONTACT's SCALE) [-].

    Returns
    -------
    FastsimGrid

    Examples
    --------
    >>> fastsim_grid(20, 10).size
    (10, 20)
    """
    nx = int(require_positive("nx", nx, "-"))
    ny = int(require_positive("ny", ny, "-"))
    if kind == "strips":
        y = -1.0 + (np.arange(ny) + 0.5) * 2.0 / ny
        half = np.sqrt(1.0 - y * y)  # strip half-length / a
        h = 2.0 * half / nx
        i = np.arange(nx)
        x = half[:, None] - (i[None, :] + 0.5) * h[:, None]
        step = np.broadcast_to(h[:, None], (ny, nx)).copy()
        width = step.copy()
        step[:, 0] = 0.5 * h
        x_spin = x + 0.5 * step
        area = h[:, None] * (2.0 / ny) * np.ones((1, nx))
        inside = np.ones((ny, nx), dtype=bool)
        extent = (1.0, 1.0)
    elif kind == "contact":
        s = float(require_positive("scale", scale, "-"))
        dx, dy = 2.0 * s / nx, 2.0 * s / ny
        xc = -s + (np.arange(nx) + 0.5) * dx
        y = -s + (np.arange(ny) + 0.5) * dy
        x = np.broadcast_to(xc[::-1][None, :], (ny, nx)).copy()  # leading edge (+x) first
        step = np.full((ny, nx), dx)
        width = step.copy()
        x_spin = x + dx / 6.0  # CONTACT set_tang_rhs: offset dq * facphi, facphi = 1/6
        area = np.full((ny, nx), dx * dy)
        inside = (1.0 - x * x - (y * y)[:, None]) > 0.0
        extent = (s, s)
    else:
        raise ParameterError(f"kind must be one of 'strips', 'contact', got {kind!r}")
    shape = np.maximum(0.0, 1.0 - x * x - (y * y)[:, None])
    return FastsimGrid(kind, x, y, step, x_spin, area, inside, shape, width, extent)


def _pressure_shape(grid: FastsimGrid, bound: str, a: float, b: float) -> np.ndarray:
    """Normal pressure per newton of load, p_n/N [1/m²], at the element centres."""
    if bound == "parabolic":
        return 2.0 / (np.pi * a * b) * grid.shape
    return 1.5 / (np.pi * a * b) * np.sqrt(grid.shape)


def _equivalent_ellipse(grid: FastsimGrid, inside: np.ndarray, a: float, b: float):
    """CONTACT's equivalent ellipse of a gridded contact (Kik-Piotrowski: area and a/b kept)."""
    area = float(np.sum(grid.area[inside])) * a * b
    cols = np.flatnonzero(inside.any(axis=0))
    rows = np.flatnonzero(inside.any(axis=1))
    length = float(grid.step[0, 0]) * a * (cols.max() - cols.min() + 1)
    width = (2.0 * grid.extent[1] / grid.size[0]) * b * (rows.max() - rows.min() + 1)
    r = np.sqrt(area / np.pi)
    return r * np.sqrt(length / width), r * np.sqrt(width / length)


# --------------------------------------------------------------------------------------------
# Kernel
# --------------------------------------------------------------------------------------------


def _fastsim_kernel(grid, a, b, xi, eta, phi, gain1, gain2, gain3, bound_per_n, mu_n, want_fields):
    """Integrate the simplified theory along every strip, for every case at once.

    ``gain_i`` = k/L_i [N/m³], shape (M, 1); ``mu_n`` = μN [N], shape (M, 1). Returns
    (fx, fy, mz) of shape (M,) and, when asked, the traction fields. Pure longitudinal cases
    (η = φ = 0 everywhere) take a one-component path (the bound is then a clip).
    """
    m = xi.shape[0]
    ny, nx = grid.size
    y = grid.y * b
    h = grid.step * a  # (ny, nx)
    hxs = h * grid.x_spin * a  # spin's rigid-slip lever times the step
    weight = grid.area * (a * b)  # (ny, nx)
    xw = grid.x * a * weight
    yw = y[:, None] * weight
    rate_x = gain1 * xi - gain3 * phi * y[None, :]  # (M, ny): d p_x / d(path)
    rate_y = gain2 * eta
    gphi = gain3 * phi
    px = np.zeros((m, ny))
    py = np.zeros((m, ny))
    fx = np.zeros(m)
    fy = np.zeros(m)
    mz = np.zeros(m)
    pure_x = not (np.any(eta) or np.any(phi))
    all_inside = bool(grid.inside.all())
    if want_fields:
        fpx = np.zeros((m, ny, nx))
        fpy = np.zeros((m, ny, nx))
        fst = np.zeros((m, ny, nx), dtype=np.int8)
    inc_x = inc_y = None
    for i in range(nx):
        if i < 2 or not np.array_equal(h[:, i], h[:, i - 1]):
            inc_x = rate_x * h[:, i]
            inc_y = rate_y * h[:, i]
        px += inc_x
        g = mu_n * bound_per_n[:, i]
        if pure_x:
            if not all_inside:
                px = np.where(grid.inside[:, i], px, 0.0)
            over = np.abs(px) > g
            np.clip(px, -g, g, out=px)
        else:
            py += inc_y
            py += gphi * hxs[:, i]
            if not all_inside:
                px = np.where(grid.inside[:, i], px, 0.0)
                py = np.where(grid.inside[:, i], py, 0.0)
            mag = np.hypot(px, py)
            over = mag > g
            if over.any():
                fac = np.where(over, g / np.where(over, mag, 1.0), 1.0)
                px *= fac
                py *= fac
            fy += py @ weight[:, i]
            mz += py @ xw[:, i]
        fx += px @ weight[:, i]
        mz -= px @ yw[:, i]
        if want_fields:
            fpx[:, :, i] = px
            fpy[:, :, i] = py
            fst[:, :, i] = np.where(grid.inside[:, i], np.where(over, 2, 1), 0)
    fields = (fpx, fpy, fst) if want_fields else None
    return fx, fy, mz, fields


def _cases(long_creep, lat_creep, spin, friction):
    xi = require_finite("long_creep", long_creep, "-")
    eta = require_finite("lat_creep", lat_creep, "-")
    phi = require_finite("spin", spin, "1/m")
    mu = require_positive("friction", friction, "-")
    xi, eta, phi, mu = np.broadcast_arrays(xi, eta, phi, mu)
    shape = xi.shape
    return shape, xi.ravel(), eta.ravel(), phi.ravel(), mu.ravel()


def fastsim(
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
    k0=1.0,
    alpha_inf=1.0,
    beta=0.0,
    flexibility: str = "kalker",
    bound: str = "parabolic",
    grid: FastsimGrid | None = None,
    flexibilities: Flexibilities | None = None,
    equivalent_ellipse: bool = False,
    tractions: bool = False,
) -> TangentialResult:
    """Creep forces by Kalker's FASTSIM, or by the modified FASTSIM with falling initial slope.

    Vectorised over cases: the creepages and μ broadcast to one array of cases; each case is
    solved on the same grid in one pass along the strips (Kalker 1982, eqs. 12-16, see the
    module docstring). With ``k0 = alpha_inf = 1`` (the defaults) this is Kalker's FASTSIM;
    otherwise the flexibilities are divided by Spiryagin's k (:func:`slope_reduction`).

    Parameters
    ----------
    long_creep, lat_creep : array_like
        Longitudinal and lateral creepage ξ, η [-].
    spin : array_like
        Spin creepage φ [1/m].
    semi_axis_x, semi_axis_y : float
        Hertzian semi-axes a (rolling direction) and b [m].
    normal_load : float
        N [N].
    shear_modulus : float
        Combined shear modulus G [Pa].
    poisson : float
        Combined Poisson's ratio ν [-].
    friction : array_like
        μ [-] per case (evaluate a slip-velocity law before, see
        :func:`rollerrig.contact.laws.creep_force`).
    k0, alpha_inf, beta : float
        Modified FASTSIM's slope reduction parameters (Spiryagin et al. 2013).
    flexibility : {"kalker", "blended"}
        Kalker's three flexibilities (original FASTSIM), or CONTACT's blend towards one
        (:func:`blended_flexibilities`).
    bound : {"parabolic", "elliptic"}
        Traction bound: Kalker's parabolic p_n = 2N/(πab)(1 - x²/a² - y²/b²) (original
        FASTSIM) or the Hertzian p_n = 3N/(2πab)√(…).
    grid : FastsimGrid, optional
        Default ``fastsim_grid(30, 30)``.
    flexibilities : Flexibilities, optional
        Given L1, L2, L3 [m³/N], overriding ``flexibility``.
    equivalent_ellipse : bool
        Evaluate k's C11 and ε on CONTACT's equivalent ellipse of the gridded contact (as
        CONTACT does) instead of the Hertzian a, b.
    tractions : bool
        Also return the traction distributions (adhesion and slip zones).

    Returns
    -------
    TangentialResult
        Forces [N] and moment [N m] of the cases, flattened in C order.

    Raises
    ------
    ParameterError
        For a non-physical input, naming it.

    Examples
    --------
    Initial slope = Kalker's linear theory G a b C11 (here C11 = 5.2037):

    >>> r = fastsim(1e-6, semi_axis_x=8e-3, semi_axis_y=4e-3, normal_load=82e3,
    ...             shear_modulus=82e9, poisson=0.28, friction=0.3)
    >>> round(float(r.fx[0]) / (82e9 * 8e-3 * 4e-3 * 1e-6), 1)
    5.2
    """
    a = float(require_positive("semi_axis_x", semi_axis_x, "m"))
    b = float(require_positive("semi_axis_y", semi_axis_y, "m"))
    n = float(require_positive("normal_load", normal_load, "N"))
    g = float(require_positive("shear_modulus", shear_modulus, "Pa"))
    nu = float(
        require_in_range("poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True)
    )
    k0, alpha_inf, beta = _check_modification(k0, alpha_inf, beta)
    if bound not in _BOUNDS:
        raise ParameterError(f"bound must be one of {_BOUNDS}, got {bound!r}")
    if flexibility not in ("kalker", "blended"):
        raise ParameterError(f"flexibility must be 'kalker' or 'blended', got {flexibility!r}")
    _, xi, eta, phi, mu = _cases(long_creep, lat_creep, spin, friction)
    grid = fastsim_grid() if grid is None else grid

    if flexibilities is not None:
        l1, l2, l3 = (
            np.broadcast_to(np.asarray(v, float), xi.shape)
            for v in (flexibilities.l1, flexibilities.l2, flexibilities.l3)
        )
    elif flexibility == "blended":
        l1, l2, l3 = _blend(a, b, g, nu, n, mu, xi, eta, phi)
    else:
        kc = kalker_coefficients(a / b, nu)
        l1, l2, l3 = (
            np.broadcast_to(v, xi.shape) for v in _kalker_flex(a, b, g, kc.c11, kc.c22, kc.c23)
        )

    pshape = _pressure_shape(grid, bound, a, b)
    if k0 == 1.0 and alpha_inf == 1.0:
        k = np.ones_like(xi)
    else:
        ae, be = (a, b)
        if equivalent_ellipse:
            ae, be = _equivalent_ellipse(grid, grid.inside & (pshape > 1e-20), a, b)
        c11 = float(kalker_coefficients(ae / be, nu).c11)
        total = _total_creepage(xi, eta, phi, ae)
        k = _slope_reduction_kernel(ae, be, g, c11, n, mu, total, k0, alpha_inf, beta)

    col = (slice(None), None)
    fx, fy, mz, fields = _fastsim_kernel(
        grid,
        a,
        b,
        xi[col],
        eta[col],
        phi[col],
        (k / l1)[col],
        (k / l2)[col],
        (k / l3)[col],
        pshape,
        (mu * n)[col],
        tractions,
    )
    field = None
    if fields is not None:
        field = TractionField(
            x=grid.x * a,
            y=np.broadcast_to((grid.y * b)[:, None], grid.size).copy(),
            px=fields[0],
            py=fields[1],
            bound=(mu * n)[:, None, None] * pshape[None],
            state=fields[2],
        )
    return TangentialResult(
        fx=fx,
        fy=fy,
        mz=mz,
        friction=mu,
        k_eff=np.asarray(k, float),
        flexibilities=Flexibilities(np.asarray(l1), np.asarray(l2), np.asarray(l3)),
        tractions=field,
    )
