"""Kalker's creepage and spin coefficients C11, C22, C23, C33 (linear theory of rolling contact).

Kalker's linear theory gives, for a Hertzian contact ellipse with semi-axes a (rolling direction
x) and b (lateral direction y), c = √(ab), combined shear modulus G and creepages ξ, η, φ:

    F_x = -G c² C11 ξ,    F_y = -G c² C22 η - G c³ C23 φ,    M_z = G c³ C23 η - G c⁴ C33 φ.

The coefficients depend only on the ellipse ratio a/b and on Poisson's ratio ν. They are
tabulated by Kalker (1990, Table E.3; first published in his 1967 thesis) at
g = a/b = 0.1 … 1.0 for a ≤ b and g = b/a = 1.0 … 0.1 for a > b, and ν = 0, 0.25, 0.5.
:data:`KALKER_TABLE` holds that table; :func:`kalker_coefficients` interpolates it and, outside
it, follows Kalker's asymptotes for slender ellipses.

References
----------
.. [1] J. J. Kalker, *On the rolling contact of two elastic bodies in the presence of dry
   friction*, Doctoral thesis, TH Delft (1967).
.. [2] J. J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer (1990),
   Table E.3 and Appendix E (asymptotes).
.. [3] E. A. H. Vollebregt, CONTACT (Kalker's program, continued by VORtech/CMCC), Fortran
   subroutine ``linrol`` of module ``m_hertz``: Table E.3 for C11, C22, C23 and the slender-
   ellipse asymptotes for C11, C22, C23, with interpolation in ν quadratic in 1/C.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np

from rollerrig._validation import require_broadcastable, require_in_range

__all__ = [
    "KALKER_TABLE",
    "MAX_ELLIPSE_RATIO",
    "KalkerCoefficients",
    "KalkerTable",
    "kalker_coefficients",
]


class KalkerTable(NamedTuple):
    """Kalker's Table E.3 (1990), arranged by increasing a/b (read-only arrays).

    Attributes
    ----------
    a_over_b : ndarray, shape (19,)
        Nodes in a/b [-]: 0.1, 0.2, …, 1.0 (the rows g = a/b, a ≤ b), then 1/0.9, 1/0.8, …, 10
        (the rows g = b/a = 0.9 … 0.1, a > b).
    g : ndarray, shape (19,)
        The table's own row label g = min(a/b, b/a) [-].
    poisson : ndarray, shape (3,)
        Poisson ratios of the columns [-]: 0, 0.25, 0.5.
    c11, c22, c23, c33 : ndarray, shape (19, 3)
        The coefficients [-], row i at ``a_over_b[i]``, column j at ``poisson[j]``.
    """

    a_over_b: np.ndarray
    g: np.ndarray
    poisson: np.ndarray
    c11: np.ndarray
    c22: np.ndarray
    c23: np.ndarray
    c33: np.ndarray


# Rows: g, then C11, C22, C23, C33, each at nu = 0, 0.25, 0.5 (Kalker 1990, Table E.3).
# C11, C22 and C23 agree entry by entry with CONTACT's linrol (m_hertz.f90); C23 at a/b = 0.8,
# nu = 0.25 is 1.25 there (a copy of that routine with 1.15 is a typo: it breaks the row's
# monotonic trend 1.03, 1.14, _, 1.36). C33 at nu = 0.25 agrees with the nu = 0.25 column of a
# public wheel-rail code; nu = 0.25 and 0.5 together agree with another code's table at
# nu = 0.3 (its entries equal 0.8 C(0.25) + 0.2 C(0.5)). The C33 column at nu = 0 could not be
# checked against a public copy.
_A_LE_B = (
    # g     C11 (0, .25, .5)     C22 (0, .25, .5)     C23 (0, .25, .5)      C33 (0, .25, .5)
    (0.1, 2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731, 6.42, 8.28, 11.7),
    (0.2, 2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809, 3.46, 4.27, 5.66),
    (0.3, 2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889, 2.49, 2.96, 3.72),
    (0.4, 2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977, 2.02, 2.32, 2.77),
    (0.5, 2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07, 1.74, 1.93, 2.22),
    (0.6, 2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18, 1.56, 1.68, 1.86),
    (0.7, 3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29, 1.43, 1.50, 1.60),
    (0.8, 3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40, 1.34, 1.37, 1.42),
    (0.9, 3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51, 1.27, 1.27, 1.27),
    (1.0, 3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63, 1.21, 1.19, 1.16),
)
_A_GT_B = (
    # g = b/a, from 0.9 down to 0.1
    (0.9, 3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77, 1.16, 1.11, 1.06),
    (0.8, 3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94, 1.10, 1.04, 0.954),
    (0.7, 3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18, 1.05, 0.965, 0.852),
    (0.6, 4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50, 1.01, 0.892, 0.751),
    (0.5, 4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96, 0.958, 0.819, 0.650),
    (0.4, 4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70, 0.912, 0.747, 0.549),
    (0.3, 5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01, 0.868, 0.674, 0.446),
    (0.2, 6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89, 0.828, 0.601, 0.341),
    (0.1, 10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0, 0.795, 0.526, 0.228),
)


def _build_table() -> KalkerTable:
    rows = np.array(_A_LE_B + _A_GT_B, dtype=float)
    g = rows[:, 0]
    a_over_b = np.concatenate([g[: len(_A_LE_B)], 1.0 / g[len(_A_LE_B) :]])
    arrays = [a_over_b, g, np.array([0.0, 0.25, 0.5])] + [
        rows[:, 1 + 3 * k : 4 + 3 * k] for k in range(4)
    ]
    for arr in arrays:
        arr.setflags(write=False)
    return KalkerTable(*arrays)


#: Kalker's creepage and spin coefficients, Kalker (1990) Table E.3 (also Kalker 1967 thesis;
#: reproduced in Iwnicki (ed.), *Handbook of Railway Vehicle Dynamics*). See :class:`KalkerTable`.
KALKER_TABLE: KalkerTable = _build_table()

_G_EDGE = 0.1  # table edge in g = min(a/b, b/a)
_LOG_NODES = np.log(KALKER_TABLE.a_over_b)


def _pchip_slopes(x, y):
    """Node slopes of the monotone piecewise cubic (PCHIP) through ``(x, y)`` along axis 0
    (at least three increasing nodes ``x``).

    Fritsch & Butland (1984): at an interior node the weighted harmonic mean of the adjacent
    secant slopes, zero where they differ in sign or one is zero; at an end the three-point
    shape-preserving formula (Moler, *Numerical Computing with MATLAB*, Sec. 3.4), the rule of
    ``scipy.interpolate.PchipInterpolator`` (tests/contact/test_kalker.py compares the two).
    Written here rather than imported: ``scipy.interpolate`` pulls in ``scipy.optimize`` and
    costs every command that builds a rig about 0.15 s of import for these 19 nodes.
    """
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    m = np.diff(y, axis=0) / h
    d = np.zeros_like(y)
    w1 = 2.0 * h[1:] + h[:-1]
    w2 = h[1:] + 2.0 * h[:-1]
    same = (np.sign(m[1:]) * np.sign(m[:-1])) > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        harmonic = (w1 + w2) / (w1 / m[:-1] + w2 / m[1:])
    d[1:-1] = np.where(same, harmonic, 0.0)
    ends = ((0, (h[0], h[1], m[0], m[1])), (-1, (h[-1], h[-2], m[-1], m[-2])))
    for end, (h0, h1, m0, m1) in ends:
        e = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        e = np.where(np.sign(e) != np.sign(m0), 0.0, e)
        e = np.where((np.sign(m0) != np.sign(m1)) & (np.abs(e) > 3.0 * np.abs(m0)), 3.0 * m0, e)
        d[end] = e
    return d


def _pchip(x_nodes, y_nodes, slopes, x):
    """The cubic Hermite interpolant with node values ``y_nodes`` and ``slopes`` at ``x``
    (within ``[x_nodes[0], x_nodes[-1]]``); the node axis of ``y_nodes`` becomes the leading
    axes of ``x``."""
    x = np.asarray(x, dtype=float)
    k = np.clip(np.searchsorted(x_nodes, x, side="right") - 1, 0, len(x_nodes) - 2)
    h = x_nodes[k + 1] - x_nodes[k]
    trailing = (None,) * (y_nodes.ndim - 1)
    t = ((x - x_nodes[k]) / h)[(..., *trailing)]
    h = h[(..., *trailing)]
    y0, y1, d0, d1 = y_nodes[k], y_nodes[k + 1], slopes[k], slopes[k + 1]
    t2 = t * t
    t3 = t2 * t
    return (
        (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + t) * h * d0
        + (-2.0 * t3 + 3.0 * t2) * y1
        + (t3 - t2) * h * d1
    )


# One monotone cubic (PCHIP) in ln(a/b) across all 19 nodes, for the 4 x 3 columns at once.
_NODE_VALUES = np.stack(
    [KALKER_TABLE.c11, KALKER_TABLE.c22, KALKER_TABLE.c23, KALKER_TABLE.c33], axis=1
)
_NODE_SLOPES = _pchip_slopes(_LOG_NODES, _NODE_VALUES)


def _table_at(log_ratio):
    """Table E.3 at ``ln(a/b)`` inside the table: shape ``(..., 4 coefficients, 3 ν)``."""
    return _pchip(_LOG_NODES, _NODE_VALUES, _NODE_SLOPES, log_ratio)


class KalkerCoefficients(NamedTuple):
    """Kalker's coefficients [-]; each field has the broadcast shape of the inputs."""

    c11: float | np.ndarray
    c22: float | np.ndarray
    c23: float | np.ndarray
    c33: float | np.ndarray


