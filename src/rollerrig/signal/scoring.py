"""Quantitative filter scoring, the filter study and Savitzky-Golay auto-tuning.

The source dissertation (Kayaalp, sections 4.5.2.5-4.5.2.6) judges smoothing filters on the
roller-shaft torque by eye: how much of the induction-motor ripple (electrical frequency
= 5 × roller rotation frequency, 14.7 Hz at 30 km/h, plus harmonics) and noise is left in the
steady parts, and whether the transient parts (ramp up, peak, release within 20 ms, oscillation
afterwards) keep their peaks without delay. Its verdict: Butterworth 1-3 at 1.2 Hz delays and
flattens the peaks; Savitzky-Golay of order 4-5 with a 111-sample window is best at 250 Hz.

This module turns those criteria into numbers:

``noise_left`` [1]
    RMS of what the filter leaves in the steady parts, relative to the raw signal's: with a truth,
    ``rms(s − truth) / rms(raw − truth)``; without, the deviation from a slow trend (1 s moving
    average of the raw signal), ``rms(s − trend) / rms(raw − trend)``.
``peak_kept`` [1]
    Extreme excursion of the smoothed signal over a transient segment divided by the reference's,
    both measured from the reference's median level in the 0.5 s before the segment; the
    reference is the truth or, truth-free, the raw signal through a 20 ms median filter (a robust
    peak: it removes spikes, not the ripple). Only segments that are peaks count (the reference
    level in the 0.5 s after the segment is at least 25 % of the excursion back from the extreme;
    a ramp to a new level has no peak). Reported for the worst such segment (largest
    ``|1 − peak_kept|``).
``peak_time_error`` [s]
    Time of the smoothed extreme minus time of the reference extreme (worst peak segment).
``lag`` [s]
    Delay of the smoothed signal against the reference over all transient segments: the shift
    ``k`` minimising ``Σ (s[n+k] − ref[n])²`` pooled over the segments (the cross-correlation
    maximum corrected for the energy entering the shifted window, which keeps ramps from
    flattening the correlation), with parabolic sub-sample refinement; positive means the
    smoothed signal comes late.
``cost`` [1]
    ``w_noise·noise_left + w_peak·|1 − peak_kept| + w_timing·(|lag| + |peak_time_error|)/τ``,
    defaults ``w = 1, 2, 1`` and ``τ = 0.5 s``: 10 % of the steady noise left, 5 % of the peak
    lost and 50 ms of delay or peak-time error cost the same (0.1). The seed's verdict rests on
    steady noise and kept peaks first; 50 ms is a small fraction of the seconds-long ramps over
    which creep and adhesion are read, but ten times the 20 ms release. Lower is better.

Long and fast recordings. The seed's study ran at 250 Hz and its windows are given there. A
recording faster than 500 Hz (19.2 kHz on an HBM QuantumX) is studied at 250 Hz by default,
on the signal decimated by a zero-phase anti-alias FIR (:mod:`rollerrig.signal.decimate`), with
the raw noise still measured at the full rate (:func:`prepare_study_signal`); a stream of chunks
or an open recording is studied in one pass holding only the 250 Hz signal
(:func:`study_signal_from_chunks`, :func:`study_signal_from_source`). Every result is a
:class:`StudyTable` whose :class:`StudyBasis` states the rate, the span and the method, and
whose ``unscored`` says why a score is missing (None in :meth:`StudyRow.as_dict`, never NaN).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import signal as sps
from scipy.ndimage import median_filter

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.signal.decimate import decimate, decimate_chunks, decimated_time, design_decimation
from rollerrig.signal.smoothing import METHODS, moving_average, smooth

__all__ = [
    "ANALYSIS_RATE_LIMIT",
    "FilterScore",
    "ScoreWeights",
    "Segmentation",
    "StudyBasis",
    "StudyRow",
    "StudySignal",
    "StudyTable",
    "SyntheticTorque",
    "default_candidates",
    "filter_study",
    "prepare_study_signal",
    "score_smoothing",
    "seed_like_torque",
    "steady_and_transient_masks",
    "study_signal_from_chunks",
    "study_signal_from_source",
    "tune_savitzky_golay",
]

SEED_SAMPLE_RATE = 250.0
"""Sampling rate of the seed's torque recordings [Hz] (the default windows are given at it)."""


def _odd(n: float, minimum: int = 3) -> int:
    k = max(round(n), minimum)
    return k if k % 2 else k + 1


def _sample_rate(time: np.ndarray) -> float:
    dt = np.diff(time)
    if dt.size == 0 or np.any(dt <= 0):
        raise ParameterError("time must be strictly increasing with at least 2 samples [s]")
    step = float(np.median(dt))
    if np.max(np.abs(dt - step)) > 0.01 * step:
        raise ParameterError("time must be uniformly sampled (within 1 % of the median step) [s]")
    return 1.0 / step


# --------------------------------------------------------------------------------------------
# segmentation
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Segmentation:
    """Steady and transient parts of a signal, as boolean masks over its samples.

    Attributes
    ----------
    steady : ndarray of bool, shape (n,)
        Samples in steady parts.
    transient : ndarray of bool, shape (n,)
        Samples in transient parts (the two may leave a guard band between them).
    """

    steady: np.ndarray
    transient: np.ndarray

    def transient_segments(self) -> list[tuple[int, int]]:
        """Contiguous transient runs as ``(start, stop)`` index pairs (stop exclusive)."""
        return _runs(self.transient)

    def steady_segments(self) -> list[tuple[int, int]]:
        """Contiguous steady runs as ``(start, stop)`` index pairs (stop exclusive)."""
        return _runs(self.steady)

    @classmethod
    def from_ranges(
        cls, n: int, steady: Iterable[tuple[int, int]], transient: Iterable[tuple[int, int]]
    ) -> Segmentation:
        """Masks from ``(start, stop)`` sample-index ranges (stop exclusive)."""
        s = np.zeros(n, bool)
        t = np.zeros(n, bool)
        for a, b in steady:
            s[a:b] = True
        for a, b in transient:
            t[a:b] = True
        return cls(s, t)


