"""Long lines drawn in report figures: reduced to their envelope (one concern, no heavy imports,
so that the twin figure does not pull in the filter study)."""

from __future__ import annotations

import numpy as np

from rollerrig._validation import ParameterError, require_whole

__all__ = ["PLOT_POINTS", "envelope"]

PLOT_POINTS = 20_000
"""Most points a line of a report figure draws [-]; longer signals are drawn as their envelope."""


def envelope(x, y, max_points: int = PLOT_POINTS):
    """A long line reduced for drawing: the minimum and maximum of ``y`` in each of
    ``max_points // 2`` consecutive bins and the first and last sample, in time order.

    A figure is ~1000 pixels wide, so the drawn line looks the same (every excursion kept),
    while the figure holds ``max_points`` points instead of millions (one hour at 1 kHz: 3.6 M
    samples per line; matplotlib keeps and transforms every point it is given).

    Parameters
    ----------
    x, y : array_like, shape (n,)
        The line [any units].
    max_points : int
        Points returned: at most ``max_points`` (>= 4), and the two ends.

    Returns
    -------
    (ndarray, ndarray)
        ``x`` and ``y`` at the kept samples (the inputs themselves when ``n <= max_points``).

    Examples
    --------
    >>> x = np.arange(10.0)
    >>> envelope(x, np.array([0, 5, 1, 1, -3, 1, 1, 1, 2, 0.0]), 4)[1]
    array([ 0.,  5., -3.,  2.,  0.])
    """
    x = np.asarray(x)
    y = np.asarray(y)
    if x.ndim != 1 or x.shape != y.shape:  # x[keep] had paired y with the wrong instants
        raise ParameterError(
            f"x (shape {x.shape}) and y (shape {y.shape}) must be 1-D arrays of the same length"
        )
    max_points = require_whole("max_points", max_points, minimum=1)
    n = y.size
    if n <= max(int(max_points), 4):
        return x, y
    bins = max(int(max_points) // 2, 2)
    k = -(-n // bins)  # samples per bin, rounded up
    m = n // k * k
    head = y[:m].reshape(-1, k)
    base = np.arange(0, m, k)
    lo, hi = base + np.argmin(head, axis=1), base + np.argmax(head, axis=1)
    idx = [np.minimum(lo, hi), np.maximum(lo, hi)]
    if m < n:  # the last, shorter bin
        tail = y[m:]
        a, b = m + int(np.argmin(tail)), m + int(np.argmax(tail))
        idx.append(np.array([min(a, b), max(a, b)]))
    ends = np.array([0, n - 1])  # the line spans the whole signal
    keep = np.unique(np.concatenate([ends, np.column_stack(idx[:2]).ravel(), *idx[2:]]))
    return x[keep], y[keep]