# --------------------------------------------------------------------------------------------
# Kernels
# --------------------------------------------------------------------------------------------


def _poisson_blend(c_at_nodes, poisson):
    """Quadratic interpolation in ν through ν = 0, 0.25, 0.5 of 1/C (as CONTACT's ``linrol``).

    ``c_at_nodes`` has the three ν columns on its last axis; ``poisson`` broadcasts against the
    other axes. 1/C is nearly linear in ν (e.g. at a = b, 1/C11 = 0.294, 0.243, 0.192), so the
    quadratic in 1/C is smooth and reproduces the three columns exactly.
    """
    w0 = (poisson - 0.25) * (poisson - 0.5) * 8.0
    w1 = -(poisson - 0.5) * poisson * 16.0
    w2 = poisson * (poisson - 0.25) * 8.0
    inverse = w0 / c_at_nodes[..., 0] + w1 / c_at_nodes[..., 1] + w2 / c_at_nodes[..., 2]
    return 1.0 / inverse


def _asymptote_a_le_b(g, poisson):
    """Kalker's asymptotes for g = a/b → 0 (ellipse narrow in the rolling direction).

    C11 = π²/(4(1-ν)), C22 = π²/4, C23 = π√g/(3(1-ν)) · (1 + ν(ln(16/g) - 5)) (CONTACT,
    ``linrol``), C33 = π²/(16(1-ν)g) (public wheel-rail codes; it meets the table at g = 0.1
    within 6 %, i.e. 6.17/8.22/12.3 against 6.42/8.28/11.7).
    """
    one_minus = 1.0 - poisson
    c11 = np.pi**2 / (4.0 * one_minus) + 0.0 * g
    c22 = np.pi**2 / 4.0 + 0.0 * g + 0.0 * poisson
    c23 = np.pi * np.sqrt(g) / (3.0 * one_minus) * (1.0 + poisson * (np.log(16.0 / g) - 5.0))
    c33 = np.pi**2 / (16.0 * one_minus * g)
    return c11, c22, c23, c33


