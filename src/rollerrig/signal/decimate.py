"""Anti-alias decimation of long signals, streamed chunk by chunk, with zero phase.

A one-hour recording at 19.2 kHz (the HBM QuantumX rate of the dissertation's laser and torque
measurements) holds 69 M samples per channel; the analyses (phases, the dynamics correction,
the filter study) need a few hundred hertz to 1 kHz. :func:`decimate_chunks` brings an iterable
of chunks to a lower rate holding only one chunk plus about two filter lengths, and yields
exactly what the one-shot :func:`decimate` returns for the concatenated signal (to rounding).

The filter (:func:`design_decimation`)
    Rational factor ``up/down`` (``target = sample_rate · up / down``, ``up <= 64``; integer
    decimation is ``up = 1``). One linear-phase low-pass FIR (Kaiser window,
    :func:`scipy.signal.firwin`) at the up-sampled rate, applied polyphase
    (:func:`scipy.signal.upfirdn`: only the kept outputs are computed). Pass band
    ``0 .. passband × target/2`` (default 0.8: 0-400 Hz at a 1 kHz target), stop band from the
    new Nyquist frequency ``target/2`` up; length from :func:`scipy.signal.kaiserord` for
    ``attenuation_dB`` (default 70 dB), so the pass-band ripple is below ``10^(-A/20)``
    (3.2e-4 at 70 dB: an in-band tone keeps its amplitude within 0.03 %) and every frequency
    above the new Nyquist is attenuated by at least ``A`` (a tone there cannot alias into the
    result by more than 3.2e-4 of its amplitude). Both figures are measured on the designed
    taps (:attr:`DecimationFilter.passband_ripple`,
    :attr:`DecimationFilter.stopband_attenuation_dB`) and stated in every description. Each
    polyphase branch is scaled to unit DC gain, so a constant passes exactly whatever the output
    phase (unscaled, the branches differ by the stop-band leakage, ~1e-6, which would print a
    faint line at ``rate/up`` on a large offset).
Zero phase
    The FIR is symmetric with ``2·K·up + 1`` taps; output sample ``m`` is centred on input
    instant ``m·down/up`` (the delay of ``K`` input samples is compensated), so the decimated
    signal is time-aligned with the input: offline, non-causal, like MATLAB ``resample``.
Ends
    Beyond its first and last sample the signal is continued by the least-squares straight line
    through its first/last ``K + 1`` samples (all samples when shorter): a constant passes
    exactly up to the ends, a ramp exactly for integer factors and to ~2e-8 of its range for
    rational ones; the end values are averages, not a single noisy sample pinned as an odd
    reflection (``filtfilt``) would pin it.
Output instants
    ``t0 + m · down / (up · sample_rate)`` for ``m = 0 .. floor((n - 1)·up/down)``: inside the
    input's span, never extrapolated.

:func:`decimate_recording` applies it to every channel of a
:class:`rollerrig.recordings.recording.Recording` and records the operation in the metadata
(``notes``, ``decimated``).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._numeric import (
    check_samples,
    power_of_two_scale,
    tidy_rate,
)

__all__ = [
    "DecimationFilter",
    "decimate",
    "decimate_chunks",
    "decimate_recording",
    "decimated_time",
    "design_decimation",
]

MAX_UP = 64
"""Largest up-sampling factor of a rational decimation [-] (filter length grows with it)."""

MAX_TAPS = 1 << 20
"""Most taps of one decimation filter [-]. The taps grow as ``A · sample_rate / (target_rate ·
(1 − passband))`` (Kaiser: 19.2 kHz → 1 Hz at 70 dB takes 829 809); the design measures the
response on an FFT grid of 64× the taps (2^26 points, 1.5 GiB at this limit), and a streamed
pass holds 2·K of input per channel. Beyond it (19.2 kHz → 0.1 Hz asked 4 GiB, 1 MHz → 1 Hz
32 GiB, a passband of 1 − 1e-15 5 EiB) the filter is decimated in stages instead: each stage's
taps grow with its own factor only."""

RATE_TOLERANCE = 1e-3
"""Largest relative difference between a requested and the achieved output rate [-]."""

_HUGE = 1e200
"""Largest magnitude a streamed chunk may hold [unit of the signal] (sums stay finite)."""
_HUGE_WHY = "the filter sums could overflow (decimate() rescales a whole array)"

_BLOCK = 1 << 18
"""New input samples gathered before a block is filtered [samples per channel]."""


@dataclass(frozen=True)
class DecimationFilter:
    """A zero-phase polyphase anti-alias decimator (see the module docstring).

    Attributes
    ----------
    sample_rate : float
        Input rate [Hz].
    up, down : int
        Rational factor: output rate = ``sample_rate · up / down``.
    taps : ndarray, shape (2·half_length·up + 1,)
        Symmetric FIR at the up-sampled rate ``sample_rate · up``, DC gain ``up``.
    half_length : int
        ``K``: input samples on each side of an output instant that it depends on [samples].
    passband_edge : float
        Upper edge of the pass band [Hz].
    stopband_edge : float
        Lower edge of the stop band [Hz] (the new Nyquist frequency).
    passband_ripple : float
        Measured ``max |H(f)/up − 1|`` over the pass band [-].
    stopband_attenuation_dB : float
        Measured ``min −20 log10 |H(f)/up|`` from the stop-band edge to ``sample_rate·up/2``
        [dB].
    design_attenuation_dB : float
        Attenuation the Kaiser design was asked for [dB].
    """

    sample_rate: float
    up: int
    down: int
    taps: np.ndarray = field(repr=False)
    half_length: int
    passband_edge: float
    stopband_edge: float
    passband_ripple: float
    stopband_attenuation_dB: float
    design_attenuation_dB: float

    @property
    def rate(self) -> float:
        """Output rate [Hz]."""
        return self.sample_rate * self.up / self.down

    def output_length(self, n: int) -> int:
        """Output samples for ``n`` input samples: ``floor((n − 1)·up/down) + 1`` [samples]."""
        return (int(n) - 1) * self.up // self.down + 1 if n > 0 else 0

    def describe(self) -> str:
        """One sentence for notes and reports."""
        factor = f"{self.down}" if self.up == 1 else f"{self.down}/{self.up}"
        return (
            f"decimated from {self.sample_rate:g} Hz to {self.rate:g} Hz (factor {factor}) by a "
            f"zero-phase linear-phase Kaiser FIR ({self.taps.size} taps at "
            f"{self.sample_rate * self.up:g} Hz, ±{self.half_length} input samples): pass band "
            f"0-{self.passband_edge:g} Hz within ±{100 * self.passband_ripple:.2g} %, stop band "
            f"from {self.stopband_edge:g} Hz attenuated >= {self.stopband_attenuation_dB:.1f} dB; "
            f"ends continued by the least-squares line through the first/last "
            f"{self.half_length + 1} samples"
        )

    def as_dict(self) -> dict:
        """JSON-ready description (rates in Hz)."""
        return {
            "from_rate_Hz": self.sample_rate,
            "rate_Hz": self.rate,
            "up": self.up,
            "down": self.down,
            "taps": int(self.taps.size),
            "half_length_samples": self.half_length,
            "passband_edge_Hz": self.passband_edge,
            "stopband_edge_Hz": self.stopband_edge,
            "passband_ripple": self.passband_ripple,
            "stopband_attenuation_dB": self.stopband_attenuation_dB,
            "method": "zero-phase Kaiser FIR, polyphase (scipy.signal.upfirdn); ends continued "
            "by a least-squares line",
        }


def _ratio(sample_rate: float, target_rate: float) -> tuple[int, int]:
    """``up, down`` with ``up <= MAX_UP`` and ``sample_rate·up/down`` closest to the target."""
    exact = Fraction(sample_rate / target_rate).limit_denominator(MAX_UP)
    down, up = exact.numerator, exact.denominator
    achieved = sample_rate * up / down
    suggestion = sample_rate / max(round(sample_rate / target_rate), 1)
    if abs(achieved / target_rate - 1.0) > RATE_TOLERANCE:
        raise ParameterError(
            f"target_rate {target_rate:g} Hz is not reachable from {sample_rate:g} Hz by a ratio "
            f"up/down with up <= {MAX_UP} within {RATE_TOLERANCE:.0e} (closest: {achieved:g} Hz); "
            f"choose sample_rate/k for an integer k, e.g. {suggestion:g} Hz"
        )
    return up, down


def _response(taps: np.ndarray, up: int, f_pass: float, f_stop: float, fs_up: float):
    """Measured pass-band ripple [-] and stop-band attenuation [dB] of the taps (FFT grid)."""
    nfft = 1 << int(np.ceil(np.log2(max(64 * taps.size, 1 << 16))))
    mag = np.abs(np.fft.rfft(taps, nfft)) / up
    f = np.fft.rfftfreq(nfft, 1.0 / fs_up)
    ripple = float(np.max(np.abs(mag[f <= f_pass] - 1.0)))
    stop = float(np.max(mag[f >= f_stop]))
    return ripple, float(-20.0 * np.log10(max(stop, 1e-300)))


def _too_long(fs: float, target: float, att: float, band: float, taps: str) -> ParameterError:
    return ParameterError(
        f"target_rate {target:g} Hz is too far below sample_rate {fs:g} Hz for one anti-alias "
        f"filter with attenuation_dB {att:g} and passband {band!r}: it needs {taps or 'over 1e308'}"
        f" taps, more than MAX_TAPS = {MAX_TAPS} (memory); decimate in stages (to a rate between "
        f"the two first), or lower attenuation_dB or passband"
    )


def design_decimation(
    sample_rate: float,
    target_rate: float,
    *,
    attenuation_dB: float = 70.0,
    passband: float = 0.8,
) -> DecimationFilter:
    """Design the zero-phase anti-alias FIR that brings ``sample_rate`` to ``target_rate``.

    Parameters
    ----------
    sample_rate : float
        Input rate [Hz].
    target_rate : float
        Output rate [Hz], below ``sample_rate``; reached as ``sample_rate·up/down`` with
        ``up <= 64`` within 1e-3 (the achieved rate is :attr:`DecimationFilter.rate`).
    attenuation_dB : float
        Kaiser design attenuation [dB], 40-150: stop-band attenuation and pass-band ripple
        ``10^(-A/20)``.
    passband : float
        Pass-band edge as a fraction of the new Nyquist frequency [-], in (0, 1).

    Returns
    -------
    DecimationFilter

    Examples
    --------
    >>> d = design_decimation(19200.0, 1000.0)
    >>> d.up, d.down, d.rate, d.passband_edge, d.stopband_edge
    (5, 96, 1000.0, 400.0, 500.0)
    >>> d.passband_ripple < 1e-3, d.stopband_attenuation_dB > 60.0
    (True, True)
    """
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    target = require_positive("target_rate", target_rate, "Hz", single=True)
    if target >= fs:
        raise ParameterError(
            f"target_rate {target:g} Hz must be below the sample rate {fs:g} Hz (decimation only)"
        )
    att = float(attenuation_dB)
    if not 40.0 <= att <= 150.0:
        raise ParameterError(f"attenuation_dB must lie in [40, 150] dB, got {attenuation_dB!r}")
    band = float(passband)
    if not 0.0 < band < 1.0:
        raise ParameterError(f"passband must lie in (0, 1) of the new Nyquist, got {passband!r}")
    # A factor beyond MAX_TAPS needs more taps than that whatever the design (Kaiser: about
    # 4.5 taps per unit of the factor at the least); checked before the ratio, which a factor
    # of 1e600 (1e300 Hz to 1e-300 Hz) overflows.
    if not fs / target <= MAX_TAPS:
        kaiser = (att - 7.95) / (2.285 * np.pi * (1.0 - band)) * (fs / target)
        raise _too_long(fs, target, att, band, f"about {kaiser:.2g}" if kaiser < 1e308 else "")
    up, down = _ratio(fs, target)
    if abs(fs * up / (down * target) - 1.0) <= 1e-9:
        fs = target * down / up  # a rate from float time stamps: take the exact ratio
    rate = fs * up / down
    fs_up = fs * up
    f_stop = rate / 2.0
    f_pass = band * f_stop
    numtaps, beta = sps.kaiserord(att, (f_stop - f_pass) / (fs_up / 2.0))
    half = max(int(np.ceil((numtaps - 1) / (2 * up))), 1)
    if 2 * half * up + 1 > MAX_TAPS:  # before firwin() allocates them
        raise _too_long(fs, target, att, band, f"{2 * half * up + 1}")
    taps = sps.firwin(2 * half * up + 1, 0.5 * (f_pass + f_stop), window=("kaiser", beta), fs=fs_up)
    for phase in range(up):  # every polyphase branch passes a constant exactly
        taps[phase::up] /= taps[phase::up].sum()
    taps.setflags(write=False)
    ripple, stop_db = _response(taps, up, f_pass, f_stop, fs_up)
    return DecimationFilter(fs, up, down, taps, half, f_pass, f_stop, ripple, stop_db, att)


# --------------------------------------------------------------------------------------------
# streaming
# --------------------------------------------------------------------------------------------
def _end_line(samples: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Least-squares line through ``samples`` (axis 0, at 0..m-1) evaluated at ``offsets``."""
    m = samples.shape[0]
    k = np.arange(m, dtype=float)
    if m == 1:
        level = samples[0]
        return np.broadcast_to(level, (offsets.size, *samples.shape[1:])).copy()
    kc = k - k.mean()
    mean = samples.mean(axis=0)
    slope = np.tensordot(kc, samples - mean, axes=(0, 0)) / float(kc @ kc)
    shift = (offsets - k.mean()).reshape(-1, *([1] * (samples.ndim - 1)))
    return mean + slope * shift


