"""Honesty diagnostics of a Polach fit (rollerrig.fit.diagnostics): where the data constrain A
and B, residual structure, distance to a known truth.

References: the Durbin-Watson statistic and the Wald-Wolfowitz runs test of statsmodels
(``statsmodels.stats.stattools.durbin_watson``, ``statsmodels.sandbox.stats.runs.
runstest_1samp``); the identifiability cases are Polach's (2005) dry set at one and at three
speeds, where A and B act through μ(w) = μ0[(1 − A)e^(−B|w|) + A] only.
"""

import warnings

import numpy as np
import pytest
from statsmodels.sandbox.stats.runs import runstest_1samp
from statsmodels.stats.stattools import durbin_watson

from rollerrig.contact.creep import POLACH_DRY
from rollerrig.fit.diagnostics import residual_structure
from rollerrig.fit.model import PARAMETER_NAMES, creep_stiffness_for_rig, polach_coa
from rollerrig.fit.polach import PolachFitWarning, fit_polach

LOAD = 4300.0
K = float(creep_stiffness_for_rig(LOAD))
SPEEDS = np.array([10.0, 30.0, 60.0]) / 3.6  # [m/s]


def _points(speeds, n=60, max_creep=0.1):
    s = np.tile(np.linspace(5e-4, max_creep, n), len(speeds))
    w = s * np.repeat(speeds, n)
    return s, w, polach_coa(s, w, LOAD, K, POLACH_DRY)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_residual_statistics_match_statsmodels(seed):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(300) + np.sin(np.linspace(0, 3 * seed, 300))
    key = rng.permutation(300).astype(float)
    r = residual_structure(e, key)
    ordered = e[np.argsort(key, kind="stable")]
    assert r.durbin_watson == pytest.approx(durbin_watson(ordered), rel=1e-12)
    z, _ = runstest_1samp(ordered, cutoff=0.0, correction=False)
    assert r.runs_z == pytest.approx(z, rel=1e-10)
    c = ordered - ordered.mean()
    assert r.lag1_autocorrelation == pytest.approx(c[:-1] @ c[1:] / (c @ c), rel=1e-12)
    assert r.lag1_threshold == pytest.approx(3 / np.sqrt(300))


def test_white_noise_is_rarely_structured_and_a_misfit_always():
    rng = np.random.default_rng(7)
    flagged = sum(residual_structure(rng.standard_normal(500)).structured for _ in range(200))
    # Both tests at 3 sigma: about 0.3 % false alarms; 200 draws give 0-3.
    assert flagged <= 4
    x = np.linspace(0, 1, 500)
    misfit = residual_structure(0.01 * (x - 0.5) ** 2 - 0.0008 + 0.001 * rng.standard_normal(500))
    assert misfit.structured and misfit.stderr_inflation > 1.2


def test_three_speeds_past_the_peak_constrain_a_and_b():
    s, w, mu = _points(SPEEDS)
    y = mu + 0.005 * np.random.default_rng(11).standard_normal(mu.size)
    fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    c = fit.coverage
    assert c.a_and_b_identifiable and fit.identifiable, c.reasons
    assert c.slip_velocity_range == pytest.approx((np.min(w), np.max(w)))
    lo, hi = c.saturated_slip_velocity_range
    assert 0 < lo < hi <= np.max(w) and c.saturated_points > 100
    assert c.falling_branch_points > 0 and c.rolling_speed_ratio > 1.5
    assert not fit.residual_structure.structured  # white noise on the right model
    d = c.as_dict()
    assert d["A_B_constrained_over_slip_velocity [m/s]"] == [lo, hi]


def test_one_slow_speed_does_not_constrain_a_and_b():
    # 5 km/h, creep up to 2 %: slip velocities below 0.03 m/s, where mu(w) has barely begun
    # to fall (B w < 0.02 with Polach's B = 0.6 s/m).
    s, w, mu = _points(np.array([5 / 3.6]), max_creep=0.02)
    y = mu + 0.002 * np.random.default_rng(0).standard_normal(mu.size)
    with pytest.warns(PolachFitWarning, match="A and B are not constrained"):
        fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    c = fit.coverage
    assert not c.a_and_b_identifiable and not fit.identifiable
    assert c.falling_branch_points == 0
    assert any("one rolling speed" in r for r in c.reasons)
    assert "NOT identifiable" in c.describe()