def _asymptote_a_gt_b(g, poisson):
    """Kalker's asymptotes for g = b/a → 0 (ellipse long in the rolling direction), Λ = ln(16/g²).

    C11 = 2π/((Λ - 2ν) g) · (1 + (3 - ln 4)/(Λ - 2ν)),
    C22 = 2π/g · (1 + (1-ν)(3 - ln 4)/((1-ν)Λ + 2ν)) / ((1-ν)Λ + 2ν),
    C23 = 2π/(3 g^1.5 ((1-ν)Λ - 2 + 4ν)) (CONTACT, ``linrol``).
    C33 has no verified asymptote here (see :func:`kalker_coefficients`).
    """
    lam = np.log(16.0 / (g * g))
    ln4 = np.log(4.0)
    d1 = lam - 2.0 * poisson
    d2 = (1.0 - poisson) * lam + 2.0 * poisson
    d3 = (1.0 - poisson) * lam - 2.0 + 4.0 * poisson
    c11 = 2.0 * np.pi / (d1 * g) * (1.0 + (3.0 - ln4) / d1)
    c22 = 2.0 * np.pi / g * (1.0 + (1.0 - poisson) * (3.0 - ln4) / d2) / d2
    c23 = 2.0 * np.pi / (3.0 * g**1.5 * d3)
    return c11, c22, c23