def _unit_scale(*arrays) -> float:
    """A power of two ``s`` with ``max |s·x|`` in [0.5, 1) (1 for all-zero input) [1/unit]."""
    peak = max((float(np.max(np.abs(a))) for a in arrays if a is not None and a.size), default=0)
    return 1.0 if peak == 0.0 else float(np.ldexp(1.0, -int(np.frexp(peak)[1])))


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    m = np.concatenate([[False], np.asarray(mask, bool), [False]])
    edges = np.flatnonzero(np.diff(m.astype(np.int8)))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def steady_and_transient_masks(
    signal,
    sample_rate: float,
    *,
    smoothing_time: float = 0.5,
    threshold: float | None = None,
    k_sigma: float = 3.0,
    margin: float = 0.25,
) -> Segmentation:
    """Find steady and transient parts from a slope-threshold rule.

    The signal (the torque request, or the measured torque itself) is smoothed by a moving average
    of ``smoothing_time`` applied twice (a triangular window of twice that length, whose ``sinc²``
    response leaves < 0.2 % of a 14.7 Hz ripple at 0.5 s), differentiated, and samples whose
    ``|slope|`` exceeds the threshold are transient. Default threshold: ``k_sigma`` robust standard
    deviations of the slope (``1.4826 × MAD``), at least ``1e-3 × peak-to-peak`` per second (so a
    clean piecewise request with zero slope in its steady parts works) and ``1e-9 × max|signal|``
    per sample (so rounding in a constant signal is no transient). Transient runs are widened
    by ``margin`` on each side; steady samples are those at least ``2·margin`` away from any
    transient core.

    Parameters
    ----------
    signal : array_like, shape (n,)
        Torque request or measured torque [N·m] (any unit works).
    sample_rate : float
        Sampling rate [Hz].
    smoothing_time : float
        Length of the moving average applied twice before differentiating [s].
    threshold : float, optional
        Slope threshold [unit of ``signal`` / s]; default from ``k_sigma``.
    k_sigma : float
        Threshold in robust standard deviations of the slope [1].
    margin : float
        Widening of the transient runs [s].

    Returns
    -------
    Segmentation
        Steady and transient masks.

    Examples
    --------
    >>> fs = 250.0
    >>> request = np.concatenate([np.zeros(500), np.linspace(0, 100, 500), 100 * np.ones(500)])
    >>> seg = steady_and_transient_masks(request, fs)
    >>> seg.transient_segments()
    [(321, 1179)]
    """
    x = require_finite("signal", signal)
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    window = _odd(smoothing_time * fs, 1)
    y = moving_average(moving_average(x, window), window)
    slope = np.gradient(y) * fs
    if threshold is None:
        sigma = 1.4826 * np.median(np.abs(slope - np.median(slope)))
        rounding = 1e-9 * float(np.max(np.abs(y))) * fs  # a constant's moving-average slope
        thr = max(k_sigma * sigma, 1e-3 * float(np.ptp(y)), rounding, 1e-300)
    else:
        thr = float(require_positive("threshold", threshold))
    core = np.abs(slope) > thr
    m = round(margin * fs)
    return Segmentation(~_dilate(core, 2 * m), _dilate(core, m))


def _dilate(mask: np.ndarray, reach: int) -> np.ndarray:
    """``mask`` widened by ``reach`` samples each side (binary dilation by ``2·reach + 1`` ones).

    Counted with a cumulative sum: O(n) time and memory whatever the reach
    (:func:`scipy.ndimage.binary_dilation` takes O(n·reach) time and, at 19.2 kHz with a
    0.25 s margin, 2.8 GB for 30 s of signal).
    """
    if reach <= 0 or not mask.any():
        return mask.copy()
    counts = np.concatenate([[0], np.cumsum(mask, dtype=np.int64)])
    i = np.arange(mask.size)
    hi = np.minimum(i + reach + 1, mask.size)
    lo = np.maximum(i - reach, 0)
    return counts[hi] > counts[lo]


def _as_segmentation(masks, n: int, raw: np.ndarray, fs: float) -> Segmentation:
    if masks is None:
        return steady_and_transient_masks(raw, fs)
    if isinstance(masks, Segmentation):
        seg = masks
    elif isinstance(masks, Mapping):
        seg = Segmentation.from_ranges(n, masks.get("steady", ()), masks.get("transient", ()))
    else:
        steady, transient = masks
        seg = Segmentation(np.asarray(steady, bool), np.asarray(transient, bool))
    if seg.steady.shape != (n,) or seg.transient.shape != (n,):
        raise ParameterError(f"masks must be boolean arrays of the signal's length {n}")
    return seg


