"""Moving averages: the centred moving average (MATLAB ``movmean``) and the Gaussian-weighted
average (MATLAB ``smoothdata(..., 'gaussian')``), their windows shrunk at the ends."""

from __future__ import annotations

import numpy as np
from scipy import signal as sps
from scipy.ndimage import uniform_filter1d

from rollerrig.signal._smoothing_input import _signal, _window

__all__ = ["gaussian", "gaussian_kernel", "moving_average"]


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
        Normalised weights [-].

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
