"""Smoothing filters for rig signals, with MATLAB-familiar semantics (windows in samples).

The source dissertation (Kayaalp, sections 4.5.2.5-4.5.2.6) compares Butterworth low-pass
filters, moving average, Gaussian, LOWESS/LOESS (and their robust variants, MATLAB ``smoothdata``
/ ``smooth`` methods ``'lowess'``, ``'loess'``, ``'rlowess'``, ``'rloess'``) and Savitzky-Golay
filters on the roller-shaft torque signal sampled at 250 Hz. Each of them is available here,
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

The filters are in :mod:`~rollerrig.signal.averaging_filters` (moving average, Gaussian),
:mod:`~rollerrig.signal.local_regression` (LOWESS/LOESS, robust or not),
:mod:`~rollerrig.signal.savitzky_golay_filter` (Savitzky-Golay and its weights) and
:mod:`~rollerrig.signal.butterworth_filter` (Butterworth); each is importable from here too.
:func:`smooth` dispatches on a method name from :data:`METHODS`, the registry used by the filter
study in :mod:`rollerrig.signal.scoring`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.signal.averaging_filters import gaussian, gaussian_kernel, moving_average
from rollerrig.signal.butterworth_filter import butterworth, butterworth_sos
from rollerrig.signal.local_regression import local_regression_kernel, loess, lowess
from rollerrig.signal.savitzky_golay_filter import savgol_basis, savgol_kernel, savitzky_golay

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
