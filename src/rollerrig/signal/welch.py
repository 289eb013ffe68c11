"""Power spectra and coherence of signals in memory: Welch averaging or the periodogram.

:func:`power_spectrum`, :func:`amplitude_spectrum` and :func:`coherence` check an array and
stream it through the Welch estimators of :mod:`rollerrig.signal.streamed_welch` (bounded working
memory; equal to :func:`scipy.signal.welch` / :func:`scipy.signal.coherence` to rounding), or
take its windowed periodogram. Their segments, detrending and one-sided scaling (Heinzel et al.
2002) are described there; the results (:class:`Spectrum`, :class:`CoherenceSpectrum`,
:class:`CrossSpectra`) are in :mod:`rollerrig.signal.spectrum_results`, the settings' checks in
:mod:`rollerrig.signal.welch_settings`. The streamed estimators and the result types are
importable from here too.

References
----------
P. D. Welch, "The use of fast Fourier transform for the estimation of power spectra", IEEE Trans.
Audio Electroacoust. 15 (1967) 70-73.
G. Heinzel, A. Rüdiger, R. Schilling, "Spectrum and spectral density estimation by the Discrete
Fourier transform (DFT)", Max-Planck-Institut für Gravitationsphysik, 2002 (sections 9-10).
J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley, 2010, section 6.1.4 (coherence).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._numeric import check_samples
from rollerrig.signal.spectrum_results import (
    CoherenceSpectrum,
    CrossSpectra,
    Spectrum,
    power_unit,
)
from rollerrig.signal.streamed_welch import (
    coherence_stream,
    cross_spectra_stream,
    welch_stream,
)
from rollerrig.signal.welch_settings import (
    MAX_MAGNITUDE,
    _check_detrend,
    _check_nperseg,
    _choice,
    _window,
    enbw,
)

__all__ = [
    "CoherenceSpectrum",
    "CrossSpectra",
    "Spectrum",
    "amplitude_spectrum",
    "coherence",
    "coherence_stream",
    "cross_spectra_stream",
    "power_spectrum",
    "power_unit",
    "welch_stream",
]

_ARRAY_CHUNK = 1 << 22  # chunk length used when an in-memory array is streamed


def _as_signal(name: str, x) -> np.ndarray:
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be an array of numbers ({exc})") from None
    if arr.ndim != 1 or arr.size < 8:
        raise ParameterError(f"{name} must be a 1-D array of at least 8 samples, got {arr.shape}")
    check_samples(arr, 0, MAX_MAGNITUDE, "no sensor reads that", name)
    return arr


def _segment_length(n: int, nperseg: int | None, default: int) -> int:
    if nperseg is None:
        return min(n, default)
    return min(_check_nperseg(nperseg), n)


def array_chunks(x: np.ndarray, size: int = _ARRAY_CHUNK) -> Iterator[np.ndarray]:
    """Consecutive views of ``x`` of ``size`` samples, for the streaming estimators."""
    for start in range(0, x.shape[-1], size):
        yield x[..., start : start + size]


def power_spectrum(
    x,
    sample_rate: float,
    method: str = "welch",
    nperseg: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
    scaling: str = "spectrum",
    noverlap: int | None = None,
    *,
    name: str = "x",
) -> Spectrum:
    """One-sided power spectrum by Welch's method or the (windowed) periodogram.

    Welch: :func:`welch_stream` over the array (bounded working memory; equal to
    :func:`scipy.signal.welch`). Periodogram: :func:`scipy.signal.periodogram`.

    Parameters
    ----------
    x : array_like, shape (n,)
        Signal [unit], uniformly sampled, finite.
    sample_rate : float
        Sampling rate f_s [Hz].
    method : {"welch", "periodogram"}
        Welch's average of overlapping windowed segments (Welch 1967) or a single windowed
        periodogram of the whole record (finest resolution, no averaging).
    nperseg : int, optional
        Welch segment length [samples]; default ``min(n, max(256, n // 4))`` (about 7 averages
        with 50 % overlap). The bin spacing is ``f_s / nperseg``. Ignored by the periodogram.
        :func:`rollerrig.signal.spectrum_settings.choose_settings` chooses it from the signal.
    window : str
        Window name understood by :func:`scipy.signal.get_window`.
    detrend : {"linear", "constant", False}
        Trend removed from each segment before the transform.
    scaling : {"spectrum", "density"}
        ``"spectrum"``: power per bin [unit²], amplitude-calibrated so that a sine of amplitude
        ``A`` at a bin centre shows a peak of ``A**2/2`` (its mean square). ``"density"``: power
        spectral density [unit²/Hz], whose integral is the variance (Heinzel et al. 2002).
    noverlap : int, optional
        Welch overlap [samples]; default ``nperseg // 2``.
    name : str
        Name of the signal in error messages (e.g. ``"channel 'torque'"``).

    Returns
    -------
    Spectrum
        Frequencies [Hz] and power; unpacks as ``f, p``.

    Examples
    --------
    >>> fs = 250.0
    >>> t = np.arange(25_000) / fs
    >>> s = power_spectrum(2.0 * np.sin(2 * np.pi * 10.0 * t), fs, nperseg=2500)
    >>> f, p = s
    >>> round(float(f[np.argmax(p)]), 3), round(float(p.max()), 3)   # A**2/2 = 2
    (10.0, 2.0)
    """
    x = _as_signal(name, x)
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    method = _choice("method", method, ("welch", "periodogram"))
    scaling = _choice("scaling", scaling, ("spectrum", "density"))
    _check_detrend(detrend)
    n = x.size
    if method == "welch":
        seg = _segment_length(n, nperseg, max(256, n // 4))
        return welch_stream(array_chunks(x), fs, seg, noverlap, window, detrend, scaling, name=name)
    w = _window(window, n)
    f, p = sps.periodogram(x, fs, window=w, detrend=detrend, scaling=scaling)
    return Spectrum(f, p, scaling, "periodogram", fs, n, 1, str(window), enbw(w, fs), 0, detrend)


def amplitude_spectrum(x, sample_rate: float, **kwargs: Any) -> tuple[np.ndarray, np.ndarray]:
    """Peak-amplitude spectrum: a sine of amplitude ``A`` at a bin centre shows as ``A``.

    ``A_k = sqrt(2 P_k)`` with ``P_k`` the ``"spectrum"``-scaled power of
    :func:`power_spectrum` (the DC bin is not amplitude-calibrated).

    Parameters
    ----------
    x : array_like, shape (n,)
        Signal [unit].
    sample_rate : float
        Sampling rate [Hz].
    **kwargs
        Passed to :func:`power_spectrum` (``method``, ``nperseg``, ``window``, ``detrend``);
        ``scaling`` is fixed to ``"spectrum"``.

    Returns
    -------
    frequency : ndarray
        Bin frequencies [Hz].
    amplitude : ndarray
        Peak amplitude per bin [unit].

    Examples
    --------
    >>> t = np.arange(6000) / 600.0
    >>> f, a = amplitude_spectrum(0.15e-3 * np.sin(2 * np.pi * 3.0 * t), 600.0, nperseg=2000)
    >>> round(float(a.max()) * 1e3, 4)   # [mm]
    0.15
    """
    if "scaling" in kwargs:
        raise ParameterError("amplitude_spectrum fixes scaling='spectrum'; do not pass scaling")
    s = power_spectrum(x, sample_rate, scaling="spectrum", **kwargs)
    return s.frequency, np.sqrt(2.0 * s.power)


def coherence(
    x,
    y,
    sample_rate: float,
    nperseg: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
    noverlap: int | None = None,
) -> CoherenceSpectrum:
    """Magnitude-squared coherence ``γ² = |S_xy|² / (S_xx S_yy)`` by Welch averaging.

    :func:`coherence_stream` over the arrays (bounded working memory; equal to
    :func:`scipy.signal.coherence`, 50 % overlap by default). For ``y = h * x + n`` with noise
    ``n`` uncorrelated with ``x``, ``γ² = |H|² S_xx / (|H|² S_xx + S_nn)`` (Bendat & Piersol
    2010, eq. 6.37): a line present in both channels with γ² near 1 comes from one source.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        The two channels [any unit], sampled together.
    sample_rate : float
        Sampling rate [Hz].
    nperseg : int, optional
        Segment length [samples]; default ``min(n, max(256, n // 8))``. Coherence needs many
        segments: with one segment it is identically 1.
    window : str
        Window name.
    detrend : {"linear", "constant", False}
        Trend removed from each segment.
    noverlap : int, optional
        Overlap [samples]; default ``nperseg // 2``.

    Returns
    -------
    CoherenceSpectrum
        Unpacks as ``f, gamma2``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.standard_normal(20_000)
    >>> f, g = coherence(x, 2.0 * x + 0.1 * rng.standard_normal(x.size), 250.0, nperseg=256)
    >>> bool(g.min() > 0.99)
    True
    """
    x = _as_signal("x", x)
    y = _as_signal("y", y)
    if x.shape != y.shape:
        raise ParameterError(f"x and y must have the same length, got {x.size} and {y.size}")
    seg = _segment_length(x.size, nperseg, max(256, x.size // 8))
    pairs = zip(array_chunks(x), array_chunks(y), strict=True)
    return coherence_stream(pairs, sample_rate, seg, noverlap, window, detrend, names=("x", "y"))
