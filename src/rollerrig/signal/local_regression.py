"""Local regression with tricube weights: LOWESS (linear) and LOESS (quadratic), and their robust
variants with bisquare re-weighting (Cleveland 1979; MATLAB ``smooth`` ``'lowess'``, ``'loess'``,
``'rlowess'``, ``'rloess'``).

The interior is one fixed kernel applied by convolution; the end fits and the robust passes are
solved from their normal equations, built by convolution, in blocks of 65 536 samples, so
memory is O(n + window), never O(window²).
"""

from __future__ import annotations

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError
from rollerrig.signal._smoothing_input import _signal, _window

__all__ = ["ROBUST_ITERATIONS", "local_regression_kernel", "loess", "lowess"]

ROBUST_ITERATIONS = 5
"""Robust re-weighting passes after the first fit (MATLAB ``smooth`` 'rlowess'/'rloess': "repeat
the previous two steps for a total of five iterations")."""


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
        Kernel weights [-] (symmetric, summing to 1).

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
