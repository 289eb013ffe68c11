"""Covariance under correlated residuals and the whiteness checks, against closed forms and
statsmodels."""

import numpy as np
import pytest

from rollerrig.calibrate.stats import (
    andrews_lag_window,
    hac_covariance,
    integrated_autocorrelation_time,
    whiteness,
)


def _ar1(rho: float, n: int, rng) -> np.ndarray:
    e = rng.standard_normal(n)
    x = np.empty(n)
    x[0] = e[0] / np.sqrt(1 - rho**2)
    for k in range(1, n):
        x[k] = rho * x[k - 1] + e[k]
    return x


def test_hac_standard_error_of_a_mean_under_ar1_noise():
    # The mean of AR(1) noise has variance sigma_x^2 (1 + rho)/(1 - rho)/n for large n (the
    # long-run variance): the sandwich must find it, the white formula is too small by
    # sqrt((1 + rho)/(1 - rho)) = 2.65 at rho = 0.75.
    rng = np.random.default_rng(5)
    rho, n = 0.75, 20000
    x = _ar1(rho, n, rng)
    a = np.ones((n, 1))
    r = x - x.mean()
    hac, white, window = hac_covariance(a, r, np.arange(n))
    exact = np.var(x) * (1 + rho) / (1 - rho) / n
    assert float(hac[0, 0]) == pytest.approx(exact, rel=0.25)
    assert float(white[0, 0]) == pytest.approx(np.var(x) / n, rel=0.05)
    assert window > 10


def test_hac_and_white_agree_on_white_residuals_and_channels_share_instants():
    rng = np.random.default_rng(6)
    n = 6000
    a = rng.standard_normal((2 * n, 2))
    r = rng.standard_normal(2 * n)
    instants = np.concatenate([np.arange(n), np.arange(n)])  # two channels, one time axis
    hac, white, window = hac_covariance(a, r, instants)
    np.testing.assert_allclose(np.sqrt(np.diag(hac)), np.sqrt(np.diag(white)), rtol=0.1)
    assert window < 5


def test_andrews_window_grows_with_persistence():
    rng = np.random.default_rng(7)
    white = andrews_lag_window(rng.standard_normal((5000, 1)))
    persistent = andrews_lag_window(_ar1(0.9, 5000, rng)[:, None])
    # Andrews (1991): L = 1.1447 (4 rho^2/((1-rho)^2 (1+rho)^2) n)^(1/3) for one AR(1) score.
    expected = 1.1447 * (4 * 0.81 / (0.01 * 3.61) * 5000) ** (1 / 3)
    assert white < 3
    assert persistent == pytest.approx(expected, rel=0.3)


def test_integrated_autocorrelation_time_of_ar1_and_of_a_difference():
    rng = np.random.default_rng(8)
    assert integrated_autocorrelation_time(_ar1(0.6, 40000, rng)) == pytest.approx(4.0, rel=0.15)
    u = rng.uniform(size=40001)
    assert integrated_autocorrelation_time(np.diff(u)) < 0.05  # a quantisation error's


def test_ljung_box_against_statsmodels():
    acorr_ljungbox = pytest.importorskip("statsmodels.stats.diagnostic").acorr_ljungbox
    rng = np.random.default_rng(9)
    for x in (rng.standard_normal(2000), _ar1(0.1, 2000, rng)):
        ours = whiteness(x)
        ref = acorr_ljungbox(x, lags=[ours["ljung_box_lags"]])
        assert ours["ljung_box_Q"] == pytest.approx(float(ref["lb_stat"].iloc[0]), rel=1e-6)
        assert ours["ljung_box_p"] == pytest.approx(float(ref["lb_pvalue"].iloc[0]), rel=1e-5)
    assert not whiteness(_ar1(0.3, 3000, rng))["white"]


def test_the_block_test_does_not_flag_long_filtered_noise():
    """Five minutes at 250 Hz of noise with the short-range correlation a DAQ's filter leaves
    (AR(1), lag-1 0.45): no structure, so p < 1e-3 in about 0.1 % of channels. A 5-lag
    Bartlett estimate of the long-run variance, 8-15 % low, had flagged 40-73 % of them."""
    from scipy.signal import lfilter

    from rollerrig.calibrate.stats import block_mean_test

    rng = np.random.default_rng(7)
    ps = [
        block_mean_test(lfilter([1.0], [1.0, -0.45], rng.standard_normal(75_000)))["block_mean_p"]
        for _ in range(20)
    ]
    assert min(ps) > 1e-3, ps
    # An anti-correlated series (an encoder's quantisation: lag-1 -0.5) is no bias either.
    c = rng.standard_normal(5001)
    assert block_mean_test(np.diff(c))["block_mean_p"] > 0.5