class _Stream:
    """State of one decimation pass: the buffer and what has been emitted."""

    def __init__(self, spec: DecimationFilter):
        self.spec = spec
        self.buf: np.ndarray | None = None  # samples [buf_start, buf_start + len)
        self.buf_start = 0
        self.head: np.ndarray | None = None  # the first K + 1 samples (front line)
        self.emitted = 0  # next output index
        self.pending: list[np.ndarray] = []  # chunks not yet in the buffer
        self.pending_len = 0
        self.shape: tuple | None = None  # trailing shape (channels) of every chunk

    def _extended(self, j0: int, j1: int, n: int | None) -> np.ndarray:
        """Samples ``x_ext[j0:j1]`` of the line-extended signal (``n`` known at the end)."""
        k = self.spec.half_length
        buf = self.buf
        shape = (j1 - j0, *buf.shape[1:])
        out = np.zeros(shape)
        # front extension: the line through x[0..K], for -K <= j < 0; zeros before are unused
        a, b = max(j0, -k), min(j1, 0)
        if a < b:
            out[a - j0 : b - j0] = _end_line(self.head, np.arange(a, b, dtype=float))
        a, b = max(j0, 0), min(j1, self.buf_start + buf.shape[0])
        if a < b:
            out[a - j0 : b - j0] = buf[a - self.buf_start : b - self.buf_start]
        if n is not None and j1 > n:
            m = min(k + 1, n)
            tail = buf[n - m - self.buf_start : n - self.buf_start]
            a = max(j0, n)
            out[a - j0 :] = _end_line(tail, np.arange(a - (n - m), j1 - (n - m), dtype=float))
        return out

    def _block(self, m0: int, m1: int, n: int | None) -> np.ndarray:
        """Outputs ``m0 .. m1-1`` by :func:`scipy.signal.upfirdn` on the needed input slice."""
        spec = self.spec
        up, down, k = spec.up, spec.down, spec.half_length
        first = (m0 * down) // up - k  # first input sample output m0 depends on
        c = -((first - k) // down)  # ceil((k - first) / down): j0 = k - c·down <= first
        j0 = k - c * down
        j1 = ((m1 - 1) * down) // up + k + 1
        z = sps.upfirdn(spec.taps, self._extended(j0, j1, n), up, down, axis=0)
        start = m0 + c * up
        return z[start : start + (m1 - m0)]

    def _gather(self) -> None:
        """Append the pending chunks to the buffer (one concatenation per block)."""
        if self.pending:
            parts = self.pending if self.buf is None else [self.buf, *self.pending]
            self.buf = parts[0] if len(parts) == 1 else np.concatenate(parts, axis=0)
            self.pending = []
            self.pending_len = 0

    def push(self, chunk: np.ndarray) -> np.ndarray | None:
        if self.shape is None:
            self.shape = chunk.shape[1:]
        elif chunk.shape[1:] != self.shape:
            raise ParameterError(
                f"chunks must all have the same channels: got {chunk.shape[1:]} after {self.shape}"
            )
        self.pending.append(chunk)
        self.pending_len += chunk.shape[0]
        spec = self.spec
        k = spec.half_length
        held = (0 if self.buf is None else self.buf.shape[0]) + self.pending_len
        if held < _BLOCK + 2 * k + spec.down:
            return None  # too little new material; wait for more
        self._gather()
        end = self.buf_start + self.buf.shape[0]
        if self.head is None:
            self.head = np.array(self.buf[: k + 1], dtype=float)
        m1 = (end - 1 - k) * spec.up // spec.down + 1  # outputs whose right neighbours exist
        if m1 <= self.emitted:
            return None
        out = self._block(self.emitted, m1, None)
        self.emitted = m1
        keep = max((m1 * spec.down) // spec.up - k - spec.down, 0)
        self.buf = self.buf[keep - self.buf_start :]
        self.buf_start = keep
        return out

    def finish(self) -> np.ndarray | None:
        self._gather()
        if self.buf is None:
            return None
        n = self.buf_start + self.buf.shape[0]
        if self.head is None:
            self.head = np.array(self.buf[: min(self.spec.half_length + 1, n)], dtype=float)
        total = self.spec.output_length(n)
        if total <= self.emitted:
            return None
        out = self._block(self.emitted, total, n)
        self.emitted = total
        return out


def _as_spec(sample_rate, target_rate, attenuation_dB, passband) -> DecimationFilter:
    if isinstance(sample_rate, DecimationFilter):
        if target_rate is not None:
            raise ParameterError("give either a DecimationFilter or target_rate, not both")
        return sample_rate
    if target_rate is None:
        raise ParameterError("target_rate [Hz] is needed")
    return design_decimation(
        sample_rate, target_rate, attenuation_dB=attenuation_dB, passband=passband
    )


def decimate_chunks(
    chunks: Iterable,
    sample_rate: float | DecimationFilter,
    target_rate: float | None = None,
    *,
    attenuation_dB: float = 70.0,
    passband: float = 0.8,
) -> Iterator[np.ndarray]:
    """Decimate a stream of chunks, yielding the decimated signal in chunks (bounded memory).

    Concatenating the yielded pieces gives :func:`decimate` of the concatenated input (to
    rounding, ~1e-15 relative), whatever the chunk sizes. Memory: the current chunk plus about
    ``2·K + 2^18`` samples per channel (``K`` = :attr:`DecimationFilter.half_length`, 1660 for
    19.2 kHz → 250 Hz), and the filter taps.

    Parameters
    ----------
    chunks : iterable of array_like, each shape (m,) or (m, channels)
        Consecutive pieces of a uniformly sampled signal [any unit], samples along axis 0; all
        with the same trailing shape. Empty chunks are skipped.
    sample_rate : float or DecimationFilter
        Input rate [Hz], or a filter from :func:`design_decimation` (then no ``target_rate``).
    target_rate : float, optional
        Output rate [Hz] (see :func:`design_decimation`).
    attenuation_dB, passband : float
        Filter design (see :func:`design_decimation`).

    Yields
    ------
    ndarray, shape (k,) or (k, channels)
        Decimated samples, in order [unit of the input].

    Examples
    --------
    >>> x = np.sin(2 * np.pi * 5.0 * np.arange(20000) / 2000.0)
    >>> pieces = decimate_chunks((x[i : i + 3000] for i in range(0, x.size, 3000)), 2000.0, 100.0)
    >>> y = np.concatenate(list(pieces))
    >>> y.size, bool(np.allclose(y, decimate(x, 2000.0, 100.0)))
    (1000, True)
    """
    spec = _as_spec(sample_rate, target_rate, attenuation_dB, passband)
    stream = _Stream(spec)
    seen = 0
    for chunk in chunks:
        c = np.asarray(chunk, dtype=float)
        if c.ndim == 0 or c.ndim > 2:
            raise ParameterError(f"chunks must be 1-D or 2-D (samples, channels), got {c.shape}")
        if c.shape[0] == 0:
            continue
        check_samples(c, seen, _HUGE, _HUGE_WHY)
        seen += c.shape[0]
        out = stream.push(c)
        if out is not None and out.shape[0]:
            yield out
    out = stream.finish()
    if out is not None and out.shape[0]:
        yield out


def decimate(
    x,
    sample_rate: float | DecimationFilter,
    target_rate: float | None = None,
    *,
    attenuation_dB: float = 70.0,
    passband: float = 0.8,
) -> np.ndarray:
    """Decimate a whole array (one-shot :func:`decimate_chunks`).

    Parameters
    ----------
    x : array_like, shape (n,) or (n, channels)
        Uniformly sampled signal [any unit], samples along axis 0 (a memory map is read in
        pieces).
    sample_rate : float or DecimationFilter
        Input rate [Hz] or a designed filter.
    target_rate : float, optional
        Output rate [Hz].
    attenuation_dB, passband : float
        Filter design (see :func:`design_decimation`).

    Returns
    -------
    ndarray, shape (floor((n-1)·up/down) + 1,) or (..., channels)
        Decimated signal [unit of ``x``].

    Examples
    --------
    A ramp passes exactly, ends included:

    >>> y = decimate(np.arange(4000.0), 4000.0, 400.0)
    >>> y.size, bool(np.allclose(y, np.arange(400) * 10.0))
    (400, True)
    """
    spec = _as_spec(sample_rate, target_rate, attenuation_dB, passband)
    arr = x if hasattr(x, "shape") else np.asarray(x, dtype=float)
    if arr.ndim == 0 or arr.shape[0] == 0:
        raise ParameterError("x must have at least one sample")
    step = 1 << 22
    peak = max(float(np.max(np.abs(arr[i : i + step]))) for i in range(0, arr.shape[0], step))
    scale = 1.0  # a power of two: exact; keeps 1e300 or 1e-300 signals inside the float range
    if np.isfinite(peak) and (peak > _HUGE or 0.0 < peak < 1.0 / _HUGE):
        scale = power_of_two_scale(peak)
    pieces = decimate_chunks(
        (arr[i : i + step] * scale for i in range(0, arr.shape[0], step)), spec
    )
    out = np.concatenate(list(pieces), axis=0)
    return out / scale if scale != 1.0 else out


def decimated_time(n: int, spec: DecimationFilter, start_time: float = 0.0) -> np.ndarray:
    """Output instants ``start_time + m·down/(up·sample_rate)`` [s] for ``n`` input samples.

    Parameters
    ----------
    n : int
        Input samples.
    spec : DecimationFilter
        The decimator.
    start_time : float
        Time of the first input sample [s].

    Returns
    -------
    ndarray, shape (spec.output_length(n),)
        Times [s].

    Examples
    --------
    >>> decimated_time(10, design_decimation(1000.0, 250.0), 2.0)
    array([2.   , 2.004, 2.008])
    """
    m = np.arange(spec.output_length(n), dtype=float)
    return float(start_time) + m * (spec.down / (spec.up * spec.sample_rate))


# --------------------------------------------------------------------------------------------
# recordings
# --------------------------------------------------------------------------------------------
def decimate_recording(
    recording,
    target_rate_Hz: float,
    *,
    names=None,
    chunk_samples: int = 1 << 20,
    attenuation_dB: float = 70.0,
    passband: float = 0.8,
):
    """Every channel of a recording brought to ``target_rate_Hz`` by :func:`decimate`.

    ``recording`` is a :class:`rollerrig.recordings.recording.Recording` in memory, or an open
    :class:`rollerrig.recordings.source.RecordingSource` (from
    :func:`rollerrig.recordings.source.open_recording`), which is then read chunk by chunk and
    never held whole: one hour at 19.2 kHz × 4 channels (2.2 GB as float64) comes out at
    1 kHz (115 MB) holding one chunk.

    Encoder counts are filtered like every other channel: the derivative of the filtered
    counts is the filtered speed (both linear), so speeds derived afterwards carry the same
    anti-alias filter and less quantisation noise than counts picked every ``down/up``
    samples would.

    Parameters
    ----------
    recording : Recording or RecordingSource
        Uniformly sampled (every step within 1 % of the median step).
    target_rate_Hz : float
        Output rate [Hz] (see :func:`design_decimation`).
    names : iterable of str, optional
        Channels to keep (default: all).
    chunk_samples : int
        Samples per chunk read from a RecordingSource [samples].
    attenuation_dB, passband : float
        Filter design (see :func:`design_decimation`).

    Returns
    -------
    Recording
        The channels with their units; metadata with a ``notes`` entry saying what was done
        and a ``decimated`` entry (:meth:`DecimationFilter.as_dict`).

    Raises
    ------
    RecordingError
        Naming the source: a non-uniform time base, an unreachable rate, non-finite samples.

    Examples
    --------
    >>> from rollerrig.recordings.recording import Recording
    >>> t = np.arange(19200) / 19200.0
    >>> rec = Recording(t, {"torque": 100.0 + t}, {"torque": "N.m"})
    >>> out = decimate_recording(rec, 1000.0)
    >>> round(out.sample_rate, 6), out.time.size, bool(np.allclose(out["torque"], 100.0 + out.time))
    (1000.0, 1000, True)
    >>> out.metadata["notes"][-1][:41]
    'decimated from 19200 Hz to 1000 Hz (facto'
    """
    from rollerrig.recordings.recording import Recording, RecordingError

    source = recording.metadata.get("source", "the recording")
    streamed = hasattr(recording, "iter_chunks")
    keep = tuple(recording.names if streamed else recording.channels) if names is None else None
    if keep is None:
        keep = (names,) if isinstance(names, str) else tuple(names)
    try:
        if streamed:
            fs = tidy_rate(recording.sample_rate)
        else:
            fs = _uniform_rate(recording.time, source)
        spec = design_decimation(
            fs, target_rate_Hz, attenuation_dB=attenuation_dB, passband=passband
        )
        if streamed:
            t0, n, values = _decimate_source(recording, keep, spec, chunk_samples)
        else:
            t0, n = float(recording.time[0]), recording.time.size
            values = {name: decimate(recording[name], spec) for name in keep}
    except RecordingError:
        raise
    except ParameterError as exc:
        raise RecordingError(f"{source}: {exc}") from None
    metadata = dict(recording.metadata)
    metadata["notes"] = [*metadata.get("notes", []), spec.describe()]
    metadata["decimated"] = spec.as_dict()
    units = {name: recording.units[name] for name in keep}
    return Recording(decimated_time(n, spec, t0), values, units, metadata)


def _uniform_rate(time: np.ndarray, source: str) -> float:
    """Rate [Hz] of a uniform time base; RecordingError naming the file, the worst step and
    the remedy otherwise (:func:`~rollerrig.recordings.timebase.require_uniform_time`)."""
    from rollerrig.recordings.timebase import require_uniform_time

    return tidy_rate(require_uniform_time(time, str(source), "decimation"))


def _decimate_source(source, names, spec, chunk_samples):
    """Stream the channels of an open RecordingSource through one decimator (all at once)."""
    state = {"t0": None, "n": 0}

    def stacked():
        for chunk in source.iter_chunks(names, chunk_samples):
            if state["t0"] is None:
                state["t0"] = float(chunk.time[0])
            state["n"] += len(chunk)
            yield np.column_stack([chunk[name] for name in names])

    pieces = list(decimate_chunks(stacked(), spec))
    if state["n"] == 0:
        raise ParameterError("the recording holds no samples")
    out = np.concatenate(pieces, axis=0)
    return state["t0"], state["n"], {name: out[:, j] for j, name in enumerate(names)}
