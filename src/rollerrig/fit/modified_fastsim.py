"""Fit the modified FASTSIM's parameters (k0, α∞, β, μ0, A, B) to measured creep–CoA points.

The sibling of :func:`rollerrig.fit.polach.fit_polach` for the modified FASTSIM (Spiryagin,
Polach & Cole 2013; :func:`rollerrig.contact.fastsim.fastsim` with ``k0, alpha_inf, beta``):
the same bounded least squares, the same covariance and the same honesty checks
(identifiability from the covariance, slip-velocity coverage of A and B, residual structure,
distance from a known truth).

Model. At each point i (creepage ξ_i in Kalker's definition, slip velocity w_i, contact load
N_i) the CoA is F_x/N of the modified FASTSIM on the Hertzian ellipse of the contact, with
μ(w) = μ0 [(1 − A) e^(−B|w|) + A] (Polach 2005, eq. 8). Under Hertz scaling (a, b ∝ N^(1/3) at
a fixed a/b) the simplified theory depends on ξ and N only through ξ·G a b C11/(μ N)
∝ ξ N^(−1/3), and so does Spiryagin's ε; each point is therefore evaluated on the ellipse of a
reference load N_ref (the median) at the equivalent creepage ξ_i (N_i/N_ref)^(−1/3), which is
exact for the law and lets one FASTSIM pass take every point.

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
point's CoA to μ is taken numerically, d ln CoA / d ln μ0); serial structure of the residuals
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
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.contact.creep import friction_kernel as _friction_kernel
from rollerrig.contact.fastsim import FastsimGrid, fastsim, fastsim_grid
from rollerrig.contact.laws import FastsimParameters
from rollerrig.fit import diagnostics as _diag
from rollerrig.fit.diagnostics import (
    ResidualStructure,
    SlipVelocityCoverage,
    residual_structure,
)

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

MODIFIED_FASTSIM_PARAMETER_NAMES = (
    "k0",
    "alpha_inf",
    "beta",
    "static_friction",
    "limit_ratio",
    "friction_decay",
)
"""Order of the parameters in a fit's ``stderr``, ``covariance`` and ``correlation``."""

MAX_FIT_POINTS = 300
"""Most points the fit uses; above it every k-th point (sorted by creep) is taken [1]."""

_LOWER = np.array([1e-3, 0.0, 0.0, 1e-3, 1e-6, 0.0])
_UPPER = np.array([1.0, 1.0, 1000.0, 1.0, 1.0, 10.0])
_CORRELATION = 0.995
_RELATIVE_STDERR = 0.5
_CONDITION = 1e10
_JAC_STEP = 1e-4


class ModifiedFastsimFitWarning(UserWarning):
    """Fitted modified-FASTSIM parameters are poorly determined by the data."""


def _params(theta, name="fitted", source="fit_modified_fastsim") -> FastsimParameters:
    k0, al, be, mu0, a, b = (float(x) for x in theta)
    return FastsimParameters(mu0, a, b, k0=k0, alpha_inf=al, beta=be, name=name, source=source)


def _theta(p: FastsimParameters) -> np.ndarray:
    return np.array([p.k0, p.alpha_inf, p.beta, p.static_friction, p.limit_ratio, p.friction_decay])


def _coa_kernel(xi_eq, w, n_ref, a, b, g, nu, theta, grid, mu_scale=1.0):
    """CoA of the modified FASTSIM at equivalent creepages (no validation of the data)."""
    k0, al, be, mu0, aa, bb = theta
    mu = mu_scale * _friction_kernel(w, mu0, aa, bb)
    r = fastsim(
        xi_eq,
        semi_axis_x=a,
        semi_axis_y=b,
        normal_load=n_ref,
        shear_modulus=g,
        poisson=nu,
        friction=mu,
        k0=k0,
        alpha_inf=al,
        beta=be,
        grid=grid,
    )
    return r.fx / n_ref