# --------------------------------------------------------------------------------------------
# scoring
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ScoreWeights:
    """Weights of the combined cost (see the module docstring).

    Attributes
    ----------
    noise : float
        Weight of ``noise_left`` [1].
    peak : float
        Weight of ``|1 − peak_kept|`` [1].
    timing : float
        Weight of ``(|lag| + |peak_time_error|) / time_scale`` [1].
    time_scale : float
        Delay that costs as much as the whole noise or peak [s].
    """

    noise: float = 1.0
    peak: float = 2.0
    timing: float = 1.0
    time_scale: float = 0.5


@dataclass(frozen=True)
class FilterScore:
    """Scores of one smoothed signal (see the module docstring for definitions).

    Attributes
    ----------
    noise_left : float
        Steady-part noise left [1] (0 = none, 1 = as raw).
    peak_kept : float
        Transient peak excursion kept [1] (1 = exact), worst segment.
    peak_time_error : float
        Peak timing error [s], worst segment.
    lag : float
        Delay on the transients [s], positive = late.
    cost : float
        Combined cost [1], lower is better.
    """

    noise_left: float
    peak_kept: float
    peak_time_error: float
    lag: float
    cost: float


class _Scorer:
    """Precomputes everything that does not depend on the smoothed signal."""

    def __init__(self, time, raw, truth, masks, weights, max_lag, base_time, raw_noise_rms=None):
        self.time = require_finite("time", time)
        raw = require_finite("raw", raw)
        n = raw.size
        if self.time.shape != (n,) or raw.ndim != 1:
            raise ParameterError("time and raw must be 1-D arrays of the same length")
        if truth is not None:
            truth = require_finite("truth", truth)
            if truth.shape != (n,):
                raise ParameterError("truth must have the length of raw")
        # Every score is a ratio or a time: scale the signals into [-1, 1] by a power of two
        # (exact in floating point) so that squares and filters cannot overflow or underflow.
        self.scale = _unit_scale(raw, truth)
        self.raw = raw * self.scale
        self.fs = _sample_rate(self.time)
        self.weights = weights or ScoreWeights()
        self.seg = _as_segmentation(masks, n, self.raw, self.fs)
        self.steady = self.seg.steady
        if truth is not None:
            self.truth = truth * self.scale
            self.noise_ref = self.truth
            self.ref = self.truth
        else:
            self.truth = None
            self.noise_ref = moving_average(self.raw, _odd(1.0 * self.fs))
            self.ref = median_filter(self.raw, size=_odd(0.02 * self.fs), mode="nearest")
        if raw_noise_rms is None:
            self.raw_noise = self._rms(self.raw - self.noise_ref)
        else:  # the raw signal's noise measured at its full rate, per analysis sample
            self.raw_noise = self._rms(np.asarray(raw_noise_rms, float) * self.scale)
        self.segments = self.seg.transient_segments()
        self.max_lag = round(max_lag * self.fs)
        nb = max(round(base_time * self.fs), 1)
        self.peaks = []
        for a, b in self.segments:
            before = self.ref[max(a - nb, 0) : a] if a > 0 else self.ref[b : b + nb]
            base = float(np.median(before)) if before.size else float(self.ref[a])
            exc = self.ref[a:b] - base
            k = int(np.argmax(np.abs(exc)))
            following = self.ref[b : b + nb] if b < n else self.ref[max(b - nb, a) : b]
            end = float(np.median(following)) - base
            if abs(end) <= 0.75 * abs(exc[k]) and exc[k] != 0:  # a peak, not a level change
                self.peaks.append((a, b, base, float(np.sign(exc[k])), float(exc[k]), a + k))

    @property
    def has_noise(self) -> bool:
        """Whether the raw steady parts carry more than rounding (1e-12 of the scaled peak)."""
        return bool(self.raw_noise > 1e-12)

    def _rms(self, r):
        return float(np.sqrt(np.mean(r[self.steady] ** 2))) if self.steady.any() else np.nan

    def _lag(self, s):
        if not self.segments:
            return np.nan
        n, lag_n = s.size, self.max_lag
        err = np.zeros(2 * lag_n + 1)
        for a, b in self.segments:
            r = self.ref[a:b]
            idx = np.clip(np.arange(a - lag_n, b + lag_n), 0, n - 1)
            ext = s[idx]
            # e(k) = Σ_n (s[n+k] − r[n])² over the segment, for k = −L..L
            sq = np.concatenate([[0.0], np.cumsum(ext * ext)])
            energy = sq[b - a :] - sq[: 2 * lag_n + 1]
            err += energy - 2.0 * sps.correlate(ext, r, mode="valid") + np.sum(r * r)
        if np.ptp(err) <= 1e-12 * float(np.max(np.abs(err))):
            return np.nan  # a flat reference: every shift fits alike, no delay to measure
        j = int(np.argmin(err))
        frac = 0.0
        if 0 < j < err.size - 1:
            c0, c1, c2 = err[j - 1], err[j], err[j + 1]
            den = c0 - 2 * c1 + c2
            frac = 0.5 * (c0 - c2) / den if den > 0 else 0.0
        return (j - lag_n + frac) / self.fs

    def score(self, smoothed) -> FilterScore:
        """Scores of ``smoothed`` given in the units of the raw signal."""
        s = np.asarray(smoothed, float)
        if s.shape != self.raw.shape:
            raise ParameterError("smoothed must have the length of raw")
        return self.score_scaled(s * self.scale)

    def score_scaled(self, s: np.ndarray) -> FilterScore:
        """Scores of ``s`` smoothed from :attr:`raw` (already scaled)."""
        noise = self._rms(s - self.noise_ref) / self.raw_noise if self.has_noise else np.nan
        kept, terr = np.nan, np.nan
        n = s.size
        for a, b, base, sign, exc, k_ref in self.peaks:
            lo, hi = max(a - self.max_lag, 0), min(b + self.max_lag, n)
            k = lo + int(np.argmax(sign * (s[lo:hi] - base)))
            ratio = (s[k] - base) / exc if exc else np.nan
            dt = float(self.time[k] - self.time[k_ref])
            if np.isnan(kept) or abs(1 - ratio) > abs(1 - kept):
                kept = float(ratio)
            if np.isnan(terr) or abs(dt) > abs(terr):
                terr = dt
        lag = self._lag(s)
        w = self.weights
        terms = [
            w.noise * noise,
            w.peak * abs(1 - kept),
            w.timing * (abs(lag) + abs(terr)) / w.time_scale,
        ]
        cost = float(np.sum(np.nan_to_num(terms, nan=0.0)))
        return FilterScore(float(noise), float(kept), float(terr), float(lag), cost)


