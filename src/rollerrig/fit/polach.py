"""Fit Polach's creep-force parameters (μ0, A, B, k_A, k_S) to measured creep-CoA points.

The model is Polach's creep law with slip-velocity-dependent friction (Polach 2005; Kayaalp
eqs. 4.19-4.20), evaluated by the same kernel as the twin
(:func:`rollerrig.contact.creep._polach_force_kernel`):

.. math::
    \\mathrm{CoA}(s, w) = \\frac{2\\mu}{\\pi}\\left(\\frac{k_A\\varepsilon}{1+(k_A\\varepsilon)^2}
        + \\arctan(k_S\\varepsilon)\\right),\\quad
    \\varepsilon = \\frac{\\pi}{4}\\frac{G a b c_{11}}{Q\\mu}s,\\quad
    \\mu = \\mu_0\\left[(1-A)e^{-B|w|} + A\\right]

with the creep stiffness G a b c11 [N] of the contact at each point's load (Hertz and Kalker;
:func:`creep_stiffness_for_rig`).

Bounded least squares (:func:`scipy.optimize.least_squares`, trust-region reflective) in the
parameters θ = (μ0, A, B, k_A, r) with k_S = r·k_A, bounds μ0 > 0, 0 < A ≤ 1, B ≥ 0,
0 < k_A ≤ 1, 0 < r ≤ 1, so that Polach's 0 < k_S ≤ k_A ≤ 1 holds by construction.

Uncertainty: with the Jacobian J of the residuals in θ at the solution (central differences,
one-sided at a bound), cov(θ) = s²·(JᵀJ)⁻¹ with s² = Σr²/(n − 5) (with a robust loss, over
the points within 3 robust standard deviations of the median residual only); it is carried to
(μ0, A, B, k_A, k_S) by the delta method (k_S = r·k_A). Standard errors are the square roots of
the diagonal, the correlation matrix is cov_ij/(σ_i σ_j). The intervals are asymptotic
(t-distribution, n − 5 degrees of freedom) and assume independent residuals of equal variance;
at a bound they are one-sided in truth and the symmetric interval is only indicative.
A :class:`PolachFitWarning` is issued when parameters are not identifiable: JᵀJ
(column-scaled) nearly singular (condition number above 1e10), a pair correlated beyond 0.995,
or a standard error above half the value — typically A and B when the slip velocities span too
small a range for μ(w) to bend (one rolling speed, low speed, creep not far past the peak). On
the default rig's contact at 4.3 kN, creep up to 10 % at two or three speeds between 10 and
60 km/h gives |corr(A, B)| ≈ 0.985; one speed (30 km/h) 0.9996; the twin's seed test 0.9986.

What the data constrain (reported on every fit, :class:`SlipVelocityCoverage`). A and B act
only through the friction coefficient μ(w), and μ only where the contact saturates: for small
ε the CoA is (2/π)(k_A + k_S)·(π/4)(G a b c11/Q)·s whatever μ is. The relative sensitivity of a
point's CoA to μ is η = 1 − ε f'(ε)/f(ε) with f(ε) = k_Aε/(1+(k_Aε)²) + arctan(k_Sε) (0 in the
linear range, 1 in full sliding); points with η ≥ 0.5 ("saturated") are those that constrain
μ(w), and their slip-velocity range [w_lo, w_hi] is where A and B are constrained. A and B are
called identifiable only when (i) at least 10 points are saturated, (ii) the fitted μ(w) has
made at least half of its fall from μ0 to A·μ0 within that range (B·w_hi ≥ ln 2), (iii) the
data hold several rolling speeds (90th/10th percentile of the saturated points' |w/s| at least
1.5) or creep reaches 3 times the creep at the fitted curve's peak: at one speed w = v·s, so
the fall of μ(w) trades with the curve's shape (k_A, k_S) unless creep goes far past the peak,
(iv) the data feel A and B: fixing B at a quarter or at four times its fitted value, or A
0.2 below or above it (the other parameters refitted each time), raises the residual sum of
squares (with a robust loss: over the inliers of the covariance) by more than 10 % (a
deliberately coarse threshold: on measured data a model error of a few per cent of the cost
cannot be excluded, and for white noise a 10 % rise is Δχ² = 0.1·n), and (v) the covariance
criteria above hold for A and B. Points past the peak of the fitted curve (the falling branch)
are counted and reported. Measured on noisy (σ = 0.005) dry-set points at 10/30/60 km/h, creep
to 10 %: identifiable in 10 of 10 noise draws; at 30 km/h alone: 1 of 10.

Residual structure (:class:`ResidualStructure`): the residuals ordered by creep are tested for
serial correlation (lag-1 autocorrelation r1 and Durbin-Watson DW = Σ(e_i − e_{i−1})²/Σe_i²,
about 2(1 − r1); flagged when r1 > 3/√n, i.e. DW < 2 − 6/√n) and for too few sign runs (the
Wald-Wolfowitz runs test, flagged when z < −3). Structured residuals mean a systematic misfit
(model error, smoothing, bias of the data): the standard errors, which assume independent
residuals, are then too small; ``stderr_inflation`` = √((1 + r1)/(1 − r1)) is the AR(1)
factor by which they at least grow.

References
----------
.. [1] O. Polach, "Creep forces in simulations of traction vehicles running on adhesion limit",
   Wear 258 (2005) 992-1000.
.. [2] B.T. Kayaalp, dissertation (University of Pardubice), eqs. 4.19-4.20.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.contact.creep import POLACH_DRY, PolachParameters, _polach_force_kernel
from rollerrig.contact.curves import CreepCurve

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

PARAMETER_NAMES = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
"""Order of the parameters in :attr:`PolachFit.stderr`, ``covariance`` and ``correlation``."""

_SMALL = 1e-9  # lower bound standing in for the open "> 0" bounds
_IDENTIFIABILITY_CORRELATION = 0.995
_IDENTIFIABILITY_RELATIVE_STDERR = 0.5
_IDENTIFIABILITY_CONDITION = 1e10
_SATURATION_SENSITIVITY = 0.5  # eta: a point's CoA at least half proportional to mu
_MIN_SATURATED_POINTS = 10
_MIN_FRICTION_FALL = float(np.log(2.0))  # B * w_hi: half of mu's fall from mu0 to A mu0
_MIN_SPEED_RATIO = 1.5  # rolling speeds of the saturated points, 90th / 10th percentile
_MIN_PAST_PEAK = 3.0  # or creep to 3 x the creep at the fitted curve's peak
_PROFILE_FACTOR = 4.0  # B / 4 and 4 B in the profile check
_PROFILE_A_STEP = 0.2  # A - 0.2 and A + 0.2 in the profile check
_PROFILE_COST_RISE = 0.10  # relative rise of the cost that counts as "the data feel B"
_STRUCTURE_Z = 3.0  # r1 > 3/sqrt(n) or runs z < -3


class PolachFitWarning(UserWarning):
    """Fitted parameters are poorly determined by the data (see the message for which)."""


def polach_coa(creep, slip_velocity, normal_load, creep_stiffness, parameters: PolachParameters):
    """Polach's CoA F/Q at given creep, slip velocity, load and creep stiffness.

    Parameters
    ----------
    creep : array_like
        s [-].
    slip_velocity : array_like
        w [m/s].
    normal_load : array_like
        Q [N].
    creep_stiffness : array_like
        G a b c11 [N] at that load.
    parameters : PolachParameters

    Returns
    -------
    numpy.ndarray
        CoA [-].

    Examples
    --------
    >>> round(float(polach_coa(0.01, 0.0833, 4300.0, 1.13e6, POLACH_DRY)), 3)
    0.421
    """
    q = np.asarray(normal_load, dtype=float)
    return (
        _polach_force_kernel(
            np.asarray(creep, dtype=float),
            np.asarray(slip_velocity, dtype=float),
            q,
            np.asarray(creep_stiffness, dtype=float),
            *parameters.as_tuple(),
        )
        / q
    )


def creep_stiffness_for_rig(normal_load, rig=None):
    """Kalker's creep stiffness G a b c11 [N] of the rig's wheel-roller contact at a load.

    Exact Hertz contact of the rig's geometry and material at the load, Kalker's c11 at its a/b
    and ν, and the combined shear modulus, as :func:`rollerrig.contact.curves.polach_creep_curve`
    and the twin compute them.

    Parameters
    ----------
    normal_load : float or array_like
        Q [N], > 0.
    rig : RigParameters or mapping, optional
        The rig (default: the bundled default rig); a ``{section: {key: value}}`` mapping in SI
        (e.g. ``json.loads(ds.attrs["provenance"])["rig"]``) also works.

    Returns
    -------
    numpy.ndarray
        G a b c11 [N].

    Examples
    --------
    >>> round(float(creep_stiffness_for_rig(4300.0)) / 1e6, 4)
    1.1295
    """
    from rollerrig.contact.curves import polach_creep_curve
    from rollerrig.rig.parameters import default_rig

    if rig is None:
        rig = default_rig()
    d = rig.to_dict() if hasattr(rig, "to_dict") else rig
    g, mat = d["geometry"], d["material"]
    q = require_positive("normal_load", normal_load, "N")
    out = np.empty(q.shape)
    unique, inverse = np.unique(q, return_inverse=True)
    values = [
        polach_creep_curve(
            np.zeros(1),
            float(load),
            1.0,
            g["wheel_radius_x"],
            g["wheel_radius_y"],
            g["roller_radius_x"],
            g["roller_radius_y"],
            POLACH_DRY,
            mat["youngs_modulus"],
            mat["poisson"],
        ).creep_stiffness
        for load in unique
    ]
    out.reshape(-1)[:] = np.asarray(values)[inverse.reshape(-1)]
    return out


@dataclass(frozen=True)
class ResidualStructure:
    """Serial structure of fit residuals ordered by creep (see the module notes).

    Attributes
    ----------
    n : int
        Number of residuals [1].
    order : str
        What the residuals were ordered by.
    durbin_watson : float
        DW = Σ(e_i − e_{i−1})²/Σe_i² [-]; about 2 for independent residuals, towards 0 for
        positively correlated ones.
    durbin_watson_threshold : float
        Structured below 2 − 6/√n [-] (the same test as ``lag1_autocorrelation`` > 3/√n).
    lag1_autocorrelation : float
        r1 [-].
    lag1_threshold : float
        3/√n [-].
    runs : int
        Runs of equal sign [1].
    expected_runs : float
        Their expectation for independent signs, 2 n₊ n₋/n + 1 [1].
    runs_z : float
        (runs − expected)/σ [-] (no continuity correction).
    runs_z_threshold : float
        Structured below −3 [-].
    structured : bool
        Either test flags it.
    stderr_inflation : float
        √((1 + r1)/(1 − r1)) for r1 > 0, else 1 [-]: the AR(1) factor by which standard errors
        computed for independent residuals are too small.
    """

    n: int
    order: str
    durbin_watson: float
    durbin_watson_threshold: float
    lag1_autocorrelation: float
    lag1_threshold: float
    runs: int
    expected_runs: float
    runs_z: float
    runs_z_threshold: float
    structured: bool
    stderr_inflation: float

    def as_dict(self) -> dict:
        """JSON-ready, with the statistics and the thresholds they were compared with."""
        return {
            "order": self.order,
            "n": self.n,
            "durbin_watson": self.durbin_watson,
            "durbin_watson_threshold": self.durbin_watson_threshold,
            "lag1_autocorrelation": self.lag1_autocorrelation,
            "lag1_threshold": self.lag1_threshold,
            "runs": self.runs,
            "expected_runs": self.expected_runs,
            "runs_z": self.runs_z,
            "runs_z_threshold": self.runs_z_threshold,
            "structured": self.structured,
            "stderr_inflation": self.stderr_inflation,
        }

    def describe(self) -> str:
        """One sentence with the statistics and thresholds."""
        verdict = (
            f"structured, standard errors too small by x{self.stderr_inflation:.3g} at least"
            if self.structured
            else "no structure found"
        )
        return (
            f"residuals ordered by {self.order}: {verdict} (Durbin-Watson {self.durbin_watson:.3f},"
            f" structured below {self.durbin_watson_threshold:.3f}; lag-1 autocorrelation "
            f"{self.lag1_autocorrelation:+.3f}, threshold {self.lag1_threshold:.3f}; runs "
            f"{self.runs} against {self.expected_runs:.1f} expected, z = {self.runs_z:+.2f}, "
            f"structured below {self.runs_z_threshold:+.0f})"
        )


def residual_structure(residuals, order_by=None, *, order: str = "creep") -> ResidualStructure:
    """Serial-structure tests of residuals: lag-1 autocorrelation, Durbin-Watson, runs test.

    Parameters
    ----------
    residuals : array_like, shape (n,)
        Residuals [any unit], n >= 3.
    order_by : array_like, shape (n,), optional
        Sort key (stable sort), e.g. the creep of each point; default the given order.
    order : str
        Name of the sort key, for the report.

    Returns
    -------
    ResidualStructure

    Examples
    --------
    White noise is not structured; a smooth misfit is:

    >>> e = np.random.default_rng(0).standard_normal(400)
    >>> residual_structure(e).structured
    False
    >>> residual_structure(np.sin(np.linspace(0, 6, 400)) + 0.1 * e).structured
    True
    """
    e = require_finite("residuals", residuals, "-").reshape(-1)
    if order_by is not None:
        key = require_finite("order_by", order_by, "-").reshape(-1)
        if key.shape != e.shape:
            raise ParameterError(f"order_by {key.shape} and residuals {e.shape} differ in shape")
        e = e[np.argsort(key, kind="stable")]
    n = e.size
    if n < 3:
        raise ParameterError(f"residual tests need at least 3 residuals, got {n}")
    ss = float(e @ e)
    if ss > 0:
        dw = float(np.sum(np.diff(e) ** 2) / ss)
        c = e - e.mean()
        cc = float(c @ c)
        r1 = float(c[:-1] @ c[1:] / cc) if cc > 0 else 0.0
    else:  # exact fit: nothing to test
        dw, r1 = 2.0, 0.0
    signs = np.sign(e)
    signs = signs[signs != 0]
    n_pos, n_neg = int(np.sum(signs > 0)), int(np.sum(signs < 0))
    m = n_pos + n_neg
    runs = int(1 + np.count_nonzero(np.diff(signs))) if m else 0
    if n_pos and n_neg and m > 1:
        expected = 2.0 * n_pos * n_neg / m + 1.0
        var = 2.0 * n_pos * n_neg * (2.0 * n_pos * n_neg - m) / (m**2 * (m - 1.0))
        z = (runs - expected) / np.sqrt(var) if var > 0 else 0.0
    else:
        expected, z = float(runs), 0.0
    lag_threshold = _STRUCTURE_Z / np.sqrt(n)
    structured = bool(r1 > lag_threshold or z < -_STRUCTURE_Z)
    inflation = float(np.sqrt((1.0 + r1) / (1.0 - r1))) if 0.0 < r1 < 1.0 else 1.0
    return ResidualStructure(
        n=int(n),
        order=order,
        durbin_watson=dw,
        durbin_watson_threshold=float(2.0 - 2.0 * lag_threshold),
        lag1_autocorrelation=r1,
        lag1_threshold=float(lag_threshold),
        runs=runs,
        expected_runs=float(expected),
        runs_z=float(z),
        runs_z_threshold=-_STRUCTURE_Z,
        structured=structured,
        stderr_inflation=inflation if r1 < 1.0 else float("inf"),
    )


@dataclass(frozen=True)
class SlipVelocityCoverage:
    """Over which slip velocities the data constrain μ(w), hence A and B (module notes).

    Attributes
    ----------
    slip_velocity_range : (float, float)
        Smallest and largest |w| of all points [m/s].
    saturated_points : int
        Points with η ≥ 0.5 (CoA at least half proportional to μ) [1].
    saturated_slip_velocity_range : (float, float) or None
        Smallest and largest |w| of the saturated points [m/s]: where A and B are constrained.
    falling_branch_points : int
        Points past the peak of the fitted curve (the CoA falls with creep there) [1].
    rolling_speed_ratio : float
        90th over 10th percentile of the saturated points' rolling speed |w/s| [-].
    creep_past_peak : float
        Largest |creep| over the creep at the fitted curve's peak (median rolling speed) [-].
    friction_fall_reached : float
        1 − exp(−B·w_hi) with the fitted B [-]: the part of μ's fall from μ0 to A·μ0 that the
        saturated points reach (0 without saturated points).
    profile_cost_rise : dict
        {"B/4": r, "4B": r}: relative rise of the cost when B is fixed there and the other
        parameters refitted [-]; empty when not computed.
    a_and_b_identifiable : bool
        All criteria of the module notes hold.
    reasons : tuple of str
        Why not, one sentence each (empty when identifiable).
    """

    slip_velocity_range: tuple[float, float]
    saturated_points: int
    saturated_slip_velocity_range: tuple[float, float] | None
    falling_branch_points: int
    rolling_speed_ratio: float
    creep_past_peak: float
    friction_fall_reached: float
    profile_cost_rise: dict
    a_and_b_identifiable: bool
    reasons: tuple[str, ...]

    def as_dict(self) -> dict:
        """JSON-ready, units in the keys, thresholds stated."""
        sat = self.saturated_slip_velocity_range
        return {
            "slip_velocity_range [m/s]": list(self.slip_velocity_range),
            "saturated_points": self.saturated_points,
            "saturated_points_definition": (
                f"eta >= {_SATURATION_SENSITIVITY}: the point's CoA is at least half proportional"
                " to the friction coefficient mu(w), through which A and B act"
            ),
            "A_B_constrained_over_slip_velocity [m/s]": None if sat is None else list(sat),
            "falling_branch_points": self.falling_branch_points,
            "rolling_speed_ratio [-]": self.rolling_speed_ratio,
            "rolling_speed_ratio_needed [-]": _MIN_SPEED_RATIO,
            "creep_past_peak [-]": self.creep_past_peak,
            "creep_past_peak_needed [-]": _MIN_PAST_PEAK,
            "criteria": "A and B identifiable only with >= 10 saturated points, half of mu's "
            "fall reached, several rolling speeds or creep far past the peak, a cost rise above "
            "10 % at B/4 and 4B, and no covariance problem of A or B",
            "friction_fall_reached [-]": self.friction_fall_reached,
            "friction_fall_needed [-]": 0.5,
            "profile_cost_rise [-]": dict(self.profile_cost_rise),
            "profile_cost_rise_needed [-]": _PROFILE_COST_RISE,
            "A_B_identifiable": self.a_and_b_identifiable,
            "reasons": list(self.reasons),
        }

    def describe(self, reasons: bool = True) -> str:
        """One sentence: the range and the verdict (with the reasons unless ``reasons=False``)."""
        lo, hi = self.slip_velocity_range
        sat = self.saturated_slip_velocity_range
        where = (
            "no saturated point"
            if sat is None
            else f"{self.saturated_points} saturated points at {sat[0]:.3g}-{sat[1]:.3g} m/s"
        )
        verdict = (
            "A and B identifiable"
            if self.a_and_b_identifiable
            else "A and B NOT identifiable" + (": " + "; ".join(self.reasons) if reasons else "")
        )
        return (
            f"slip velocity {lo:.3g}-{hi:.3g} m/s ({where}, {self.falling_branch_points} past "
            f"the peak; fitted mu(w) reaches {100 * self.friction_fall_reached:.0f} % of its fall"
            f" there): {verdict}"
        )


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

    def truth_distance(self, truth, warn_sigma: float = 3.0) -> dict:
        """Distance of each fitted parameter from a known truth, in standard errors.

        Parameters
        ----------
        truth : PolachParameters or mapping
            The true set (e.g. the twin's, from a synthetic recording's metadata), by
            :data:`PARAMETER_NAMES`.
        warn_sigma : float
            Distances beyond this many standard errors are flagged [-].

        Returns
        -------
        dict
            By parameter name: ``true``, ``fitted``, ``stderr``, ``sigma`` (|fitted − true| /
            stderr, None when the stderr is 0 or not finite, with ``why``), ``sigma_ar1``
            (the same with the stderr inflated for residual autocorrelation) and
            ``beyond_warn_sigma``.
        """
        if isinstance(truth, PolachParameters):
            true = dict(zip(PARAMETER_NAMES, truth.as_tuple(), strict=True))
        else:
            true = {k: float(truth[k]) for k in PARAMETER_NAMES}
        fitted = dict(zip(PARAMETER_NAMES, self.parameters.as_tuple(), strict=True))
        inflation = (
            self.residual_structure.stderr_inflation if self.residual_structure is not None else 1.0
        )
        out = {}
        for k in PARAMETER_NAMES:
            sd = float(self.stderr[k])
            diff = abs(fitted[k] - true[k])
            row = {"true": true[k], "fitted": fitted[k], "stderr": sd if np.isfinite(sd) else None}
            if np.isfinite(sd) and sd > 0:
                row["sigma"] = diff / sd
                row["sigma_ar1"] = diff / (sd * inflation) if np.isfinite(inflation) else None
                row["beyond_warn_sigma"] = bool(diff / sd > warn_sigma)
            else:
                row["sigma"] = row["sigma_ar1"] = None
                row["why"] = f"standard error is {sd!r}: no distance in standard errors"
                row["beyond_warn_sigma"] = False
            out[k] = row
        return out

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
        Creep s [-] at each point.
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
        (``"soft_l1"``, ``"huber"``, ``"cauchy"``, ``"arctan"``).
    f_scale : float
        Residual scale of the robust loss [-] (ignored by ``"linear"``).
    name : str
        Name of the fitted :class:`PolachParameters`.

    Returns
    -------
    PolachFit

    Warns
    -----
    PolachFitWarning
        When parameters are not identifiable from the data.

    Examples
    --------
    Exact points of the dry set at two speeds:

    >>> s = np.tile(np.linspace(0.0005, 0.08, 40), 2)
    >>> v = np.repeat([30 / 3.6, 60 / 3.6], 40)
    >>> k = 1.1295e6
    >>> mu = polach_coa(s, s * v, 4300.0, k, POLACH_DRY)
    >>> fit = fit_polach(s, mu, 4300.0, k, slip_velocity=s * v)
    >>> round(fit.parameters.static_friction, 6), round(fit.parameters.k_slip, 6)
    (0.55, 0.4)
    """
    s = require_finite("creep", creep, "-").reshape(-1)
    y = require_finite("coa", coa, "-").reshape(-1)
    if s.shape != y.shape:
        raise ParameterError(f"creep {s.shape} and coa {y.shape} must have the same length")
    n = s.size
    if n < 6:
        raise ParameterError(f"need at least 6 points to fit 5 parameters, got {n}")
    q = np.broadcast_to(require_positive("normal_load", normal_load, "N"), s.shape).astype(float)
    if isinstance(creep_stiffness, CreepCurve):
        k = creep_stiffness.creep_stiffness * (q / creep_stiffness.normal_load) ** (2.0 / 3.0)
    else:
        k = np.broadcast_to(require_positive("creep_stiffness", creep_stiffness, "N"), s.shape)
        k = k.astype(float)
    if slip_velocity is None:
        if rolling_speed is None:
            raise ParameterError("give slip_velocity [m/s] or rolling_speed [m/s]")
        w = s * np.broadcast_to(require_positive("rolling_speed", rolling_speed, "m/s"), s.shape)
    else:
        w = np.broadcast_to(require_finite("slip_velocity", slip_velocity, "m/s"), s.shape)
        w = w.astype(float)

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

    sol = optimize.least_squares(
        residuals,
        theta0,
        bounds=(lower, upper),
        loss=loss,
        f_scale=f_scale,
        x_scale="jac",
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
        max_nfev=20000,
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
    cov_theta = s2 * cov_scaled / np.outer(scale, scale)
    cov = transform @ cov_theta @ transform.T
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(divide="ignore", invalid="ignore"):
        corr = cov / np.outer(sd, sd)
    problems = []
    if not np.isfinite(cond) or cond > _IDENTIFIABILITY_CONDITION:
        problems.append(f"J^T J is nearly singular (condition number {cond:.3g})")
        sd = np.where(sd == 0, np.inf, sd)
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

    coverage = _coverage(
        s, w, q, k, _theta_to_parameters(theta), 0.5 * float(res[inlier] @ res[inlier]), cost_with,
        ab_covariance_problems,
    )  # fmt: skip
    own = [r for r in coverage.reasons if r not in ab_covariance_problems]
    if own:
        problems.append("A and B are not constrained by the data (" + "; ".join(own) + ")")
    structure = None
    if float(np.sqrt(np.mean(res**2))) > 1e-9 * max(float(np.max(np.abs(y))), 1e-12):
        structure = residual_structure(res, s, order="creep")
    span = float(np.ptp(np.abs(w)))
    if structure is not None and structure.structured:
        warnings.warn(
            "Polach fit residuals are structured, the model misses a systematic part of the "
            f"data: {structure.describe()}; the standard errors assume independent residuals.",
            PolachFitWarning,
            stacklevel=2,
        )
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
        message=str(sol.message),
        creep=s,
        slip_velocity=w,
        normal_load=q,
        creep_stiffness=k,
        coa=y,
        residual_structure=structure,
        coverage=coverage,
    )