def _kalker_kernel(a_over_b, poisson):
    """Kalker coefficients (c11, c22, c23, c33) for broadcast arrays a/b > 0 and ν ∈ [0, 0.5]."""
    a_over_b, poisson = np.broadcast_arrays(
        np.asarray(a_over_b, dtype=float), np.asarray(poisson, dtype=float)
    )
    log_ratio = np.log(a_over_b)
    log_inside = np.clip(log_ratio, _LOG_NODES[0], _LOG_NODES[-1])
    # (..., 4 coefficients, 3 nu-columns) -> blend in nu -> (..., 4)
    at_nodes = _table_at(log_inside)
    inside = _poisson_blend(at_nodes, poisson[..., None])
    edge_lo = _poisson_blend(_table_at(_LOG_NODES[0]), poisson[..., None])  # a/b = 0.1
    edge_hi = _poisson_blend(_table_at(_LOG_NODES[-1]), poisson[..., None])  # a/b = 10

    # Below the table: asymptote times a correction factor that equals table/asymptote at the
    # edge g = 0.1 and relaxes linearly in g to 1 at g = 0 (continuous, exact limit).
    g_lo = np.minimum(a_over_b, _G_EDGE)
    asym_lo = np.stack(_asymptote_a_le_b(g_lo, poisson), axis=-1)
    asym_lo_edge = np.stack(_asymptote_a_le_b(np.full_like(g_lo, _G_EDGE), poisson), axis=-1)
    weight_lo = (g_lo / _G_EDGE)[..., None]
    below = asym_lo * (1.0 + (edge_lo / asym_lo_edge - 1.0) * weight_lo)

    # Above the table (g = b/a < 0.1): the same rule for C11, C22, C23; C33 held at its edge.
    g_hi = np.minimum(1.0 / a_over_b, _G_EDGE)
    asym_hi = np.stack(_asymptote_a_gt_b(g_hi, poisson), axis=-1)
    asym_hi_edge = np.stack(_asymptote_a_gt_b(np.full_like(g_hi, _G_EDGE), poisson), axis=-1)
    weight_hi = (g_hi / _G_EDGE)[..., None]
    above3 = asym_hi * (1.0 + (edge_hi[..., :3] / asym_hi_edge - 1.0) * weight_hi)
    above = np.concatenate([above3, edge_hi[..., 3:]], axis=-1)

    is_below = (log_ratio < _LOG_NODES[0])[..., None]
    is_above = (log_ratio > _LOG_NODES[-1])[..., None]
    result = np.where(is_below, below, np.where(is_above, above, inside))
    return result[..., 0], result[..., 1], result[..., 2], result[..., 3]


# --------------------------------------------------------------------------------------------
# Public function
# --------------------------------------------------------------------------------------------


MAX_ELLIPSE_RATIO = 1e8
"""Largest ellipse ratio a/b (and b/a) :func:`kalker_coefficients` takes [-]."""