def score_smoothing(
    time,
    raw,
    smoothed,
    truth=None,
    masks=None,
    weights: ScoreWeights | None = None,
    *,
    max_lag: float = 0.5,
    base_time: float = 0.5,
) -> FilterScore:
    """Score a smoothed signal against the raw one (and the truth when known).

    Parameters
    ----------
    time : array_like, shape (n,)
        Uniform sample times [s].
    raw : array_like, shape (n,)
        Raw signal [N·m or any unit].
    smoothed : array_like, shape (n,)
        Smoothed signal [unit of ``raw``].
    truth : array_like, shape (n,), optional
        Noise-free signal [unit of ``raw``] (synthetic data).
    masks : Segmentation, (steady, transient) boolean arrays, or mapping, optional
        Steady/transient parts; a mapping holds ``"steady"`` and ``"transient"`` lists of
        ``(start, stop)`` index ranges. Default: :func:`steady_and_transient_masks` on ``raw``.
    weights : ScoreWeights, optional
        Cost weights.
    max_lag : float
        Largest lag searched and peak-search widening [s].
    base_time : float
        Span before a transient whose median reference level is the excursion base [s].

    Returns
    -------
    FilterScore
        The scores.

    Examples
    --------
    A pure delay of 5 samples at 250 Hz is a lag of 0.02 s:

    >>> fs = 250.0
    >>> t = np.arange(2000) / fs
    >>> x = np.exp(-0.5 * ((t - 4.0) / 0.1) ** 2)
    >>> seg = Segmentation.from_ranges(t.size, [(0, 500)], [(900, 1100)])
    >>> d = score_smoothing(t, x, np.roll(x, 5), truth=x, masks=seg)
    >>> round(d.lag, 4), round(d.peak_time_error, 4)
    (0.02, 0.02)
    """
    scorer = _Scorer(time, raw, truth, masks, weights, max_lag, base_time)
    return scorer.score(smoothed)


# --------------------------------------------------------------------------------------------
# the filter study and Savitzky-Golay tuning
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class StudyRow:
    """One candidate filter's scores in a study.

    Attributes
    ----------
    rank : int
        1 = lowest cost.
    method : str
        Key of :data:`rollerrig.signal.smoothing.METHODS`.
    params : dict
        The method's parameters (windows in samples, cut-off in Hz).
    label : str
        Short description.
    score : FilterScore
        The scores.
    sample_rate : float, optional
        Rate the filter ran at [Hz]: ``params["window"]`` counts samples at it.
    """

    rank: int
    method: str
    params: dict = field(hash=False)
    label: str
    score: FilterScore
    sample_rate: float | None = None

    def as_dict(self) -> dict:
        """Flat dict for tables (``rank, label, method, params..., scores...``).

        A score the recording does not allow (no steady part, no peak, no transient) is None;
        :attr:`StudyTable.unscored` says why. With ``sample_rate`` known, also
        ``sample_rate_Hz`` (the rate the windows count samples at) and, for windowed methods,
        ``window_s`` [s].
        """
        s = self.score
        extra = {}
        if self.sample_rate is not None:
            extra["sample_rate_Hz"] = self.sample_rate
            if "window" in self.params:
                extra["window_s"] = self.params["window"] / self.sample_rate
        return {
            "rank": self.rank,
            "label": self.label,
            "method": self.method,
            **self.params,
            **extra,
            "noise_left": _finite_or_none(s.noise_left),
            "peak_kept": _finite_or_none(s.peak_kept),
            "peak_time_error_s": _finite_or_none(s.peak_time_error),
            "lag_s": _finite_or_none(s.lag),
            "cost": s.cost,
        }


def _finite_or_none(value: float) -> float | None:
    """The value, or None where it is not a finite number (see ``StudyTable.unscored``)."""
    return float(value) if np.isfinite(value) else None


def _label(method: str, params: Mapping) -> str:
    if method == "butterworth":
        kind = "zero-phase" if params.get("zero_phase", True) else "causal"
        return f"Butterworth {params.get('order', 2)} @ {params['cutoff']:g} Hz {kind}"
    if method == "savitzky_golay":
        return f"SG order {params['order']} w{params['window']}"
    names = {
        "moving_average": "MA",
        "gaussian": "Gaussian",
        "lowess": "LOWESS",
        "loess": "LOESS",
        "rlowess": "rLOWESS",
        "rloess": "rLOESS",
    }
    return f"{names.get(method, method)} w{params['window']}"


