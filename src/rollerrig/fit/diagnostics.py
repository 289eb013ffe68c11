"""Honesty diagnostics of a Polach fit: what the data constrain, residual structure, truth.

What the data constrain (:class:`SlipVelocityCoverage`, reported on every fit). A and B act
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
criteria of :func:`rollerrig.fit.polach.fit_polach` hold for A and B. Points past the peak of
the fitted curve (the falling branch) are counted and reported. Measured on noisy (σ = 0.005)
dry-set points at 10/30/60 km/h, creep to 10 %: identifiable in 10 of 10 noise draws; at
30 km/h alone: 1 of 10.

Residual structure (:class:`ResidualStructure`): the residuals ordered by creep are tested for
serial correlation (lag-1 autocorrelation r1 and Durbin-Watson DW = Σ(e_i − e_{i−1})²/Σe_i²,
about 2(1 − r1); flagged when r1 > 3/√n, i.e. DW < 2 − 6/√n) and for too few sign runs (the
Wald-Wolfowitz runs test, flagged when z < −3). Structured residuals mean a systematic misfit
(model error, smoothing, bias of the data): the standard errors, which assume independent
residuals, are then too small; ``stderr_inflation`` = √((1 + r1)/(1 − r1)) is the AR(1)
factor by which they at least grow.

Distance from a known truth (:func:`truth_distance`): for synthetic recordings, how many
standard errors each fitted parameter lies from the twin's set.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError, require_finite
from rollerrig.contact.creep import PolachParameters
from rollerrig.fit.model import PARAMETER_NAMES, polach_coa

__all__ = [
    "ResidualStructure",
    "SlipVelocityCoverage",
    "distance_row",
    "fit_residual_structure",
    "past_peak_words",
    "residual_structure",
    "slip_velocity_coverage",
    "truth_distance",
]

_SATURATION_SENSITIVITY = 0.5  # eta: a point's CoA at least half proportional to mu
_MIN_SATURATED_POINTS = 10
_MIN_FRICTION_FALL = float(np.log(2.0))  # B * w_hi: half of mu's fall from mu0 to A mu0
_MIN_SPEED_RATIO = 1.5  # rolling speeds of the saturated points, 90th / 10th percentile
_MIN_PAST_PEAK = 3.0  # or creep to 3 x the creep at the fitted curve's peak
_PROFILE_FACTOR = 4.0  # B / 4 and 4 B in the profile check
_PROFILE_A_STEP = 0.2  # A - 0.2 and A + 0.2 in the profile check
_PROFILE_COST_RISE = 0.10  # relative rise of the cost that counts as "the data feel B"
_STRUCTURE_Z = 3.0  # r1 > 3/sqrt(n) or runs z < -3


@dataclass(frozen=True)
class ResidualStructure:
    """Serial structure of fit residuals ordered by creep (see the module notes).

    Attributes
    ----------
    n : int
        Number of residuals [-].
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
        Runs of equal sign [-].
    expected_runs : float
        Their expectation for independent signs, 2 n₊ n₋/n + 1 [-].
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


ROUND_OFF_SHARE = 1e-7
"""Residuals whose rms is below this share of the largest |CoA| are the optimiser's tolerance,
not the data's: an exact Polach fit of the model's own curve ends at 1.4e-10 or 5.8e-10 rms as
the creep stiffness's last bit changes, and no measured CoA is known to 1e-7."""


def fit_residual_structure(residuals, creep, coa) -> ResidualStructure | None:
    """:func:`residual_structure` of a fit's ``residuals`` ordered by ``creep``, or None where
    they are at the optimiser's tolerance (:data:`ROUND_OFF_SHARE` of the largest |``coa``|):
    a test of round-off for structure only finds the optimiser's path."""
    residuals = np.asarray(residuals, dtype=float)
    scale = max(float(np.max(np.abs(coa))), 1e-12)
    if float(np.sqrt(np.mean(residuals**2))) <= ROUND_OFF_SHARE * scale:
        return None
    return residual_structure(residuals, creep, order="creep")


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
        Points with η ≥ 0.5 (CoA at least half proportional to μ) [-].
    saturated_slip_velocity_range : (float, float) or None
        Smallest and largest |w| of the saturated points [m/s]: where A and B are constrained.
    falling_branch_points : int
        Points past the peak of the fitted curve (the CoA falls with creep there) [-].
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


def past_peak_words(past_peak: float, law: str, no_peak: bool) -> str:
    """How far creep goes past the peak of the fitted ``law``'s own curve, in words: the ratio
    of the largest creep to that curve's peak creep, or its bound where the curve has no peak
    up to twice the largest creep.

    Examples
    --------
    >>> past_peak_words(1.54, "Polach", False)
    "creep only to 1.54 x the fitted Polach curve's peak creep"
    >>> past_peak_words(0.5, "modified-FASTSIM", True)
    "creep only to 0.50 x the fitted modified-FASTSIM curve's peak creep at most (that curve still rises at twice the largest creep)"
    """  # noqa: E501
    text = f"creep only to {past_peak:.2f} x the fitted {law} curve's peak creep"
    if no_peak:
        text += " at most (that curve still rises at twice the largest creep)"
    return text


def _percent(fraction: float) -> str:
    value = 100.0 * fraction
    return f"{0.0 if abs(value) < 0.05 else value:.1f}"