def kalker_coefficients(a_over_b, poisson) -> KalkerCoefficients:
    """Kalker's creepage and spin coefficients C11, C22, C23, C33 for an ellipse a/b and ν.

    Interpolation rule (inside the table, 0.1 ≤ a/b ≤ 10):

    1. in a/b: one monotone piecewise-cubic Hermite interpolant (PCHIP) in ln(a/b) through all
       19 table nodes (a/b = 0.1 … 1 … 10), separately for each coefficient and ν column. It is
       continuously differentiable everywhere, a/b = 1 included, reproduces the nodes exactly and
       adds no overshoot between them;
    2. in ν: the quadratic through ν = 0, 0.25, 0.5 of 1/C (the rule of CONTACT's ``linrol``),
       exact at the three columns.

    Outside the table Kalker's slender-ellipse asymptotes are used, made continuous at the table
    edge g = 0.1 by a correction factor that equals table/asymptote at the edge and tends
    linearly in g to 1 as g → 0, so the result tends to the exact asymptote:

    * a/b < 0.1 (g = a/b): C11 = π²/(4(1-ν)), C22 = π²/4,
      C23 = π√g/(3(1-ν))·(1 + ν(ln(16/g) - 5)) (Kalker 1990 App. E, as in CONTACT's ``linrol``),
      C33 = π²/(16(1-ν)g) (as in public wheel-rail codes; not checked against Kalker's text);
    * a/b > 10 (g = b/a, Λ = ln(16/g²)): C11 = 2π/((Λ-2ν)g)·(1 + (3-ln 4)/(Λ-2ν)),
      C22 = 2π/g·(1 + (1-ν)(3-ln 4)/((1-ν)Λ+2ν))/((1-ν)Λ+2ν), C23 = 2π/(3g^1.5((1-ν)Λ-2+4ν))
      (Kalker 1990 App. E, as in CONTACT's ``linrol``). For C33 no asymptote could be verified
      (the expression π/4·(1 - (νΛ-2)/((1-ν)Λ-2+4ν)) found in public codes misses the table at
      b/a = 0.1 by 35-90 %), so C33 is held at its value at a/b = 10 (clamped).

    CONTACT's ``linrol`` instead switches to the bare asymptotes for g = min(a/b, b/a) < 0.101,
    the table's edge rows g = 0.1 included. There the two differ: at a/b = 10, ν = 0.28,
    C11 = 11.83 here (Kalker's table) and 11.40 in CONTACT (the asymptote), +3.8 % (C22
    +2.3 %); at a/b = 0.1, C22 +2.2 % and C23 +5.5 %. Here Kalker's table holds at all its
    nodes, and the blend towards the asymptotes begins beyond them.

    Parameters
    ----------
    a_over_b : array_like
        Ellipse ratio a/b [-], a along the rolling direction, in [1e-8, 1e8]
        (:data:`MAX_ELLIPSE_RATIO`).
    poisson : array_like
        Combined Poisson ratio ν [-], in [0, 0.5] (see
        :func:`rollerrig.contact.hertz.combined_elastic_constants`).

    Returns
    -------
    KalkerCoefficients
        ``(c11, c22, c23, c33)`` [-], broadcast over the inputs.

    Raises
    ------
    ParameterError
        If a/b lies outside [1e-8, 1e8] or ν outside [0, 0.5], or their shapes do not
        broadcast together (naming both and their shapes).

    References
    ----------
    Kalker (1967), thesis; Kalker (1990), *Three-Dimensional Elastic Bodies in Rolling Contact*,
    Table E.3 and Appendix E; Vollebregt, CONTACT, subroutine ``linrol``.

    Examples
    --------
    >>> c = kalker_coefficients(1.0, 0.25)
    >>> [round(float(v), 2) for v in c]
    [4.12, 3.67, 1.47, 1.19]
    >>> round(float(kalker_coefficients(1.6076, 0.3).c11), 3)
    4.896
    """
    # Beyond 1e8 either way no contact of solids is that slender, and far beyond it the
    # asymptotes' arithmetic breaks down (at 1e300 (b/a)² underflows: C11 = 0, C23 NaN).
    ratio = require_in_range(
        "a_over_b", a_over_b, 1.0 / MAX_ELLIPSE_RATIO, MAX_ELLIPSE_RATIO, "-",
        low_inclusive=True, high_inclusive=True,
    )  # fmt: skip
    nu = require_in_range(
        "poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True
    )
    if ratio.ndim == 0 and nu.ndim == 0:
        return _scalar_coefficients(float(ratio), float(nu))
    # numpy's own error ("operands could not be broadcast together") named neither.
    ratio, nu = require_broadcastable(a_over_b=ratio, poisson=nu)
    c11, c22, c23, c33 = _kalker_kernel(ratio, nu)
    return KalkerCoefficients(_out(c11), _out(c22), _out(c23), _out(c33))


@lru_cache(maxsize=1024)
def _scalar_coefficients(a_over_b: float, poisson: float) -> KalkerCoefficients:
    """:func:`kalker_coefficients` of one ellipse, kept: the fits and the transfer evaluate
    FASTSIM thousands of times on one contact, and each evaluation interpolated the table
    again (0.3 ms, half the cost of a modified-FASTSIM fit)."""
    c11, c22, c23, c33 = _kalker_kernel(a_over_b, poisson)
    return KalkerCoefficients(_out(c11), _out(c22), _out(c23), _out(c33))


def _out(arr):
    arr = np.asarray(arr)
    return arr[()] if arr.ndim == 0 else arr
