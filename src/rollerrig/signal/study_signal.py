"""The signal a filter study scores: at its analysis rate, over its span, with its raw noise.

The seed's study ran at 250 Hz and its windows are given there. A recording faster than 500 Hz
(19.2 kHz on an HBM QuantumX) is studied at 250 Hz by default, on the signal decimated by a
zero-phase anti-alias FIR (:mod:`rollerrig.signal.decimate`), with the raw noise still measured at
the full rate (:func:`prepare_study_signal`); a stream of chunks or an open recording is studied
in one pass holding only the 250 Hz signal (:func:`study_signal_from_chunks`,
:func:`study_signal_from_source`). Each returns a :class:`StudySignal`, whose
:meth:`StudySignal.filter_study` and :meth:`StudySignal.tune_savitzky_golay` run the study and
whose :class:`rollerrig.signal.study_table.StudyBasis` states the rate, the span and the method.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._numeric import check_samples, odd, tidy_rate, uniform_sample_rate
from rollerrig.signal.decimate import decimate, decimate_chunks, decimated_time, design_decimation
from rollerrig.signal.filter_candidates import (
    SEED_SAMPLE_RATE,
    default_candidates,
    savitzky_golay_candidates,
)
from rollerrig.signal.filter_score import Scorer, ScoreWeights, check_record, unit_scale
from rollerrig.signal.steady_transient import Segmentation, as_segmentation
from rollerrig.signal.study_table import StudyBasis, StudyTable, rank_filters

__all__ = [
    "ANALYSIS_RATE_LIMIT",
    "StudySignal",
    "prepare_study_signal",
    "study_signal_from_chunks",
    "study_signal_from_source",
]

_STREAM_LIMIT = 1e150
"""Largest magnitude a streamed study signal may reach [unit] (its squares stay finite)."""

ANALYSIS_RATE_LIMIT = 2.0 * SEED_SAMPLE_RATE
"""Recordings faster than this [Hz] are studied at :data:`SEED_SAMPLE_RATE` by default."""


def _analysis_rate(source_rate: float, analysis_rate) -> float:
    """The rate a study runs at [Hz]: ``"auto"``, None (the source rate) or a number."""
    if analysis_rate is None:
        return source_rate
    if isinstance(analysis_rate, str):
        if analysis_rate != "auto":
            raise ParameterError(
                f"analysis_rate must be 'auto', None or a rate [Hz], got {analysis_rate!r}"
            )
        return SEED_SAMPLE_RATE if source_rate > ANALYSIS_RATE_LIMIT else source_rate
    rate = require_positive("analysis_rate", analysis_rate, "Hz", single=True)
    return min(rate, source_rate)


def _span_indices(n: int, t0: float, fs: float, span) -> tuple[int, int]:
    """Sample range [i0, i1) of a uniformly sampled signal inside ``span = (start, end)`` [s]."""
    if span is None:
        return 0, n
    try:
        start, end = (float(v) for v in span)
    except (TypeError, ValueError):
        raise ParameterError(f"span must be (start, end) [s], got {span!r}") from None
    if not (np.isfinite(start) and np.isfinite(end) and end > start):
        raise ParameterError(f"span must be (start, end) [s] with end > start, got {span!r}")
    i0 = max(int(np.ceil((start - t0) * fs - 1e-9)), 0)
    i1 = min(int(np.floor((end - t0) * fs + 1e-9)) + 1, n)
    if i1 - i0 < 2:
        raise ParameterError(
            f"span {start:g}-{end:g} s holds fewer than 2 samples of the signal "
            f"({t0:g}-{t0 + (n - 1) / fs:g} s)"
        )
    return i0, i1


class _FullRateNoise:
    """RMS of ``raw − reference`` at the source rate, binned onto the analysis instants.

    The reference is the truth (given per chunk) or the centred moving average of
    ``window`` samples with ends shrunk (:func:`rollerrig.signal.smoothing.moving_average`, as
    the scorer's truth-free reference), computed in a stream from running sums over a buffer
    of ``window`` samples. Source sample ``j`` belongs to analysis sample
    ``round(j·up/down)``. Values are multiplied by ``scale`` (a power of two) before squaring.
    """

    def __init__(self, window: int, up: int, down: int, scale: float = 1.0):
        self.half = window // 2
        self.up, self.down, self.scale = up, down, scale
        self.buf = np.zeros(0)
        self.buf_start = 0  # global index of buf[0]
        self.next = 0  # next sample whose deviation is due
        self.sums = np.zeros(0)
        self.counts = np.zeros(0)

    def _bin(self, start: int, dev: np.ndarray) -> None:
        j = start + np.arange(dev.size, dtype=np.int64)
        m = (2 * j * self.up + self.down) // (2 * self.down)  # round(j·up/down), halves up
        top = int(m[-1]) + 1
        if top > self.sums.size:
            grow = max(top, 2 * self.sums.size)
            self.sums = np.concatenate([self.sums, np.zeros(grow - self.sums.size)])
            self.counts = np.concatenate([self.counts, np.zeros(grow - self.counts.size)])
        lo = int(m[0])
        self.sums[lo:top] += np.bincount(m - lo, weights=(dev * self.scale) ** 2)
        self.counts[lo:top] += np.bincount(m - lo)

    def _emit(self, stop: int, end: int, truth: np.ndarray | None) -> None:
        """Deviations of samples ``next .. stop-1``; the signal is known up to ``end``."""
        if stop <= self.next:
            return
        i = np.arange(self.next, stop)
        local = i - self.buf_start
        if truth is not None:
            ref = truth
        else:
            cs = np.concatenate([[0.0], np.cumsum(self.buf)])
            lo = np.maximum(i - self.half, 0) - self.buf_start
            hi = np.minimum(i + self.half + 1, end) - self.buf_start
            ref = (cs[hi] - cs[lo]) / (hi - lo)
        self._bin(self.next, self.buf[local] - ref)
        self.next = stop

    def push(self, chunk: np.ndarray, truth: np.ndarray | None = None) -> None:
        self.buf = np.concatenate([self.buf, chunk])
        end = self.buf_start + self.buf.size
        if truth is not None:
            self._emit(end, end, truth)
        else:
            self._emit(end - self.half, end, None)
        keep = max(self.next - self.half, 0)
        self.buf = self.buf[keep - self.buf_start :]
        self.buf_start = keep

    def finish(self, n_out: int) -> np.ndarray:
        end = self.buf_start + self.buf.size
        self._emit(end, end, None)
        sums, counts = self.sums[:n_out], self.counts[:n_out]
        if sums.size < n_out:
            sums = np.concatenate([sums, np.zeros(n_out - sums.size)])
            counts = np.concatenate([counts, np.zeros(n_out - counts.size)])
        rms = np.sqrt(np.divide(sums, counts, out=np.zeros(n_out), where=counts > 0))
        return rms / self.scale


@dataclass(frozen=True)
class StudySignal:
    """The signal a filter study scores, at its analysis rate, with where it came from.

    Build it with :func:`prepare_study_signal` (arrays) or :func:`study_signal_from_chunks`
    (a stream of chunks); run :meth:`filter_study` and :meth:`tune_savitzky_golay` on it.

    Attributes
    ----------
    time : ndarray
        Uniform instants at the analysis rate [s].
    raw : ndarray
        Signal [unit of the input].
    truth : ndarray or None
        Noise-free signal, filtered like ``raw`` [unit of the input].
    masks : Segmentation or None
        Steady/transient parts on ``time`` (None: found from ``raw``).
    basis : StudyBasis
        Rate, span and method.
    raw_noise_rms : ndarray or None
        When decimated: RMS of the raw signal's deviation from its reference (the truth, or
        its 1 s moving average) measured at the source rate, over the source samples nearest
        each analysis instant [unit of ``raw``]; the ``noise_left`` denominator.
    """

    time: np.ndarray
    raw: np.ndarray
    truth: np.ndarray | None
    masks: Segmentation | None
    basis: StudyBasis
    raw_noise_rms: np.ndarray | None = None

    def _scorer(self, weights) -> Scorer:
        return Scorer(
            self.time, self.raw, self.truth, self.masks, weights, 0.5, 0.5, self.raw_noise_rms
        )

    def filter_study(
        self,
        candidates: Sequence[tuple[str, Mapping]] | None = None,
        weights: ScoreWeights | None = None,
    ) -> StudyTable:
        """Score and rank filters on this signal (:func:`rollerrig.signal.scoring.filter_study`)."""
        scorer = self._scorer(weights)
        if candidates is None:
            candidates = default_candidates(scorer.fs)
        return rank_filters(scorer, candidates, self.basis)

    def tune_savitzky_golay(
        self,
        orders: Iterable[int] = range(2, 8),
        windows: Iterable[int] | None = None,
        weights: ScoreWeights | None = None,
    ) -> tuple[int, int, StudyTable]:
        """Best Savitzky-Golay order and window (see
        :func:`rollerrig.signal.scoring.tune_savitzky_golay`).

        Returns the window in samples at the *source* rate; the table's at the analysis rate.
        """
        scorer = self._scorer(weights)
        candidates = savitzky_golay_candidates(scorer.fs, orders, windows)
        table = rank_filters(scorer, candidates, self.basis)
        best = table[0].params
        window = best["window"]
        ratio = self.basis.source_rate / self.basis.analysis_rate
        if self.basis.decimation is not None:  # the same span in seconds, made odd
            window = max(odd((window - 1) * ratio + 1, 1), best["order"] + 1 + best["order"] % 2)
        return best["order"], int(window), table


def _masks_on(masks, n: int, index: np.ndarray) -> Segmentation | None:
    """Masks given at the source rate (length n), taken at source samples ``index``."""
    if masks is None:
        return None
    seg = as_segmentation(masks, n, np.zeros(0), 1.0)
    return Segmentation(seg.steady[index], seg.transient[index])


def prepare_study_signal(
    time,
    raw,
    truth=None,
    masks=None,
    *,
    analysis_rate="auto",
    span: tuple[float, float] | None = None,
) -> StudySignal:
    """The signal a study scores: ``raw`` over ``span``, decimated to the analysis rate if needed.

    The candidate windows of the seed's study are samples at 250 Hz (Kayaalp 4.5.2.5-4.5.2.6;
    :data:`SEED_SAMPLE_RATE`); scaled to 19.2 kHz they grow to 10 000 samples and the study
    would smooth 69 M samples per hour 170 times. Above :data:`ANALYSIS_RATE_LIMIT` (500 Hz) the
    study therefore runs, by default, on the signal decimated to 250 Hz by the zero-phase
    anti-alias FIR of :mod:`rollerrig.signal.decimate` (pass band 0-100 Hz within 0.03 %, stop
    band from 125 Hz, >= 70 dB): the rate and windows it was designed for. The candidates
    remove everything above a few hertz, so the smoothed signal is the same at either rate. The
    raw signal's noise, the denominator of ``noise_left``, is measured at the source rate in the
    same pass (deviation from the truth or from the 1 s moving average, binned onto the analysis
    instants): the broadband noise the decimation removes still counts as raw noise, and the
    scores are those of the study at the full rate (measured on 30 s of the seed-like torque at
    19.2 kHz, 51 candidates: the same six best in the same order, ``peak_kept`` within 0.003,
    ``lag`` within 5 ms, ``noise_left`` mostly within 5 % and within 20 % except for zero-phase
    Butterworth, whose end padding is a number of samples, so its end transients change with
    the rate). The :class:`StudyBasis` of the result says which rate, span and method were
    used.

    Parameters
    ----------
    time : array_like, shape (n,)
        Uniform sample times [s].
    raw : array_like, shape (n,)
        Raw signal [any unit].
    truth : array_like, shape (n,), optional
        Noise-free signal [unit of ``raw``]; decimated like ``raw``.
    masks : optional
        Steady/transient parts at the source rate (see
        :func:`rollerrig.signal.filter_score.score_smoothing`); default: found
        from the analysed signal.
    analysis_rate : "auto", None or float
        ``"auto"``: 250 Hz above 500 Hz, else the source rate; None: the source rate; a number:
        that rate [Hz] (capped at the source rate).
    span : (float, float), optional
        Part of the recording to study, ``(start, end)`` [s]; default all of it.

    Returns
    -------
    StudySignal
        At the analysis rate, with the masks taken at the nearest source samples.

    Examples
    --------
    >>> from rollerrig.signal.synthetic_torque import seed_like_torque
    >>> sig = seed_like_torque(sample_rate=2000.0)
    >>> s = prepare_study_signal(sig.time, sig.raw, sig.truth, sig.segmentation)
    >>> s.basis.analysis_rate, s.raw.size, s.masks.steady.size
    (250.0, 5000, 5000)
    """
    t_all, x_all, truth_all = check_record(time, raw, truth)
    n = x_all.size
    fs = tidy_rate(uniform_sample_rate(t_all))
    i0, i1 = _span_indices(n, float(t_all[0]), fs, span)
    rate = _analysis_rate(fs, analysis_rate)
    seg_index = np.arange(i0, i1)
    noise_rms = None
    if rate >= fs * (1.0 - 1e-9):
        t, x = t_all[i0:i1], x_all[i0:i1]
        tr = None if truth_all is None else truth_all[i0:i1]
        how = None
        rate = fs
    else:
        spec = design_decimation(fs, rate)
        x = decimate(x_all[i0:i1], spec)
        tr = None if truth_all is None else decimate(truth_all[i0:i1], spec)
        t = decimated_time(i1 - i0, spec, float(t_all[i0]))
        how = spec.describe()
        rate = spec.rate
        full = _FullRateNoise(
            odd(1.0 * fs), spec.up, spec.down, unit_scale(x_all[i0:i1], truth_all)
        )
        full.push(x_all[i0:i1], None if truth_all is None else truth_all[i0:i1])
        noise_rms = full.finish(x.size)
        step = spec.down / spec.up
        seg_index = i0 + np.minimum(np.round(np.arange(x.size) * step).astype(int), i1 - i0 - 1)
    seg = _masks_on(masks, n, seg_index)
    basis = StudyBasis(fs, rate, float(t[0]), float(t[-1]), int(x.size), how)
    return StudySignal(t, x, tr, seg, basis, noise_rms)


def study_signal_from_chunks(
    chunks: Iterable,
    sample_rate: float,
    *,
    start_time: float = 0.0,
    analysis_rate="auto",
    span: tuple[float, float] | None = None,
) -> StudySignal:
    """The study signal from a stream of chunks (a long recording read piece by piece).

    Only the decimated signal (250 Hz: 7 MB per hour) and one chunk are held in memory; chunks
    outside ``span`` are skipped. Equal to :func:`prepare_study_signal` on the concatenated
    chunks (to rounding).

    Parameters
    ----------
    chunks : iterable of array_like, shape (m,)
        Consecutive pieces of one channel [any unit].
    sample_rate : float
        Rate of the chunks [Hz].
    start_time : float
        Time of the first sample [s].
    analysis_rate : "auto", None or float
        See :func:`prepare_study_signal`.
    span : (float, float), optional
        ``(start, end)`` [s] to study; default everything.

    Returns
    -------
    StudySignal
        At the analysis rate, without truth or masks (found from the signal when scored).

    Examples
    --------
    >>> from rollerrig.signal.synthetic_torque import seed_like_torque
    >>> sig = seed_like_torque(sample_rate=2000.0)
    >>> s = study_signal_from_chunks((sig.raw[i : i + 4096] for i in range(0, 40000, 4096)),
    ...                              2000.0, span=(2.0, 18.0))
    >>> s.basis.start, s.basis.end, s.raw.size
    (2.0, 18.0, 4001)
    """
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    t0 = float(start_time)
    if not np.isfinite(t0):
        raise ParameterError(f"start_time must be finite [s], got {start_time!r}")
    start_i, stop_i = (0, None) if span is None else _span_indices(1 << 62, t0, fs, span)
    count = {"n": 0}
    rate = _analysis_rate(fs, analysis_rate)
    spec = None if rate >= fs * (1.0 - 1e-9) else design_decimation(fs, rate)
    noise = None if spec is None else _FullRateNoise(odd(1.0 * fs), spec.up, spec.down)

    def within():
        pos = 0
        for chunk in chunks:
            c = np.asarray(chunk, dtype=float)
            if c.ndim != 1:
                raise ParameterError(f"chunks must be 1-D (one channel), got shape {c.shape}")
            a, b = max(start_i - pos, 0), c.size if stop_i is None else min(stop_i - pos, c.size)
            if a < b:
                piece = c[a:b]
                check_samples(piece, pos + a, _STREAM_LIMIT, "its squares overflow")
                count["n"] += b - a
                if noise is not None:
                    noise.push(piece)
                yield piece
            pos += c.size
            if stop_i is not None and pos >= stop_i:
                return

    if spec is None:
        pieces = list(within())
        how, rate = None, fs
    else:
        pieces = list(decimate_chunks(within(), spec))
        how, rate = spec.describe(), spec.rate
    n = count["n"]
    if n < 2:
        raise ParameterError(
            f"the stream holds {n} samples{'' if span is None else f' inside span {span}'}; "
            "a filter study needs a signal"
        )
    x = np.concatenate(pieces)
    t_first = t0 + start_i / fs
    t = t_first + np.arange(n) / fs if spec is None else decimated_time(n, spec, t_first)
    basis = StudyBasis(fs, rate, float(t[0]), float(t[-1]), int(x.size), how)
    noise_rms = None if noise is None else noise.finish(x.size)
    return StudySignal(t, x, None, None, basis, noise_rms)


def study_signal_from_source(
    source,
    channel: str,
    *,
    analysis_rate="auto",
    span: tuple[float, float] | None = None,
    chunk_samples: int = 1 << 20,
) -> StudySignal:
    """The study signal of one channel of an open recording, read chunk by chunk.

    ``source`` is a :class:`rollerrig.recordings.source.RecordingSource` (from
    :func:`rollerrig.recordings.source.open_recording`); only the samples inside ``span`` are read
    from disk, and only one chunk plus the decimated signal are held
    (:func:`study_signal_from_chunks`): one hour at 19.2 kHz is studied in about 20 s within
    300 MB (2 CPUs).

    Parameters
    ----------
    source : RecordingSource
        The open recording (``sample_rate``, ``n_samples``, ``read``, ``iter_chunks``).
    channel : str
        Channel to study (e.g. ``"torque"``).
    analysis_rate : "auto", None or float
        See :func:`prepare_study_signal`.
    span : (float, float), optional
        ``(start, end)`` [s] on the recording's time axis; default all of it.
    chunk_samples : int
        Samples per chunk read [samples].

    Returns
    -------
    StudySignal
        As :func:`study_signal_from_chunks` returns it.
    """
    fs = tidy_rate(source.sample_rate)
    t0 = float(source.read((channel,), 0, 1).time[0])
    start, stop = 0, int(source.n_samples)
    if span is not None:
        start, stop = _span_indices(stop, t0, fs, span)
    chunks = (
        c[channel] for c in source.iter_chunks((channel,), chunk_samples, start=start, stop=stop)
    )
    return study_signal_from_chunks(
        chunks, fs, start_time=t0 + start / fs, analysis_rate=analysis_rate
    )
