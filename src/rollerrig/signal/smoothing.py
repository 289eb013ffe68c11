"""Smoothing filters for rig signals, with MATLAB-familiar semantics (windows in samples).

The source dissertation (Kayaalp, sections 4.5.2.5-4.5.2.6) compares Butterworth low-pass
filters, moving average, Gaussian, LOWESS/LOESS (and their robust variants, MATLAB ``smoothdata``
/ ``smooth`` methods ``'lowess'``, ``'loess'``, ``'rlowess'``, ``'rloess'``) and Savitzky-Golay
filters on the roller-shaft torque signal sampled at 250 Hz. This module implements each of them
on uniformly sampled 1-D arrays:

=====================  ======================================  ==================================
method                 window / ends                           reference
=====================  ======================================  ==================================
``moving_average``     ``window`` samples; shrinks at ends     MATLAB ``movmean`` / ``smoothdata``
``gaussian``           span ``window``, σ = ``window``/5;      MATLAB ``smoothdata('gaussian')``
                       shrinks and renormalises at ends
``lowess``/``loess``   ``window`` samples, tricube weights;    Cleveland (1979); MATLAB
                       local linear / quadratic; shrinks       ``smooth``/``smoothdata``
``savitzky_golay``     ``window`` samples; polynomial fit to   Savitzky & Golay (1964); MATLAB
                       the first/last window at the ends       ``sgolayfilt``; scipy ``interp``
``butterworth``        cut-off [Hz]; zero-phase (forward-      MATLAB ``butter`` + ``filtfilt``
                       backward) or causal                     / ``filter``
=====================  ======================================  ==================================

Every function returns an array of the input's length. Fixed kernels are applied by FFT
overlap-add convolution, :func:`scipy.signal.oaconvolve` with ``mode="same"`` (zero padding beyond
the signal; the same result as direct convolution to rounding, about 5e-16 relative). Memory is
O(n + window·order) for every
method, whatever the window: at 19.2 kHz the seed's windows grow to 10 000 samples, where a
matrix of end-fit weights (half-window × window values) would take 0.4 GB; the end fits of
LOWESS/LOESS and Savitzky-Golay are solved from their normal equations or a window-by-order QR
instead, and the robust re-weighting runs in blocks of 65 536 samples.

:func:`smooth` dispatches on a method name from :data:`METHODS`, the registry used by the filter
study in :mod:`rollerrig.signal.scoring`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import signal as sps
from scipy.linalg import solve_triangular
from scipy.ndimage import uniform_filter1d

from rollerrig._validation import ParameterError, require_finite, require_positive

__all__ = [
    "METHODS",
    "SmoothingMethod",
    "butterworth",
    "butterworth_sos",
    "gaussian",
    "gaussian_kernel",
    "local_regression_kernel",
    "loess",
    "lowess",
    "method_reach",
    "moving_average",
    "savgol_basis",
    "savgol_kernel",
    "savitzky_golay",
    "smooth",
]

ROBUST_ITERATIONS = 5
"""Robust re-weighting passes after the first fit (MATLAB ``smooth`` 'rlowess'/'rloess': "repeat
the previous two steps for a total of five iterations")."""


# --------------------------------------------------------------------------------------------
# validation helpers
# --------------------------------------------------------------------------------------------
def _signal(x) -> np.ndarray:
    arr = require_finite("x", x)
    if arr.ndim != 1:
        raise ParameterError(f"x must be a 1-D signal, got shape {arr.shape}")
    if arr.size == 0:
        raise ParameterError("x must have at least one sample")
    return arr


def _window(window, *, odd: bool, minimum: int = 1) -> int:
    try:
        w = int(window)
    except (TypeError, ValueError) as exc:
        raise ParameterError(
            f"window must be an integer number of samples, got {window!r}"
        ) from exc
    if w != window or w < minimum:
        raise ParameterError(f"window must be an integer >= {minimum} [samples], got {window!r}")
    if odd and w % 2 == 0:
        raise ParameterError(f"window must be odd [samples], got {w}; use {w + 1} or {w - 1}")
    return w


# --------------------------------------------------------------------------------------------
# moving average and Gaussian
# --------------------------------------------------------------------------------------------
def moving_average(x, window: int) -> np.ndarray:
    """Centred moving average with the window shrunk at the ends (MATLAB ``movmean``).

    ``y[i]`` is the mean of ``x[i - a .. i + b]`` over the samples that exist, with
    ``a = b = (window - 1)/2`` for odd windows and ``a = window/2``, ``b = window/2 - 1`` for
    even windows (MATLAB: "centred about the current and previous elements").

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal [any unit].
    window : int
        Window length [samples], >= 1.

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal [unit of ``x``].

    Examples
    --------
    >>> moving_average([1.0, 2.0, 3.0, 4.0, 5.0], 3)
    array([1.5, 2. , 3. , 4. , 4.5])
    """
    x = _signal(x)
    w = _window(window, odd=False)
    # uniform_filter1d with cval=0 gives sum/w; rescale the ends by the count of existing samples.
    y = uniform_filter1d(x, w, mode="constant", cval=0.0)
    n = x.size
    before, after = w // 2, w - 1 - w // 2
    edge = np.unique(np.r_[0 : min(before, n), max(n - after, 0) : n])
    count = np.minimum(edge, before) + np.minimum(n - 1 - edge, after) + 1
    y[edge] *= w / count
    return y


def gaussian_kernel(window: int) -> np.ndarray:
    """Gaussian weights over a span of ``window`` samples, σ = window/5, summing to 1.

    MATLAB ``smoothdata(..., 'gaussian', window)`` fixes the standard deviation at 1/5 of the
    window width (MathWorks Answers 406563, C. Turnes, 2018): ``w(k) ∝ exp(-k²/(2σ²))`` for
    offsets ``k = -(window-1)/2 .. (window-1)/2``.

    Parameters
    ----------
    window : int
        Odd span [samples].

    Returns
    -------
    ndarray, shape (window,)
        Normalised weights [1].

    Examples
    --------
    >>> round(float(gaussian_kernel(5).sum()), 12)
    1.0
    """
    w = _window(window, odd=True)
    k = np.arange(w) - (w - 1) / 2.0
    sigma = w / 5.0
    g = np.exp(-0.5 * (k / sigma) ** 2)
    return g / g.sum()


def gaussian(x, window: int) -> np.ndarray:
    """Gaussian-weighted moving average (MATLAB ``smoothdata(x, 'gaussian', window)``).

    Weights :func:`gaussian_kernel` (σ = window/5); at the ends the window is truncated to the
    existing samples and the remaining weights are rescaled to sum to 1, as MATLAB does.

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal [any unit].
    window : int
        Odd span [samples].

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal [unit of ``x``].

    Examples
    --------
    MATLAB Answers 406563: ``smoothdata(g, 'gaussian', 5)`` begins 0.1330, 0.0861, 0.0728.

    >>> g = [0.27, -0.13, 0.3, -0.1, -0.12, -0.01, -0.21, -0.13, -0.11, -0.05, -0.26, 0.04]
    >>> np.round(gaussian(g, 5)[:3], 4)
    array([0.133 , 0.0861, 0.0728])
    """
    x = _signal(x)
    kern = gaussian_kernel(window)
    num = sps.oaconvolve(x, kern, mode="same")
    h = kern.size // 2
    den = np.ones_like(x)
    if h and x.size > 2 * h:
        # weight sums are 1 in the interior; only the first/last h samples are truncated.
        edge = np.cumsum(kern)[h : 2 * h]
        den[:h] = edge
        den[-h:] = edge[::-1]
    elif h:
        den = sps.oaconvolve(np.ones_like(x), kern, mode="same")
    return num / den


# --------------------------------------------------------------------------------------------
# local regression (LOWESS / LOESS) with tricube weights
# --------------------------------------------------------------------------------------------
def _tricube(half: int) -> np.ndarray:
    """Tricube weights at offsets -half..half, scaled by the half-window (zero at ±half)."""
    u = np.abs(np.arange(-half, half + 1)) / half
    return (1.0 - u**3) ** 3


def local_regression_kernel(window: int, degree: int) -> np.ndarray:
    """Interior LOWESS/LOESS kernel: the fitted value at the window centre as weights on samples.

    The local polynomial of ``degree`` is fitted by weighted least squares with tricube weights
    ``w(k) = (1 - |k/h|³)³``, ``h = (window-1)/2`` (Cleveland 1979, eq. 2; MATLAB ``smooth``:
    "d(x) is the distance to the most distant predictor value within the span"). The value at the
    centre is linear in the samples: ``ŷ = Σ c_k x_{i+k}``, ``c = e₀ᵀ (XᵀWX)⁻¹ XᵀW``.

    Parameters
    ----------
    window : int
        Odd span [samples].
    degree : int
        1 (LOWESS) or 2 (LOESS).

    Returns
    -------
    ndarray, shape (window,)
        Kernel weights [1] (symmetric, summing to 1).

    Examples
    --------
    >>> c = local_regression_kernel(7, 2)
    >>> round(float(c.sum()), 12), bool(np.allclose(c, c[::-1]))
    (1.0, True)
    """
    w = _window(window, odd=True, minimum=3)
    h = (w - 1) // 2
    wt = _tricube(h)
    u = np.arange(-h, h + 1) / h
    vander = np.vander(u, degree + 1, increasing=True)
    gram = vander.T @ (wt[:, None] * vander)
    return np.linalg.solve(gram, (vander * wt[:, None]).T)[0]


_ROBUST_BLOCK = 1 << 16
"""Output samples per block of the weighted local fit [samples] (bounds its temporaries)."""


def _weighted_local_fit(
    x: np.ndarray, weights: np.ndarray, half: int, degree: int, fallback: np.ndarray
) -> np.ndarray:
    """Local polynomial values ``ŷ[i]`` with per-sample weights (tricube × ``weights``).

    The weighted normal equations at sample i have entries ``S_k = Σ_o w(o) u^k r[i+o]`` and
    ``T_k = Σ_o w(o) u^k r[i+o] x[i+o]`` with ``u = o/h``, ``w`` the tricube weights and ``r``
    the per-sample weights: each is a correlation of ``r`` or ``r·x`` with a fixed kernel of
    ``2h + 1`` samples, so they are computed by convolution; zero padding beyond the signal gives
    the shrunk end windows (the interior tricube scale ``h`` is kept). The (degree+1)² systems
    are solved in one batched call per block of :data:`_ROBUST_BLOCK` outputs, so temporaries
    are O(block + window), never O(window²). Where a system is singular (too many zero weights)
    ``fallback`` is kept.
    """
    n = x.size
    u = np.arange(-half, half + 1) / half
    wt = _tricube(half)
    kernels = [(wt * u**k)[::-1] for k in range(2 * degree + 1)]
    y = np.array(fallback, dtype=float, copy=True)
    block = max(_ROBUST_BLOCK, 4 * (2 * half + 1))
    for a in range(0, n, block):
        b = min(a + block, n)
        lo, hi = max(a - half, 0), min(b + half, n)
        r = weights[lo:hi]
        rx = r * x[lo:hi]
        s = [sps.oaconvolve(r, kern, mode="same")[a - lo : b - lo] for kern in kernels]
        t = [sps.oaconvolve(rx, k, mode="same")[a - lo : b - lo] for k in kernels[: degree + 1]]
        gram = np.empty((b - a, degree + 1, degree + 1))
        for j in range(degree + 1):
            for k in range(degree + 1):
                gram[:, j, k] = s[j + k]
        rhs = np.stack(t, axis=1)
        det = np.linalg.det(gram)
        scale = np.prod(np.diagonal(gram, axis1=1, axis2=2), axis=1)
        ok = np.abs(det) > 1e-10 * np.maximum(scale, 1e-300)
        if np.any(ok):
            y[a:b][ok] = np.linalg.solve(gram[ok], rhs[ok][..., None])[:, 0, 0]
    return y


def _local_fit(x: np.ndarray, window: int, degree: int) -> np.ndarray:
    """Non-robust local polynomial smoothing with shrinking end windows.

    Interior: one fixed kernel (:func:`local_regression_kernel`) by convolution. The first and
    last ``h`` samples: the weighted fit over the samples that exist, solved from the normal
    equations of the first/last ``2h`` samples (:func:`_weighted_local_fit` with unit weights),
    O(window) memory.
    """
    h = (window - 1) // 2
    n = x.size
    y = sps.oaconvolve(x, local_regression_kernel(window, degree), mode="same")
    m = min(2 * h, n)
    ones = np.ones(m)
    head, tail = x[:m], x[n - m :][::-1]
    y[:h] = _weighted_local_fit(head, ones, h, degree, y[:m])[:h]
    y[n - h :] = _weighted_local_fit(tail, ones, h, degree, y[n - m :][::-1])[:h][::-1]
    return y


def _bisquare_weights(residual: np.ndarray) -> np.ndarray:
    """Robust weights ``(1 - (r / 6 MAD)²)²`` for ``|r| < 6 MAD``, else 0; MAD = median |r|."""
    mad = np.median(np.abs(residual))
    if mad == 0.0:
        return (residual == 0.0).astype(float)
    q = np.minimum(np.abs(residual) / (6.0 * mad), 1.0)
    return (1.0 - q**2) ** 2


def _local_regression(x, window, degree, robust, iterations) -> np.ndarray:
    x = _signal(x)
    w = _window(window, odd=True, minimum=3 + 2 * degree)
    if x.size < w:
        raise ParameterError(f"x has {x.size} samples, fewer than window = {w} [samples]")
    y = _local_fit(x, w, degree)
    if robust:
        n_iter = int(iterations)
        if n_iter < 0:
            raise ParameterError(f"iterations must be >= 0, got {iterations!r}")
        scale = float(np.max(np.abs(x)))
        h = (w - 1) // 2
        for _ in range(n_iter):
            residual = x - y
            if np.median(np.abs(residual)) <= 1e-12 * scale:
                break  # the fit is exact to rounding; bisquare weights would only amplify noise
            y = _weighted_local_fit(x, _bisquare_weights(residual), h, degree, y)
    return y


def lowess(x, window: int, robust: bool = False, iterations: int = ROBUST_ITERATIONS):
    """Locally weighted linear regression (MATLAB ``'lowess'``; ``robust=True``: ``'rlowess'``).

    At each sample a straight line is fitted by weighted least squares to the ``window`` samples
    centred on it, with tricube weights ``(1 - |k/h|³)³``, ``h = (window-1)/2`` (Cleveland 1979);
    the window shrinks at the ends to the existing samples (weights keep the interior scale ``h``).
    The interior is one fixed kernel (:func:`local_regression_kernel`) applied by convolution.

    Robust variant (Cleveland 1979, MATLAB ``smooth``): residuals ``r`` give bisquare weights
    ``(1 - (r/6 MAD)²)²`` (zero for ``|r| >= 6 MAD``, ``MAD = median |r|``), the fit is repeated
    with tricube × robust weights, ``iterations`` times (default 5, as MATLAB; statsmodels
    ``lowess(it=iterations)`` is the same scheme). Iterations stop early when ``MAD`` is at
    rounding level (``<= 1e-12 max|x|``): the fit is then exact and re-weighting by rounding
    noise would only discard good samples. Where the robust weights leave a local fit
    undetermined, the previous pass's value is kept.

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal [any unit], ``n >= window``.
    window : int
        Odd span [samples], >= 5.
    robust : bool
        Apply the bisquare robustness iterations.
    iterations : int
        Robust re-weighting passes after the first fit.

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal [unit of ``x``].

    Examples
    --------
    A straight line is reproduced exactly, ends included:

    >>> t = np.arange(20.0)
    >>> bool(np.allclose(lowess(3.0 + 0.5 * t, 7), 3.0 + 0.5 * t))
    True
    """
    return _local_regression(x, window, 1, robust, iterations)


def loess(x, window: int, robust: bool = False, iterations: int = ROBUST_ITERATIONS):
    """Locally weighted quadratic regression (MATLAB ``'loess'``; ``robust=True``: ``'rloess'``).

    As :func:`lowess` with a local polynomial of degree 2 (Cleveland & Devlin 1988); statsmodels
    offers degree 1 only. Window >= 7 so that the end fits (``h`` non-zero weights) are determined.

    Parameters
    ----------
    x, window, robust, iterations
        As in :func:`lowess` (signal [any unit], odd span [samples] but >= 7, robust
        re-weighting and its passes).

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal [unit of ``x``].

    Examples
    --------
    >>> t = np.arange(30.0)
    >>> bool(np.allclose(loess(1.0 - 0.2 * t + 0.03 * t**2, 9), 1.0 - 0.2 * t + 0.03 * t**2))
    True
    """
    return _local_regression(x, window, 2, robust, iterations)


# --------------------------------------------------------------------------------------------
# Savitzky-Golay
# --------------------------------------------------------------------------------------------
def savitzky_golay(x, window: int, order: int, deriv: int = 0, sample_rate: float | None = None):
    """Savitzky-Golay smoothing or differentiation (Savitzky & Golay 1964; MATLAB ``sgolayfilt``).

    Least-squares polynomial of degree ``order`` over ``window`` samples centred on each sample
    (Kayaalp, section 4.5.2.6: minimise ``ε_N = Σ_{n=-M}^{M} (Σ_k a_k n^k − x[n])²``); the
    value (or ``deriv``-th derivative) of the polynomial at the centre. Ends: the polynomial fitted
    to the first/last ``window`` samples is evaluated there (scipy ``mode="interp"``, as MATLAB
    ``sgolayfilt``). The least-squares problems are solved on the abscissa scaled to [-1, 1]
    (QR), so the weights stay exact to rounding at any window (19.2 kHz windows of 10 000
    samples included); :func:`scipy.signal.savgol_filter` gives the same result where its
    unscaled weights are accurate (small windows, low orders) and wrong ones beyond (window 201,
    order 7 returns ~0 for a constant). Memory O(n + window·order).

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal [any unit], ``n >= window``.
    window : int
        Odd frame length [samples], > ``order``.
    order : int
        Polynomial degree, >= 0.
    deriv : int
        Derivative order, 0 <= deriv <= order.
    sample_rate : float, optional
        Sampling rate [Hz]; with it derivatives are per second (unit of ``x`` / s^deriv), without
        it per sample.

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal or derivative.

    Examples
    --------
    Savitzky & Golay (1964), Table I: 5-point quadratic smoothing = (−3, 12, 17, 12, −3)/35.

    >>> x = np.zeros(9); x[4] = 35.0
    >>> savitzky_golay(x, 5, 2)[2:7]
    array([-3., 12., 17., 12., -3.])
    """
    x = _signal(x)
    w = _window(window, odd=True)
    p = int(order)
    if p != order or p < 0 or p >= w:
        raise ParameterError(f"order must be an integer in [0, window) = [0, {w}), got {order!r}")
    d = int(deriv)
    if d != deriv or d < 0 or d > p:
        raise ParameterError(f"deriv must be an integer in [0, order] = [0, {p}], got {deriv!r}")
    if x.size < w:
        raise ParameterError(f"x has {x.size} samples, fewer than window = {w} [samples]")
    delta = 1.0
    if sample_rate is not None:
        delta = 1.0 / float(require_positive("sample_rate", sample_rate, "Hz"))
    n = x.size
    h = w // 2
    q, r = _savgol_basis(w, p)
    y = sps.oaconvolve(x, _savgol_kernel(q, r, h, d, delta), mode="same")
    if h:
        y[:h] = _savgol_end(x[:w], q, r, h, d, delta, np.arange(-h, 0))
        y[n - h :] = _savgol_end(x[n - w :], q, r, h, d, delta, np.arange(1, h + 1))
    return y


def _savgol_basis(window: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Reduced QR of the Vandermonde matrix of ``u = k/h``, ``k = -h..h`` (scaled to [-1, 1]).

    Scaling the abscissa keeps the least-squares problem well conditioned (~1e3 for order 7)
    whatever the window: :func:`scipy.signal.savgol_coeffs` uses the raw integers ``k`` and
    loses every digit at high rates (scipy 1.17: window 201, order 7 returns weights summing to
    8e-7 instead of 1; window 111, order 4 sums to 1 + 1.2e-11).
    """
    h = window // 2
    u = np.arange(-h, h + 1) / max(h, 1)
    q, r = np.linalg.qr(np.vander(u, order + 1, increasing=True))
    return q, r


def _savgol_kernel(q, r, half: int, deriv: int, delta: float) -> np.ndarray:
    """Convolution kernel of the ``deriv``-th derivative at the window centre [1/s^deriv]."""
    e = np.zeros(r.shape[0])
    e[deriv] = float(np.prod(np.arange(1, deriv + 1))) / (max(half, 1) * delta) ** deriv
    dot = q @ solve_triangular(r, e, trans="T")  # row `deriv` of pinv(A), scaled
    return dot[::-1].copy()


def _savgol_end(xw, q, r, half: int, deriv: int, delta: float, offsets) -> np.ndarray:
    """The polynomial fitted to the window ``xw`` (or its derivative) ``offsets`` from its centre.

    MATLAB ``sgolayfilt`` / scipy ``mode="interp"``: the first and last ``h`` samples take the
    fit over the first/last full window.
    """
    coef = np.polynomial.Polynomial(solve_triangular(r, q.T @ xw))
    if deriv:
        coef = coef.deriv(deriv) / (max(half, 1) * delta) ** deriv
    return coef(np.asarray(offsets, dtype=float) / max(half, 1))


# --------------------------------------------------------------------------------------------
# Butterworth
# --------------------------------------------------------------------------------------------
def butterworth_sos(sample_rate: float, cutoff: float, order: int) -> np.ndarray:
    """Second-order sections of a digital Butterworth low-pass (``scipy.signal.butter``).

    Parameters
    ----------
    sample_rate : float
        Sampling rate [Hz].
    cutoff : float
        −3 dB cut-off frequency of the single pass [Hz], below ``sample_rate / 2``.
    order : int
        Filter order, >= 1.

    Returns
    -------
    ndarray, shape (ceil(order/2), 6)
        Second-order sections.

    Examples
    --------
    >>> butterworth_sos(250.0, 1.2, 3).shape
    (2, 6)
    """
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    fc = float(require_positive("cutoff", cutoff, "Hz"))
    if fc >= fs / 2:
        raise ParameterError(
            f"cutoff must be below the Nyquist frequency {fs / 2:g} Hz, got {fc:g}"
        )
    o = int(order)
    if o != order or o < 1:
        raise ParameterError(f"order must be an integer >= 1, got {order!r}")
    return sps.butter(o, fc, btype="low", fs=fs, output="sos")


def butterworth(x, sample_rate: float, cutoff: float, order: int = 2, zero_phase: bool = True):
    """Butterworth low-pass, zero-phase (forward-backward) or causal.

    Zero-phase: :func:`scipy.signal.sosfiltfilt` (as MATLAB ``filtfilt``) — no delay, magnitude
    ``|H(f)|²`` (effective order ``2·order``, −6 dB at ``cutoff``), odd-extension padding at the
    ends. Causal: :func:`scipy.signal.sosfilt` from rest (as MATLAB ``filter``) — magnitude
    ``|H(f)|`` and the group delay ``−dφ/dω`` the seed blames for the lag (Kayaalp, section
    4.5.2.5).

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal [any unit].
    sample_rate : float
        Sampling rate [Hz].
    cutoff : float
        Cut-off frequency [Hz] (the seed uses 1.2 Hz).
    order : int
        Filter order, >= 1 (the seed compares 1, 2 and 3).
    zero_phase : bool
        Forward-backward filtering (True) or a single causal pass (False).

    Returns
    -------
    ndarray, shape (n,)
        Filtered signal [unit of ``x``].

    Examples
    --------
    >>> y = butterworth(np.ones(500), 250.0, 1.2, 2)
    >>> bool(np.allclose(y, 1.0))
    True
    """
    x = _signal(x)
    sos = butterworth_sos(sample_rate, cutoff, order)
    if zero_phase:
        try:
            return sps.sosfiltfilt(sos, x)
        except ValueError as exc:  # fewer samples than the edge padding
            raise ParameterError(
                f"x has {x.size} samples, too few for a zero-phase Butterworth of order {order} "
                f"({exc})"
            ) from None
    return sps.sosfilt(sos, x)


# --------------------------------------------------------------------------------------------
# registry and dispatcher
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SmoothingMethod:
    """A registered smoothing method.

    Attributes
    ----------
    name : str
        Registry key (also the MATLAB-like label).
    function : callable
        ``function(x, **params)`` (Butterworth also takes ``sample_rate``).
    parameters : tuple of str
        Parameter names the method takes, besides the signal.
    fixed : dict
        Parameters the registry entry fixes (e.g. ``robust=True`` for ``'rlowess'``).
    needs_sample_rate : bool
        Whether ``sample_rate`` [Hz] must be given.
    finite_support : bool
        True when each output sample depends on a finite window of input samples (FIR-like:
        streams exactly in chunks), False for IIR filters.
    description : str
        One line for tables and legends.
    """

    name: str
    function: Callable[..., np.ndarray]
    parameters: tuple[str, ...]
    fixed: dict
    needs_sample_rate: bool
    finite_support: bool
    description: str


METHODS: dict[str, SmoothingMethod] = {
    m.name: m
    for m in (
        SmoothingMethod("moving_average", moving_average, ("window",), {}, False, True,
                        "moving average (MATLAB movmean)"),
        SmoothingMethod("gaussian", gaussian, ("window",), {}, False, True,
                        "Gaussian-weighted average, σ = window/5"),
        SmoothingMethod("lowess", lowess, ("window",), {"robust": False}, False, True,
                        "local linear regression, tricube"),
        SmoothingMethod("loess", loess, ("window",), {"robust": False}, False, True,
                        "local quadratic regression, tricube"),
        SmoothingMethod("rlowess", lowess, ("window", "iterations"), {"robust": True}, False,
                        False, "robust local linear regression (bisquare, 6 MAD)"),
        SmoothingMethod("rloess", loess, ("window", "iterations"), {"robust": True}, False,
                        False, "robust local quadratic regression (bisquare, 6 MAD)"),
        SmoothingMethod("savitzky_golay", savitzky_golay, ("window", "order", "deriv"), {},
                        False, True, "Savitzky-Golay polynomial smoothing"),
        SmoothingMethod("butterworth", butterworth, ("cutoff", "order", "zero_phase"), {},
                        True, False, "Butterworth low-pass"),
    )
}  # fmt: skip
"""Smoothing methods by name. The robust local regressions use the global MAD of the residuals,
so they are not finite-support filters."""


def smooth(x, method: str, *, sample_rate: float | None = None, **params) -> np.ndarray:
    """Smooth ``x`` with a registered method.

    Parameters
    ----------
    x : array_like, shape (n,)
        Uniformly sampled signal [any unit].
    method : str
        A key of :data:`METHODS`.
    sample_rate : float, optional
        Sampling rate [Hz]; required by ``'butterworth'`` and used by Savitzky-Golay derivatives.
    **params
        The method's parameters (see ``METHODS[method].parameters``).

    Returns
    -------
    ndarray, shape (n,)
        Smoothed signal.

    Examples
    --------
    >>> smooth(np.arange(5.0), "moving_average", window=3)
    array([0.5, 1. , 2. , 3. , 3.5])
    """
    spec = _spec(method)
    unknown = set(params) - set(spec.parameters)
    if unknown:
        raise ParameterError(
            f"method {method!r} takes parameters {list(spec.parameters)}, got {sorted(unknown)}"
        )
    kwargs = {**spec.fixed, **params}
    if spec.needs_sample_rate:
        if sample_rate is None:
            raise ParameterError(f"method {method!r} needs sample_rate [Hz]")
        return spec.function(x, sample_rate, **kwargs)
    if method == "savitzky_golay" and sample_rate is not None:
        kwargs["sample_rate"] = sample_rate
    return spec.function(x, **kwargs)


def _spec(method: str) -> SmoothingMethod:
    try:
        return METHODS[method]
    except KeyError:
        raise ParameterError(f"unknown method {method!r}; known: {sorted(METHODS)}") from None


def method_reach(method: str, **params) -> int:
    """How many samples on each side one output sample of a finite-support method depends on.

    Parameters
    ----------
    method : str
        A finite-support key of :data:`METHODS`.
    **params
        The method's parameters (``window``).

    Returns
    -------
    int
        Half-window [samples] (``window // 2``).

    Examples
    --------
    >>> method_reach("savitzky_golay", window=111, order=4)
    55
    """
    spec = _spec(method)
    if not spec.finite_support:
        raise ParameterError(f"method {method!r} has no finite support (IIR or global weights)")
    return int(params["window"]) // 2


# Public names of the Savitzky-Golay weights, for the filters' exact weights (estimation).
savgol_basis = _savgol_basis
savgol_kernel = _savgol_kernel
