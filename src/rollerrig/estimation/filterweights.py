"""Weights of the correction's linear filters: per-sample and phase-mean noise gains.

A white noise of variance σ² through a linear filter y = W x has, at sample i, the variance
σ² ‖W_i‖² (the squared norm of row i), and in the mean over samples [a, b) the variance
σ² ‖(1/m) Σ W_i‖². :func:`savitzky_golay_matrix` and :func:`encoder_speed_matrix` give the
exact matrices of :func:`rollerrig.signal.smoothing.savitzky_golay` (its end rows included)
and of :func:`rollerrig.measure.quantities.encoder_speed` (gate 1); :class:`BandedFilter`
keeps only the rows near the ends and one interior row, so a recording of millions of samples
costs a matrix of 4·half+1 rows.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import solve_triangular

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.signal.smoothing import savgol_basis as _savgol_basis
from rollerrig.signal.smoothing import savgol_kernel as _savgol_kernel

__all__ = ["BandedFilter", "after_encoder_speed", "encoder_speed_matrix", "savitzky_golay_matrix"]


class BandedFilter:
    """A linear filter on n samples whose rows are one kernel except within ``half`` of the ends.

    Built from the filter's matrix on 4·half+1 samples (the whole matrix when n is not
    longer), so the end rows of the Savitzky-Golay fits and of the encoder difference are
    exact.
    """

    def __init__(self, matrix_of, n: int, half: int):
        """``matrix_of(size)``: the filter's matrix on ``size`` samples."""
        self.n, self.h = n, half
        size = n if n <= 4 * half + 1 else 4 * half + 1
        matrix = matrix_of(size)
        self.size = size
        if size == n:
            self.full = matrix
        else:
            self.full = None
            self.head = matrix[: 2 * half]
            self.centre = matrix[2 * half]
            self.tail = matrix[size - 2 * half :]

    def row_norm2(self) -> np.ndarray:
        if self.full is not None:
            return np.sum(self.full**2, axis=1)
        out = np.full(self.n, float(np.sum(self.centre**2)))
        out[: 2 * self.h] = np.sum(self.head**2, axis=1)
        out[self.n - 2 * self.h :] = np.sum(self.tail**2, axis=1)
        return out

    def mean_norm2(self, start: int, stop: int) -> float:
        """‖(1/m) Σ_{start<=i<stop} W_i‖² (the variance gain of a mean over those samples)."""
        m = stop - start
        if m <= 0:
            return 0.0
        if self.full is not None:
            return float(np.sum(self.full[start:stop].sum(axis=0) ** 2) / m**2)
        n, h, size = self.n, self.h, self.size
        v = np.zeros(n)
        lo, hi = max(start, 2 * h), min(stop, n - 2 * h)
        if hi > lo:  # interior rows: the centre row shifted; v[k] = (ind * centre)[k + 2h]
            a, b = max(lo - 2 * h, 0), min(hi + 2 * h, n)
            ind = np.zeros(b - a)
            ind[lo - a : hi - a] = 1.0
            v[a:b] += np.convolve(ind, self.centre)[2 * h : 2 * h + b - a]
        for i in range(start, min(stop, 2 * h)):
            v[:size] += self.head[i]
        for i in range(max(start, n - 2 * h), stop):
            v[n - size :] += self.tail[i - (n - 2 * h)]
        return float(np.sum(v**2) / m**2)


def savitzky_golay_matrix(size: int, window: int, order: int, deriv: int = 0, delta=1.0):
    """The matrix W of :func:`rollerrig.signal.smoothing.savitzky_golay` on ``size`` samples.

    ``savitzky_golay(x, window, order, deriv, 1/delta) == W @ x``: the centred kernel inside,
    the polynomial fitted to the first/last window at the ends (``mode="interp"``).

    Examples
    --------
    >>> from rollerrig.signal.smoothing import savitzky_golay
    >>> x = np.random.default_rng(0).standard_normal(30)
    >>> W = savitzky_golay_matrix(30, 7, 3)
    >>> bool(np.allclose(W @ x, savitzky_golay(x, 7, 3)))
    True

    The window is centred on its sample, so its length is odd:

    >>> savitzky_golay_matrix(30, 6, 3)
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: window must be an odd integer >= 1 [samples] (centred on its sample), got 6; use 7 or 5
    """  # noqa: E501
    window, order, deriv = _check_savgol(size, window, order, deriv)
    delta = require_positive("delta", delta, "s", single=True)
    h = window // 2
    q, r = _savgol_basis(window, order)
    kernel = _savgol_kernel(q, r, h, deriv, delta)[::-1]  # weights of x[i-h .. i+h]
    out = np.zeros((size, size))
    for i in range(h, size - h):
        out[i, i - h : i + h + 1] = kernel
    # ends: the fit over the first/last window, evaluated (or differentiated) at the offsets
    fit = solve_triangular(r, q.T)  # (order+1, window): coefficients in u = k/h
    scale = (max(h, 1) * delta) ** deriv
    for offsets, rows, cols in (
        (np.arange(-h, 0), slice(0, h), slice(0, window)),
        (np.arange(1, h + 1), slice(size - h, size), slice(size - window, size)),
    ):
        u = offsets / max(h, 1)
        powers = np.arange(order + 1)
        coef = np.where(powers >= deriv, _falling(powers, deriv), 0.0)
        vander = coef * u[:, None] ** np.maximum(powers - deriv, 0)
        out[rows, cols] = vander @ fit / scale
    return out


