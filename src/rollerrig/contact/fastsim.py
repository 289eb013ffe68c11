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

The integration along the strips (:func:`fastsim`) is defined here; its parts in their own
modules: the flexibilities in :mod:`~rollerrig.contact.flexibilities`, the modified FASTSIM's
k in :mod:`~rollerrig.contact.slope_reduction`, the grids and the pressure on them in
:mod:`~rollerrig.contact.ellipse_grid`, the result types in
:mod:`~rollerrig.contact.tangential_result` (their public names are also importable from here).

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

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_flag,
    require_in_range,
    require_positive,
)
from rollerrig.contact.ellipse_grid import (
    _BOUNDS,
    FastsimGrid,
    _checked_grid,
    _equivalent_ellipse,
    _pressure_shape,
    fastsim_grid,
)
from rollerrig.contact.flexibilities import (
    Flexibilities,
    _blend,
    _kalker_flex,
    blended_flexibilities,
    kalker_flexibilities,
)
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.slope_reduction import (
    _check_modification,
    _slope_reduction_kernel,
    _total_creepage,
    slope_reduction,
)
from rollerrig.contact.tangential_result import TangentialResult, TractionField

# rollerrig.contact.strip takes the kernel's helpers (_cases, _fastsim_kernel, _kalker_flex,
# _pressure_shape) from here.
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
    xi, eta, phi, mu = require_broadcastable(long_creep=xi, lat_creep=eta, spin=phi, friction=mu)
    shape = xi.shape
    return shape, xi.ravel(), eta.ravel(), phi.ravel(), mu.ravel()


def _given_flexibilities(flexibilities, shape: tuple[int, ...]) -> tuple[np.ndarray, ...]:
    """Given L1, L2, L3 [m³/N] checked (finite, > 0) and flattened over the cases of ``shape``
    (the creepages and ``friction`` broadcast together): each a single number, an array of that
    shape, or one that broadcasts to it. A mismatch had reached numpy's broadcast error, which
    names neither the fields nor the cases; a negative or NaN flexibility had given forces of
    the wrong sign, or NaN."""
    if not isinstance(flexibilities, Flexibilities):
        raise ParameterError(
            "flexibilities must be a Flexibilities (l1, l2, l3 [m³/N]; see "
            f"kalker_flexibilities), got a {type(flexibilities).__name__}"
        )
    values = {
        name: require_positive(f"flexibilities.{name}", getattr(flexibilities, name), "m³/N")
        for name in ("l1", "l2", "l3")
    }

    def fits(v: np.ndarray) -> bool:
        try:
            return np.broadcast_shapes(v.shape, shape) == shape
        except ValueError:
            return False

    if not all(fits(v) for v in values.values()):
        shown = ", ".join(
            f"{name} (shape {v.shape}{'' if fits(v) else ', does not fit'})"
            for name, v in values.items()
        )
        raise ParameterError(
            f"flexibilities {shown}: each must be a single number or have the shape of the "
            f"cases, {shape} (long_creep, lat_creep, spin and friction broadcast together)"
        )
    return tuple(np.broadcast_to(v, shape).reshape(-1) for v in values.values())


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
    otherwise the flexibilities are divided by Spiryagin's k
    (:func:`~rollerrig.contact.slope_reduction.slope_reduction`).

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
        (:func:`~rollerrig.contact.flexibilities.blended_flexibilities`).
    bound : {"parabolic", "elliptic"}
        Traction bound: Kalker's parabolic p_n = 2N/(πab)(1 - x²/a² - y²/b²) (original
        FASTSIM) or the Hertzian p_n = 3N/(2πab)√(…).
    grid : FastsimGrid, optional
        Default ``fastsim_grid(30, 30)``.
    flexibilities : Flexibilities, optional
        Given L1, L2, L3 [m³/N], overriding ``flexibility``: each finite and > 0, a single
        number or an array of the cases' shape (or one that broadcasts to it).
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
        For a non-physical input, naming it, or for creepages and ``friction`` whose shapes do
        not broadcast together (naming them and their shapes).

    Examples
    --------
    Initial slope = Kalker's linear theory G a b C11 (here C11 = 5.2037):

    >>> r = fastsim(1e-6, semi_axis_x=8e-3, semi_axis_y=4e-3, normal_load=82e3,
    ...             shear_modulus=82e9, poisson=0.28, friction=0.3)
    >>> round(float(r.fx[0]) / (82e9 * 8e-3 * 4e-3 * 1e-6), 1)
    5.2
    """
    a = require_positive("semi_axis_x", semi_axis_x, "m", single=True)
    b = require_positive("semi_axis_y", semi_axis_y, "m", single=True)
    n = require_positive("normal_load", normal_load, "N", single=True)
    g = require_positive("shear_modulus", shear_modulus, "Pa", single=True)
    nu = require_in_range(
        "poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True, single=True
    )
    k0, alpha_inf, beta = _check_modification(k0, alpha_inf, beta)
    if bound not in _BOUNDS:
        raise ParameterError(f"bound must be one of {_BOUNDS}, got {bound!r}")
    if flexibility not in ("kalker", "blended"):
        raise ParameterError(f"flexibility must be 'kalker' or 'blended', got {flexibility!r}")
    shape, xi, eta, phi, mu = _cases(long_creep, lat_creep, spin, friction)
    grid = _checked_grid(grid)
    tractions = require_flag("tractions", tractions)
    equivalent_ellipse = require_flag("equivalent_ellipse", equivalent_ellipse)

    if flexibilities is not None:
        l1, l2, l3 = _given_flexibilities(flexibilities, shape)
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