def default_candidates(sample_rate: float = SEED_SAMPLE_RATE) -> list[tuple[str, dict]]:
    """The seed's filter grid (Kayaalp, sections 4.5.2.5-4.5.2.6), windows scaled to the rate.

    Butterworth orders 1-3 at 1.2 Hz, causal and zero-phase; moving average (11, 33, 65, 111,
    131), Gaussian (33, 65, 111, 131), LOWESS/LOESS (33, 65, 131), robust LOWESS/LOESS
    (33, 65, 131); Savitzky-Golay orders 2-7 × windows (33, 65, 111, 131). Windows are samples
    at 250 Hz, multiplied by ``sample_rate / 250`` (and made odd) at other rates.

    Parameters
    ----------
    sample_rate : float
        Sampling rate [Hz].

    Returns
    -------
    list of (str, dict)
        ``(method, params)`` pairs.

    Examples
    --------
    >>> len(default_candidates())
    51
    """
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))

    def w(k: int) -> int:
        return _odd(k * fs / SEED_SAMPLE_RATE, 5)

    out: list[tuple[str, dict]] = []
    for zero_phase in (True, False):
        for order in (1, 2, 3):
            out.append(("butterworth", {"cutoff": 1.2, "order": order, "zero_phase": zero_phase}))
    out += [("moving_average", {"window": w(k)}) for k in (11, 33, 65, 111, 131)]
    out += [("gaussian", {"window": w(k)}) for k in (33, 65, 111, 131)]
    for method in ("lowess", "loess", "rlowess", "rloess"):
        out += [(method, {"window": w(k)}) for k in (33, 65, 131)]
    out += [
        ("savitzky_golay", {"window": w(k), "order": p})
        for p in range(2, 8)
        for k in (33, 65, 111, 131)
    ]
    return out


@dataclass(frozen=True)
class StudyBasis:
    """Where a filter study was computed: at which rate, over which span, from what signal.

    Attributes
    ----------
    source_rate : float
        Rate of the recording given [Hz].
    analysis_rate : float
        Rate the filters ran and were scored at [Hz]; the study's windows count samples at it.
    start, end : float
        Span of the recording the study covers [s] (first and last analysed instant).
    samples : int
        Samples scored (at ``analysis_rate``).
    decimation : str or None
        How the signal was brought to ``analysis_rate``
        (:meth:`rollerrig.signal.decimate.DecimationFilter.describe`), None at the source rate.
    """

    source_rate: float
    analysis_rate: float
    start: float
    end: float
    samples: int
    decimation: str | None = None

    def note(self) -> str:
        """One sentence for outputs: rate, span and method."""
        where = (
            f"filter study computed at {self.analysis_rate:g} Hz (windows in samples at that "
            f"rate) over {self.start:.3f}-{self.end:.3f} s ({self.samples} samples)"
        )
        if self.decimation is None:
            return where + ", at the recording's own rate"
        return (
            f"{where}, on the signal {self.decimation}; noise_left is relative to the raw "
            f"signal's noise measured at {self.source_rate:g} Hz (the candidate filters pass "
            "nothing above a few hertz, so smoothing before or after decimating is the same)"
        )

    def as_dict(self) -> dict:
        """JSON-ready (rates in Hz, times in s)."""
        return {
            "source_rate_Hz": self.source_rate,
            "analysis_rate_Hz": self.analysis_rate,
            "start_s": self.start,
            "end_s": self.end,
            "samples": self.samples,
            "decimation": self.decimation,
            "note": self.note(),
        }


class StudyTable(list):
    """Ranked :class:`StudyRow` list with where it was computed and what it could not score.

    Attributes
    ----------
    basis : StudyBasis or None
        Rate, span and method of the study.
    unscored : dict of str to str
        Scores that are NaN in every row (None in :meth:`StudyRow.as_dict`), with the reason
        (e.g. ``{"peak_kept": "no transient segment is a peak ..."}``).
    """

    def __init__(self, rows=(), basis: StudyBasis | None = None, unscored=None):
        super().__init__(rows)
        self.basis = basis
        self.unscored = dict(unscored or {})

    def unscored_notes(self) -> list[str]:
        """One sentence per entry of :attr:`unscored`, for consoles and reports."""
        return [
            why if key == "not_run" else f"{key} not scored: {why}"
            for key, why in self.unscored.items()
        ]


