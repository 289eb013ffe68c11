"""How the band of a roller-to-track transfer is built, and which construction a fit gets.

Two constructions (:func:`rollerrig.analysis.transfer.transfer_curve`):

``"model"``
    The fit determines its parameters (identifiable, residuals without serial structure): the
    law's curve on the roller is the measured curve, and the band is a Monte Carlo of the
    fit's covariance (JCGM 101). Draws outside the parameters' bounds are drawn again, never
    clipped (clipping piles draws on a bound and moves the band away from the curve).

``"measured points"``
    The fit does not determine its parameters, or its residuals are structured (the law is
    not the data's: a noise-free curve of another law is both). The covariance then describes
    nothing (on CONTACT's exact curve Polach's μ0 has a standard error of 2.4 on 0.43), and
    the law's curve misses the measured points by several per cent where the transition to
    sliding lies. The roller level is then taken from the measured points themselves, and only
    the *factor* F_rail/F_roller from the law:

    .. math:: \\mathrm{CoA}_\\mathrm{rail}(\\xi) = \\hat y(\\xi)\\, f(\\theta, \\xi),
              \\qquad \\hat y = y_\\mathrm{law}(\\hat\\theta) + \\rho(\\xi),

    with ρ the residuals (measured − fitted) smoothed by a cubic smoothing spline whose
    smoothing generalised cross-validation chooses [3]_ (:func:`measured_level`): with few
    points on a smooth curve it goes through them, with many scattered ones it is their local
    mean; through the points themselves when they are :data:`MIN_SMOOTHED` or fewer. The
    random scatter of ŷ is the points' noise (pseudo-residuals [1]_) through the smoother's
    linear map. The parameters θ range over the
    *plausible set*: the Beale region [2]_
    S(θ) ≤ S(θ̂)·(1 + p/(n − p)·F_{p, n−p}(0.95)), S the sum of squared residuals on the
    measured points, sampled by drawing from the covariance at the largest of a few shrinking
    scales that keeps at least a fifth of a pilot batch inside (θ̂ always in). No linearisation,
    no clipping: a parameter the data do not see moves as far as the data allow.

In both, the law's own error in the factor (:data:`~rollerrig.analysis.transfer.LAW_FACTOR_ERROR`,
the largest error measured against CONTACT's exact theory) is a *bound*, added to the band's
edges as a factor (1 ± e(ξ)); it is not drawn, since a largest error measured at one geometry
is not a distribution. And the central curve is always inside its band (the band is the union
of the quantile interval and the central curve: with a skewed plausible set the quantiles can
lie to one side of the best fit).

Why not only the model's band with a wider covariance: a fit to data of another law puts its
error where the law's shape differs (Polach's slow saturation: −9 % at ξ = 1e-5, −6 % at
2.5e-4 on CONTACT's exact roller curve), and no parameter draw moves the curve there while
keeping it near the other points; carrying the measured level over does, and leaves the law
only the ratio of two ellipses, which is what it is for.

References
----------
.. [1] T. Gasser, L. Sroka, C. Jennen-Steinmetz, Residual variance and residual pattern in
   nonlinear regression, Biometrika 73 (1986) 625-633.
.. [2] E.M.L. Beale, Confidence regions in non-linear estimation, J. R. Stat. Soc. B 22
   (1960) 41-88; D.M. Bates, D.G. Watts, *Nonlinear Regression Analysis and its
   Applications*, Wiley (1988), sec. 6.1.
.. [3] P. Craven, G. Wahba, Smoothing noisy data with spline functions, Numer. Math. 31
   (1979) 377-403.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "MAX_POINTS",
    "MEASURED_POINTS",
    "MIN_SMOOTHED",
    "MODEL",
    "beale_threshold",
    "choose_construction",
    "measured_level",
    "plausible_draws",
    "pseudo_residual_sigma",
]

MODEL = "model"
MEASURED_POINTS = "measured points"
MIN_SMOOTHED = 30
"""Fewest nodes the measured level is smoothed on [-]; with fewer it goes through them
(linear interpolation). Cross-validation cannot tell a law's misfit, sharp where its
saturation differs from the data's, from noise on a dozen points: on CONTACT's exact roller
curve (12 points, σ = 0.005 added) a GCV spline's level missed the curve by 0.0075 at the knee
(ξ = 3e-3), and the band then covered 9 of 11 creepages; through the points, 11."""

MAX_POINTS = 200
"""Largest number of nodes of the measured level's smoothing spline (more points are first
averaged in bins of equal count) [-]."""

_PILOT = 40
_SCALES = (1.0, 0.3, 0.1, 0.03, 0.01, 0.003)
_MIN_ACCEPTANCE = 0.2


def choose_construction(fit) -> tuple[str, str]:
    """``(construction, why)``: ``"model"`` for a fit that determines its parameters with
    residuals free of serial structure, else ``"measured points"``.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> choose_construction(NS(identifiable=False, residual_structure=None))[0]
    'measured points'
    """
    structure = getattr(fit, "residual_structure", None)
    structured = bool(structure is not None and structure.structured)
    if not fit.identifiable:
        why = "the fit does not determine its parameters from these data (not identifiable)"
        if structured:
            why += " and its residuals are structured (the law is not the data's)"
        return MEASURED_POINTS, why
    if structured:
        return MEASURED_POINTS, (
            "the fit's residuals are structured: the law misses a systematic part of the "
            "measured curve (its covariance then understates what is not known)"
        )
    return MODEL, "the fit determines its parameters and its residuals show no serial structure"


def pseudo_residual_sigma(x, r) -> float:
    """Standard deviation of the noise in ``r`` at abscissae ``x`` from the pseudo-residuals
    of Gasser et al. (1986): each point against the line through its two neighbours [same unit
    as r]; 0 with fewer than three points.

    .. math:: \\tilde e_i = \\frac{(x_{i+1}-x_i) r_{i-1} + (x_i-x_{i-1}) r_{i+1}}
              {x_{i+1}-x_{i-1}} - r_i, \\quad
              \\hat\\sigma^2 = \\frac{1}{n-2}\\sum c_i^2 \\tilde e_i^2,\\;
              c_i^2 = (a_i^2 + b_i^2 + 1)^{-1}

    Examples
    --------
    >>> x = np.arange(200.0)
    >>> r = np.random.default_rng(0).normal(0.0, 0.01, 200)
    >>> round(pseudo_residual_sigma(x, r), 2)
    0.01
    """
    x = np.asarray(x, float)
    r = np.asarray(r, float)
    if x.size < 3:
        return 0.0
    order = np.argsort(x, kind="stable")
    x, r = x[order], r[order]
    span = x[2:] - x[:-2]
    ok = span > 0
    if not np.any(ok):
        return float(np.std(r, ddof=1))
    a = np.where(ok, (x[2:] - x[1:-1]) / np.where(ok, span, 1.0), 0.5)
    b = 1.0 - a
    e = a * r[:-2] + b * r[2:] - r[1:-1]
    c2 = 1.0 / (a**2 + b**2 + 1.0)
    return float(np.sqrt(np.mean(c2 * e**2)))


def _spline_hat(x, w, lam, at):
    """The smoothing spline's linear map from the data at ``x`` (weights ``w``) to its values
    at ``at``, for a fixed ``lam``: shape (len(at), len(x))."""
    from scipy.interpolate import make_smoothing_spline

    return make_smoothing_spline(x, np.eye(x.size), w=w, lam=lam)(at)


def _gcv_lambda(x, r, w):
    """The smoothing parameter minimising generalised cross-validation,
    n·RSS_w/(n − tr H)² [3]_, on a grid of 10^-12...10^2 (x scaled to [0, 1])."""
    n = x.size
    best, best_lam = np.inf, 1e-12
    for lam in np.logspace(-12, 2, 29):
        h = _spline_hat(x, w, lam, x)
        dof = n - float(np.trace(h))
        if dof < 0.5:
            continue
        rss = float(np.sum(w * (h @ r - r) ** 2))
        score = n * rss / dof**2
        if score < best:
            best, best_lam = score, lam
    return best_lam


def measured_level(xi_pts, y, fitted, xi_grid, law_grid):
    """The measured roller level on the output grid and its standard uncertainty.

    ŷ = the law's curve + the residuals (measured − fitted) smoothed by a cubic smoothing spline
    in creepage whose smoothing generalised cross-validation chooses [3]_ (their local mean
    where they scatter); with :data:`MIN_SMOOTHED` nodes or fewer, linearly interpolated
    through them (a dozen points cannot tell misfit from noise). Ties are merged, and beyond
    :data:`MAX_POINTS` the points are first averaged in bins of equal count (weights: the
    counts). Below the first point, the first residual in proportion to the law's curve (the
    CoA vanishes with the creepage); beyond the last, held. Its uncertainty:
    σ·√(Σ_j H_gj²/c_j), H the smoother's
    linear map, c_j the counts, σ the points' noise from pseudo-residuals [1]_.

    Parameters
    ----------
    xi_pts, y, fitted : ndarray
        Creepage [-], measured and fitted CoA [-] of the points.
    xi_grid, law_grid : ndarray
        The output grid [-] and the law's fitted curve on it [-].

    Returns
    -------
    level : ndarray
        ŷ on the grid [-].
    u : ndarray
        Standard uncertainty of ŷ [-].
    sigma : float
        The noise of a point [-].
    nodes : int
        Points (or bins) the spline was fitted to.

    Examples
    --------
    >>> x = np.linspace(0.001, 0.01, 12)
    >>> lvl, u, s, nb = measured_level(x, 1.1 * x, x, x, x)
    >>> bool(np.allclose(lvl, 1.1 * x, atol=1e-6)), nb
    (True, 12)
    """
    order = np.argsort(xi_pts, kind="stable")
    x, r = xi_pts[order], (y - fitted)[order]
    sigma = pseudo_residual_sigma(x, r)
    ux, inverse, counts = np.unique(x, return_inverse=True, return_counts=True)
    means = np.bincount(inverse, weights=r) / counts
    if ux.size > MAX_POINTS:
        groups = np.array_split(np.arange(ux.size), MAX_POINTS)
        c = np.array([counts[g].sum() for g in groups], float)
        ux = np.array([np.sum(ux[g] * counts[g]) for g in groups]) / c
        means = np.array([np.sum(means[g] * counts[g]) for g in groups]) / c
        counts = c
    counts = np.asarray(counts, float)
    lo_x, span = ux[0], ux[-1] - ux[0]
    if ux.size < 5 or span <= 0:
        r_g = np.full(xi_grid.shape, float(np.average(means, weights=counts)))
        u_g = np.full(xi_grid.shape, sigma / np.sqrt(counts.sum()))
        return law_grid + r_g, u_g, sigma, int(ux.size)
    xn = (ux - lo_x) / span
    w = counts / counts.mean()
    at = (np.clip(xi_grid, ux[0], ux[-1]) - lo_x) / span
    if ux.size <= MIN_SMOOTHED:
        hat = np.array([np.interp(at, xn, e) for e in np.eye(ux.size)]).T
    else:
        hat = _spline_hat(xn, w, _gcv_lambda(xn, means, w), at)
    r_g = hat @ means
    u_g = sigma * np.sqrt(np.sum(hat**2 / counts, axis=1))
    below = xi_grid < ux[0]
    law_c = float(np.interp(ux[0], xi_grid, law_grid))
    if np.any(below) and law_c > 0:
        scale = np.clip(law_grid[below] / law_c, 0.0, 1.0)
        r_g[below] *= scale
        u_g[below] *= scale
    return law_grid + r_g, u_g, sigma, int(ux.size)


def beale_threshold(sse_min: float, n: int, p: int) -> float:
    """Largest sum of squared residuals in Beale's 95 % region [CoA²]:
    S(θ̂)·(1 + p/(n − p)·F_{p, n−p}(0.95)).

    Examples
    --------
    >>> round(beale_threshold(1.0, 12, 5), 3)
    3.837
    """
    from scipy import stats

    dof = max(int(n) - int(p), 1)
    return float(sse_min) * (1.0 + p / dof * float(stats.f.ppf(0.95, p, dof)))


def plausible_draws(theta, cov, sse, lower, upper, draws, rng, feasible=None):
    """Parameter sets in Beale's region around ``theta``, drawn from the covariance at the
    largest scale of ``_SCALES`` whose pilot keeps at least a fifth inside.

    Parameters
    ----------
    theta : ndarray
        The fit.
    cov : ndarray
        Its covariance (non-finite entries taken as 0: such a parameter is held).
    sse : callable
        θ → sum of squared residuals on the measured points [CoA²].
    lower, upper : ndarray
        Bounds; a draw outside is reflected back inside once, and rejected if still out.
    draws : int
        Number wanted.
    rng : numpy.random.Generator
    feasible : callable, optional
        θ → bool, a further constraint (Polach's kS ≤ kA).

    Returns
    -------
    thetas : ndarray, shape (m, p)
        θ̂ first, then the accepted draws (m ≤ draws).
    info : dict
        The threshold, the scale, the acceptance.
    """
    p = theta.size
    cov = np.where(np.isfinite(cov), cov, 0.0)
    cov = 0.5 * (cov + cov.T)
    # a standard error the data do not bound (J^T J near singular: thousands of times the
    # value) only wastes the proposals: capped at half the value (0.01 for a value near zero),
    # the correlations kept; the region's test decides what is plausible, not the cap
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    cap = np.maximum(0.5 * np.abs(theta), 0.01)
    shrink = np.where(sd > cap, cap / np.where(sd > 0, sd, 1.0), 1.0)
    cov = cov * np.outer(shrink, shrink)
    evals, evecs = np.linalg.eigh(cov)
    root = evecs * np.sqrt(np.clip(evals, 0.0, None))
    s0 = float(sse(theta))
    info = {"sse_fit": s0}

    def admissible(t):
        if np.any(t < lower) or np.any(t > upper):
            return False
        return True if feasible is None else bool(feasible(t))

    span = np.where(np.isfinite(upper - lower), upper - lower, np.inf)

    def reflect(batch):
        # a parameter at its bound (common where the data do not see it) would lose half its
        # draws; reflected back inside, it keeps them (a symmetric proposal on the bounded set)
        low = batch < lower
        batch = np.where(low, 2 * lower - batch, batch)
        high = batch > upper
        return np.where(high & np.isfinite(span), 2 * upper - batch, batch)

    def accept(batch, limit):
        out = []
        for t in reflect(batch):
            if admissible(t) and sse(t) <= limit:
                out.append(t)
        return out

    kept = [theta]
    n_points = info["points"] = int(getattr(sse, "points", 0))
    limit = beale_threshold(s0, n_points, p) if n_points > p else s0 * 4.0
    info["sse_limit"] = limit
    if not np.any(root) or not np.isfinite(s0):
        info.update(scale=0.0, acceptance=0.0)
        return np.array(kept), info
    chosen = None
    for scale in _SCALES:
        pilot = theta + scale * rng.standard_normal((_PILOT, p)) @ root.T
        ok = accept(pilot, limit)
        if len(ok) >= _MIN_ACCEPTANCE * _PILOT:
            chosen = scale
            kept.extend(ok)
            break
    if chosen is None:
        info.update(scale=0.0, acceptance=0.0)
        return np.array(kept), info
    tries = 0
    batch_size = max(draws - len(kept) + 1, 1)
    total, accepted = _PILOT, len(kept) - 1
    while len(kept) < draws and tries < 4:
        batch = theta + chosen * rng.standard_normal((batch_size, p)) @ root.T
        ok = accept(batch, limit)
        kept.extend(ok[: draws - len(kept)])
        total += batch_size
        accepted += len(ok)
        tries += 1
    info.update(scale=chosen, acceptance=accepted / max(total, 1))
    return np.array(kept), info
