"""Creep laws as one-dimensional tables for the twin's right-hand side.

For pure longitudinal creepage on a Hertzian ellipse, the normalised force of every law of the
FASTSIM family depends on one number only,

.. math:: \\frac{F_x}{\\mu N} = f(\\varepsilon), \\qquad
          \\varepsilon = \\frac{G\\,a\\,b\\,C_{11}\\,\\xi}{\\mu N},

odd in ε. For Kalker's FASTSIM on the package's grid (:func:`rollerrig.contact.fastsim_grid`,
normalised to the unit ellipse) this holds whatever a/b and ν are: the increment of the traction
along a strip is (3/8)·ε·(h/a) times μN/(ab) and the bound is (2/π)·μN/(ab) times the shape of
the unit ellipse, so one table serves every rig (checked to round-off in the tests). The modified
FASTSIM is FASTSIM with its flexibilities divided by Spiryagin's k, i.e. f evaluated at k·ε, with
k a function of ε alone for pure longitudinal creepage (:func:`rollerrig.contact.fastsim.
slope_reduction`: ε_s = (π/4)·k0·ε), so it uses FASTSIM's table and k is computed beside it.
FaStrip's f depends on a/b and ν as well: its table is made for the rig's contact.

A table holds f and f' at ``nodes`` equally spaced ε in [0, ε_max]; between nodes the twin takes
the cubic Hermite interpolant (continuous slope, so forward-difference Jacobians of the
right-hand side are meaningful). f' at a node is the central difference of f over one node
spacing, which smooths the kinks of the discrete FASTSIM (piecewise linear in ε, one kink where an
element starts to slip). Beyond ε_max the law is saturated: f = f(ε_max), f' = 0.

The friction coefficient μ(w) is not in the table: the twin evaluates Polach's exponential form
with the slip velocity, as :func:`rollerrig.contact.laws.creep_force` does.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from rollerrig._validation import ParameterError, require_finite, require_whole
from rollerrig.contact.laws import check_law
from rollerrig.contact.slope_reduction import _check_modification

__all__ = ["TABLE_NODES", "TABULATED_LAWS", "CreepTable", "creep_table", "table_ratio"]

TABLE_NODES = 513
"""Nodes of a creep table [-] (the twin's parameter vector holds this many values and slopes);
the Hermite interpolant is within 1e-5 of μN of the discrete FASTSIM (tests)."""

TABULATED_LAWS = ("fastsim", "modified-fastsim", "fastrip")
"""The laws the twin evaluates from a table (``"polach"`` is closed form)."""

_PROBE_MAX = 40.0  # ε up to which saturation is looked for [-]
_SATURATION_MARGIN = 1.05  # ε_max = this × the first ε where the law is saturated
_MIN_NODES = 2  # the cubic Hermite interpolant needs one interval, its two end nodes
# A law evaluation a node: 200 times the 513 the twin uses is far past any gain in accuracy,
# and a typo of a few digits more would run for hours or run out of memory.
_MAX_NODES = 100_000


@dataclass(frozen=True)
class CreepTable:
    """F_x/(μN) of a creep law against ε = G a b C11 ξ/(μN), at equally spaced ε >= 0.

    Attributes
    ----------
    law : str
        ``"fastsim"`` (also the modified FASTSIM's table) or ``"fastrip"``.
    eps_max : float
        Last node ε_max [-]; beyond it the law is saturated.
    values : ndarray, shape (nodes,)
        f(ε) = F_x/(μN) [-] at the nodes ε_i = i ε_max/(nodes - 1).
    slopes : ndarray, shape (nodes,)
        df/dε [-] at the nodes.
    aspect_ratio, poisson : float
        a/b [-] and ν [-] the table was made for (NaN where it does not depend on them).
    """

    law: str
    eps_max: float
    values: np.ndarray
    slopes: np.ndarray
    aspect_ratio: float = float("nan")
    poisson: float = float("nan")

    @property
    def step(self) -> float:
        """Node spacing in ε [-]."""
        return self.eps_max / (self.values.size - 1)

    def to_dict(self) -> dict:
        """What the table is, for provenance records (not its numbers)."""
        return {
            "law": self.law,
            "nodes": int(self.values.size),
            "eps_max": self.eps_max,
            "saturated_value": float(self.values[-1]),
            "aspect_ratio": self.aspect_ratio,
            "poisson": self.poisson,
            "interpolation": "cubic Hermite in eps = G a b C11 xi / (mu N)",
        }


def _ratio_function(law: str, aspect_ratio: float, poisson: float):
    """f(ε) of ``law`` for an array of ε >= 0, on a unit-load contact with a/b = aspect_ratio."""
    from rollerrig.contact.fastsim import fastsim
    from rollerrig.contact.kalker import kalker_coefficients
    from rollerrig.contact.strip import fastrip

    b = 1e-3
    a = aspect_ratio * b
    g, load, mu = 1e9, 1.0, 1.0
    c11 = float(kalker_coefficients(a / b, poisson).c11)
    solve = fastsim if law == "fastsim" else fastrip

    def ratio(eps):
        xi = np.asarray(eps, float) * mu * load / (g * a * b * c11)
        kw = dict(
            semi_axis_x=a,
            semi_axis_y=b,
            normal_load=load,
            shear_modulus=g,
            poisson=poisson,
            friction=mu,
        )
        zero = np.zeros_like(xi)
        return np.asarray(solve(xi, zero, zero, **kw).fx) / (mu * load)

    return ratio


@lru_cache(maxsize=32)
def _table(law: str, aspect_ratio: float, poisson: float, nodes: int) -> CreepTable:
    ratio = _ratio_function(law, aspect_ratio, poisson)
    probe = np.linspace(0.0, _PROBE_MAX, 401)
    values = ratio(probe)
    saturated = np.abs(values - values[-1]) <= 1e-12 * max(1.0, abs(values[-1]))
    first = probe[int(np.argmax(saturated))] if saturated.any() else _PROBE_MAX
    eps_max = min(_PROBE_MAX, _SATURATION_MARGIN * float(first))
    eps = np.linspace(0.0, eps_max, nodes)
    h = eps[1] - eps[0]
    y = ratio(eps)
    hi = eps + 0.5 * h
    lo = np.maximum(eps - 0.5 * h, 0.0)
    # f is odd: the central difference at 0 is f(h/2)/(h/2).
    s = (ratio(hi) - ratio(lo) * (lo > 0.0)) / (hi - lo)
    y.setflags(write=False)
    s.setflags(write=False)
    keep_geometry = law == "fastrip"
    return CreepTable(
        law="fastrip" if keep_geometry else "fastsim",
        eps_max=float(eps_max),
        values=y,
        slopes=s,
        aspect_ratio=float(aspect_ratio) if keep_geometry else float("nan"),
        poisson=float(poisson) if keep_geometry else float("nan"),
    )


def creep_table(
    law: str, aspect_ratio: float = 1.0, poisson: float = 0.3, nodes: int = TABLE_NODES
) -> CreepTable:
    """The table of a creep law for pure longitudinal creepage, made once and kept.

    Parameters
    ----------
    law : {"fastsim", "modified-fastsim", "fastrip"}
        The law; ``"modified-fastsim"`` gets FASTSIM's table (its k is applied to ε by the
        caller, :func:`table_ratio`).
    aspect_ratio : float
        a/b of the contact [-] (FaStrip only; FASTSIM's table does not depend on it).
    poisson : float
        Combined ν [-] (FaStrip only).
    nodes : int
        Number of nodes [-], a whole number in [2, 100 000] (the cubic Hermite interpolation
        between nodes needs at least one interval; the node spacing is ε_max/(nodes - 1)).

    Returns
    -------
    CreepTable

    Raises
    ------
    ParameterError
        An unknown law (with a did-you-mean), ``"polach"`` (closed form, not tabulated), or
        ``nodes`` not a whole number in [2, 100 000].

    Examples
    --------
    >>> t = creep_table("fastsim")
    >>> round(t.eps_max, 2), round(float(t.values[-1]), 4)
    (3.57, 1.0)
    """
    check_law(law)
    if law not in TABULATED_LAWS:
        raise ParameterError(f"law {law!r} is closed form; tabulated laws: {TABULATED_LAWS}")
    nodes = require_whole("nodes", nodes, minimum=_MIN_NODES, maximum=_MAX_NODES)
    if law == "fastrip":
        return _table("fastrip", float(aspect_ratio), float(poisson), int(nodes))
    return _table("fastsim", 1.0, 0.3, int(nodes))


def table_ratio(table: CreepTable, eps, k0=1.0, alpha_inf=1.0, beta=0.0):
    """F_x/(μN) of a tabulated law at ε = G a b C11 ξ/(μN), vectorised (for checks and plots).

    The same interpolation and slope reduction as the twin's right-hand side
    (:func:`rollerrig.rig.model._law_ratio`), in numpy.

    Parameters
    ----------
    table : CreepTable
        From :func:`creep_table`.
    eps : array_like
        ε [-], signed.
    k0, alpha_inf, beta : float
        Modified FASTSIM's slope reduction (defaults: none, Kalker's FASTSIM).

    Returns
    -------
    numpy.ndarray
        F_x/(μN) [-], with the sign of ε.

    Examples
    --------
    >>> round(float(table_ratio(creep_table("fastsim"), 1e-3)), 5)
    0.001
    """
    e0 = require_finite("eps", eps, "-")
    k0, alpha_inf, beta = _check_modification(k0, alpha_inf, beta)  # as fastsim's
    e = np.abs(e0)
    es = 0.25 * np.pi * k0 * e
    k = k0 * (alpha_inf + (1.0 - alpha_inf) / (1.0 + beta * es))
    u = k * e / table.step
    n = table.values.size
    i = np.clip(np.floor(u).astype(int), 0, n - 2)
    t = np.clip(u - i, 0.0, 1.0)
    h = table.step
    y0, y1 = table.values[i], table.values[i + 1]
    s0, s1 = table.slopes[i] * h, table.slopes[i + 1] * h
    t2, t3 = t * t, t * t * t
    val = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * s0 + (-2 * t3 + 3 * t2) * y1
    val = val + (t3 - t2) * s1
    return np.sign(e0) * val
