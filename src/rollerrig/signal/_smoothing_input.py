"""The signal and the window of a smoothing filter checked (a finite 1-D signal, a window in
samples, odd where the filter is centred), with the same words for every filter."""

from __future__ import annotations

import numpy as np

from rollerrig._validation import ParameterError, require_finite

__all__: list[str] = []


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
