"""How an estimate compares with the truth: RMS and largest error, lag
(:func:`estimator_performance`).
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from rollerrig.estimation.contact_estimate import ContactEstimate
from rollerrig.estimation.estimator_inputs import _array
from rollerrig.estimation.estimator_parameters import _positive
from rollerrig.recordings.recording import RecordingError

__all__ = ["estimator_performance"]


def estimator_performance(
    estimate, truth_contact_torque, sample_rate: float, *, max_lag: float = 0.5, unit="N.m"
) -> dict:
    """Lag and errors of an estimate against the truth.

    Parameters
    ----------
    estimate : ContactEstimate or array_like, shape (n,)
        The estimate (its ``contact_torque`` for a :class:`ContactEstimate`); any signal on
        the truth's samples works (a CoA with ``unit="-"``).
    truth_contact_torque : array_like, shape (n,)
        The true signal at the same instants [unit].
    sample_rate : float
        [Hz], > 0.
    max_lag : float
        Largest lag searched, either sign [s], > 0.
    unit : str
        Unit of the signals, for the keys (default N.m).

    Returns
    -------
    dict
        ``"lag [s]"``: where the correlation coefficient of the estimate and the shifted truth
        over their overlap peaks (parabolic interpolation between samples; > 0: the estimate
        comes later; None with ``"lag_note"`` when a signal has no variation);
        ``"rms_error [unit]"``, ``"max_abs_error [unit]"``, ``"bias [unit]"`` (mean of
        estimate − truth); ``"samples"``.

    Examples
    --------
    >>> t = np.arange(2000) / 250.0
    >>> truth = np.sin(2 * np.pi * 0.5 * t)
    >>> late = np.sin(2 * np.pi * 0.5 * (t - 0.02))
    >>> round(estimator_performance(late, truth, 250.0, unit="-")["lag [s]"], 3)
    0.02
    """
    est = estimate.contact_torque if isinstance(estimate, ContactEstimate) else estimate
    x = _array("estimate", est, unit, "the estimate")
    y = _array("truth_contact_torque", truth_contact_torque, unit, "the truth")
    if x.ndim == 0 or x.shape != y.shape:
        raise RecordingError(
            f"estimate ({x.size} samples) and truth ({y.size} samples) must be arrays on the "
            "same instants (same length)"
        )
    if x.size < 3:
        raise RecordingError(f"the performance needs at least 3 samples, got {x.size}")
    fs = _positive("sample_rate", sample_rate, "Hz")
    lag_max = _positive("max_lag", max_lag, "s")
    err = x - y
    out: dict = {
        "lag [s]": None,
        f"rms_error [{unit}]": float(np.sqrt(np.mean(err**2))),
        f"max_abs_error [{unit}]": float(np.max(np.abs(err))),
        f"bias [{unit}]": float(np.mean(err)),
        "samples": int(x.size),
    }
    xc, yc = x - x.mean(), y - y.mean()
    if not (np.any(xc) and np.any(yc)):
        out["lag_note"] = "a signal has no variation: no lag can be measured"
        return out
    m = max(1, min(round(lag_max * fs), x.size - 3))
    c = _lagged_correlation(xc, yc, m)
    i = int(np.argmax(c))
    frac = 0.0
    if 0 < i < c.size - 1:
        den = c[i - 1] - 2.0 * c[i] + c[i + 1]
        if den < 0.0:
            frac = 0.5 * (c[i - 1] - c[i + 1]) / den
    out["lag [s]"] = float((i - m + frac) / fs)
    if i in (0, c.size - 1):
        out["lag_note"] = f"the correlation peaks at the edge of the search (±{lag_max:g} s)"
    return out


def _lagged_correlation(x: np.ndarray, y: np.ndarray, m: int) -> np.ndarray:
    """Pearson correlation of x[i] with y[i − l] over their overlap, for l = −m..m.

    The products by FFT (:func:`scipy.signal.correlate`), the overlap's sums by cumulative
    sums: O(n log n) for all lags. A lag's overlap has n − |l| samples, so the coefficient
    is not biased towards short lags the way a zero-padded correlation is.
    """
    n = x.size
    full = signal.correlate(x, y, mode="full", method="fft")
    lags = np.arange(-m, m + 1)
    sxy = full[n - 1 - m : n + m]

    def sums(v):
        c1 = np.concatenate([[0.0], np.cumsum(v)])
        c2 = np.concatenate([[0.0], np.cumsum(v * v)])
        return c1, c2

    cx, cxx = sums(x)
    cy, cyy = sums(y)
    pos = np.maximum(lags, 0)
    neg = np.maximum(-lags, 0)
    # x[i] for i in [pos, n − neg), y[j] for j in [neg, n − pos).
    count = n - np.abs(lags)
    sx, sxx = cx[n - neg] - cx[pos], cxx[n - neg] - cxx[pos]
    sy, syy = cy[n - pos] - cy[neg], cyy[n - pos] - cyy[neg]
    cov = sxy - sx * sy / count
    var = np.maximum(sxx - sx * sx / count, 0.0) * np.maximum(syy - sy * sy / count, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(var > 0.0, cov / np.sqrt(var), 0.0)
    return r
