"""The Butterworth low-pass: its second-order sections, and the filter zero-phase (forward-backward,
MATLAB ``filtfilt``) or causal (MATLAB ``filter``)."""

from __future__ import annotations

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._smoothing_input import _signal

__all__ = ["butterworth", "butterworth_sos"]


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
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    fc = require_positive("cutoff", cutoff, "Hz", single=True)
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
