"""The transfer's creep law on one Hertz ellipse: its CoA, its transfer factor, its fit's
residual sum of squares and the draws of its surface parameters
(:mod:`rollerrig.analysis.transfer`).

θ holds a law's surface parameters: Polach's (μ0, A, B, k_A, k_S), the modified FASTSIM's
(k0, α∞, β, μ0, A, B). The factor F_rail/F_roller of the modified FASTSIM is taken from the
strip theory with the same parameters (:func:`factor_coa`), whose error against Kalker's exact
theory is the smaller (:data:`rollerrig.analysis.transfer.LAW_FACTOR_ERROR`).
"""

from __future__ import annotations

import numpy as np

from rollerrig.analysis.transfer_geometry import HertzEllipse
from rollerrig.contact.creep import friction_kernel as _friction_kernel
from rollerrig.contact.creep import polach_force_kernel as _polach_force_kernel
from rollerrig.contact.fastsim import fastsim_grid
from rollerrig.contact.strip import fastrip

__all__ = [
    "POLACH_NAMES",
    "draws_within_bounds",
    "factor_coa",
    "law_bounds",
    "law_coa",
    "sse_on_points",
]


def law_coa(law, theta, xi, w, load, ell: HertzEllipse, g, nu, grid):
    """CoA of the law with surface parameters ``theta`` on ellipse ``ell`` at one load."""
    if law == "polach":
        mu0, aa, bb, ka, ks = theta
        k = g * ell.a * ell.b * ell.c11
        return _polach_force_kernel(xi, w, load, k, mu0, aa, bb, ka, ks) / load
    from rollerrig.fit.modified_fastsim import coa_kernel as _coa_kernel

    return _coa_kernel(xi, w, load, ell.a, ell.b, g, nu, np.asarray(theta), grid)


def factor_coa(law, theta, xi, w, load, ell: HertzEllipse, g, nu):
    """CoA whose ratio between two ellipses is the law's transfer factor F_rail/F_roller.

    Polach's law: its own closed form. The modified FASTSIM: the modified FaStrip with the same
    six parameters (:func:`rollerrig.contact.strip.fastrip`, k0, α∞, β on the strip theory),
    on 30 strips in closed form: the strip theory's saturation shape follows Kalker's exact
    theory closer (factor within 0.75 % of CONTACT's, FASTSIM's 2.46 %:
    :data:`~rollerrig.analysis.transfer.LAW_FACTOR_ERROR`), and as cheap as FASTSIM for pure
    creepage.
    """
    if law == "polach":
        return law_coa(law, theta, xi, w, load, ell, g, nu, None)
    k0, al, be, mu0, aa, bb = theta
    mu = _friction_kernel(w, mu0, aa, bb)
    r = fastrip(
        xi, semi_axis_x=ell.a, semi_axis_y=ell.b, normal_load=load, shear_modulus=g, poisson=nu,
        friction=mu, k0=k0, alpha_inf=al, beta=be, grid=_STRIPS,
    )  # fmt: skip
    return r.fx / load


_STRIPS = fastsim_grid(30, 30)  # FaStrip's default discretisation, as measured against CONTACT

POLACH_NAMES = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
_POLACH_LOWER = np.array([1e-3, 1e-6, 0.0, 1e-6, 1e-6])
_POLACH_UPPER = np.array([2.0, 1.0, 50.0, 1.0, 1.0])  # draws only: the physical range
_SSE_POINTS = 150  # points of S(θ) for the plausible set (evenly thinned in creepage order)


def law_bounds(law):
    """Lower and upper bounds of a draw, and a further constraint (Polach's kS <= kA)."""
    if law == "polach":
        return _POLACH_LOWER, _POLACH_UPPER, lambda t: t[4] <= t[3]
    from rollerrig.fit.modified_fastsim import PARAMETER_LOWER as _LOWER
    from rollerrig.fit.modified_fastsim import PARAMETER_UPPER as _UPPER

    return _LOWER, _UPPER, None


def draws_within_bounds(theta, cov, lower, upper, feasible, draws, rng):
    """``draws`` normal draws about ``theta`` with covariance ``cov``; those outside the
    bounds drawn again (up to 20 rounds, then θ̂ in their place): never clipped."""
    cov = 0.5 * (cov + cov.T)
    evals, evecs = np.linalg.eigh(cov)
    root = evecs * np.sqrt(np.clip(evals, 0.0, None))
    out = np.tile(theta, (draws, 1))
    todo = np.arange(draws)
    for _ in range(20):
        if todo.size == 0:
            break
        t = theta + rng.standard_normal((todo.size, theta.size)) @ root.T
        ok = np.all((t >= lower) & (t <= upper), axis=1)
        if feasible is not None:
            ok &= np.array([bool(feasible(row)) for row in t])
        out[todo[ok]] = t[ok]
        todo = todo[~ok]
    return out


def sse_on_points(law, xi_pts, y, w_pts, q_pts, n_ref, ell, g, nu, grid, theta):
    """θ -> the sum of squared residuals of the law on the roller at (up to
    ``_SSE_POINTS``) measured points, each at its own load; and the fitted CoA at every point."""
    order = np.argsort(xi_pts, kind="stable")
    keep = order[:: max(1, int(np.ceil(xi_pts.size / _SSE_POINTS)))]

    def model(t, idx):
        if law == "polach":
            k = g * ell.a * ell.b * ell.c11 * np.cbrt((q_pts[idx] / n_ref) ** 2)
            mu0, aa, bb, ka, ks = t
            return _polach_force_kernel(xi_pts[idx], w_pts[idx], q_pts[idx], k, mu0, aa, bb, ka,
                                        ks) / q_pts[idx]  # fmt: skip
        from rollerrig.fit.modified_fastsim import coa_kernel as _coa_kernel

        xi_eq = xi_pts[idx] * np.cbrt(n_ref / q_pts[idx])
        return _coa_kernel(xi_eq, w_pts[idx], n_ref, ell.a, ell.b, g, nu, np.asarray(t), grid)

    def sse(t):
        r = model(t, keep) - y[keep]
        value = float(r @ r)
        return value if np.isfinite(value) else np.inf

    sse.points = int(keep.size)
    return sse, model(theta, np.arange(xi_pts.size))