def modified_fastsim_coa(
    creep,
    slip_velocity,
    normal_load,
    semi_axis_x,
    semi_axis_y,
    shear_modulus,
    poisson,
    parameters: FastsimParameters,
    *,
    reference_load=None,
    grid: FastsimGrid | None = None,
):
    """CoA F_x/N of the modified FASTSIM at points of possibly different loads.

    .. math:: \\mathrm{CoA}_i = \\frac{F_x(\\xi_i (N_i/N_\\mathrm{ref})^{-1/3},\\, w_i;\\,
              a, b, N_\\mathrm{ref})}{N_\\mathrm{ref}}

    exact under Hertz scaling (see the module notes).

    Parameters
    ----------
    creep : array_like
        Creepage ξ [-] in Kalker's definition (referred to the mean rolling speed).
    slip_velocity : array_like
        w [m/s] (only |w| enters μ).
    normal_load : float or array_like
        N [N] per point.
    semi_axis_x, semi_axis_y : float
        Hertzian a, b [m] at ``reference_load``.
    shear_modulus : float
        Combined G [Pa].
    poisson : float
        Combined ν [-].
    parameters : FastsimParameters
        k0, α∞, β, μ0, A, B.
    reference_load : float, optional
        Load of the given semi-axes [N]; default the median of ``normal_load``.
    grid : FastsimGrid, optional
        Discretisation (default ``fastsim_grid(30, 30)``).

    Returns
    -------
    numpy.ndarray
        CoA [-], the shape of ``creep``.

    Examples
    --------
    >>> from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM as P
    >>> c = modified_fastsim_coa([0.002, 0.02], [0.017, 0.17], 4300.0, 3.4e-3, 2.7e-3,
    ...                          8.08e10, 0.3, P)
    >>> [round(float(x), 3) for x in c]
    [0.267, 0.33]
    """
    s = require_finite("creep", creep, "-")
    w = np.broadcast_to(require_finite("slip_velocity", slip_velocity, "m/s"), s.shape)
    q = np.broadcast_to(require_positive("normal_load", normal_load, "N"), s.shape)
    n_ref = float(np.median(q)) if reference_load is None else float(reference_load)
    require_positive("reference_load", n_ref, "N")
    xi_eq = s * np.cbrt(n_ref / q)
    theta = _theta(parameters)
    g = fastsim_grid() if grid is None else grid
    out = _coa_kernel(
        xi_eq.ravel(), w.ravel(), n_ref, semi_axis_x, semi_axis_y, shear_modulus, poisson,
        theta, g,
    )  # fmt: skip
    return out.reshape(s.shape)