def slip_velocity_coverage(
    s: np.ndarray,
    w: np.ndarray,
    q: np.ndarray,
    k: np.ndarray,
    params: tuple[float, float, float, float, float],
    best_cost: float,
    cost_with: Callable[[int, float], float],
    covariance_problems: list[str],
) -> SlipVelocityCoverage:
    """Slip-velocity coverage and the A/B identifiability verdict (module notes).

    Parameters
    ----------
    s, w, q, k : ndarray, shape (n,)
        Creep [-], slip velocity [m/s], normal load [N] and creep stiffness [N] of the points.
    params : tuple of float
        The fitted (μ0, A, B, k_A, k_S).
    best_cost : float
        Half the residual sum of squares of the fit (over the covariance's inliers) [-].
    cost_with : callable
        ``cost_with(index, value)``: the best fit's cost with parameter ``index`` (1: A,
        2: B) fixed at ``value``, the others refitted [-].
    covariance_problems : list of str
        The fit's covariance problems that concern A or B (criterion (v)).
    """
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
    at = int(np.argmax(curve))
    peak_creep = float(grid[at])
    past_peak = s_max / peak_creep
    # "x the peak creep" is of the fitted law's own curve: another law fitted to the same points
    # (a transfer's modified FASTSIM) places its peak elsewhere. At the grid's end the curve has
    # no peak within it: the ratio is a bound.
    reach = past_peak_words(past_peak, "Polach", at == grid.size - 1)
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
            f"one rolling speed (the saturated points' median {v_med:.3g} m/s, "
            f"{3.6 * v_med:.3g} km/h; 90/10 percentile ratio {speed_ratio:.2f}, "
            f"{_MIN_SPEED_RATIO:g} needed) and {reach} "
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


AT_BOUND_WHY = "at a bound of the search: its interval is one-sided, no distance in standard errors"
"""Why a parameter at a bound of the fit's search has no distance from the truth in standard
errors (:func:`truth_distance`)."""


def truth_distance(fit, truth, warn_sigma: float = 3.0) -> dict:
    """Distance of each fitted parameter from a known truth, in standard errors.

    Parameters
    ----------
    fit : rollerrig.fit.polach.PolachFit
        The fit (its parameters, standard errors and residual structure); taken by what it
        has, so that this module need not import the one that uses it.
    truth : PolachParameters or mapping
        The true set (e.g. the twin's, from a synthetic recording's metadata), by
        :data:`rollerrig.fit.model.PARAMETER_NAMES`.
    warn_sigma : float
        Distances beyond this many standard errors are flagged [-].

    Returns
    -------
    dict
        By parameter name: ``true``, ``fitted``, ``stderr``, ``sigma`` (|fitted − true| /
        stderr, None when the stderr is 0 or not finite, or the parameter at a bound of the
        search (``fit.at_bound``), with ``why``), ``sigma_ar1``
        (the same with the stderr inflated for residual autocorrelation) and
        ``beyond_warn_sigma``.
    """
    if isinstance(truth, PolachParameters):
        true = dict(zip(PARAMETER_NAMES, truth.as_tuple(), strict=True))
    else:
        true = {k: float(truth[k]) for k in PARAMETER_NAMES}
    fitted = dict(zip(PARAMETER_NAMES, fit.parameters.as_tuple(), strict=True))
    structure = fit.residual_structure
    inflation = structure.stderr_inflation if structure is not None else 1.0
    at_bound = set(getattr(fit, "at_bound", ()))
    unidentified = set(fit.unidentified()) if hasattr(fit, "unidentified") else set()
    rows = {
        k: distance_row(
            true[k], fitted[k], float(fit.stderr[k]), k in at_bound, warn_sigma, inflation
        )
        for k in PARAMETER_NAMES
    }
    for k in unidentified - at_bound:
        # No distance in standard errors that are not an uncertainty (PolachFit.unidentified).
        rows[k].update(sigma=None, sigma_ar1=None, beyond_warn_sigma=False, why=UNIDENTIFIED_WHY)
    return rows


UNIDENTIFIED_WHY = (
    "A and B are not identifiable from these data (see the fit's coverage): their standard "
    "errors are no uncertainty, so no distance in standard errors"
)


def distance_row(
    true: float, fitted: float, stderr: float, at_bound: bool, warn_sigma: float,
    inflation: float | None = None,
) -> dict:  # fmt: skip
    """One parameter's row of :func:`truth_distance` (and of the modified FASTSIM fit's):
    ``true``, ``fitted``, ``stderr``, ``sigma``, ``beyond_warn_sigma``, ``why`` where there is
    no distance, and ``sigma_ar1`` where an ``inflation`` of the standard error is given."""
    finite = bool(np.isfinite(stderr) and stderr > 0)
    row = {"true": true, "fitted": fitted, "stderr": stderr if np.isfinite(stderr) else None}
    if at_bound:
        # The interval of a parameter at a bound of the search is one-sided: its symmetric
        # standard error (A at 1.5e-8 +- 1.3e-6) had made "316 826 sigma".
        row["sigma"] = None
        row["why"] = AT_BOUND_WHY
    elif finite:
        row["sigma"] = abs(fitted - true) / stderr
    else:
        row["sigma"] = None
        row["why"] = f"standard error is {stderr!r}: no distance in standard errors"
    if inflation is not None:
        usable = row["sigma"] is not None and np.isfinite(inflation)
        row["sigma_ar1"] = row["sigma"] / inflation if usable else None
    row["beyond_warn_sigma"] = bool(row["sigma"] is not None and row["sigma"] > warn_sigma)
    return row
