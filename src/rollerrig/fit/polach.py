"""Fit Polach's creep-force parameters (μ0, A, B, k_A, k_S) to measured creep-CoA points.

The model (Polach's creep law with slip-velocity-dependent friction, Kayaalp eqs. 4.19-4.20)
and the creep stiffness of the rig's contact are in :mod:`rollerrig.fit.model`; what the data
constrain, the residual structure and the distance from a known truth, reported on every fit,
in :mod:`rollerrig.fit.diagnostics`.

Bounded least squares (:func:`scipy.optimize.least_squares`, trust-region reflective) in the
parameters θ = (μ0, A, B, k_A, r) with k_S = r·k_A, bounds μ0 > 0, 0 < A ≤ 1, B ≥ 0,
0 < k_A ≤ 1, 0 < r ≤ 1, so that Polach's 0 < k_S ≤ k_A ≤ 1 holds by construction.

Uncertainty: with the Jacobian J of the residuals in θ at the solution (central differences,
one-sided at a bound), cov(θ) = s²·(JᵀJ)⁻¹ with s² = Σr²/(n − 5) (with a robust loss, over
the points within 3 robust standard deviations of the median residual only); it is carried to
(μ0, A, B, k_A, k_S) by the delta method (k_S = r·k_A). Standard errors are the square roots of
the diagonal, the correlation matrix is cov_ij/(σ_i σ_j). The intervals are asymptotic
(t-distribution, n − 5 degrees of freedom) and assume independent residuals of equal variance;
at a bound they are one-sided in truth and the symmetric interval is only indicative. A
parameter along a direction the data do not see (an eigenvalue of the scaled JᵀJ below
1e-12 of the largest: B once A reaches 1, say) has an infinite standard error.
A :class:`PolachFitWarning` is issued when parameters are not identifiable: JᵀJ
(column-scaled) nearly singular (condition number above 1e10), a pair correlated beyond 0.995,
or a standard error above half the value — typically A and B when the slip velocities span too
small a range for μ(w) to bend (one rolling speed, low speed, creep not far past the peak). On
the default rig's contact at 4.3 kN, creep up to 10 % at two or three speeds between 10 and
60 km/h gives |corr(A, B)| ≈ 0.985; one speed (30 km/h) 0.9996; the twin's seed test 0.9986.
The warning also names the A/B coverage criteria that fail
(:func:`rollerrig.fit.diagnostics.slip_velocity_coverage`) and structured residuals
(:func:`rollerrig.fit.diagnostics.residual_structure`).

References
----------
.. [1] O. Polach, "Creep forces in simulations of traction vehicles running on adhesion limit",
   Wear 258 (2005) 992-1000.
.. [2] B.T. Kayaalp, dissertation (University of Pardubice), eqs. 4.19-4.20.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import optimize, stats

from rollerrig._validation import (
    ParameterError,
    did_you_mean,
    require_broadcastable,
    require_finite,
    require_positive,
)
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.creep import polach_force_kernel as _polach_force_kernel
from rollerrig.contact.curves import CreepCurve
from rollerrig.fit.diagnostics import (
    ResidualStructure,
    SlipVelocityCoverage,
    fit_residual_structure,
    residual_structure,
    slip_velocity_coverage,
    truth_distance,
)
from rollerrig.fit.model import PARAMETER_NAMES, creep_stiffness_for_rig, polach_coa

__all__ = [
    "PARAMETER_NAMES",
    "PolachFit",
    "PolachFitWarning",
    "ResidualStructure",
    "SlipVelocityCoverage",
    "creep_stiffness_for_rig",
    "fit_polach",
    "polach_coa",
    "residual_structure",
]

_SMALL = 1e-9  # lower bound standing in for the open "> 0" bounds
_IDENTIFIABILITY_CORRELATION = 0.995
_IDENTIFIABILITY_RELATIVE_STDERR = 0.5
_IDENTIFIABILITY_CONDITION = 1e10
_STOP_CORRELATION = 0.9999  # a pair this correlated: the data see one combination of the two
_LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")  # scipy's least_squares


class PolachFitWarning(UserWarning):
    """Fitted parameters are poorly determined by the data (see the message for which)."""


def _theta_to_parameters(theta) -> tuple[float, float, float, float, float]:
    mu0, a, b, ka, r = (float(x) for x in theta)
    return mu0, a, b, ka, r * ka


@dataclass(frozen=True)
class PolachFit:
    """Result of :func:`fit_polach`.

    Attributes
    ----------
    parameters : PolachParameters
        The fitted set.
    stderr : dict of str to float
        Standard errors by parameter name (:data:`PARAMETER_NAMES`) [units of the parameter].
    covariance : ndarray, shape (5, 5)
        Covariance of (μ0, A, B, k_A, k_S).
    correlation : ndarray, shape (5, 5)
        Correlation matrix of (μ0, A, B, k_A, k_S) [-].
    residuals : ndarray
        Model minus measured CoA at each point [-].
    rmse : float
        Root-mean-square of the residuals [-].
    dof : int
        Degrees of freedom of the covariance: n − 5 (inliers only with a robust loss).
    at_bound : tuple of str
        Parameters at a bound of the search (k_S at k_A counts as ``"k_slip"``).
    identifiable : bool
        False when a :class:`PolachFitWarning` was issued.
    success : bool
        Whether the optimiser reported convergence.
    message : str
        The optimiser's message.
    creep, slip_velocity, normal_load, creep_stiffness, coa : ndarray
        The data that were fitted.
    residual_structure : ResidualStructure or None
        Serial structure of the residuals ordered by creep (None for an exact fit).
    coverage : SlipVelocityCoverage or None
        Over which slip velocities the data constrain A and B, and whether they do.
    data_gain : ndarray, shape (5, n) or None
        Linearised change of (μ0, A, B, k_A, k_S) per unit change of each point's CoA
        (Gauss-Newton at the solution; 0 for a robust fit's outliers): how an error the points
        share moves the fit (:meth:`with_systematic`).
    stderr_statistical : dict or None
        The standard errors from the residuals' scatter alone, where :meth:`with_systematic`
        added the data's systematic errors to :attr:`stderr` (None: :attr:`stderr` is that).
    systematic : dict or None
        Input name -> the parameters' shifts (by :data:`PARAMETER_NAMES`) for a one-standard-
        uncertainty error of that input, as added by :meth:`with_systematic`.
    """

    parameters: PolachParameters
    stderr: dict
    covariance: np.ndarray
    correlation: np.ndarray
    residuals: np.ndarray
    rmse: float
    dof: int
    at_bound: tuple[str, ...]
    identifiable: bool
    success: bool
    message: str
    creep: np.ndarray = field(repr=False)
    slip_velocity: np.ndarray = field(repr=False)
    normal_load: np.ndarray = field(repr=False)
    creep_stiffness: np.ndarray = field(repr=False)
    coa: np.ndarray = field(repr=False)
    residual_structure: ResidualStructure | None = None
    coverage: SlipVelocityCoverage | None = None
    data_gain: np.ndarray | None = field(default=None, repr=False)
    stderr_statistical: dict | None = None
    systematic: dict | None = None

    def with_systematic(self, errors: dict) -> PolachFit:
        """This fit with the data's systematic errors in its covariance and standard errors.

        The standard errors of :func:`fit_polach` come from the residuals' scatter: they cover
        the noise, not an error every point shares (a sensor's class, the air spring's area,
        the roller's radius), which moves the whole curve and so the parameters (μ0 by the
        CoA's scale error: 3-50 times the scatter's standard errors on the bundled test). Each
        input's shift of the parameters, G e with G the fit's linearised :attr:`data_gain`,
        adds G e eᵀ Gᵀ to the covariance (JCGM 100 §5.1.2, independent inputs).

        Parameters
        ----------
        errors : dict of str to ndarray
            Input name -> the change of each fitted point's CoA for a one-standard-uncertainty
            error of that input [-] (independent inputs; correlated ones as independent
            combinations).

        Returns
        -------
        PolachFit
            With :attr:`stderr` and :attr:`covariance` the total, :attr:`stderr_statistical`
            the scatter's alone and :attr:`systematic` each input's shifts. Parameters the data
            do not determine keep an infinite standard error.
        """
        if self.data_gain is None or not errors:
            return self
        shifts = {name: self.data_gain @ np.asarray(e, dtype=float) for name, e in errors.items()}
        added = sum(np.outer(d, d) for d in shifts.values())
        cov = self.covariance + added
        old = np.array([self.stderr[k] for k in PARAMETER_NAMES])
        sd = np.where(np.isfinite(old), np.sqrt(np.clip(np.diag(cov), 0.0, None)), old)
        with np.errstate(divide="ignore", invalid="ignore"):
            corr = cov / np.outer(sd, sd)
        corr[~np.isfinite(old), :] = corr[:, ~np.isfinite(old)] = np.nan
        return replace(
            self,
            stderr=dict(zip(PARAMETER_NAMES, sd.tolist(), strict=True)),
            covariance=cov,
            correlation=corr,
            stderr_statistical=dict(self.stderr),
            systematic={
                name: dict(zip(PARAMETER_NAMES, d.tolist(), strict=True))
                for name, d in shifts.items()
            },
        )

    def truth_distance(self, truth, warn_sigma: float = 3.0) -> dict:
        """Distance of each fitted parameter from a known truth, in standard errors.

        See :func:`rollerrig.fit.diagnostics.truth_distance` (``truth``: PolachParameters or a
        mapping by :data:`PARAMETER_NAMES`; ``warn_sigma`` [-]).
        """
        return truth_distance(self, truth, warn_sigma)

    def unidentified(self) -> tuple[str, ...]:
        """Parameters the data do not pin down: A and B (``"limit_ratio"``,
        ``"friction_decay"``) where :attr:`coverage` says they are not identifiable; their
        standard errors are then the curvature of an undetermined fit, not an uncertainty."""
        if self.coverage is not None and not self.coverage.a_and_b_identifiable:
            return ("limit_ratio", "friction_decay")
        return ()

    def shown(self, name: str) -> str:
        """``"value ± stderr"`` of parameter ``name`` for a table, or ``"value (not
        identifiable)"`` where the data do not pin it down (:meth:`unidentified`): A at
        0.7553 +- 0.0066 had read as a tight 53.5 σ from a truth of 0.4."""
        value = dict(zip(PARAMETER_NAMES, self.parameters.as_tuple(), strict=True))[name]
        if name in self.unidentified():
            return f"{value:.4g} (not identifiable)"
        return f"{value:.4g} ± {self.stderr[name]:.2g}"

    def confidence_interval(self, level: float = 0.95) -> dict[str, tuple[float, float]]:
        """Symmetric asymptotic interval of each parameter (t-distribution, ``dof``)."""
        q = float(stats.t.ppf(0.5 + 0.5 * level, max(self.dof, 1)))
        values = dict(zip(PARAMETER_NAMES, self.parameters.as_tuple(), strict=True))
        return {k: (values[k] - q * self.stderr[k], values[k] + q * self.stderr[k]) for k in values}

    def curve(self, creep, slip_velocity=None, rolling_speed=None, normal_load=None):
        """Fitted CoA at ``creep`` [-].

        Parameters
        ----------
        creep : array_like
            s [-].
        slip_velocity : array_like, optional
            w [m/s]; default ``creep × rolling_speed``.
        rolling_speed : float, optional
            v [m/s]; default the median |w|/|s| of the fitted data.
        normal_load : float, optional
            Q [N]; default the median load of the fitted data (with its creep stiffness
            scaled by (Q/Q_median)^(2/3), as the Hertz semi-axes scale).
        """
        s = require_finite("creep", creep, "-")
        if slip_velocity is None:
            if rolling_speed is None:
                ok = np.abs(self.creep) > 1e-6
                rolling_speed = float(np.median(np.abs(self.slip_velocity[ok] / self.creep[ok])))
            slip_velocity = s * rolling_speed
        q_med = float(np.median(self.normal_load))
        k_med = float(np.median(self.creep_stiffness))
        q = q_med if normal_load is None else float(normal_load)
        k = k_med * (q / q_med) ** (2.0 / 3.0)
        return polach_coa(s, slip_velocity, q, k, self.parameters)


def _jacobian(fun, theta, lower, upper):
    """Central differences, one-sided next to a bound."""
    theta = np.asarray(theta, dtype=float)
    jac = np.empty((fun(theta).size, theta.size))
    for j in range(theta.size):
        h = 1e-6 * max(abs(theta[j]), 1e-3)
        up = min(theta[j] + h, upper[j])
        dn = max(theta[j] - h, lower[j])
        tp, tm = theta.copy(), theta.copy()
        tp[j], tm[j] = up, dn
        jac[:, j] = (fun(tp) - fun(tm)) / (up - dn)
    return jac


_UNSEEN_EIGENVALUE = 1e-12
"""Directions of the column-scaled J^T J whose eigenvalue is below this fraction of the largest
are taken as unseen by the data: there the pseudo-inverse's variance is rounding, not data
(it drops them below about 1e-15), so a parameter along them has no finite standard error."""


def _unseen_parameters(jtj: np.ndarray) -> np.ndarray:
    """Which parameters of the column-scaled ``jtj`` take part (a component above 1e-3) in a
    direction the data do not see (:data:`_UNSEEN_EIGENVALUE`)."""
    values, vectors = np.linalg.eigh(jtj)
    null = values <= max(float(values[-1]), 0.0) * _UNSEEN_EIGENVALUE
    return np.any(np.abs(vectors[:, null]) > 1e-3, axis=1)


def _undetermined(fun, theta, lower, upper) -> str:
    """What the data do not determine at ``theta`` (scaled J^T J nearly singular, a pair
    correlated beyond :data:`_STOP_CORRELATION`), or ``""``: the test that decides whether a
    fit is polished. Stricter than the warning's (:data:`_IDENTIFIABILITY_CORRELATION`): a
    fit whose parameters are merely poorly determined is still polished, as before."""
    jac = _jacobian(fun, theta, lower, upper)
    scale = np.linalg.norm(jac, axis=0)
    scale[scale == 0] = 1.0
    jtj = (jac / scale).T @ (jac / scale)
    cond = float(np.linalg.cond(jtj))
    if not np.isfinite(cond) or cond > _IDENTIFIABILITY_CONDITION:
        return f"all five parameters (J^T J condition number {cond:.3g})"
    cov = np.linalg.pinv(jtj)
    sd = np.sqrt(np.clip(np.diag(cov), 1e-300, None))
    corr = np.abs(cov / np.outer(sd, sd))
    np.fill_diagonal(corr, 0.0)
    i, j = np.unravel_index(int(np.argmax(corr)), corr.shape)
    if corr[i, j] > _STOP_CORRELATION:
        names = (*PARAMETER_NAMES[:4], "k_slip/k_adhesion")  # θ holds the ratio kS/kA
        return f"{names[i]} apart from {names[j]} (correlation {corr[i, j]:.4f})"
    return ""


def fit_polach(
    creep,
    coa,
    normal_load,
    creep_stiffness,
    slip_velocity=None,
    rolling_speed=None,
    *,
    initial: PolachParameters | None = None,
    loss: str = "linear",
    f_scale: float = 0.01,
    name: str = "fitted",
) -> PolachFit:
    """Fit Polach's parameters to creep-CoA points.

    Parameters
    ----------
    creep : array_like, shape (n,)
        Creep s [-] at each point, nonzero at 6 points at least (a point at zero creep
        constrains no parameter).
    coa : array_like, shape (n,)
        Measured CoA F/Q [-].
    normal_load : float or array_like
        Q [N] (scalar or per point).
    creep_stiffness : float, array_like or CreepCurve
        G a b c11 [N] at the load (scalar or per point), or a :class:`CreepCurve` whose
        ``creep_stiffness`` (scaled by (Q/Q_curve)^(2/3) per point) is used; see
        :func:`creep_stiffness_for_rig`.
    slip_velocity : array_like, optional
        w [m/s] at each point; default ``creep × rolling_speed``.
    rolling_speed : float or array_like, optional
        v [m/s], needed when ``slip_velocity`` is not given.
    initial : PolachParameters, optional
        Starting point; default a neutral set (μ0 from the largest |CoA|, A = 0.5, B = 0.3,
        k_A = 0.7, k_S = 0.35).
    loss : str
        ``"linear"`` (least squares) or a robust loss of :func:`scipy.optimize.least_squares`
        (``"soft_l1"``, ``"huber"``, ``"cauchy"``, ``"arctan"``), or a callable as it takes.
    f_scale : float
        Residual scale of the robust loss [-], > 0 (ignored by ``"linear"``).
    name : str
        Name of the fitted :class:`PolachParameters`.

    Returns
    -------
    PolachFit

    Warns
    -----
    PolachFitWarning
        When parameters are not identifiable from the data. A fit whose parameters the data
        cannot separate at all (J^T J singular, or two of them correlated beyond 0.9999) stops
        at the optimiser's default tolerances instead of being polished to 1e-15, and the
        warning and ``message`` say so.

    Examples
    --------
    Exact points of the dry set at two speeds:

    >>> from rollerrig.contact.creep import POLACH_DRY
    >>> s = np.tile(np.linspace(0.0005, 0.08, 40), 2)
    >>> v = np.repeat([30 / 3.6, 60 / 3.6], 40)
    >>> k = 1.1295e6
    >>> mu = polach_coa(s, s * v, 4300.0, k, POLACH_DRY)
    >>> fit = fit_polach(s, mu, 4300.0, k, slip_velocity=s * v)
    >>> round(fit.parameters.static_friction, 6), round(fit.parameters.k_slip, 6)
    (0.55, 0.4)
    """
    if not (callable(loss) or (isinstance(loss, str) and loss in _LOSSES)):
        hint = did_you_mean(loss, _LOSSES) if isinstance(loss, str) else ""
        raise ParameterError(
            f"loss must be one of {', '.join(map(repr, _LOSSES))} (or a callable, as "
            f"scipy.optimize.least_squares takes), got {loss!r}{hint}"
        )
    f_scale_arr = require_positive("f_scale", f_scale, "-")
    if f_scale_arr.ndim:
        raise ParameterError(
            f"f_scale must be a single number > 0 [-], got shape {f_scale_arr.shape}"
        )
    f_scale = float(f_scale_arr)
    s = require_finite("creep", creep, "-").reshape(-1)
    y = require_finite("coa", coa, "-").reshape(-1)
    if s.shape != y.shape:
        raise ParameterError(f"creep {s.shape} and coa {y.shape} must have the same length")
    n = s.size
    if n < 6:
        raise ParameterError(f"need at least 6 points to fit 5 parameters, got {n}")
    moving = int(np.count_nonzero(s))
    if moving < 6:
        # At zero creep the model's CoA is 0 whatever the parameters: such a point constrains
        # none of them (all of them zero had ended in a ZeroDivisionError in the diagnostics).
        raise ParameterError(
            f"creep must be nonzero [-] at 6 points at least to fit 5 parameters (at zero creep "
            f"the model's CoA is 0 whatever the parameters), got {moving} of {n}"
        )

    def per_point(name: str, value, unit: str, check=require_positive) -> np.ndarray:
        # One value per point or one for all: creep's length or a single number, named in
        # the message where it is neither (numpy's own broadcast error names nothing).
        arr = check(name, value, unit)
        arr = arr.reshape(-1) if arr.ndim else arr
        return require_broadcastable(creep=s, **{name: arr})[1].astype(float)

    q = per_point("normal_load", normal_load, "N")
    if isinstance(creep_stiffness, CreepCurve):
        k = creep_stiffness.creep_stiffness * (q / creep_stiffness.normal_load) ** (2.0 / 3.0)
    else:
        k = per_point("creep_stiffness", creep_stiffness, "N")
    if slip_velocity is None:
        if rolling_speed is None:
            raise ParameterError("give slip_velocity [m/s] or rolling_speed [m/s]")
        w = s * per_point("rolling_speed", rolling_speed, "m/s")
    else:
        w = per_point("slip_velocity", slip_velocity, "m/s", require_finite)

    if initial is None:
        mu0_guess = float(np.clip(np.max(np.abs(y)) * 1.1, 0.05, 2.0))
        theta0 = np.array([mu0_guess, 0.5, 0.3, 0.7, 0.5])
    else:
        p = initial
        theta0 = np.array(
            [p.static_friction, p.limit_ratio, p.friction_decay, p.k_adhesion,
             p.k_slip / p.k_adhesion]
        )  # fmt: skip
    lower = np.array([_SMALL, _SMALL, 0.0, _SMALL, _SMALL])
    upper = np.array([np.inf, 1.0, np.inf, 1.0, 1.0])
    theta0 = np.clip(theta0, lower + 1e-6, np.minimum(upper - 1e-6, 1e6))

    def residuals(theta):
        mu0, a, b, ka, r = theta
        return _polach_force_kernel(s, w, q, k, mu0, a, b, ka, r * ka) / q - y

    # First at the optimiser's default tolerances; polished to 1e-15 only when the data
    # determine the parameters there. Where they do not, further iterations only move along
    # directions the data cannot see (thousands of evaluations for nothing): stopped, and said.
    common = {"bounds": (lower, upper), "loss": loss, "f_scale": f_scale, "x_scale": "jac"}
    sol = optimize.least_squares(residuals, theta0, max_nfev=2000, **common)
    undetermined = _undetermined(residuals, sol.x, lower, upper)
    stopped_early = ""
    if undetermined:
        stopped_early = (
            f"the fit stopped at the optimiser's default tolerances after {sol.nfev} "
            f"evaluations, not polished, since the data do not determine {undetermined}"
        )
    else:
        sol = optimize.least_squares(
            residuals, sol.x, xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=20000, **common
        )
    theta = sol.x
    res = residuals(theta)
    jac = _jacobian(residuals, theta, lower, upper)
    inlier = np.ones(n, dtype=bool)
    if loss != "linear":
        # Robust fit: the covariance is taken on the points within 3 robust standard
        # deviations (1.4826 x MAD) of the median residual; the outliers would inflate s^2.
        dev = np.abs(res - np.median(res))
        sigma = 1.4826 * float(np.median(dev))
        if sigma > 0:
            inlier = dev <= 3.0 * sigma
    dof = max(int(inlier.sum()) - 5, 1)
    s2 = float(res[inlier] @ res[inlier]) / dof
    jac = jac[inlier]
    # Delta method: d(mu0, A, B, kA, kS)/d(theta).
    transform = np.eye(5)
    transform[4, 3], transform[4, 4] = theta[4], theta[3]
    scale = np.linalg.norm(jac, axis=0)
    scale[scale == 0] = 1.0
    js = jac / scale
    jtj = js.T @ js
    cond = float(np.linalg.cond(jtj))
    cov_scaled = np.linalg.pinv(jtj)
    # Gauss-Newton: data y + dy move theta by (J^T J)^+ J^T dy (the residuals are model - y).
    gain = np.zeros((5, n))
    gain[:, inlier] = transform @ ((cov_scaled @ js.T) / scale[:, None])
    cov_theta = s2 * cov_scaled / np.outer(scale, scale)
    cov = transform @ cov_theta @ transform.T
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    singular = not np.isfinite(cond) or cond > _IDENTIFIABILITY_CONDITION
    # The pseudo-inverse drops the directions the data do not see: a parameter that moves
    # along one of them (a zero Jacobian column, e.g. B once A reaches 1) would keep the
    # rounding remainder as its standard error and correlations beyond +-1. It is
    # undetermined: standard error infinite, correlations undefined.
    unseen = _unseen_parameters(jtj) if singular else np.zeros(5, dtype=bool)
    unseen[4] |= unseen[3]  # k_S = r k_A
    with np.errstate(divide="ignore", invalid="ignore"):
        corr = cov / np.outer(sd, sd)
    corr[unseen, :] = corr[:, unseen] = np.nan
    problems = []
    if singular:
        problems.append(f"J^T J is nearly singular (condition number {cond:.3g})")
        sd = np.where((sd == 0) | unseen, np.inf, sd)
    for i in range(5):
        for j in range(i + 1, 5):
            if np.isfinite(corr[i, j]) and abs(corr[i, j]) > _IDENTIFIABILITY_CORRELATION:
                problems.append(
                    f"{PARAMETER_NAMES[i]} and {PARAMETER_NAMES[j]} are correlated "
                    f"({corr[i, j]:+.4f})"
                )
    values = np.array(_theta_to_parameters(theta))
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = sd / np.abs(values)
    for i in np.flatnonzero(~(relative <= _IDENTIFIABILITY_RELATIVE_STDERR)):
        problems.append(
            f"{PARAMETER_NAMES[i]} has a standard error of {relative[i]:.3g} x its value"
            if np.isfinite(relative[i])
            else f"{PARAMETER_NAMES[i]} is not determined at all (no finite standard error)"
        )
    ab_covariance_problems = [p for p in problems if "limit_ratio" in p or "friction_decay" in p]

    def cost_with(index: int, value: float) -> float:
        """Cost of the best fit with θ[index] (1: A, 2: B) fixed at ``value``."""
        free = [i for i in range(5) if i != index]
        lo4, hi4 = lower[free], upper[free]
        start = np.clip(theta[free], lo4 + 1e-9, np.minimum(hi4 - 1e-9, 1e6))

        def res4(t4):
            full = np.empty(5)
            full[free], full[index] = t4, value
            mu0_, a_, b_, ka_, r_ = full
            return _polach_force_kernel(s, w, q, k, mu0_, a_, b_, ka_, r_ * ka_) / q - y

        sol4 = optimize.least_squares(
            res4, start, bounds=(lo4, hi4), loss=loss, f_scale=f_scale, x_scale="jac",
            max_nfev=2000,
        )  # fmt: skip
        r4 = sol4.fun[inlier]  # over the covariance's inliers, as the best fit's cost below
        return 0.5 * float(r4 @ r4)

    coverage = slip_velocity_coverage(
        s, w, q, k, _theta_to_parameters(theta), 0.5 * float(res[inlier] @ res[inlier]), cost_with,
        ab_covariance_problems,
    )  # fmt: skip
    own = [r for r in coverage.reasons if r not in ab_covariance_problems]
    if own:
        problems.append("A and B are not constrained by the data (" + "; ".join(own) + ")")
    structure = fit_residual_structure(res, s, y)
    span = float(np.ptp(np.abs(w)))
    if structure is not None and structure.structured:
        warnings.warn(
            "Polach fit residuals are structured, the model misses a systematic part of the "
            f"data: {structure.describe()}; the standard errors assume independent residuals.",
            PolachFitWarning,
            stacklevel=2,
        )
    if problems and stopped_early:
        problems.append(stopped_early)
    if problems:
        warnings.warn(
            "Polach parameters poorly determined by the data: "
            + "; ".join(problems)
            + f". Slip velocity spans {span:.3g} m/s; A and B need a wide range of slip "
            "velocities (several rolling speeds, or creep well past the peak).",
            PolachFitWarning,
            stacklevel=2,
        )
    tol = 1e-7
    at_bound = []
    names_theta = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
    for j, nm in enumerate(names_theta):
        if theta[j] <= lower[j] + tol or theta[j] >= upper[j] - tol:
            at_bound.append(nm)
    mu0, a, b, ka, ks = _theta_to_parameters(theta)
    params = PolachParameters(mu0, a, b, ka, min(ks, ka), name=name, source="fit_polach")
    return PolachFit(
        parameters=params,
        stderr=dict(zip(PARAMETER_NAMES, sd.tolist(), strict=True)),
        covariance=cov,
        correlation=corr,
        residuals=res,
        rmse=float(np.sqrt(np.mean(res**2))),
        dof=dof,
        at_bound=tuple(at_bound),
        identifiable=not problems,
        success=bool(sol.success),
        message=str(sol.message) + (f" ({stopped_early})" if stopped_early else ""),
        creep=s,
        slip_velocity=w,
        normal_load=q,
        creep_stiffness=k,
        coa=y,
        residual_structure=structure,
        coverage=coverage,
        data_gain=gain,
    )