@dataclass(frozen=True)
class ModifiedFastsimFit:
    """Result of :func:`fit_modified_fastsim`.

    Attributes
    ----------
    parameters : FastsimParameters
        The fitted set.
    stderr : dict of str to float
        Standard errors by :data:`MODIFIED_FASTSIM_PARAMETER_NAMES` (inf where J^T J is
        singular) [units of the parameter].
    covariance, correlation : ndarray, shape (6, 6)
        Of (k0, α∞, β, μ0, A, B).
    residuals : ndarray
        Model minus measured CoA at each fitted point [-].
    rmse : float
        [-].
    dof : int
        n − 6.
    at_bound : tuple of str
        Parameters at a bound of the search.
    identifiable : bool
        False when a :class:`ModifiedFastsimFitWarning` was issued.
    problems : tuple of str
        Why not, one sentence each.
    success : bool
        Optimiser convergence.
    message : str
        Optimiser message.
    creep, slip_velocity, normal_load, coa : ndarray
        The fitted data (ξ [-], w [m/s], N [N], CoA [-]).
    semi_axis_x, semi_axis_y, shear_modulus, poisson, reference_load : float
        The contact the law was evaluated on (a, b [m] at N_ref [N]; G [Pa]; ν [-]).
    points_available : int
        Points given before thinning.
    residual_structure : ResidualStructure or None
    coverage : SlipVelocityCoverage or None
    grid : FastsimGrid
    """

    parameters: FastsimParameters
    stderr: dict
    covariance: np.ndarray
    correlation: np.ndarray
    residuals: np.ndarray
    rmse: float
    dof: int
    at_bound: tuple[str, ...]
    identifiable: bool
    problems: tuple[str, ...]
    success: bool
    message: str
    creep: np.ndarray = field(repr=False)
    slip_velocity: np.ndarray = field(repr=False)
    normal_load: np.ndarray = field(repr=False)
    coa: np.ndarray = field(repr=False)
    semi_axis_x: float = 0.0
    semi_axis_y: float = 0.0
    shear_modulus: float = 0.0
    poisson: float = 0.0
    reference_load: float = 0.0
    points_available: int = 0
    residual_structure: ResidualStructure | None = None
    coverage: SlipVelocityCoverage | None = None
    grid: FastsimGrid | None = field(default=None, repr=False)

    @property
    def values(self) -> dict[str, float]:
        """Fitted values by :data:`MODIFIED_FASTSIM_PARAMETER_NAMES`."""
        return dict(
            zip(MODIFIED_FASTSIM_PARAMETER_NAMES, _theta(self.parameters).tolist(), strict=True)
        )

    def confidence_interval(self, level: float = 0.95) -> dict[str, tuple[float, float]]:
        """Symmetric asymptotic interval of each parameter (t-distribution, ``dof``)."""
        q = float(stats.t.ppf(0.5 + 0.5 * level, max(self.dof, 1)))
        return {k: (v - q * self.stderr[k], v + q * self.stderr[k]) for k, v in self.values.items()}

    def curve(self, creep, slip_velocity=None, rolling_speed=None, normal_load=None):
        """Fitted CoA at Kalker creepages ``creep`` [-] on the fitted contact.

        ``slip_velocity`` [m/s] defaults to creep × ``rolling_speed`` [m/s] (default the
        median |w/ξ| of the data); ``normal_load`` [N] to the reference load.
        """
        s = require_finite("creep", creep, "-")
        if slip_velocity is None:
            if rolling_speed is None:
                ok = np.abs(self.creep) > 1e-6
                rolling_speed = float(np.median(np.abs(self.slip_velocity[ok] / self.creep[ok])))
            slip_velocity = s * rolling_speed
        q = self.reference_load if normal_load is None else normal_load
        return modified_fastsim_coa(
            s, slip_velocity, q, self.semi_axis_x, self.semi_axis_y, self.shear_modulus,
            self.poisson, self.parameters, reference_load=self.reference_load, grid=self.grid,
        )  # fmt: skip

    def truth_distance(self, truth: FastsimParameters, warn_sigma: float = 3.0) -> dict:
        """Distance of each fitted parameter from a known set, in standard errors [-]."""
        true = dict(zip(MODIFIED_FASTSIM_PARAMETER_NAMES, _theta(truth).tolist(), strict=True))
        out = {}
        for k, v in self.values.items():
            sd = float(self.stderr[k])
            row = {"true": true[k], "fitted": v, "stderr": sd if np.isfinite(sd) else None}
            if np.isfinite(sd) and sd > 0:
                row["sigma"] = abs(v - true[k]) / sd
                row["beyond_warn_sigma"] = bool(row["sigma"] > warn_sigma)
            else:
                row["sigma"] = None
                row["why"] = f"standard error is {sd!r}: no distance in standard errors"
                row["beyond_warn_sigma"] = False
            out[k] = row
        return out

    def summary(self) -> dict:
        """JSON-ready: values, standard errors (None with the reason when not finite), the
        correlation matrix, the honesty diagnostics."""
        stderr = {k: (float(v) if np.isfinite(v) else None) for k, v in self.stderr.items()}
        corr = np.where(np.isfinite(self.correlation), self.correlation, np.nan)
        out = {
            "law": "modified-fastsim",
            "parameters": {
                "k0 [-]": self.parameters.k0,
                "alpha_inf [-]": self.parameters.alpha_inf,
                "beta [-]": self.parameters.beta,
                "mu0 [-]": self.parameters.static_friction,
                "A [-]": self.parameters.limit_ratio,
                "B [s/m]": self.parameters.friction_decay,
            },
            "stderr": stderr,
            "correlation": {
                "order": list(MODIFIED_FASTSIM_PARAMETER_NAMES),
                "matrix": [[None if not np.isfinite(x) else float(x) for x in row] for row in corr],
            },
            "rmse [-]": self.rmse,
            "dof": self.dof,
            "points": int(self.creep.size),
            "points_available": self.points_available,
            "at_bound": list(self.at_bound),
            "identifiable": self.identifiable,
            "problems": list(self.problems),
            "contact": {
                "semi_axis_x [m]": self.semi_axis_x,
                "semi_axis_y [m]": self.semi_axis_y,
                "shear_modulus [Pa]": self.shear_modulus,
                "poisson [-]": self.poisson,
                "reference_load [N]": self.reference_load,
            },
            "residual_structure": None
            if self.residual_structure is None
            else self.residual_structure.as_dict(),
            "slip_velocity_coverage": None if self.coverage is None else self.coverage.as_dict(),
            "success": self.success,
        }
        if any(v is None for v in stderr.values()):
            out["stderr_null_because"] = "J^T J singular: not determined by the data"
        return out