def _unscored(scorer: _Scorer) -> dict[str, str]:
    """Why a score is NaN for every filter on this signal (keys as in StudyRow.as_dict)."""
    why = {}
    if not scorer.steady.any():
        why["noise_left"] = (
            "no steady part: no stretch of the signal lies 0.5 s or more from a transient"
        )
    elif not scorer.has_noise:
        why["noise_left"] = "the raw signal has no noise in its steady parts (beyond rounding)"
    if not scorer.peaks:
        reason = (
            "no transient segment is a peak (each ends at a new level)"
            if scorer.segments
            else "no transient segment: the signal has no ramp, peak or release"
        )
        why["peak_kept"] = why["peak_time_error_s"] = reason
    if not scorer.segments:
        why["lag_s"] = "no transient segment to measure a delay on"
    return why


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
    rate = float(require_positive("analysis_rate", analysis_rate, "Hz"))
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

    def _scorer(self, weights) -> _Scorer:
        return _Scorer(
            self.time, self.raw, self.truth, self.masks, weights, 0.5, 0.5, self.raw_noise_rms
        )

    def _run(self, scorer: _Scorer, candidates) -> StudyTable:
        results = []
        not_run: list[str] = []
        for method, params in candidates:
            if method not in METHODS:
                raise ParameterError(f"unknown method {method!r}; known: {sorted(METHODS)}")
            try:
                y = smooth(scorer.raw, method, sample_rate=scorer.fs, **params)
            except ParameterError as exc:
                # The seed's windows scale with the rate: on a slow or short recording some
                # filters do not exist (a LOWESS of 5 samples, a window longer than the signal).
                # They are left out and listed; the others are still ranked.
                not_run.append(f"{_label(method, params)} ({exc})")
                continue
            results.append((method, dict(params), scorer.score_scaled(y)))
        if not results:
            raise ParameterError(
                f"no filter of the study can run on this signal ({scorer.raw.size} samples at "
                f"{scorer.fs:.6g} Hz): {'; '.join(not_run[:3])}"
                f"{' ...' if len(not_run) > 3 else ''}; the study needs a longer recording "
                "(several seconds) at a rate of at least about 50 Hz"
            )
        results.sort(key=lambda r: r[2].cost)
        rate = self.basis.analysis_rate
        rows = [StudyRow(i + 1, m, p, _label(m, p), s, rate) for i, (m, p, s) in enumerate(results)]
        why = _unscored(scorer)
        if not_run:
            distinct = list(dict.fromkeys(not_run))  # windows 33 and 65 may both shrink to 5
            why["not_run"] = f"{len(not_run)} filter(s) cannot run on this signal: " + "; ".join(
                distinct
            )
        for key, attr in (("noise_left", "noise_left"), ("peak_kept", "peak_kept"),
                          ("peak_time_error_s", "peak_time_error"), ("lag_s", "lag")):  # fmt: skip
            if rows and key not in why and all(np.isnan(getattr(r.score, attr)) for r in rows):
                why[key] = "not determined by this signal (a flat reference)"
        return StudyTable(rows, self.basis, why)

    def filter_study(
        self,
        candidates: Sequence[tuple[str, Mapping]] | None = None,
        weights: ScoreWeights | None = None,
    ) -> StudyTable:
        """Score and rank filters on this signal (see :func:`filter_study`)."""
        scorer = self._scorer(weights)
        if candidates is None:
            candidates = default_candidates(scorer.fs)
        return self._run(scorer, candidates)

    def tune_savitzky_golay(
        self,
        orders: Iterable[int] = range(2, 8),
        windows: Iterable[int] | None = None,
        weights: ScoreWeights | None = None,
    ) -> tuple[int, int, StudyTable]:
        """Best Savitzky-Golay order and window (see :func:`tune_savitzky_golay`).

        Returns the window in samples at the *source* rate; the table's at the analysis rate.
        """
        scorer = self._scorer(weights)
        if windows is None:
            windows = sorted(
                {_odd(k * scorer.fs / SEED_SAMPLE_RATE, 5) for k in range(11, 202, 10)}
            )
        candidates = [
            ("savitzky_golay", {"window": int(w), "order": int(p)})
            for p in orders
            for w in windows
            if int(p) < int(w)
        ]
        if not candidates:
            raise ParameterError("no (order, window) pair with order < window [samples]")
        table = self._run(scorer, candidates)
        best = table[0].params
        window = best["window"]
        ratio = self.basis.source_rate / self.basis.analysis_rate
        if self.basis.decimation is not None:  # the same span in seconds, made odd
            window = max(_odd((window - 1) * ratio + 1, 1), best["order"] + 1 + best["order"] % 2)
        return best["order"], int(window), table


