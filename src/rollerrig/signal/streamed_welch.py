"""Power and cross spectra by Welch averaging of a stream of chunks, in bounded memory.

:func:`welch_stream` and :func:`cross_spectra_stream` take an iterable of chunks (a file reader, a
memory map, a generator) and average windowed, detrended segments as they arrive, holding only
one chunk, less than one segment of history and a fixed batch of segments; the result equals
:func:`scipy.signal.welch` / :func:`scipy.signal.csd` / :func:`scipy.signal.coherence` on the
concatenated signal (same segments, window, detrending and scaling) to rounding. One hour at
19.2 kHz (69 M samples) then needs a few tens of MB beyond the chunk being read, instead of
several copies of the whole record. The front ends for arrays in memory are in
:mod:`rollerrig.signal.welch`.

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

from collections.abc import Iterable

import numpy as np

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._numeric import check_samples
from rollerrig.signal.channel_checks import constant_channel_message
from rollerrig.signal.spectrum_results import CoherenceSpectrum, CrossSpectra, Spectrum
from rollerrig.signal.welch_settings import (
    MAX_MAGNITUDE,
    _check_detrend,
    _check_segments,
    _choice,
    _window,
    enbw,
)

__all__ = ["coherence_stream", "cross_spectra_stream", "welch_stream"]

_BATCH_SAMPLES = 1 << 21  # samples per batch of segments (16 MB of float64 per channel)
_ROUND_OFF = 1e-10  # residual RMS / magnitude below which a detrended signal counts as empty


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
                    constant_channel_message(name, self.first[c], self.consumed, "has no spectrum")
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
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
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