def _percent(fraction: float) -> str:
    value = 100.0 * fraction
    return f"{0.0 if abs(value) < 0.05 else value:.1f}"


def _coverage(s, w, q, k, params, best_cost, cost_with, covariance_problems):
    """Slip-velocity coverage and the A/B identifiability verdict (module notes)."""
    mu0, a, b, ka, ks = params
    aw = np.abs(w)
    mu = mu0 * ((1.0 - a) * np.exp(-b * aw) + a)
    eps = 0.25 * np.pi * k * np.abs(s) / (q * mu)
    f = ka * eps / (1.0 + (ka * eps) ** 2) + np.arctan(ks * eps)
    fp = ka * (1.0 - (ka * eps) ** 2) / (1.0 + (ka * eps) ** 2) ** 2 + ks / (1.0 + (ks * eps) ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(f > 0, 1.0 - eps * fp / f, 0.0)
    saturated = eta >= _SATURATION_SENSITIVITY
    n_sat = int(np.sum(saturated))
    sat_range = (float(aw[saturated].min()), float(aw[saturated].max())) if n_sat else None
    # Past the peak: the fitted CoA falls when creep grows at the point's rolling speed.
    h = 1e-4
    p = PolachParameters(mu0, a, b, ka, min(ks, ka), name="fitted", source="fit_polach")
    up = polach_coa(s * (1 + h), w * (1 + h), q, k, p)
    dn = polach_coa(s * (1 - h), w * (1 - h), q, k, p)
    falling = int(np.sum(np.sign(s) * (up - dn) < 0))
    reached = 1.0 - float(np.exp(-b * sat_range[1])) if sat_range else 0.0
    # Rolling speeds v = |w/s| of the saturated points and how far past the peak creep goes.
    ok = saturated & (np.abs(s) > 0)
    v = np.abs(w[ok] / s[ok]) if np.any(ok) else np.abs(w[np.abs(s) > 0] / s[np.abs(s) > 0])
    speed_ratio = float(np.percentile(v, 90) / np.percentile(v, 10)) if v.size else 1.0
    v_med = float(np.median(v)) if v.size else 1.0
    s_max = float(np.max(np.abs(s)))
    grid = np.linspace(s_max / 2000, 2 * s_max, 4000)
    curve = polach_coa(grid, grid * v_med, float(np.median(q)), float(np.median(k)), p)
    peak_creep = float(grid[int(np.argmax(curve))])
    past_peak = s_max / peak_creep
    reasons = []
    if n_sat < _MIN_SATURATED_POINTS:
        reasons.append(
            f"only {n_sat} point(s) where the contact saturates (CoA at least half proportional to"
            f" mu), {_MIN_SATURATED_POINTS} needed: creep does not reach the saturation (mu0 is"
            " not constrained either)"
        )
    if reached < 0.5:
        reasons.append(
            f"the saturated points reach {100 * reached:.0f} % of mu's fall from mu0 to A mu0 "
            f"(B w_max = {b * (sat_range[1] if sat_range else 0.0):.3g}, "
            f"{_MIN_FRICTION_FALL:.3g} needed): slip velocities too small for A"
        )
    if speed_ratio < _MIN_SPEED_RATIO and past_peak < _MIN_PAST_PEAK:
        reasons.append(
            f"one rolling speed ({v_med:.3g} m/s; 90/10 percentile ratio {speed_ratio:.2f}, "
            f"{_MIN_SPEED_RATIO:g} needed) and creep only to {past_peak:.2f} x the peak creep "
            f"({_MIN_PAST_PEAK:g} needed): with w = v s, the fall of mu(w) trades with the "
            "curve's shape (kA, kS); test at several speeds or far past the peak"
        )
    rise = {}
    if n_sat >= _MIN_SATURATED_POINTS and b > 0:
        trials = [
            ("B/4", 2, b / _PROFILE_FACTOR),
            ("4B", 2, b * _PROFILE_FACTOR),
            (f"A-{_PROFILE_A_STEP:g}", 1, a - _PROFILE_A_STEP),
            (f"A+{_PROFILE_A_STEP:g}", 1, a + _PROFILE_A_STEP),
        ]
        for label, index, value in trials:
            if index == 1 and not 0.0 < value <= 1.0:
                continue  # A outside its bounds
            cost = cost_with(index, value)
            rise[label] = (cost - best_cost) / best_cost if best_cost > 0 else float("inf")
        flat = [lbl for lbl, r in rise.items() if not r > _PROFILE_COST_RISE]
        if flat:
            reasons.append(
                "the data hardly feel A and B: fixing "
                + " or ".join(f"{lbl} raises the cost by {_percent(rise[lbl])} %" for lbl in flat)
                + f" (more than {100 * _PROFILE_COST_RISE:.0f} % needed)"
            )
    reasons.extend(covariance_problems)
    rise = {lbl: (float(r) if np.isfinite(r) else None) for lbl, r in rise.items()}
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