def _masks_on(masks, n: int, index: np.ndarray) -> Segmentation | None:
    """Masks given at the source rate (length n), taken at source samples ``index``."""
    if masks is None:
        return None
    seg = _as_segmentation(masks, n, np.zeros(0), 1.0)
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
        Steady/transient parts at the source rate (see :func:`score_smoothing`); default: found
        from the analysed signal.
    analysis_rate : "auto", None or float
        ``"auto"``: 250 Hz above 500 Hz, else the source rate; None: the source rate; a number:
        that rate [Hz] (capped at the source rate).
    span : (float, float), optional
        Part of the recording to study, ``(start, end)`` [s]; default all of it.

    Returns
    -------
    StudySignal

    Examples
    --------
    >>> sig = seed_like_torque(sample_rate=2000.0)
    >>> s = prepare_study_signal(sig.time, sig.raw, sig.truth, sig.segmentation)
    >>> s.basis.analysis_rate, s.raw.size, s.masks.steady.size
    (250.0, 5000, 5000)
    """
    t_all = require_finite("time", time)
    x_all = require_finite("raw", raw)
    n = x_all.size
    if t_all.shape != (n,) or x_all.ndim != 1:
        raise ParameterError("time and raw must be 1-D arrays of the same length")
    fs = float(f"{_sample_rate(t_all):.10g}")  # 19200.000000001 from float time stamps: 19200
    truth_all = None
    if truth is not None:
        truth_all = require_finite("truth", truth)
        if truth_all.shape != (n,):
            raise ParameterError("truth must have the length of raw")
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
            _odd(1.0 * fs), spec.up, spec.down, _unit_scale(x_all[i0:i1], truth_all)
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

    Examples
    --------
    >>> sig = seed_like_torque(sample_rate=2000.0)
    >>> s = study_signal_from_chunks((sig.raw[i : i + 4096] for i in range(0, 40000, 4096)),
    ...                              2000.0, span=(2.0, 18.0))
    >>> s.basis.start, s.basis.end, s.raw.size
    (2.0, 18.0, 4001)
    """
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    t0 = float(start_time)
    if not np.isfinite(t0):
        raise ParameterError(f"start_time must be finite [s], got {start_time!r}")
    start_i, stop_i = (0, None) if span is None else _span_indices(1 << 62, t0, fs, span)
    count = {"n": 0}
    rate = _analysis_rate(fs, analysis_rate)
    spec = None if rate >= fs * (1.0 - 1e-9) else design_decimation(fs, rate)
    noise = None if spec is None else _FullRateNoise(_odd(1.0 * fs), spec.up, spec.down)

    def within():
        pos = 0
        for chunk in chunks:
            c = np.asarray(chunk, dtype=float)
            if c.ndim != 1:
                raise ParameterError(f"chunks must be 1-D (one channel), got shape {c.shape}")
            a, b = max(start_i - pos, 0), c.size if stop_i is None else min(stop_i - pos, c.size)
            if a < b:
                piece = c[a:b]
                if not np.all(np.isfinite(piece)):
                    raise ParameterError(
                        f"the signal has non-finite values in samples {pos + a}..{pos + b - 1}"
                    )
                big = float(np.max(np.abs(piece)))
                if big > _STREAM_LIMIT:
                    raise ParameterError(
                        f"the signal reaches {big:.3g} near sample {pos + a}, beyond "
                        f"{_STREAM_LIMIT:.0e} where its squares overflow; check the channel's "
                        "scale and unit"
                    )
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

    ``source`` is a :class:`rollerrig.measure.source.RecordingSource` (from
    :func:`rollerrig.measure.source.open_recording`); only the samples inside ``span`` are read
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
    """
    fs = float(f"{float(source.sample_rate):.10g}")
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


def filter_study(
    time,
    raw,
    truth=None,
    masks=None,
    candidates: Sequence[tuple[str, Mapping]] | None = None,
    weights: ScoreWeights | None = None,
    *,
    analysis_rate="auto",
    span: tuple[float, float] | None = None,
) -> StudyTable:
    """Score a grid of filters on one recording and rank them by cost (lowest first).

    Recordings faster than 500 Hz are studied at 250 Hz, on the signal decimated by an
    anti-alias FIR (see :func:`prepare_study_signal`); the table's ``basis`` says at which rate,
    over which span and how (:meth:`StudyBasis.note`).

    Parameters
    ----------
    time : array_like, shape (n,)
        Uniform sample times [s].
    raw : array_like, shape (n,)
        Raw signal, e.g. roller-shaft torque [N·m].
    truth : array_like, shape (n,), optional
        Noise-free signal (synthetic data) [unit of ``raw``].
    masks : optional
        Steady/transient parts at the rate of ``time`` (see :func:`score_smoothing`).
    candidates : sequence of (str, mapping), optional
        ``(method, params)`` pairs, windows in samples at the analysis rate; default
        :func:`default_candidates` at the analysis rate.
    weights : ScoreWeights, optional
        Cost weights.
    analysis_rate : "auto", None or float
        See :func:`prepare_study_signal`.
    span : (float, float), optional
        ``(start, end)`` [s] to study; default the whole recording.

    Returns
    -------
    StudyTable
        Ranked rows (a list) with ``basis`` (:class:`StudyBasis`).

    Examples
    --------
    >>> sig = seed_like_torque(duration=20.0)
    >>> rows = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation,
    ...                     candidates=[("moving_average", {"window": 33}),
    ...                                 ("butterworth", {"cutoff": 1.2, "order": 3})])
    >>> [r.label for r in rows]
    ['MA w33', 'Butterworth 3 @ 1.2 Hz zero-phase']
    >>> rows.basis.analysis_rate, rows.basis.decimation is None
    (250.0, True)
    """
    prepared = prepare_study_signal(time, raw, truth, masks, analysis_rate=analysis_rate, span=span)
    return prepared.filter_study(candidates, weights)


def tune_savitzky_golay(
    time,
    raw,
    truth=None,
    masks=None,
    orders: Iterable[int] = range(2, 8),
    windows: Iterable[int] | None = None,
    weights: ScoreWeights | None = None,
    *,
    analysis_rate="auto",
    span: tuple[float, float] | None = None,
) -> tuple[int, int, StudyTable]:
    """Choose the Savitzky-Golay order and window with the lowest cost for one recording.

    The seed tunes by eye per speed (10, 30, 60 km/h) and settles on order 4-5, window 111 at
    250 Hz; this does the same search on the cost of :func:`score_smoothing`, at the analysis
    rate of :func:`prepare_study_signal` (250 Hz for recordings faster than 500 Hz).

    Parameters
    ----------
    time : array_like, shape (n,)
        Uniform sample times [s].
    raw : array_like, shape (n,)
        Raw signal [N·m].
    truth : array_like, shape (n,), optional
        Noise-free signal [unit of ``raw``].
    masks : optional
        Steady/transient parts at the rate of ``time`` (see :func:`score_smoothing`).
    orders : iterable of int
        Polynomial orders to try.
    windows : iterable of int, optional
        Odd windows [samples at the analysis rate]; default 11, 21, ..., 201 at 250 Hz, scaled
        to the analysis rate (0.04-0.8 s).
    weights : ScoreWeights, optional
        Cost weights.
    analysis_rate : "auto", None or float
        See :func:`prepare_study_signal`.
    span : (float, float), optional
        ``(start, end)`` [s] to study; default the whole recording.

    Returns
    -------
    order : int
        Best polynomial order.
    window : int
        Best window [samples at the rate of ``time``]: when the signal was decimated, the
        table's window ``w`` at the analysis rate spans ``(w − 1)/analysis_rate`` seconds; the
        window of the same span at the source rate (made odd) is returned.
    table : StudyTable
        All combinations, ranked (windows at the analysis rate), with ``basis``.

    Examples
    --------
    >>> sig = seed_like_torque(duration=20.0)
    >>> order, window, table = tune_savitzky_golay(
    ...     sig.time, sig.raw, sig.truth, sig.segmentation, orders=[2, 4], windows=[33, 111])
    >>> len(table), order in (2, 4), window in (33, 111)
    (4, True, True)
    """
    prepared = prepare_study_signal(time, raw, truth, masks, analysis_rate=analysis_rate, span=span)
    return prepared.tune_savitzky_golay(orders, windows, weights)


# --------------------------------------------------------------------------------------------
# a seed-like synthetic torque signal
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SyntheticTorque:
    """A synthetic roller-shaft torque record with known truth.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    raw : ndarray
        Measured-like torque [N·m]: truth + motor ripple + noise.
    truth : ndarray
        Noise-free torque [N·m].
    torque_request : ndarray
        Piecewise torque request [N·m].
    segmentation : Segmentation
        Steady and transient parts by construction.
    sample_rate : float
        Sampling rate [Hz].
    """

    time: np.ndarray
    raw: np.ndarray
    truth: np.ndarray
    torque_request: np.ndarray
    segmentation: Segmentation
    sample_rate: float


def seed_like_torque(
    sample_rate: float = SEED_SAMPLE_RATE,
    duration: float = 20.0,
    electrical_frequency: float = 14.7,
    ripple: tuple[float, ...] = (15.0, 6.0),
    noise: float = 5.0,
    seed: int = 0,
) -> SyntheticTorque:
    """A torque record shaped like the seed's (Kayaalp, sections 4.5.2.4-4.5.2.6).

    Layout over 20 s (scaled to ``duration``): steady 100 N·m; ramp 4-9.6 s to 320 N·m, then a
    sharper rise to a 400 N·m adhesion peak at 10 s; release to 220 N·m within 20 ms; damped
    oscillation after it (3 Hz, 60 N·m, 0.35 s decay); steady; ramp down 14-16 s to 100 N·m;
    steady. Added: induction-motor ripple at ``electrical_frequency`` (14.7 Hz at 30 km/h
    = 5 × the roller rotation frequency) and its harmonics with amplitudes ``ripple`` [N·m], and
    white noise of standard deviation ``noise`` [N·m].

    Parameters
    ----------
    sample_rate : float
        Sampling rate [Hz].
    duration : float
        Record length [s].
    electrical_frequency : float
        Ripple fundamental [Hz].
    ripple : tuple of float
        Amplitudes of the fundamental and its harmonics [N·m].
    noise : float
        White-noise standard deviation [N·m].
    seed : int
        Random seed.

    Returns
    -------
    SyntheticTorque
        The record.

    Examples
    --------
    >>> sig = seed_like_torque()
    >>> sig.raw.shape, round(float(sig.truth.max()))
    ((5000,), 400)
    """
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    dur = float(require_positive("duration", duration, "s"))
    n = round(dur * fs)
    t = np.arange(n) / fs
    c = dur / 20.0
    t_up, t_knee, t_peak, t_rel = 4.0 * c, 9.6 * c, 10.0 * c, 0.02
    t_hold, t_down = 14.0 * c, 16.0 * c
    base, knee, peak, after = 100.0, 320.0, 400.0, 220.0
    u = np.clip((t - t_up) / (t_knee - t_up), 0.0, 1.0)
    q = np.clip((t - t_knee) / (t_peak - t_knee), 0.0, 1.0)
    rise = base + (knee - base) * u + (peak - knee) * (1.0 - (1.0 - q) ** 2)
    v = np.clip((t - t_peak) / t_rel, 0.0, 1.0)
    drop = peak + (after - peak) * 0.5 * (1 - np.cos(np.pi * v))
    td = np.maximum(t - t_peak - t_rel, 0.0)
    osc = 60.0 * np.exp(-td / 0.35) * np.sin(2 * np.pi * 3.0 * td)
    w = np.clip((t - t_hold) / (t_down - t_hold), 0.0, 1.0)
    down = after + (base - after) * w
    truth = np.where(t < t_peak, rise, np.where(t < t_hold, drop + osc, down))
    ramp = np.clip((t - t_up) / (t_peak - t_up), 0.0, 1.0)
    request = np.where(
        t < t_peak, base + (peak + 20.0 - base) * ramp, np.where(t < t_hold, after, down)
    )
    rng = np.random.default_rng(seed)
    disturbance = noise * rng.standard_normal(n)
    for k, amp in enumerate(ripple, start=1):
        disturbance += amp * np.sin(
            2 * np.pi * k * electrical_frequency * t + rng.uniform(0, 2 * np.pi)
        )
    raw = truth + disturbance

    def idx(a: float, b: float) -> tuple[int, int]:
        return round(a * fs), round(b * fs)

    seg = Segmentation.from_ranges(
        n,
        steady=[
            idx(0.5 * c, t_up - 0.5 * c),
            idx(t_peak + 2.0 * c, t_hold - 0.5 * c),
            idx(t_down + 0.5 * c, dur - 0.5 * c),
        ],
        transient=[
            idx(t_up - 0.25 * c, t_peak + 1.5 * c),
            idx(t_hold - 0.25 * c, t_down + 0.25 * c),
        ],
    )
    return SyntheticTorque(t, raw, truth, request, seg, fs)
