"""Power and cross spectra by Welch averaging, in bounded memory, from arrays or streams of chunks.

:func:`welch_stream` and :func:`cross_spectra_stream` take an iterable of chunks (a file reader, a
memory map, a generator) and average windowed, detrended segments as they arrive, holding only
one chunk, less than one segment of history and a fixed batch of segments; the result equals
:func:`scipy.signal.welch` / :func:`scipy.signal.csd` / :func:`scipy.signal.coherence` on the
concatenated signal (same segments, window, detrending and scaling) to rounding. One hour at
19.2 kHz (69 M samples) then needs a few tens of MB beyond the chunk being read, instead of
several copies of the whole record.

Segments (scipy's convention, ``boundary=None``, ``padded=False``): segment ``k`` covers samples
``k·step … k·step + nperseg − 1`` with ``step = nperseg − noverlap``, ``k = 0 … K − 1``,
``K = (n − noverlap) // step``; samples after the last full segment are not used. Each segment is
detrended (``"linear"``: least-squares line removed; ``"constant"``: mean removed), multiplied by
the window ``w`` and transformed (``nfft = nperseg``). One-sided scaling (Heinzel et al. 2002):
``"spectrum"`` multiplies ``|X|²`` by ``1/(Σw)²`` (a sine of amplitude ``A`` at a bin centre reads
``A²/2``), ``"density"`` by ``1/(f_s Σw²)`` [unit²/Hz]; every bin but DC (and Nyquist for even
``nperseg``) is doubled. The cross spectrum is ``conj(X)·Y`` with the same scaling, and the
magnitude-squared coherence ``|S_xy|² / (S_xx S_yy)``.

References
----------
P. D. Welch, "The use of fast Fourier transform for the estimation of power spectra", IEEE Trans.
Audio Electroacoust. 15 (1967) 70-73.
G. Heinzel, A. Rüdiger, R. Schilling, "Spectrum and spectral density estimation by the Discrete
Fourier transform (DFT)", Max-Planck-Institut für Gravitationsphysik, 2002 (sections 9-10).
J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley, 2010, section 6.1.4 (coherence).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._numeric import check_samples

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

#: Largest magnitude accepted in a signal: beyond it |X|² of a segment overflows double precision
#: for long segments, and no sensor reads it (1e300 in a file is a scale or parsing error).
MAX_MAGNITUDE = 1e100

_BATCH_SAMPLES = 1 << 21  # samples per batch of segments (16 MB of float64 per channel)
_ARRAY_CHUNK = 1 << 22  # chunk length used when an in-memory array is streamed
_ROUND_OFF = 1e-10  # residual RMS / magnitude below which a detrended signal counts as empty


# --------------------------------------------------------------------------------------------
# Result types
# --------------------------------------------------------------------------------------------


class _FrequencyPair:
    """Unpacks as its first two fields, ``frequency, values = spectrum`` (spectra dataclasses)."""

    def __iter__(self) -> Iterator[np.ndarray]:
        return (getattr(self, f.name) for f in fields(self)[:2])


@dataclass(frozen=True)
class Spectrum(_FrequencyPair):
    """A one-sided power spectrum.

    Unpacks as ``frequency, power = spectrum``.

    Attributes
    ----------
    frequency : ndarray
        Bin frequencies [Hz].
    power : ndarray
        Power per bin [unit²] (``scaling="spectrum"``) or power spectral density [unit²/Hz]
        (``scaling="density"``).
    scaling : str
        ``"spectrum"`` or ``"density"``.
    method : str
        ``"welch"`` or ``"periodogram"``.
    sample_rate : float
        Sampling rate [Hz].
    nperseg : int
        Samples per segment (the whole record for the periodogram).
    n_segments : int
        Number of averaged segments (1 for the periodogram).
    window : str
        Window name.
    enbw : float
        Equivalent noise bandwidth of the window [Hz] (1.5 bins for Hann).
    noverlap : int
        Overlap of consecutive segments [samples] (0 for the periodogram).
    detrend : str or bool
        Trend removed from each segment: ``"linear"``, ``"constant"`` or False.
    """

    frequency: np.ndarray
    power: np.ndarray
    scaling: str
    method: str
    sample_rate: float
    nperseg: int
    n_segments: int
    window: str
    enbw: float
    noverlap: int = 0
    detrend: str | bool = "linear"

    @property
    def resolution(self) -> float:
        """Bin spacing Δf [Hz]."""
        return float(self.frequency[1] - self.frequency[0])


@dataclass(frozen=True)
class CoherenceSpectrum(_FrequencyPair):
    """Magnitude-squared coherence γ²(f) of two channels; unpacks as ``frequency, coherence``.

    Attributes
    ----------
    frequency : ndarray
        Bin frequencies [Hz].
    coherence : ndarray
        γ² in [0, 1].
    n_segments : int
        Averaged segments (the bias of γ² is about ``(1 - γ²)² / n_segments``).
    nperseg : int
        Samples per segment (0 when unknown).
    noverlap : int
        Overlap [samples].
    window : str
        Window name.
    detrend : str or bool
        Trend removed from each segment.
    """

    frequency: np.ndarray
    coherence: np.ndarray
    n_segments: int
    nperseg: int = 0
    noverlap: int = 0
    window: str = "hann"
    detrend: str | bool = "linear"


@dataclass(frozen=True)
class CrossSpectra:
    """Auto and cross spectra of two channels from one Welch pass.

    Attributes
    ----------
    x, y : Spectrum
        Power spectra of the two channels.
    cross : ndarray of complex
        Cross spectrum ``conj(X)·Y`` averaged over segments, in the scaling of ``x`` and ``y``
        [unit_x·unit_y] or [unit_x·unit_y/Hz].
    """

    x: Spectrum
    y: Spectrum
    cross: np.ndarray

    @property
    def coherence(self) -> CoherenceSpectrum:
        """Magnitude-squared coherence ``|S_xy|² / (S_xx S_yy)`` (0 where a channel is empty)."""
        den = self.x.power * self.y.power
        gamma = np.divide(np.abs(self.cross) ** 2, den, out=np.zeros_like(den), where=den > 0.0)
        s = self.x
        return CoherenceSpectrum(
            s.frequency,
            np.clip(gamma, 0.0, 1.0),
            s.n_segments,
            s.nperseg,
            s.noverlap,
            s.window,
            s.detrend,
        )


# --------------------------------------------------------------------------------------------
# Validation helpers
# --------------------------------------------------------------------------------------------


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


def enbw(window: np.ndarray, sample_rate: float) -> float:
    """Equivalent noise bandwidth ``f_s Σw² / (Σw)²`` of a window [Hz]."""
    return float(sample_rate) * float(np.sum(window**2)) / float(np.sum(window)) ** 2


# --------------------------------------------------------------------------------------------
# The streaming accumulator
# --------------------------------------------------------------------------------------------


class _WelchAccumulator:
    """Sums of |X_c|² per channel (and conj(X_0)·X_1) over Welch segments fed chunk by chunk."""

    def __init__(self, names, nperseg, noverlap, window, detrend, cross):
        self.names = tuple(names)
        self.k = len(self.names)
        self.nperseg, self.noverlap = nperseg, noverlap
        self.step = nperseg - noverlap
        self.window = window
        self.detrend = detrend
        self.cross = cross
        self.buffer = np.empty((self.k, 0))
        self.consumed = 0  # samples fed so far
        self.n_segments = 0
        nfreq = nperseg // 2 + 1
        self.auto = np.zeros((self.k, nfreq))
        self.xy = np.zeros(nfreq, dtype=complex) if cross else None
        self.low = np.full(self.k, np.inf)
        self.high = np.full(self.k, -np.inf)
        self.first = np.full(self.k, np.nan)
        self.batch = max(1, _BATCH_SAMPLES // (self.k * nperseg))
        if detrend == "linear":
            t = np.arange(nperseg) - 0.5 * (nperseg - 1)
            self.ramp = t / np.sqrt(float(t @ t))
        else:
            self.ramp = None

    def _check(self, chunk: np.ndarray) -> None:
        for c, name in enumerate(self.names):
            check_samples(chunk[c], self.consumed, MAX_MAGNITUDE, "no sensor reads that", name)
        if chunk.shape[1]:
            if self.consumed == 0:
                self.first = chunk[:, 0].copy()
            self.low = np.minimum(self.low, chunk.min(axis=1))
            self.high = np.maximum(self.high, chunk.max(axis=1))

    def feed(self, chunk: np.ndarray) -> None:
        self._check(chunk)
        self.consumed += chunk.shape[1]
        buf = np.concatenate([self.buffer, chunk], axis=1) if self.buffer.shape[1] else chunk
        n = buf.shape[1]
        count = 0 if n < self.nperseg else (n - self.nperseg) // self.step + 1
        if count:
            view = np.lib.stride_tricks.sliding_window_view(buf, self.nperseg, axis=1)
            for start in range(0, count, self.batch):
                stop = min(count, start + self.batch)
                self._segments(view[:, start * self.step : (stop - 1) * self.step + 1 : self.step])
        # Keep what the next segment needs (a copy, so the caller's chunk can be freed).
        self.buffer = np.array(buf[:, count * self.step :], dtype=float)

    def _segments(self, seg: np.ndarray) -> None:
        """Accumulate a batch of segments, shape (k, b, nperseg)."""
        if self.detrend in ("linear", "constant"):
            seg = seg - seg.mean(axis=-1, keepdims=True)
            if self.ramp is not None:
                seg -= (seg @ self.ramp)[..., None] * self.ramp
        else:
            seg = np.array(seg)
        seg *= self.window
        spec = np.fft.rfft(seg, axis=-1)
        self.auto += np.sum(spec.real**2 + spec.imag**2, axis=1)
        if self.xy is not None:
            self.xy += np.sum(np.conj(spec[0]) * spec[1], axis=0)
        self.n_segments += seg.shape[1]

    def finish(self, sample_rate: float, scaling: str):
        if self.n_segments == 0:
            raise ParameterError(
                f"{' and '.join(self.names)} {'has' if self.k == 1 else 'have'} "
                f"{self.consumed} samples, fewer than one segment of {self.nperseg}: record a "
                "longer signal or choose a shorter segment"
            )
        for c, name in enumerate(self.names):
            if self.high[c] == self.low[c]:
                raise ParameterError(
                    f"{name} is constant ({self.first[c]:g} in all {self.consumed} samples): it "
                    "has no spectrum; check that the channel is connected and mapped"
                )
        w = self.window
        scale = (
            1.0 / float(np.sum(w)) ** 2
            if scaling == "spectrum"
            else 1.0 / (sample_rate * float(np.sum(w * w)))
        )
        double = slice(1, None) if self.nperseg % 2 else slice(1, -1)
        auto = self.auto * (scale / self.n_segments)
        auto[:, double] *= 2.0
        # Variance left after detrending (Parseval with the window's noise bandwidth in bins);
        # below 1e-10 of the signal's magnitude it is round-off, not a measurement.
        bins = self.nperseg * float(np.sum(w * w)) / float(np.sum(w)) ** 2
        variance = (
            np.sum(auto, axis=1) / bins
            if scaling == "spectrum"
            else np.sum(auto, axis=1) * sample_rate / self.nperseg
        )
        magnitude = np.maximum(np.abs(self.low), np.abs(self.high))
        for c, name in enumerate(self.names):
            if not np.sqrt(variance[c]) > _ROUND_OFF * magnitude[c]:
                trend = {"linear": "its linear trend", "constant": "its mean"}.get(
                    self.detrend, "a constant"
                )
                raise ParameterError(
                    f"{name} has no variation beyond {trend} (residual RMS "
                    f"{np.sqrt(variance[c]):.3g}, values up to {magnitude[c]:.3g}): no spectrum"
                )
        xy = None
        if self.xy is not None:
            xy = self.xy * (scale / self.n_segments)
            xy[double] *= 2.0
        return auto, xy


def _as_chunk(chunk, k: int, what: str) -> np.ndarray:
    if k == 1:
        arr = np.asarray(chunk, dtype=float)
        if arr.ndim != 1:
            raise ParameterError(f"{what} chunks must be 1-D arrays, got shape {arr.shape}")
        return arr[None, :]
    try:
        x, y = chunk
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{what} chunks must be (x, y) pairs of 1-D arrays") from exc
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.ndim != 1 or x.shape != y.shape:
        raise ParameterError(
            f"{what} chunks must be (x, y) pairs of 1-D arrays of equal length, got shapes "
            f"{x.shape} and {y.shape}"
        )
    return np.stack([x, y])


def _stream(chunks, k, sample_rate, nperseg, noverlap, window, detrend, scaling, names):
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    seg, overlap = _check_segments(nperseg, noverlap)
    _choice("scaling", scaling, ("spectrum", "density"))
    _check_detrend(detrend)
    w = _window(window, seg)
    acc = _WelchAccumulator(names, seg, overlap, w, detrend, cross=k == 2)
    what = "welch_stream" if k == 1 else "cross_spectra_stream"
    for chunk in chunks:
        acc.feed(_as_chunk(chunk, k, what))
    auto, xy = acc.finish(fs, scaling)
    f = np.fft.rfftfreq(seg, 1.0 / fs)
    bw = enbw(w, fs)
    spectra = [
        Spectrum(
            f, auto[c], scaling, "welch", fs, seg, acc.n_segments, str(window), bw, overlap, detrend
        )
        for c in range(k)
    ]
    return spectra, xy


def welch_stream(
    chunks: Iterable,
    sample_rate: float,
    nperseg: int,
    noverlap: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
    scaling: str = "spectrum",
    *,
    name: str = "x",
) -> Spectrum:
    """Welch power spectrum of a signal given as an iterable of chunks, in bounded memory.

    Equal (to rounding) to ``scipy.signal.welch(np.concatenate(chunks), sample_rate,
    window, nperseg, noverlap, detrend=detrend, scaling=scaling)``; chunks may have any
    lengths, including 0. Memory: one chunk, less than one segment of history and a batch of
    segments (about 2 M samples), whatever the record length.

    Parameters
    ----------
    chunks : iterable of array_like, shape (m_i,)
        Consecutive pieces of the signal [unit], finite.
    sample_rate : float
        Sampling rate f_s [Hz].
    nperseg : int
        Segment length [samples], >= 8; the bin spacing is ``f_s / nperseg``.
    noverlap : int, optional
        Overlap [samples]; default ``nperseg // 2``.
    window : str
        Window name understood by :func:`scipy.signal.get_window`.
    detrend : {"linear", "constant", False}
        Trend removed from each segment.
    scaling : {"spectrum", "density"}
        Power per bin [unit²] or power spectral density [unit²/Hz].
    name : str
        Name of the signal in error messages (e.g. the channel).

    Returns
    -------
    Spectrum

    Raises
    ------
    ParameterError
        Non-finite or absurdly large samples (naming the sample), a constant signal, fewer
        samples than one segment, or invalid settings.

    Examples
    --------
    >>> fs = 250.0
    >>> x = 2.0 * np.sin(2 * np.pi * 10.0 * np.arange(25_000) / fs)
    >>> s = welch_stream((x[i : i + 999] for i in range(0, x.size, 999)), fs, 2500)
    >>> round(float(s.frequency[np.argmax(s.power)]), 3), round(float(s.power.max()), 3)
    (10.0, 2.0)
    """
    (s,), _ = _stream(chunks, 1, sample_rate, nperseg, noverlap, window, detrend, scaling, (name,))
    return s


def cross_spectra_stream(
    chunks: Iterable,
    sample_rate: float,
    nperseg: int,
    noverlap: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
    scaling: str = "spectrum",
    *,
    names: tuple[str, str] = ("x", "y"),
) -> CrossSpectra:
    """Auto and cross spectra of two channels given as an iterable of ``(x, y)`` chunk pairs.

    One Welch pass (see :func:`welch_stream`): the auto spectra equal
    :func:`scipy.signal.welch` of each channel, the cross spectrum :func:`scipy.signal.csd`
    (``conj(X)·Y``), and :attr:`CrossSpectra.coherence` :func:`scipy.signal.coherence`, all on
    the concatenated channels, to rounding.

    Parameters
    ----------
    chunks : iterable of (array_like, array_like)
        Consecutive pieces of the two channels, equal lengths within a pair [unit_x], [unit_y].
    sample_rate, nperseg, noverlap, window, detrend, scaling
        As in :func:`welch_stream`.
    names : tuple of str
        Names of the channels in error messages.

    Returns
    -------
    CrossSpectra

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.standard_normal(20_000)
    >>> y = 2.0 * x + 0.1 * rng.standard_normal(x.size)
    >>> cs = cross_spectra_stream([(x[:7000], y[:7000]), (x[7000:], y[7000:])], 250.0, 256)
    >>> bool(cs.coherence.coherence.min() > 0.99)
    True
    """
    (sx, sy), xy = _stream(
        chunks, 2, sample_rate, nperseg, noverlap, window, detrend, scaling, tuple(names)
    )
    return CrossSpectra(sx, sy, xy)


def coherence_stream(
    chunks: Iterable,
    sample_rate: float,
    nperseg: int,
    noverlap: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
    *,
    names: tuple[str, str] = ("x", "y"),
) -> CoherenceSpectrum:
    """Magnitude-squared coherence of two channels streamed as ``(x, y)`` chunk pairs.

    :attr:`CrossSpectra.coherence` of :func:`cross_spectra_stream`; equal to
    :func:`scipy.signal.coherence` on the concatenated channels, to rounding.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> x = rng.standard_normal(8192)
    >>> c = coherence_stream([(x, x + rng.standard_normal(x.size))], 100.0, 256)
    >>> 0.3 < float(np.median(c.coherence)) < 0.7
    True
    """
    return cross_spectra_stream(
        chunks, sample_rate, nperseg, noverlap, window, detrend, "spectrum", names=names
    ).coherence


# --------------------------------------------------------------------------------------------
# Array front ends
# --------------------------------------------------------------------------------------------


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
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
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


def power_unit(unit: str | None, scaling: str = "spectrum") -> str:
    """Unit of a power spectrum of a signal in ``unit``: squared as a whole, per Hz for a density.

    Examples
    --------
    >>> power_unit("N.m"), power_unit("m", "density"), power_unit(None)
    ('(N.m)²', 'm²/Hz', '1²')
    """
    u = unit or "1"
    # (N.m)², not N.m², which reads as newton square metre.
    squared = f"({u})²" if any(c in u for c in "./*· ") else f"{u}²"
    return f"{squared}/Hz" if scaling == "density" else squared