def test_a_systematic_misfit_is_flagged_and_warned():
    # Data from the dry set with a smooth bias (as smoothing or a missing correction leave).
    s, w, mu = _points(SPEEDS)
    y = mu + 0.01 * np.sin(40 * s)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    assert fit.residual_structure.structured
    assert any("residuals are structured" in str(x.message) for x in caught)
    d = fit.residual_structure.as_dict()
    assert d["durbin_watson"] < d["durbin_watson_threshold"]


def test_truth_distance_in_standard_errors():
    s, w, mu = _points(SPEEDS)
    y = mu + 0.005 * np.random.default_rng(11).standard_normal(mu.size)
    fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    d = fit.truth_distance(POLACH_DRY)
    assert set(d) == set(PARAMETER_NAMES)
    for name, row in d.items():
        if name in fit.at_bound:  # a one-sided interval: no distance (test below)
            assert row["sigma"] is None
            continue
        expected = abs(row["fitted"] - row["true"]) / fit.stderr[name]
        assert row["sigma"] == pytest.approx(expected)
        assert row["beyond_warn_sigma"] == (expected > 3)
    # A wrong truth is far away.
    far = fit.truth_distance(
        {
            **{n: v for n, v in zip(PARAMETER_NAMES, POLACH_DRY.as_tuple(), strict=True)},
            "static_friction": 0.3,
        }
    )
    assert far["static_friction"]["beyond_warn_sigma"]


def test_exact_fit_has_no_residual_test():
    s, w, mu = _points(SPEEDS[1:])
    fit = fit_polach(s, mu, LOAD, K, slip_velocity=w)
    assert fit.residual_structure is None  # residuals at round-off level
    assert fit.truth_distance(POLACH_DRY)["static_friction"]["sigma"] is not None


def test_residuals_at_the_optimisers_tolerance_are_not_tested():
    # Below ROUND_OFF_SHARE of the largest |CoA| a structure test would only see the
    # optimiser's path; above it, a trend in the residuals is structure.
    from rollerrig.fit.diagnostics import ROUND_OFF_SHARE, fit_residual_structure

    creep = np.linspace(0.001, 0.1, 120)
    coa = 0.4 * np.ones_like(creep)
    trend = np.sin(creep * 60.0)
    assert fit_residual_structure(0.5 * ROUND_OFF_SHARE * 0.4 * trend, creep, coa) is None
    structure = fit_residual_structure(1e-3 * trend, creep, coa)
    assert structure is not None and structure.structured


def test_a_parameter_at_a_bound_has_no_distance_in_standard_errors():
    """A fit whose A ends at its bound 1 (a curve with no friction fall) has a one-sided
    interval there: no σ distance from the truth (a symmetric standard error had made
    "A ± 1.3e-6 ... 316 826 σ" on the quarter-scale rig's test), and no note of it."""
    from rollerrig.contact.creep import PolachParameters
    from rollerrig.fit.diagnostics import AT_BOUND_WHY

    flat = PolachParameters(0.36, 1.0, 0.0, 0.27, 0.08)
    s = np.linspace(5e-4, 0.02, 200)
    w = s * 10 / 3.6
    y = polach_coa(s, w, LOAD, K, flat) + 0.002 * np.random.default_rng(1).standard_normal(s.size)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PolachFitWarning)
        fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    assert "limit_ratio" in fit.at_bound
    row = fit.truth_distance(PolachParameters(0.36, 0.4, 0.2, 0.27, 0.08))["limit_ratio"]
    assert row["sigma"] is None and row["why"] == AT_BOUND_WHY and not row["beyond_warn_sigma"]
    # Off its bound a parameter keeps its distance.
    assert fit.truth_distance(flat)["static_friction"]["sigma"] is not None


def test_how_far_past_the_peak_names_the_law_and_a_bound():
    # analyze (Polach) said "creep only to 1.54 x the peak creep" and transfer (modified
    # FASTSIM) "0.50 x the peak creep" of the same data: each is of its own fitted law's
    # curve, and 0.50 was the end of the search grid (no peak up to twice the largest creep).
    from rollerrig.fit.diagnostics import past_peak_words

    assert past_peak_words(1.54, "Polach", False) == (
        "creep only to 1.54 x the fitted Polach curve's peak creep"
    )
    text = past_peak_words(0.5, "modified-FASTSIM", True)
    assert "0.50 x the fitted modified-FASTSIM curve's peak creep at most" in text
    assert "still rises at twice the largest creep" in text
