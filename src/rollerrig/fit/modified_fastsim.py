"""Fit the modified FASTSIM's parameters (k0, α∞, β, μ0, A, B) to measured creep–CoA points.

The sibling of :func:`rollerrig.fit.polach.fit_polach` for the modified FASTSIM (Spiryagin,
Polach & Cole 2013; :func:`rollerrig.contact.fastsim.fastsim` with ``k0, alpha_inf, beta``):
the same bounded least squares, the same covariance and the same honesty checks
(identifiability from the covariance, slip-velocity coverage of A and B, residual structure,
distance from a known truth).

Model. :mod:`rollerrig.fit.modified_fastsim_model`: each point evaluated on the ellipse of a
reference load at its equivalent creepage, which is exact for the law and lets one FASTSIM pass
take every point. The result: :mod:`rollerrig.fit.modified_fastsim_result`.

Fit. :func:`scipy.optimize.least_squares` (trust-region reflective) in θ = (k0, α∞, β, μ0, A,
B), bounds 0 < k0 ≤ 1, 0 ≤ α∞ ≤ 1, 0 ≤ β ≤ 1000, 0 < μ0 ≤ 1, 0 < A ≤ 1, 0 ≤ B ≤ 10 s/m (dry
steel on steel has μ0 below 1, published B are 0.1-1 s/m: a parameter at these bounds is the
data's lack of information, reported in ``at_bound``), started
from the measured initial slope (k0) and several (α∞, β) (the best start kept). FASTSIM's
force is piecewise smooth in θ (elements enter the slip zone one by one), so the Jacobian is
taken by central differences with a relative step of 1e-4, not 1e-6. At most
:data:`MAX_FIT_POINTS` points are fitted (every k-th, stated).

Uncertainty and honesty, as :mod:`rollerrig.fit.polach`: cov(θ) = s²(JᵀJ)⁻¹, s² = Σr²/(n − 6);
a :class:`ModifiedFastsimFitWarning` when JᵀJ (column-scaled) is nearly singular (condition
above 1e10), a pair is correlated beyond 0.995 or a standard error exceeds half its value; the
slip-velocity coverage of A and B (:class:`~rollerrig.fit.diagnostics.SlipVelocityCoverage`,
with the criteria and thresholds of :mod:`rollerrig.fit.diagnostics`: the sensitivity of each
point's CoA to μ is taken numerically, d ln CoA / d ln μ0:
:mod:`rollerrig.fit.modified_fastsim_coverage`); serial structure of the residuals
(:func:`~rollerrig.fit.diagnostics.residual_structure`). k0, α∞ and β are expected to trade
with each other and with μ0 on one curve at one speed: the warning then names the pairs.

References
----------
.. [1] M. Spiryagin, O. Polach, C. Cole, "Creep force modelling for rail traction vehicles
   based on the Fastsim algorithm", Vehicle System Dynamics 51 (2013) 1765-1783.
.. [2] J.J. Kalker, "A fast algorithm for the simplified theory of rolling contact", Vehicle
   System Dynamics 11 (1982) 1-13.
.. [3] O. Polach, Wear 258 (2005) 992-1000 (the friction law μ(w)).
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy import optimize

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_positive,
    require_whole,
)
from rollerrig.contact.ellipse_grid import FastsimGrid, fastsim_grid
from rollerrig.contact.laws import FastsimParameters
from rollerrig.fit.diagnostics import fit_residual_structure
from rollerrig.fit.modified_fastsim_coverage import _coverage
from rollerrig.fit.modified_fastsim_model import (
    MODIFIED_FASTSIM_PARAMETER_NAMES,
    PARAMETER_LOWER,
    PARAMETER_UPPER,
    _params,
    _theta,
    coa_kernel,
    modified_fastsim_coa,
)
from rollerrig.fit.modified_fastsim_result import ModifiedFastsimFit

# The fit is defined here; the law (names, bounds, CoA) and the result are importable from here
# as from their own modules.
__all__ = [
    "MAX_FIT_POINTS",
    "MODIFIED_FASTSIM_PARAMETER_NAMES",
    "PARAMETER_LOWER",
    "PARAMETER_UPPER",
    "ModifiedFastsimFit",
    "ModifiedFastsimFitWarning",
    "coa_kernel",
    "fit_modified_fastsim",
    "modified_fastsim_coa",
]

MAX_FIT_POINTS = 300
"""Most points the fit uses; above it every k-th point (sorted by creep) is taken [-]."""

_CORRELATION = 0.995
_RELATIVE_STDERR = 0.5
_CONDITION = 1e10
_JAC_STEP = 1e-4


class ModifiedFastsimFitWarning(UserWarning):
    """Fitted modified-FASTSIM parameters are poorly determined by the data."""


def _jacobian(fun, theta):
    jac = None
    for j in range(theta.size):
        h = _JAC_STEP * max(abs(theta[j]), 1e-2)
        up, dn = min(theta[j] + h, PARAMETER_UPPER[j]), max(theta[j] - h, PARAMETER_LOWER[j])
        tp, tm = theta.copy(), theta.copy()
        tp[j], tm[j] = up, dn
        col = (fun(tp) - fun(tm)) / (up - dn)
        if jac is None:
            jac = np.empty((col.size, theta.size))
        jac[:, j] = col
    return jac


def fit_modified_fastsim(
    creep,
    coa,
    normal_load,
    semi_axis_x,
    semi_axis_y,
    shear_modulus,
    poisson,
    slip_velocity=None,
    rolling_speed=None,
    *,
    reference_load=None,
    initial: FastsimParameters | None = None,
    grid: FastsimGrid | None = None,
    max_points: int = MAX_FIT_POINTS,
    profile: bool = True,
    name: str = "fitted",
) -> ModifiedFastsimFit:
    """Fit k0, α∞, β and μ0, A, B of the modified FASTSIM to creep–CoA points.

    Parameters
    ----------
    creep : array_like, shape (n,)
        Creepage ξ [-], Kalker's (referred to the mean rolling speed; convert a rig's creep
        with :func:`rollerrig.contact.kinematics.kalker_creepage`).
    coa : array_like, shape (n,)
        Measured CoA F/N [-].
    normal_load : float or array_like
        N [N], scalar or per point.
    semi_axis_x, semi_axis_y : float
        Hertzian a, b [m] of the contact at ``reference_load``.
    shear_modulus : float
        Combined G [Pa].
    poisson : float
        Combined ν [-].
    slip_velocity : array_like, optional
        w [m/s]; default creep × ``rolling_speed``.
    rolling_speed : float or array_like, optional
        v [m/s], needed without ``slip_velocity``.
    reference_load : float, optional
        The load of a, b [N]; default the median load.
    initial : FastsimParameters, optional
        Start (default: k0 from the initial slope, several α∞, β tried).
    grid : FastsimGrid, optional
        Discretisation; default ``fastsim_grid(30, 30)``.
    max_points : int
        Most points fitted (every k-th above it, sorted by creep).
    profile : bool
        Compute the A/B profile check of the coverage (4 refits; slower).
    name : str
        Name of the fitted set.

    Returns
    -------
    ModifiedFastsimFit

    Warns
    -----
    ModifiedFastsimFitWarning
        Parameters poorly determined, A and B not constrained, or structured residuals.

    Examples
    --------
    Recover the Eurosprinter set from its own curve at two speeds (coarse grid for speed):

    >>> import warnings
    >>> from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM as P
    >>> from rollerrig.contact.fastsim import fastsim_grid
    >>> g = fastsim_grid(16, 16)
    >>> xi = np.tile(np.linspace(5e-4, 0.06, 30), 2)
    >>> w = xi * np.repeat([5.0, 20.0], 30)
    >>> y = modified_fastsim_coa(xi, w, 1e5, 6e-3, 5e-3, 8.08e10, 0.3, P, grid=g)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     f = fit_modified_fastsim(xi, y, 1e5, 6e-3, 5e-3, 8.08e10, 0.3, slip_velocity=w,
    ...                              grid=g, profile=False)
    >>> round(f.parameters.k0, 3), round(f.parameters.static_friction, 3)
    (0.54, 0.36)
    """
    s = require_finite("creep", creep, "-").reshape(-1)
    y = require_finite("coa", coa, "-").reshape(-1)
    if s.shape != y.shape:
        raise ParameterError(f"creep {s.shape} and coa {y.shape} must have the same length")
    n_given = s.size
    if n_given < 7:
        raise ParameterError(f"need at least 7 points to fit 6 parameters, got {n_given}")
    moving = int(np.count_nonzero(s))
    if moving < 7:
        # At zero creep the law's CoA is 0 whatever the parameters: such a point constrains
        # none of them (all of them zero had ended in a ZeroDivisionError).
        raise ParameterError(
            f"creep must be nonzero [-] at 7 points at least to fit 6 parameters (at zero creep "
            f"the law's CoA is 0 whatever the parameters), got {moving} of {n_given}"
        )

    def per_point(name: str, value, unit: str, check=require_positive) -> np.ndarray:
        # creep's length or a single number, named where it is neither (fit_polach's rule)
        arr = check(name, value, unit)
        arr = arr.reshape(-1) if arr.ndim else arr
        return require_broadcastable(creep=s, **{name: arr})[1].astype(float)

    q = per_point("normal_load", normal_load, "N")
    if slip_velocity is None:
        if rolling_speed is None:
            raise ParameterError("give slip_velocity [m/s] or rolling_speed [m/s]")
        w = s * per_point("rolling_speed", rolling_speed, "m/s")
    else:
        w = per_point("slip_velocity", slip_velocity, "m/s", require_finite)
    a = require_positive("semi_axis_x", semi_axis_x, "m", single=True)
    b = require_positive("semi_axis_y", semi_axis_y, "m", single=True)
    g_mod = require_positive("shear_modulus", shear_modulus, "Pa", single=True)
    nu = float(poisson)
    if reference_load is None:
        n_ref = float(np.median(q))
    else:
        n_ref = require_positive("reference_load", reference_load, "N", single=True)
    grid = fastsim_grid() if grid is None else grid
    if not isinstance(grid, FastsimGrid):
        raise ParameterError(
            f"grid must be a FastsimGrid (rollerrig.contact.ellipse_grid.fastsim_grid), got "
            f"{type(grid).__name__}"
        )
    max_points = require_whole("max_points", max_points, minimum=7)
    order = np.argsort(s, kind="stable")
    step = max(1, int(np.ceil(n_given / int(max_points))))
    keep = order[::step]
    s, y, q, w = s[keep], y[keep], q[keep], w[keep]
    n = s.size
    xi_eq = s * np.cbrt(n_ref / q)

    def model(theta, mu_scale=1.0):
        return coa_kernel(xi_eq, w, n_ref, a, b, g_mod, nu, theta, grid, mu_scale)

    def residuals(theta):
        return model(theta) - y

    from rollerrig.contact.kalker import kalker_coefficients

    c11 = float(kalker_coefficients(a / b, nu).c11)
    stiffness = g_mod * a * b * c11 / n_ref  # CoA per unit equivalent creepage at k = 1
    if initial is None:
        small = np.abs(y) < 0.3 * np.max(np.abs(y))
        small &= np.abs(xi_eq) > 0
        if np.count_nonzero(small) >= 2:
            slope = float(np.sum(y[small] * xi_eq[small]) / np.sum(xi_eq[small] ** 2))
        else:
            slope = stiffness
        k0 = float(np.clip(slope / stiffness, 0.01, 1.0))
        mu0 = float(np.clip(1.1 * np.max(np.abs(y)), 0.02, 0.99))
        starts = [
            np.array([k0, al, be, mu0 if b0 < 3 else min(1.2 * mu0, 0.99), a0, b0])
            for al, be, a0, b0 in (
                (0.5, 0.5, 0.5, 0.3),
                (0.2, 2.0, 0.7, 2.0),
                (0.3, 1.0, 0.75, 3.0),
            )
        ]
    else:
        starts = [_theta(initial)]
    best = None
    for start in starts:
        start = np.clip(start, PARAMETER_LOWER + 1e-6, PARAMETER_UPPER - 1e-6)
        sol = optimize.least_squares(
            residuals, start, bounds=(PARAMETER_LOWER, PARAMETER_UPPER), x_scale="jac",
            diff_step=_JAC_STEP, xtol=1e-10, ftol=1e-10, gtol=1e-10, max_nfev=400,
        )  # fmt: skip
        if best is None or sol.cost < best.cost:
            best = sol
    theta = best.x
    res = residuals(theta)
    jac = _jacobian(residuals, theta)
    dof = max(n - 6, 1)
    s2 = float(res @ res) / dof
    scale = np.linalg.norm(jac, axis=0)
    scale[scale == 0] = 1.0
    js = jac / scale
    jtj = js.T @ js
    cond = float(np.linalg.cond(jtj))
    cov = s2 * np.linalg.pinv(jtj) / np.outer(scale, scale)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(divide="ignore", invalid="ignore"):
        corr = cov / np.outer(sd, sd)
    names = MODIFIED_FASTSIM_PARAMETER_NAMES
    problems: list[str] = []
    if not np.isfinite(cond) or cond > _CONDITION:
        problems.append(f"J^T J is nearly singular (condition number {cond:.3g})")
        sd = np.where(sd == 0, np.inf, sd)
    for i in range(6):
        for j in range(i + 1, 6):
            if np.isfinite(corr[i, j]) and abs(corr[i, j]) > _CORRELATION:
                problems.append(f"{names[i]} and {names[j]} are correlated ({corr[i, j]:+.4f})")
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = sd / np.abs(theta)
    for i in np.flatnonzero(~(relative <= _RELATIVE_STDERR)):
        if theta[i] == 0.0 and names[i] in ("alpha_inf", "beta", "friction_decay"):
            # At its lower bound 0: the relative error is undefined; the bound is reported.
            continue
        problems.append(f"{names[i]} has a standard error of {relative[i]:.3g} x its value")
    ab_problems = [p for p in problems if "limit_ratio" in p or "friction_decay" in p]

    def cost_with(index: int, value: float) -> float:
        """Best cost with A (index 1) or B (index 2) fixed (Polach's numbering)."""
        k = 4 if index == 1 else 5
        free = [i for i in range(6) if i != k]

        def res5(t5):
            full = np.empty(6)
            full[free], full[k] = t5, value
            return residuals(full)

        start = np.clip(theta[free], PARAMETER_LOWER[free] + 1e-9, PARAMETER_UPPER[free] - 1e-9)
        sol5 = optimize.least_squares(
            res5, start, bounds=(PARAMETER_LOWER[free], PARAMETER_UPPER[free]), x_scale="jac",
            diff_step=_JAC_STEP, max_nfev=100,
        )  # fmt: skip
        return 0.5 * float(sol5.fun @ sol5.fun)

    coverage = _coverage(
        s, w, q, y, theta, model, 0.5 * float(res @ res), cost_with if profile else None,
        ab_problems, n_ref, a, b, g_mod, nu, grid,
    )  # fmt: skip
    own = [r for r in coverage.reasons if r not in ab_problems]
    if own:
        problems.append("A and B are not constrained by the data (" + "; ".join(own) + ")")
    structure = fit_residual_structure(res, s, y)
    if structure is not None and structure.structured:
        warnings.warn(
            "modified FASTSIM fit residuals are structured, the model misses a systematic part "
            f"of the data: {structure.describe()}; the standard errors assume independent "
            "residuals.",
            ModifiedFastsimFitWarning,
            stacklevel=2,
        )
    if problems:
        warnings.warn(
            "modified FASTSIM parameters poorly determined by the data: " + "; ".join(problems),
            ModifiedFastsimFitWarning,
            stacklevel=2,
        )
    at_bound = tuple(
        nm
        for j, nm in enumerate(names)
        if theta[j] <= PARAMETER_LOWER[j] + 1e-7 or theta[j] >= PARAMETER_UPPER[j] - 1e-7
    )
    return ModifiedFastsimFit(
        parameters=_params(theta, name=name),
        stderr=dict(zip(names, sd.tolist(), strict=True)),
        covariance=cov,
        correlation=corr,
        residuals=res,
        rmse=float(np.sqrt(np.mean(res**2))),
        dof=dof,
        at_bound=at_bound,
        identifiable=not problems,
        problems=tuple(problems),
        success=bool(best.success),
        message=str(best.message),
        creep=s,
        slip_velocity=w,
        normal_load=q,
        coa=y,
        semi_axis_x=a,
        semi_axis_y=b,
        shear_modulus=g_mod,
        poisson=nu,
        reference_load=n_ref,
        points_available=n_given,
        residual_structure=structure,
        coverage=coverage,
        grid=grid,
    )
