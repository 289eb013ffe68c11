"""Smoothing filters against published tables, closed forms, MATLAB examples and peer libraries."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy import signal as sps

from rollerrig._validation import ParameterError
from rollerrig.signal.smoothing import (
    METHODS,
    butterworth,
    butterworth_sos,
    gaussian,
    gaussian_kernel,
    local_regression_kernel,
    loess,
    lowess,
    moving_average,
    savitzky_golay,
    smooth,
)


def _impulse_response(window, order, deriv=0):
    """Weights c_k with y[i] = Σ c_k x[i+k], read off the response to a unit impulse."""
    n = 4 * window
    x = np.zeros(n)
    x[n // 2] = 1.0
    y = savitzky_golay(x, window, order, deriv)
    h = window // 2
    return y[n // 2 - h : n // 2 + h + 1][::-1]


# --- Savitzky-Golay: published coefficient tables -----------------------------------------
@pytest.mark.parametrize(
    ("window", "order", "numerators", "norm"),
    [
        # Savitzky & Golay (1964), Table I (quadratic/cubic smoothing), 5, 7 and 9 points;
        # Press et al., Numerical Recipes (2nd ed.), §14.8 table: M=2 -> -0.086 0.343 0.486 ...
        (5, 2, [-3, 12, 17, 12, -3], 35),
        (7, 3, [-2, 3, 6, 7, 6, 3, -2], 21),
        (9, 2, [-21, 14, 39, 54, 59, 54, 39, 14, -21], 231),
        # Savitzky & Golay (1964), Table II (quartic/quintic), 7 and 9 points;
        # Numerical Recipes §14.8: M=4, 9 points -> 0.035 -0.128 0.070 0.315 0.417 ...
        (7, 4, [5, -30, 75, 131, 75, -30, 5], 231),
        (9, 4, [15, -55, 30, 135, 179, 135, 30, -55, 15], 429),
    ],
)
def test_savitzky_golay_smoothing_coefficients_match_published_tables(
    window, order, numerators, norm
):
    expected = np.array(numerators, float) / norm
    assert_allclose(_impulse_response(window, order), expected, atol=1e-14)
    assert_allclose(sps.savgol_coeffs(window, order, use="dot"), expected, atol=1e-14)


def test_savitzky_golay_first_derivative_matches_published_table():
    # Savitzky & Golay (1964), Table III: 5-point quadratic first derivative (-2,-1,0,1,2)/10
    expected = np.array([-2.0, -1.0, 0.0, 1.0, 2.0]) / 10.0
    assert_allclose(_impulse_response(5, 2, deriv=1), expected, atol=1e-14)
    assert_allclose(sps.savgol_coeffs(5, 2, deriv=1, use="dot"), expected, atol=1e-14)


def _exact_savgol_weights(window, order, deriv=0):
    """Savitzky-Golay weights (dot orientation, per sample) in exact rational arithmetic.

    c_k = d! Σ_j z_j k^j with (AᵀA) z = e_d, A_kj = k^j, k = -h..h: the normal equations of the
    least-squares polynomial (Savitzky & Golay 1964) solved with fractions, no rounding at all.
    """
    h = window // 2
    ks = range(-h, h + 1)
    n = order + 1
    powers = [sum(Fraction(k) ** m for k in ks) for m in range(2 * order + 1)]
    rows = [[powers[i + j] for j in range(n)] + [Fraction(int(i == deriv))] for i in range(n)]
    for c in range(n):  # Gauss-Jordan, exact
        pivot = next(r for r in range(c, n) if rows[r][c] != 0)
        rows[c], rows[pivot] = rows[pivot], rows[c]
        for r in range(n):
            if r != c and rows[r][c] != 0:
                f = rows[r][c] / rows[c][c]
                rows[r] = [a - f * b for a, b in zip(rows[r], rows[c], strict=True)]
    z = [rows[i][n] / rows[i][i] for i in range(n)]
    scale = math.factorial(deriv)
    return np.array([float(scale * sum(z[j] * Fraction(k) ** j for j in range(n))) for k in ks])


@pytest.mark.parametrize(
    ("window", "order", "deriv"), [(111, 4, 0), (201, 7, 0), (201, 7, 3), (31, 2, 1), (2001, 6, 0)]
)
def test_savitzky_golay_weights_equal_exact_rational_least_squares(window, order, deriv):
    # scipy 1.17 savgol_coeffs (unscaled integer abscissa) is off by 1.2e-11 at (111, 4),
    # 4e-9 at (201, 7, deriv 3) and returns weights summing to 8e-7 instead of 1 at (201, 7):
    # window 201, order 7 is in the seed's tuning grid at 250 Hz. Ours: rounding only (the
    # impulse response of a unit impulse, FFT path for the longest window: 2e-15 absolute).
    exact = _exact_savgol_weights(window, order, deriv)
    assert_allclose(_impulse_response(window, order, deriv), exact, rtol=0, atol=2e-15)


@pytest.mark.parametrize(("window", "order", "deriv"), [(31, 2, 1), (51, 3, 0), (111, 4, 0)])
def test_savitzky_golay_equals_scipy_savgol_filter_on_long_input(window, order, deriv):
    # long inputs take the FFT interior path; ends as savgol_filter(mode="interp"). Compared
    # where scipy's own weights are accurate: 1e-12, and 1e-10 at (111, 4) whose scipy weights
    # carry 1.2e-11 (see the exact-weight test above).
    x = np.cumsum(np.random.default_rng(1).standard_normal(60_000))
    ours = savitzky_golay(x, window, order, deriv, sample_rate=250.0)
    ref = sps.savgol_filter(x, window, order, deriv=deriv, delta=1 / 250.0, mode="interp")
    tol = 1e-10 if window > 100 else 1e-12
    assert_allclose(ours, ref, rtol=0, atol=tol * np.max(np.abs(ref)))


def test_savitzky_golay_at_19k2_windows_reproduces_its_polynomials_ends_included():
    # The seed's window 111 at 250 Hz is 8525 samples at 19.2 kHz: a degree-7 polynomial over
    # 5 windows must come back exactly (scipy 1.17 savgol_filter returns garbage here), and the
    # interior weights applied by direct summation must agree with the FFT path.
    u = np.linspace(-1.0, 1.0, 5 * 8525)
    poly = np.polynomial.polynomial.polyval(u, [3.0, -1.0, 2.0, 0.5, -2.0, 1.0, 0.7, -0.4])
    assert_allclose(savitzky_golay(poly, 8525, 7), poly, rtol=0, atol=1e-9)
    x = np.cumsum(np.random.default_rng(2).standard_normal(30_000))
    w = _impulse_response(8525, 4)
    direct = np.convolve(x, w[::-1], mode="valid")
    assert_allclose(savitzky_golay(x, 8525, 4)[4262:-4262], direct, rtol=0,
                    atol=1e-12 * np.max(np.abs(x)))  # fmt: skip


def test_savitzky_golay_derivative_in_physical_units():
    fs = 250.0
    t = np.arange(2000) / fs
    # exact for a polynomial of the filter's degree, ends included (mode "interp")
    x = 3.0 * t**3 - t
    assert_allclose(savitzky_golay(x, 21, 3, 1, fs), 9.0 * t**2 - 1.0, rtol=1e-9, atol=1e-9)
    assert_allclose(savitzky_golay(x, 21, 3, 2, fs), 18.0 * t, rtol=1e-9, atol=1e-7)
    # a 2 Hz sine: the quartic fit over 84 ms is biased by 1.5e-4 relative
    f = 2.0
    dx = savitzky_golay(np.sin(2 * np.pi * f * t), 21, 4, deriv=1, sample_rate=fs)
    assert_allclose(
        dx, 2 * np.pi * f * np.cos(2 * np.pi * f * t), rtol=0, atol=1e-3 * 2 * np.pi * f
    )


@settings(max_examples=30, deadline=None)
@given(
    order=st.integers(0, 6),
    coeffs=st.lists(st.floats(-2.0, 2.0), min_size=7, max_size=7),
    half=st.integers(4, 30),
)
def test_savitzky_golay_reproduces_polynomials_of_its_degree(order, coeffs, half):
    u = np.linspace(-1.0, 1.0, 400)
    x = np.polynomial.polynomial.polyval(u, coeffs[: order + 1])
    y = savitzky_golay(x, 2 * half + 1, max(order, 0) if order < 2 * half + 1 else 0)
    assert_allclose(y, x, atol=1e-8)


# --- local regression ---------------------------------------------------------------------
@settings(max_examples=30, deadline=None)
@given(coeffs=st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3), half=st.integers(3, 40))
def test_loess_reproduces_quadratics_and_lowess_lines_everywhere(coeffs, half):
    u = np.linspace(-1.0, 1.0, 300)
    quad = np.polynomial.polynomial.polyval(u, coeffs)
    line = np.polynomial.polynomial.polyval(u, coeffs[:2])
    assert_allclose(loess(quad, 2 * half + 1), quad, atol=1e-9)
    assert_allclose(lowess(line, 2 * half + 1), line, atol=1e-9)
    assert_allclose(loess(quad, 2 * half + 1, robust=True, iterations=2), quad, atol=1e-8)


def test_local_regression_kernel_is_normalised_and_symmetric():
    for degree in (1, 2):
        c = local_regression_kernel(131, degree)
        assert_allclose(c.sum(), 1.0, atol=1e-13)
        assert_allclose(c, c[::-1], atol=1e-15)
    # degree 1 with symmetric weights: the fit at the centre is the weighted mean (Cleveland 1979)
    w = (1 - np.abs(np.arange(-65, 66) / 65) ** 3) ** 3
    assert_allclose(local_regression_kernel(131, 1), w / w.sum(), atol=1e-15)


@pytest.mark.parametrize("window", [31, 131])
def test_lowess_interior_equals_statsmodels(window):
    # statsmodels.nonparametric.lowess with frac = window/n, it=0, delta=0 uses the `window`
    # nearest neighbours and tricube weights scaled by the farthest one: in the interior that is
    # our centred window. At the ends statsmodels keeps `window` neighbours (an asymmetric
    # window) while we shrink it (MATLAB smoothdata), so only the interior is compared.
    lowess_sm = pytest.importorskip("statsmodels.nonparametric.smoothers_lowess").lowess
    rng = np.random.default_rng(2)
    n = 2000
    t = np.arange(n, dtype=float)
    y = np.sin(t / 50) + 0.3 * rng.standard_normal(n)
    ref = lowess_sm(y, t, frac=window / n, it=0, delta=0.0, return_sorted=False)
    h = window // 2
    assert_allclose(lowess(y, window)[h:-h], ref[h:-h], rtol=0, atol=1e-12)


@pytest.mark.parametrize(("window", "iterations"), [(31, 3), (65, 5), (131, 5)])
def test_robust_lowess_interior_close_to_statsmodels(window, iterations):
    # Same bisquare weights (1 - (r / 6 median|r|)²)² and the same number of re-weighting passes
    # (statsmodels it = our iterations). The residuals at the ends differ (window shifted there,
    # shrunk here), which moves the global median |r| slightly, so the interior agrees closely
    # but not to rounding: measured max difference 1.3e-4 for noise σ = 0.2.
    lowess_sm = pytest.importorskip("statsmodels.nonparametric.smoothers_lowess").lowess
    rng = np.random.default_rng(3)
    n = 3000
    t = np.arange(n, dtype=float)
    y = np.sin(t / 80) + 0.2 * rng.standard_normal(n)
    y[rng.integers(0, n, 30)] += 3.0
    ours = lowess(y, window, robust=True, iterations=iterations)
    ref = lowess_sm(y, t, frac=window / n, it=iterations, delta=0.0, return_sorted=False)
    m = (iterations + 2) * (window // 2)
    assert_allclose(ours[m:-m], ref[m:-m], rtol=0, atol=1e-3)


def test_robust_local_regression_resists_outliers():
    n = 1000
    x = np.sin(np.arange(n) / 60.0)
    y = x + 0.01 * np.random.default_rng(7).standard_normal(n)
    y[500] += 20.0
    plain = np.abs(loess(y, 41) - x)[480:520].max()
    robust = np.abs(loess(y, 41, robust=True) - x)[480:520].max()
    assert plain > 1.0
    assert robust < 0.01


# --- moving average and Gaussian ----------------------------------------------------------
# --- fixed kernels: scipy.signal.oaconvolve(mode="same") ----------------------------------
@pytest.mark.parametrize(
    ("n", "m"), [(1, 1), (7, 1), (3, 7), (50, 51), (1000, 25), (20_000, 111), (100_000, 1001)]
)
def test_oaconvolve_same_equals_the_former_zero_padded_direct_convolution(n, m):
    # The fixed kernels used to go through a hand-written _fir_same, y[i] = Σ_j k[j] x[i + h - j]
    # with h = (m - 1) // 2 and zeros beyond the signal (np.convolve(x, k)[h : h + n]);
    # scipy.signal.oaconvolve(x, k, mode="same") is the same convolution (kernel flipped, the
    # same centring, also for a kernel longer than the signal) to rounding.
    rng = np.random.default_rng(n + m)
    x, k = rng.standard_normal(n), rng.standard_normal(m)  # an asymmetric kernel
    h = (m - 1) // 2
    old = np.convolve(x, k)[h : h + n]
    new = sps.oaconvolve(x, k, mode="same")
    assert new.shape == (n,)
    assert np.max(np.abs(new - old)) <= 1e-14 * np.sum(np.abs(k)) * np.max(np.abs(x))
    if m > 2:  # a correlation (kernel not flipped) is another result: the orientation is pinned
        assert not np.allclose(new, np.convolve(x, k[::-1])[h : h + n])


@pytest.mark.parametrize("window", [5, 33, 111, 1601])
def test_filter_interiors_equal_the_former_direct_convolution(window):
    # Gaussian, LOWESS/LOESS and Savitzky-Golay apply one fixed kernel away from the ends; the
    # results equal the former direct sums np.convolve(x, kernel)[h : h + n] to rounding.
    rng = np.random.default_rng(window)
    x = 100.0 + np.cumsum(rng.standard_normal(20_000))
    n, h = x.size, window // 2
    inner = slice(h, n - h)

    def direct(kernel):
        return np.convolve(x, kernel)[h : h + n][inner]

    scale = np.max(np.abs(x))
    assert np.max(np.abs(gaussian(x, window)[inner] - direct(gaussian_kernel(window)))) < (
        1e-13 * scale
    )
    for degree, f in ((1, lowess), (2, loess)):
        if window >= 3 + 2 * degree:
            kern = local_regression_kernel(window, degree)
            assert np.max(np.abs(f(x, window)[inner] - direct(kern))) < 1e-12 * scale
    weights = _impulse_response(window, 3) if window < 1000 else None
    if weights is not None:  # y[i] = Σ c_k x[i+k]: the convolution kernel is c reversed
        got = savitzky_golay(x, window, 3)[inner]
        assert np.max(np.abs(got - direct(weights[::-1]))) < 1e-12 * scale


def test_moving_average_matches_matlab_movmean_example():
    # MATLAB documentation, movmean, "Centered Moving Average of Vector"
    a = [4, 8, 6, -1, -2, -3, -1, 3, 4, 5]
    expected = [6.0, 6.0, 13 / 3, 1.0, -2.0, -2.0, -1 / 3, 2.0, 4.0, 4.5]
    assert_allclose(moving_average(a, 3), expected, atol=1e-14)


@pytest.mark.parametrize("window", [1, 2, 3, 10, 111])
def test_moving_average_interior_equals_numpy_convolve_and_ends_shrink(window):
    x = np.random.default_rng(4).standard_normal(500)
    y = moving_average(x, window)
    ref = np.convolve(x, np.ones(window) / window, mode="valid")
    before = window // 2
    assert_allclose(y[before : before + ref.size], ref, atol=1e-13)
    # ends: mean of the existing samples (MATLAB: even windows take one more sample behind)
    after = window - 1 - before
    assert_allclose(y[0], x[: after + 1].mean(), atol=1e-13)
    assert_allclose(y[-1], x[-before - 1 :].mean(), atol=1e-13)


def test_gaussian_kernel_sums_to_one_with_sigma_window_over_five():
    for window in (5, 33, 131):
        k = gaussian_kernel(window)
        assert_allclose(k.sum(), 1.0, atol=1e-14)
        offsets = np.arange(window) - window // 2
        assert_allclose(k[0] / k[window // 2], np.exp(-0.5 * (offsets[0] / (window / 5)) ** 2))


def test_gaussian_matches_matlab_smoothdata_example():
    # MathWorks Answers 406563 (C. Turnes, 2018): smoothdata(g, 'gaussian', 5), 4 decimals;
    # σ = window/5, ends renormalised over the existing samples.
    g = [0.27, -0.13, 0.3, -0.1, -0.12, -0.01, -0.21, -0.13, -0.11, -0.05, -0.26, 0.04]
    expected = [0.1330, 0.0861, 0.0728, -0.0039, -0.0703, -0.0971, -0.1313, -0.1338, -0.1139,
                -0.1154, -0.1196, -0.0715]  # fmt: skip
    assert_allclose(gaussian(g, 5), expected, atol=5e-5)


def test_gaussian_long_input_equals_direct_weighted_average():
    x = np.random.default_rng(5).standard_normal(20_000)
    k = gaussian_kernel(131)
    num = np.convolve(x, k)[65 : 65 + x.size]
    den = np.convolve(np.ones_like(x), k)[65 : 65 + x.size]
    assert_allclose(gaussian(x, 131), num / den, atol=1e-12)


# --- Butterworth --------------------------------------------------------------------------
def test_zero_phase_filters_add_no_delay_on_symmetric_pulse():
    fs = 250.0
    t = np.arange(5000) / fs
    pulse = np.exp(-0.5 * ((t - 10.0) / 0.3) ** 2)
    lags = np.arange(-200, 201)
    for method, params in [
        ("butterworth", {"cutoff": 1.2, "order": 3}),
        ("savitzky_golay", {"window": 111, "order": 4}),
        ("loess", {"window": 131}),
        ("gaussian", {"window": 65}),
        ("moving_average", {"window": 65}),
    ]:
        y = smooth(pulse, method, sample_rate=fs, **params)
        xc = sps.correlate(y, pulse, mode="full")[pulse.size - 1 + lags]
        assert lags[np.argmax(xc)] == 0, method


@pytest.mark.parametrize("order", [1, 2, 3])
def test_causal_butterworth_low_frequency_group_delay_matches_closed_form(order):
    # Analog Butterworth poles p_k = Ω_c exp(jθ_k): τ(0) = Σ -Re(p_k)/|p_k|² = 1/(Ω_c sin(π/2n)).
    # The bilinear transform keeps the delay at DC (dΩ/dω = 1 there) with the prewarped cut-off
    # Ω_c = 2 fs tan(π fc / fs).
    fs, fc = 250.0, 1.2
    omega_c = 2 * fs * np.tan(np.pi * fc / fs)
    tau0 = 1.0 / (omega_c * np.sin(np.pi / (2 * order)))
    b, a = sps.sos2tf(butterworth_sos(fs, fc, order))
    _, gd = sps.group_delay((b, a), w=[1e-4], fs=fs)
    assert_allclose(gd[0] / fs, tau0, rtol=1e-5)
    # a ramp comes out delayed by exactly τ(0) once the transient has died away
    t = np.arange(20000) / fs
    y = butterworth(t, fs, fc, order, zero_phase=False)
    assert_allclose(t[-1] - y[-1], tau0, rtol=1e-6)


def test_zero_phase_butterworth_squares_the_magnitude():
    fs, fc = 250.0, 1.2
    t = np.arange(50000) / fs
    x = np.sin(2 * np.pi * fc * t)
    y = butterworth(x, fs, fc, 2)
    # |H(fc)|² = 1/2 for a Butterworth of any order
    assert_allclose(np.max(np.abs(y[10000:-10000])), 0.5, rtol=2e-3)


# --- dispatcher and validation ------------------------------------------------------------
def test_dispatcher_runs_every_registered_method():
    x = np.random.default_rng(6).standard_normal(400)
    params = {
        "moving_average": {"window": 11},
        "gaussian": {"window": 11},
        "lowess": {"window": 11},
        "loess": {"window": 11},
        "rlowess": {"window": 11},
        "rloess": {"window": 11, "iterations": 2},
        "savitzky_golay": {"window": 11, "order": 3},
        "butterworth": {"cutoff": 5.0, "order": 2},
    }
    assert set(params) == set(METHODS)
    for name, p in params.items():
        y = smooth(x, name, sample_rate=250.0, **p)
        assert y.shape == x.shape and np.all(np.isfinite(y))
    assert_allclose(smooth(x, "rlowess", window=11), lowess(x, 11, robust=True))


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda x: smooth(x, "median", window=3), "unknown method"),
        (lambda x: smooth(x, "gaussian", span=3), "takes parameters"),
        (lambda x: smooth(x, "butterworth", cutoff=1.0), "sample_rate"),
        (lambda x: savitzky_golay(x, 10, 2), "odd"),
        (lambda x: savitzky_golay(x, 5, 5), "order"),
        (lambda x: loess(x, 5), "window"),
        (lambda x: butterworth(x, 250.0, 200.0), "Nyquist"),
        (lambda x: moving_average(x, 0), "window"),
    ],
)
def test_invalid_parameters_raise_named_errors(call, match):
    with pytest.raises(ParameterError, match=match):
        call(np.zeros(50))


# --- high rates: windows of thousands of samples ------------------------------------------
@pytest.mark.parametrize(
    ("method", "params"),
    [("loess", {}), ("lowess", {}), ("rloess", {"iterations": 2}),
     ("savitzky_golay", {"order": 5}), ("gaussian", {}), ("moving_average", {})],
)  # fmt: skip
def test_windows_of_20001_samples_need_memory_linear_in_the_signal(method, params):
    # The seed's windows at 19.2 kHz are up to 10 061 samples; a per-window least-squares matrix
    # (the former end-row cache: h × window × 8 bytes) would take 1.6 GB here. Every method must
    # stay within a few copies of the signal (tracemalloc sees numpy's buffers) and, where the
    # method reproduces polynomials, do so up to the ends.
    import tracemalloc

    n, w = 60_000, 20_001
    u = np.linspace(-1.0, 1.0, n)
    x = 2.0 + u - 3.0 * u**2
    tracemalloc.start()
    y = smooth(x, method, window=w, **params)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 40 * x.nbytes  # 19 MB; window² would be 3.2 GB
    if method in ("loess", "rloess", "savitzky_golay"):
        assert_allclose(y, x, rtol=0, atol=1e-9)
