"""Chunked (streaming) smoothing of long recordings with bounded memory.

A one-hour DAQ recording at 19.2 kHz holds about 69 M samples per channel; smoothing it whole
needs several copies of every channel in memory. :func:`filter_chunks` consumes an iterable of
chunks (from a file reader, a memory map, a generator) and yields the filtered signal chunk by
chunk, holding only one chunk plus a fixed overlap:

* finite-support filters (moving average, Gaussian, LOWESS/LOESS, Savitzky-Golay): each output
  sample depends on ``window // 2`` samples either side, so every chunk is filtered together with
  ``window`` samples of history and the last ``window // 2`` outputs wait for the next chunk. The
  ends of the recording get exactly the whole-array end handling. The result equals the
  whole-array result to rounding (FFT block boundaries move; ~1e-13 relative);
* causal Butterworth (``zero_phase=False``): ``sosfilt`` carries its state ``zi`` from chunk to
  chunk — the same recursion as the whole-array pass, equal to rounding;
* zero-phase Butterworth: the forward-backward filter has an infinite (decaying) two-sided
  impulse response, so a chunk is filtered with ``P`` samples of padding either side
  (overlap-save) and the padded parts are dropped. ``P`` (:func:`zero_phase_padding`) is chosen
  so that the impulse-response tail beyond ``P`` sums to less than ``tolerance``; the error
  against the whole-array result is then below ``tolerance × peak-to-peak(x)`` (measured about
  0.02 × tolerance × peak-to-peak on random walks, orders 1-3, tolerance 1e-3..1e-12; the tests
  assert ≤ tolerance × peak-to-peak). For 1.2 Hz, order 2 at 19.2 kHz and tolerance 1e-9, ``P``
  is about 3.9 s of samples;
* robust LOWESS/LOESS use the median of *all* residuals and are refused.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal.smoothing import METHODS, butterworth_sos, method_reach, smooth

__all__ = ["filter_array_chunked", "filter_chunks", "iter_chunks", "zero_phase_padding"]

MAX_ORDER = 32
"""Highest Butterworth order streamed zero-phase [-]. scipy's design loses the filter beyond
it: measured with scipy 1.17, the sections of order 56 at cutoff/sample_rate = 5e-7 (0.01 Hz at
19.2 kHz) have DC gain 0 instead of 1 (the gain, a product over 2·order poles, underflows), and
an order 1000 ends in a LinAlgError; 32 keeps a margin and is 192 dB per octave (the rig's
study compares orders 1-3)."""

MAX_PADDING = 1 << 24
"""Longest impulse response searched for the padding [samples]: 2^24 samples, 128 MiB per
array (the search holds a few), and :func:`filter_chunks` then holds 2·P samples per channel
besides each chunk. At 19.2 kHz it is 14.6 min, longer than any phase of a rig test; a
filter that rings longer (a cut-off of 1 mHz at 19.2 kHz asked 90 M samples, 10^-4 Hz 9 GiB)
belongs after decimation (:mod:`rollerrig.signal.decimate`)."""


def zero_phase_padding(sample_rate: float, cutoff: float, order: int, tolerance: float = 1e-9):
    """Padding [samples] for overlap-save zero-phase Butterworth filtering.

    The smallest ``P`` with ``Σ_{k>=P} |h[k]| <= tolerance``, ``h`` the impulse response of the
    causal Butterworth filter (its tail bounds both the truncated forward-backward response and the
    decay of the edge transients of a padded segment).

    Parameters
    ----------
    sample_rate : float
        Sampling rate [Hz].
    cutoff : float
        Cut-off frequency [Hz].
    order : int
        Filter order.
    tolerance : float
        Allowed impulse-response tail [-], in (0, 1).

    Returns
    -------
    int
        Padding [samples].

    Examples
    --------
    >>> p = zero_phase_padding(19200.0, 1.2, 2)
    >>> 3.0 < p / 19200.0 < 4.0
    True
    """
    if (
        isinstance(order, bool | np.bool_)
        or not isinstance(order, int | np.integer | float | np.floating)
        or not 1 <= order <= MAX_ORDER
        or int(order) != order
    ):  # before butter(), which allocates by the order (10**9: 7 GiB)
        raise ParameterError(
            f"order must be an integer in [1, {MAX_ORDER}] (scipy's Butterworth sections lose "
            f"their gain at higher orders), got {order!r}"
        )
    sos = butterworth_sos(sample_rate, cutoff, order)
    tol = require_positive("tolerance", tolerance, single=True)
    if tol >= 1.0:
        raise ParameterError(f"tolerance must lie in (0, 1), got {tol:g}")
    _, poles, _ = sps.sos2zpk(sos)
    radius = float(np.max(np.abs(poles)))
    # length over which the slowest pole decays well below the tolerance (log(tol) + log(1e-3):
    # tol·1e-3 underflows to 0 for tol < 5e-321); a pole at or within rounding of the unit
    # circle (cutoff/sample_rate ~ 1e-16) never decays: refused with the too-long ones
    decay = np.log(radius) if radius < 1.0 else 0.0
    estimate = (np.log(tol) + np.log(1e-3)) / decay if decay < 0.0 else np.inf
    estimate += 16 * int(order) + 64
    if not estimate <= MAX_PADDING:
        fs, fc = float(sample_rate), float(cutoff)
        raise ParameterError(
            f"cutoff {fc:g} Hz is too low for zero-phase streaming at sample_rate {fs:g} Hz "
            f"(order {int(order)}, tolerance {tol:g}): the impulse response needs about "
            f"{estimate:.3g} samples to decay, more than MAX_PADDING = {MAX_PADDING} samples "
            f"(memory); decimate first, or raise cutoff or tolerance"
        )
    length = int(np.ceil(estimate))
    impulse = np.zeros(length)
    impulse[0] = 1.0
    h = np.abs(sps.sosfilt(sos, impulse))
    tail = np.cumsum(h[::-1])[::-1]  # tail[k] = Σ_{j>=k} |h[j]|
    return int(np.argmax(tail <= tol)) if np.any(tail <= tol) else length


def iter_chunks(x, chunk_size: int) -> Iterator[np.ndarray]:
    """Consecutive views of ``x`` (axis 0) of ``chunk_size`` samples (the last may be shorter).

    Parameters
    ----------
    x : array_like, shape (n, ...)
        Samples along axis 0 (a memory map works without loading it).
    chunk_size : int
        Samples per chunk, >= 1.

    Yields
    ------
    ndarray
        Views of ``x``.

    Examples
    --------
    >>> [c.tolist() for c in iter_chunks(np.arange(5), 2)]
    [[0, 1], [2, 3], [4]]
    """
    size = int(chunk_size)
    if size < 1 or size != chunk_size:
        raise ParameterError(f"chunk_size must be an integer >= 1 [samples], got {chunk_size!r}")
    for start in range(0, len(x), size):
        yield x[start : start + size]


def _apply(x: np.ndarray, method: str, sample_rate, params) -> np.ndarray:
    if x.ndim == 1:
        return smooth(x, method, sample_rate=sample_rate, **params)
    out = np.empty(x.shape)
    for j in range(x.shape[1]):
        out[:, j] = smooth(x[:, j], method, sample_rate=sample_rate, **params)
    return out


def _causal_stream(chunks, sos) -> Iterator[np.ndarray]:
    zi = None
    for chunk in chunks:
        c = np.asarray(chunk, dtype=float)
        if c.shape[0] == 0:
            continue
        if zi is None:
            zi = np.zeros((sos.shape[0], 2, *c.shape[1:]))
        y, zi = sps.sosfilt(sos, c, axis=0, zi=zi)
        yield y


def _windowed_stream(
    chunks, method, sample_rate, params, reach, history, minimum
) -> Iterator[np.ndarray]:
    """Overlap-save: keep ``history`` samples before the next output, wait for ``reach`` after."""
    pending: np.ndarray | None = None
    origin = 0  # global index of pending[0]
    emitted = 0  # global index of the next sample to emit
    for chunk in chunks:
        c = np.asarray(chunk, dtype=float)
        if c.shape[0] == 0:
            continue
        pending = c if pending is None else np.concatenate([pending, c], axis=0)
        stop = origin + pending.shape[0] - reach  # outputs before stop have their full window
        if stop - emitted < max(reach, 1) or pending.shape[0] < minimum:
            continue  # too little new material; wait for more
        y = _apply(pending, method, sample_rate, params)
        yield y[emitted - origin : stop - origin]
        emitted = stop
        keep = max(stop - history, 0)
        pending = pending[keep - origin :]
        origin = keep
    if pending is not None and emitted < origin + pending.shape[0]:
        y = _apply(pending, method, sample_rate, params)
        yield y[emitted - origin :]


def filter_chunks(
    chunks: Iterable,
    method: str,
    *,
    sample_rate: float | None = None,
    tolerance: float = 1e-9,
    **params,
) -> Iterator[np.ndarray]:
    """Filter a stream of chunks, yielding the filtered signal in chunks (bounded memory).

    Concatenating the yielded chunks gives the whole-array result of
    :func:`rollerrig.signal.smoothing.smooth` (to rounding for finite-support methods and causal
    Butterworth; within about ``tolerance × peak-to-peak(x)`` for zero-phase Butterworth). The
    yielded chunks need not align with the input chunks (finite-support methods hold back the
    last half-window until the next chunk arrives).

    Parameters
    ----------
    chunks : iterable of array_like, each shape (m,) or (m, channels)
        Consecutive pieces of the signal [any unit], samples along axis 0.
    method : str
        A key of :data:`rollerrig.signal.smoothing.METHODS` except the robust ``'rlowess'`` and
        ``'rloess'`` (they use the median of all residuals).
    sample_rate : float, optional
        Sampling rate [Hz] (Butterworth; Savitzky-Golay derivatives).
    tolerance : float
        Impulse-response tail allowed for zero-phase Butterworth padding [-].
    **params
        The method's parameters.

    Yields
    ------
    ndarray
        Filtered samples, in order.

    Examples
    --------
    >>> x = np.sin(np.arange(1000) / 20.0)
    >>> y = np.concatenate(list(filter_chunks(iter_chunks(x, 128), "savitzky_golay",
    ...                                       window=31, order=3)))
    >>> bool(np.allclose(y, smooth(x, "savitzky_golay", window=31, order=3)))
    True
    """
    if method not in METHODS:
        raise ParameterError(f"unknown method {method!r}; known: {sorted(METHODS)}")
    if method == "butterworth":
        if sample_rate is None:
            raise ParameterError("method 'butterworth' needs sample_rate [Hz]")
        order = params.get("order", 2)
        if not params.get("zero_phase", True):
            yield from _causal_stream(chunks, butterworth_sos(sample_rate, params["cutoff"], order))
            return
        pad = zero_phase_padding(sample_rate, params["cutoff"], order, tolerance)
        yield from _windowed_stream(chunks, method, sample_rate, params, pad, pad, 2 * pad)
        return
    if not METHODS[method].finite_support:
        raise ParameterError(
            f"method {method!r} cannot be streamed: its robust weights use the median of all "
            "residuals; filter the whole array with smooth() instead"
        )
    reach = method_reach(method, **params)
    window = int(params["window"])
    # a window of history keeps every end fit (Savitzky-Golay 'interp') at full length
    yield from _windowed_stream(chunks, method, sample_rate, params, reach, window + reach, window)


def filter_array_chunked(
    x, method: str, *, chunk_size: int = 1 << 20, sample_rate: float | None = None, **params
) -> np.ndarray:
    """Filter an array (or memory map) chunk by chunk into a new array.

    Parameters
    ----------
    x : array_like, shape (n,) or (n, channels)
        Signal [any unit], samples along axis 0.
    method : str
        See :func:`filter_chunks`.
    chunk_size : int
        Samples per chunk.
    sample_rate : float, optional
        Sampling rate [Hz].
    **params
        The method's parameters.

    Returns
    -------
    ndarray
        Filtered signal, same shape as ``x``.

    Examples
    --------
    >>> x = np.arange(10.0)
    >>> filter_array_chunked(x, "moving_average", chunk_size=3, window=3)[:3]
    array([0.5, 1. , 2. ])
    """
    out = np.empty(np.shape(x))
    pos = 0
    for piece in filter_chunks(
        iter_chunks(x, chunk_size), method, sample_rate=sample_rate, **params
    ):
        out[pos : pos + piece.shape[0]] = piece
        pos += piece.shape[0]
    return out