def _check_savgol(size, window, order, deriv) -> tuple[int, int, int]:
    """``window, order, deriv`` of :func:`savitzky_golay_matrix` as ints, or ParameterError in
    the words of :func:`rollerrig.signal.smoothing.savitzky_golay`."""
    w, p, d, n = (
        require_finite(name, value, unit)
        for name, value, unit in (
            ("window", window, "samples"),
            ("order", order, ""),
            ("deriv", deriv, ""),
            ("size", size, "samples"),
        )
    )
    if w.ndim or w % 1 or w < 1 or w % 2 == 0:
        even = not (w.ndim or w % 1) and w >= 2
        hint = f"; use {int(w) + 1} or {int(w) - 1}" if even else ""
        raise ParameterError(
            f"window must be an odd integer >= 1 [samples] (centred on its sample), "
            f"got {window!r}{hint}"
        )
    w = int(w)
    if p.ndim or p % 1 or not 0 <= p < w:
        raise ParameterError(f"order must be an integer in [0, window) = [0, {w}), got {order!r}")
    p = int(p)
    if d.ndim or d % 1 or not 0 <= d <= p:
        raise ParameterError(f"deriv must be an integer in [0, order] = [0, {p}], got {deriv!r}")
    if n.ndim or n % 1 or n < w:
        raise ParameterError(
            f"size must be an integer >= window = {w} [samples] (the end rows fit a whole "
            f"window), got {size!r}"
        )
    return w, p, int(d)


def _falling(k, d: int):
    """k (k-1) ... (k-d+1), elementwise."""
    out = np.ones_like(k, dtype=float)
    for j in range(d):
        out = out * (k - j)
    return out


def encoder_speed_matrix(size: int, fs: float, cpr: float) -> np.ndarray:
    """Counts -> speed of :func:`rollerrig.measure.quantities.encoder_speed` (gate 1) [rad/s].

    Parameters
    ----------
    size : int
        Samples [-].
    fs : float
        Sample rate [Hz].
    cpr : float
        Counts per revolution [-].

    Examples
    --------
    >>> encoder_speed_matrix(3, 250.0, 10000)[1].round(6).tolist()
    [-0.15708, 0.15708, 0.0]
    """
    n = require_finite("size", size, "samples")
    if n.ndim or n % 1 or n < 2:
        # row 0 repeats row 1 (the first difference needs a sample before it), as
        # encoder_speed needs at least two samples
        raise ParameterError(
            f"size must be an integer >= 2 [samples] (a speed is a difference of two counts), "
            f"got {size!r}"
        )
    fs = require_positive("fs", fs, "Hz", single=True)
    cpr = require_positive("cpr", cpr, "1", single=True)
    size = int(n)
    scale = 2.0 * math.pi / cpr * fs
    out = np.zeros((size, size))
    i = np.arange(1, size)
    out[i, i] = scale
    out[i, i - 1] = -scale
    out[0] = out[1]  # sample 0 repeats sample 1
    return out


def after_encoder_speed(weights: np.ndarray, fs: float, cpr: float) -> np.ndarray:
    """``weights @ encoder_speed_matrix(size, fs, cpr)`` without the dense product.

    The encoder difference is bidiagonal (row 0 repeats row 1), so the product is a difference
    of neighbouring columns: O(size²) instead of O(size³).

    Examples
    --------
    >>> W = np.arange(16.0).reshape(4, 4)
    >>> dense = W @ encoder_speed_matrix(4, 250.0, 1e4)
    >>> bool(np.allclose(after_encoder_speed(W, 250.0, 1e4), dense))
    True
    """
    scale = 2.0 * math.pi / cpr * fs
    out = np.empty_like(weights)
    out[:, :-1] = scale * (weights[:, :-1] - weights[:, 1:])
    out[:, -1] = scale * weights[:, -1]
    out[:, 0] -= 2.0 * scale * weights[:, 0]  # row 0 of the difference is row 1: -1 at 0 ...
    out[:, 1] += scale * weights[:, 0]  # ... and +1 at 1
    return out
