"""Savitzky-Golay smoothing and differentiation (Savitzky & Golay 1964; MATLAB ``sgolayfilt``),
and its weights: the least-squares basis on the abscissa scaled to [-1, 1] and the convolution
kernel at the window's centre (public for the filters' exact weights in
:mod:`rollerrig.estimation.filterweights`)."""

from __future__ import annotations

import numpy as np
from scipy import signal as sps
from scipy.linalg import solve_triangular

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._smoothing_input import _signal, _window

__all__ = ["savgol_basis", "savgol_kernel", "savitzky_golay"]


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
        delta = 1.0 / require_positive("sample_rate", sample_rate, "Hz", single=True)
    n = x.size
    h = w // 2
    q, r = savgol_basis(w, p)
    y = sps.oaconvolve(x, savgol_kernel(q, r, h, d, delta), mode="same")
    if h:
        y[:h] = _savgol_end(x[:w], q, r, h, d, delta, np.arange(-h, 0))
        y[n - h :] = _savgol_end(x[n - w :], q, r, h, d, delta, np.arange(1, h + 1))
    return y


def savgol_basis(window: int, order: int) -> tuple[np.ndarray, np.ndarray]:
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


def savgol_kernel(q, r, half: int, deriv: int, delta: float) -> np.ndarray:
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
