"""The settings of a Welch estimate checked: segment length and overlap, window, detrending,
scaling; the largest magnitude a signal may hold; the window's equivalent noise bandwidth.

Shared by the streamed estimators (:mod:`rollerrig.signal.streamed_welch`) and their array front
ends (:mod:`rollerrig.signal.welch`), so that both refuse the same settings with the same words.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_finite, require_positive

__all__ = ["MAX_MAGNITUDE", "enbw"]

#: Largest magnitude accepted in a signal: beyond it |X|² of a segment overflows double precision
#: for long segments, and no sensor reads it (1e300 in a file is a scale or parsing error).
MAX_MAGNITUDE = 1e100


def _choice(name: str, value, allowed: Sequence) -> Any:
    if value not in allowed:
        raise ParameterError(f"{name} must be one of {list(allowed)}, got {value!r}")
    return value


def _check_detrend(detrend) -> str | bool:
    if detrend is True or detrend not in ("linear", "constant", False):
        raise ParameterError(
            f"detrend must be one of ['linear', 'constant', False], got {detrend!r}"
        )
    return detrend


def _check_nperseg(nperseg) -> int:
    if isinstance(nperseg, bool) or int(nperseg) != nperseg or nperseg < 8:
        raise ParameterError(f"nperseg must be an integer >= 8 [samples], got {nperseg!r}")
    return int(nperseg)


def _check_segments(nperseg, noverlap) -> tuple[int, int]:
    seg = _check_nperseg(nperseg)
    overlap = seg // 2 if noverlap is None else noverlap
    if isinstance(overlap, bool) or int(overlap) != overlap or not 0 <= overlap < seg:
        raise ParameterError(
            f"noverlap must be an integer in [0, {seg}) [samples], got {noverlap!r}"
        )
    return seg, int(overlap)


def _window(window: str, nperseg: int) -> np.ndarray:
    try:
        return sps.get_window(window, nperseg)
    except (ValueError, TypeError) as exc:
        raise ParameterError(f"window {window!r} is not a window scipy knows: {exc}") from exc


def enbw(window, sample_rate: float) -> float:
    """Equivalent noise bandwidth ``f_s Σw² / (Σw)²`` of a window [Hz].

    Parameters
    ----------
    window : array_like, shape (n,)
        Window weights [-], finite, with a sum that is not zero.
    sample_rate : float
        Sampling rate [Hz], > 0.

    Examples
    --------
    >>> enbw(np.ones(8), 100.0)  # rectangular: one bin, f_s / n
    12.5
    >>> enbw(np.zeros(8), 100.0)
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: window must not sum to zero [-] (the equivalent noise bandwidth f_s Σw²/(Σw)² divides by it), got Σw = 0 over 8 samples
    """  # noqa: E501
    w = require_finite("window", window, "1")
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    if w.ndim != 1 or w.size == 0:
        raise ParameterError(
            f"window must be a 1-D array of at least one weight [-], got shape {w.shape}"
        )
    total = float(np.sum(w))
    # A sum within the rounding of summing n terms ((n-1)·eps·Σ|w|) is zero: the quotient of a
    # window like [1, -1] (or one antisymmetric to rounding) is rounding noise, not a bandwidth.
    if abs(total) <= w.size * np.finfo(float).eps * float(np.sum(np.abs(w))):
        raise ParameterError(
            "window must not sum to zero [-] (the equivalent noise bandwidth f_s Σw²/(Σw)² "
            f"divides by it), got Σw = {total:g} over {w.size} samples"
        )
    return fs * float(np.sum(w**2)) / total**2
