"""Whiteness of residuals in time order: autocorrelation, Ljung–Box, the integrated
autocorrelation time (Sokal's window) and the effective number of samples.

Used by the calibration (its channels' residuals) and the estimators (their innovations).
Whiteness (:func:`whiteness`), per channel: the lag-1 autocorrelation, Durbin–Watson and runs
test of :func:`rollerrig.fit.diagnostics.residual_structure`, the Ljung–Box (1978) statistic
Q = n(n+2) Σ_{k≤m} ρ_k²/(n−k) over m = 20 lags with its χ²_m p-value, and the integrated
autocorrelation time τ = 1 + 2 Σ_k ρ_k (Sokal's window: the smallest K ≥ 5 τ(K)), whose
n/τ is the effective number of independent samples.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats as _stats

from rollerrig._validation import ParameterError, require_finite
from rollerrig.fit.diagnostics import residual_structure

__all__ = [
    "LJUNG_BOX_LAGS",
    "autocorrelation",
    "integrated_autocorrelation_time",
    "whiteness",
]

LJUNG_BOX_LAGS = 20
"""Lags of the Ljung–Box statistic [-]."""
_LJUNG_BOX_ALPHA = 0.01  # white below this p-value is rejected
_SOKAL_C = 5.0  # Sokal's window constant


def _series(x) -> np.ndarray:
    """``x`` as a finite 1-D float series of at least 2 samples (a NaN had made every lag's
    correlation 0: a series that looked white)."""
    x = require_finite("x", x, "-")
    if x.ndim != 1 or x.size < 2:
        raise ParameterError(f"x must be a 1-D series of at least 2 samples, got shape {x.shape}")
    return x


def autocorrelation(x: np.ndarray, max_lag: int) -> np.ndarray:
    """Sample autocorrelation ρ_0..ρ_max_lag of ``x`` (biased estimator, FFT).

    Examples
    --------
    >>> rho = autocorrelation(np.random.default_rng(0).standard_normal(4000), 3)
    >>> float(rho[0]), bool(np.all(np.abs(rho[1:]) < 0.05))
    (1.0, True)
    """
    x = _series(x)
    lag = require_finite("max_lag", max_lag, "-", single=True)  # NaN had reached int(): ValueError
    if not (lag == int(lag) and 0 <= lag < x.size):
        raise ParameterError(
            f"max_lag must be a whole number in [0, {x.size - 1}] (the series' length - 1), "
            f"got {max_lag!r}"
        )
    max_lag = int(max_lag)
    x = x - float(np.mean(x))
    n = x.size
    size = 1 << math.ceil(math.log2(2 * n))
    f = np.fft.rfft(x, size)
    acov = np.fft.irfft(f * np.conj(f), size)[: max_lag + 1]
    if not acov[0] > 0.0:
        out = np.zeros(max_lag + 1)
        out[0] = 1.0
        return out
    return acov / acov[0]


def integrated_autocorrelation_time(x: np.ndarray) -> float:
    """τ = 1 + 2 Σ_{k=1}^{K} ρ_k with Sokal's window (smallest K with K ≥ 5 τ(K)) [samples].

    n/τ is the effective sample size of the mean of ``x``; τ < 1 for negatively correlated
    samples (an encoder speed's quantisation error: τ → 0).

    Examples
    --------
    >>> e = np.random.default_rng(1).standard_normal(20000)
    >>> round(integrated_autocorrelation_time(e), 1)
    1.0
    >>> ar = np.zeros(20000)
    >>> for k in range(1, ar.size): ar[k] = 0.5 * ar[k - 1] + e[k]
    >>> abs(integrated_autocorrelation_time(ar) - 3.0) < 0.2  # (1 + 0.5) / (1 - 0.5)
    True
    """
    x = _series(x)
    max_lag = max(1, min(x.size // 2, 2000))
    rho = autocorrelation(x, max_lag)
    tau = 1.0 + 2.0 * np.cumsum(rho[1:])
    lags = np.arange(1, max_lag + 1)
    ok = np.flatnonzero(lags >= _SOKAL_C * tau)
    k = int(ok[0]) if ok.size else max_lag - 1
    return float(max(tau[k], 1.0 / x.size))


def whiteness(residuals: np.ndarray) -> dict:
    """Whiteness checks of one channel's residuals in time order, JSON-ready.

    Returns
    -------
    dict
        ``n``, ``lag1_autocorrelation``, ``durbin_watson``, ``runs_z`` (with their thresholds
        and ``structured`` from :func:`rollerrig.fit.diagnostics.residual_structure`),
        ``ljung_box_Q``, ``ljung_box_lags``, ``ljung_box_p``, ``white`` (Ljung–Box p ≥ 0.01),
        ``integrated_autocorrelation_time [samples]`` and ``effective_samples``.

    Examples
    --------
    >>> w = whiteness(np.random.default_rng(2).standard_normal(3000))
    >>> w["white"], w["structured"]
    (True, False)
    """
    e = np.asarray(residuals, dtype=float)
    structure = residual_structure(e, order="time").as_dict()
    n = e.size
    m = min(LJUNG_BOX_LAGS, n - 2)
    rho = autocorrelation(e, m)
    q = float(n * (n + 2) * np.sum(rho[1:] ** 2 / (n - np.arange(1, m + 1))))
    p = float(_stats.chi2.sf(q, m))
    tau = integrated_autocorrelation_time(e)
    return {
        **structure,
        "ljung_box_Q": q,
        "ljung_box_lags": int(m),
        "ljung_box_p": p,
        "white": bool(p >= _LJUNG_BOX_ALPHA),
        "integrated_autocorrelation_time [samples]": tau,
        "effective_samples": float(n / tau),
    }