def _jacobian(fun, theta):
    jac = None
    for j in range(theta.size):
        h = _JAC_STEP * max(abs(theta[j]), 1e-2)
        up, dn = min(theta[j] + h, _UPPER[j]), max(theta[j] - h, _LOWER[j])
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
    q = np.broadcast_to(require_positive("normal_load", normal_load, "N"), s.shape).astype(float)
    if slip_velocity is None:
        if rolling_speed is None:
            raise ParameterError("give slip_velocity [m/s] or rolling_speed [m/s]")
        v = np.broadcast_to(require_positive("rolling_speed", rolling_speed, "m/s"), s.shape)
        w = s * v
    else:
        w = np.broadcast_to(require_finite("slip_velocity", slip_velocity, "m/s"), s.shape)
        w = w.astype(float)
    a = float(require_positive("semi_axis_x", semi_axis_x, "m"))
    b = float(require_positive("semi_axis_y", semi_axis_y, "m"))
    g_mod = float(require_positive("shear_modulus", shear_modulus, "Pa"))
    nu = float(poisson)
    n_ref = float(np.median(q)) if reference_load is None else float(reference_load)
    require_positive("reference_load", n_ref, "N")
    grid = fastsim_grid() if grid is None else grid
    if int(max_points) < 7:
        raise ParameterError(f"max_points must be at least 7, got {max_points!r}")
    order = np.argsort(s, kind="stable")
    step = max(1, int(np.ceil(n_given / int(max_points))))
    keep = order[::step]
    s, y, q, w = s[keep], y[keep], q[keep], w[keep]
    n = s.size
    xi_eq = s * np.cbrt(n_ref / q)

    def model(theta, mu_scale=1.0):
        return _coa_kernel(xi_eq, w, n_ref, a, b, g_mod, nu, theta, grid, mu_scale)

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
        start = np.clip(start, _LOWER + 1e-6, _UPPER - 1e-6)
        sol = optimize.least_squares(
            residuals, start, bounds=(_LOWER, _UPPER), x_scale="jac", diff_step=_JAC_STEP,
            xtol=1e-10, ftol=1e-10, gtol=1e-10, max_nfev=400,
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

        start = np.clip(theta[free], _LOWER[free] + 1e-9, _UPPER[free] - 1e-9)
        sol5 = optimize.least_squares(
            res5, start, bounds=(_LOWER[free], _UPPER[free]), x_scale="jac",
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
    structure = None
    if float(np.sqrt(np.mean(res**2))) > 1e-9 * max(float(np.max(np.abs(y))), 1e-12):
        structure = residual_structure(res, s, order="creep")
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
        if theta[j] <= _LOWER[j] + 1e-7 or theta[j] >= _UPPER[j] - 1e-7
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


def _coverage(s, w, q, y, theta, model, best_cost, cost_with, ab_problems, n_ref, a, b, g, nu,
              grid) -> SlipVelocityCoverage:  # fmt: skip
    """The A/B coverage of :mod:`rollerrig.fit.diagnostics` for the modified FASTSIM.

    The sensitivity of a point's CoA to μ is taken numerically, η = d ln CoA / d ln μ0 (central
    difference, ±1 %); the peak and the falling branch from the fitted law at the median
    rolling speed; criteria and thresholds those of :mod:`rollerrig.fit.diagnostics`.
    """
    aw = np.abs(w)
    h = 0.01
    up, dn = model(theta, 1.0 + h), model(theta, 1.0 - h)
    base = model(theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(np.abs(base) > 0, (up - dn) / (2.0 * h * base), 0.0)
    saturated = eta >= _diag._SATURATION_SENSITIVITY
    n_sat = int(np.sum(saturated))
    sat_range = (float(aw[saturated].min()), float(aw[saturated].max())) if n_sat else None
    bb = float(theta[5])
    reached = 1.0 - float(np.exp(-bb * sat_range[1])) if sat_range else 0.0
    nz = np.abs(s) > 0
    ok = saturated & nz
    v = np.abs(w[ok] / s[ok]) if np.any(ok) else np.abs(w[nz] / s[nz])
    speed_ratio = float(np.percentile(v, 90) / np.percentile(v, 10)) if v.size else 1.0
    v_med = float(np.median(v)) if v.size else 1.0
    s_max = float(np.max(np.abs(s)))
    grid_s = np.linspace(s_max / 400, 2 * s_max, 400)
    curve = _coa_kernel(grid_s, grid_s * v_med, n_ref, a, b, g, nu, theta, grid)
    peak = float(grid_s[int(np.argmax(curve))])
    past_peak = s_max / peak
    # Past the peak: the fitted CoA falls with creep at the point's own rolling speed.
    xi_eq = s * np.cbrt(n_ref / q)
    hh = 1e-3
    c_up = _coa_kernel(xi_eq * (1 + hh), w * (1 + hh), n_ref, a, b, g, nu, theta, grid)
    c_dn = _coa_kernel(xi_eq * (1 - hh), w * (1 - hh), n_ref, a, b, g, nu, theta, grid)
    falling = int(np.sum(np.sign(s) * (c_up - c_dn) < 0))
    reasons = []
    if n_sat < _diag._MIN_SATURATED_POINTS:
        reasons.append(
            f"only {n_sat} point(s) where the contact saturates (CoA at least half proportional "
            f"to mu), {_diag._MIN_SATURATED_POINTS} needed"
        )
    if reached < 0.5:
        reasons.append(
            f"the saturated points reach {100 * reached:.0f} % of mu's fall from mu0 to A mu0 "
            f"(B w_max = {bb * (sat_range[1] if sat_range else 0.0):.3g}, "
            f"{_diag._MIN_FRICTION_FALL:.3g} needed): slip velocities too small for A"
        )
    if speed_ratio < _diag._MIN_SPEED_RATIO and past_peak < _diag._MIN_PAST_PEAK:
        reasons.append(
            f"one rolling speed ({v_med:.3g} m/s; 90/10 percentile ratio {speed_ratio:.2f}, "
            f"{_diag._MIN_SPEED_RATIO:g} needed) and creep only to {past_peak:.2f} x the peak "
            f"creep ({_diag._MIN_PAST_PEAK:g} needed): with w = v s the fall of mu(w) trades "
            "with the curve's shape (k0, alpha_inf, beta)"
        )
    rise = {}
    if cost_with is not None and n_sat >= _diag._MIN_SATURATED_POINTS and bb > 0:
        aa = float(theta[4])
        trials = [
            ("B/4", 2, bb / _diag._PROFILE_FACTOR),
            ("4B", 2, min(bb * _diag._PROFILE_FACTOR, float(_UPPER[5]))),
            (f"A-{_diag._PROFILE_A_STEP:g}", 1, aa - _diag._PROFILE_A_STEP),
            (f"A+{_diag._PROFILE_A_STEP:g}", 1, aa + _diag._PROFILE_A_STEP),
        ]
        for label, index, value in trials:
            if index == 1 and not 0.0 < value <= 1.0:
                continue
            cost = cost_with(index, value)
            rise[label] = (cost - best_cost) / best_cost if best_cost > 0 else float("inf")
        flat = [lbl for lbl, r in rise.items() if not r > _diag._PROFILE_COST_RISE]
        if flat:
            reasons.append(
                "the data hardly feel A and B: fixing "
                + " or ".join(f"{lbl} raises the cost by {100 * rise[lbl]:.1f} %" for lbl in flat)
                + f" (more than {100 * _diag._PROFILE_COST_RISE:.0f} % needed)"
            )
    elif cost_with is None:
        reasons.append("profile check of A and B not made (profile=False)")
    reasons.extend(ab_problems)
    rise = {k: (float(r) if np.isfinite(r) else None) for k, r in rise.items()}
    return SlipVelocityCoverage(
        slip_velocity_range=(float(aw.min()), float(aw.max())),
        saturated_points=n_sat,
        saturated_slip_velocity_range=sat_range,
        falling_branch_points=falling,
        rolling_speed_ratio=speed_ratio,
        creep_past_peak=past_peak,
        friction_fall_reached=reached,
        profile_cost_rise=rise,
        a_and_b_identifiable=not reasons,
        reasons=tuple(reasons),
    )


# Public names for the roller-to-track transfer (rollerrig.analysis.transfer).
coa_kernel = _coa_kernel
PARAMETER_LOWER = _LOWER
PARAMETER_UPPER = _UPPER
