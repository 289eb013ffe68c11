"""How well a smoothing filter did on one signal: the scores, their weights and the scorer.

The source dissertation (Kayaalp, sections 4.5.2.5-4.5.2.6) judges smoothing filters on the
roller-shaft torque by eye: how much of the induction-motor ripple (electrical frequency
= 5 × roller rotation frequency, 14.7 Hz at 30 km/h, plus harmonics) and noise is left in the
steady parts, and whether the transient parts (ramp up, peak, release within 20 ms, oscillation
afterwards) keep their peaks without delay. Its verdict: Butterworth 1-3 at 1.2 Hz delays and
flattens the peaks; Savitzky-Golay of order 4-5 with a 111-sample window is best at 250 Hz.

This module turns those criteria into numbers:

``noise_left`` [-]
    RMS of what the filter leaves in the steady parts, relative to the raw signal's: with a truth,
    ``rms(s − truth) / rms(raw − truth)``; without, the deviation from a slow trend (1 s moving
    average of the raw signal), ``rms(s − trend) / rms(raw − trend)``.
``peak_kept`` [-]
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
``cost`` [-]
    ``w_noise·noise_left + w_peak·|1 − peak_kept| + w_timing·(|lag| + |peak_time_error|)/τ``,
    defaults ``w = 1, 2, 1`` and ``τ = 0.5 s``: 10 % of the steady noise left, 5 % of the peak
    lost and 50 ms of delay or peak-time error cost the same (0.1). The seed's verdict rests on
    steady noise and kept peaks first; 50 ms is a small fraction of the seconds-long ramps over
    which creep and adhesion are read, but ten times the 20 ms release. Lower is better.

:func:`score_smoothing` scores one smoothed signal; :class:`Scorer` precomputes what does not
depend on the filter, so that the filter study (:mod:`rollerrig.signal.scoring`) scores each
candidate in one call.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal as sps
from scipy.ndimage import median_filter

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.signal._numeric import odd, power_of_two_scale, uniform_sample_rate
from rollerrig.signal.smoothing import moving_average
from rollerrig.signal.steady_transient import Segmentation, as_segmentation

__all__ = ["FilterScore", "ScoreWeights", "Scorer", "score_smoothing"]


def check_record(time, raw, truth=None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """``time``, ``raw`` and ``truth`` as finite 1-D float arrays of one length.

    Raises
    ------
    ParameterError
        A non-finite value, or arrays of other shapes.
    """
    time = require_finite("time", time)
    raw = require_finite("raw", raw)
    n = raw.size
    if time.shape != (n,) or raw.ndim != 1:
        raise ParameterError("time and raw must be 1-D arrays of the same length")
    if truth is not None:
        truth = require_finite("truth", truth)
        if truth.shape != (n,):
            raise ParameterError("truth must have the length of raw")
    return time, raw, truth


def unit_scale(*arrays) -> float:
    """A power of two ``s`` with ``max |s·x|`` in [0.5, 1) (1 for all-zero input) [1/unit]."""
    peak = max((float(np.max(np.abs(a))) for a in arrays if a is not None and a.size), default=0)
    return power_of_two_scale(peak)


@dataclass(frozen=True)
class ScoreWeights:
    """Weights of the combined cost (see the module docstring).

    Attributes
    ----------
    noise : float
        Weight of ``noise_left`` [-].
    peak : float
        Weight of ``|1 − peak_kept|`` [-].
    timing : float
        Weight of ``(|lag| + |peak_time_error|) / time_scale`` [-].
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
        Steady-part noise left [-] (0 = none, 1 = as raw).
    peak_kept : float
        Transient peak excursion kept [-] (1 = exact), worst segment.
    peak_time_error : float
        Peak timing error [s], worst segment.
    lag : float
        Delay on the transients [s], positive = late.
    cost : float
        Combined cost [-], lower is better.
    """

    noise_left: float
    peak_kept: float
    peak_time_error: float
    lag: float
    cost: float


class Scorer:
    """Precomputes everything that does not depend on the smoothed signal.

    Arguments as in :func:`score_smoothing`; ``raw_noise_rms`` [unit of ``raw``], when given,
    is the raw signal's noise measured at a higher rate (the ``noise_left`` denominator of a
    decimated study, :class:`rollerrig.signal.study_signal.StudySignal`).
    """

    seg: Segmentation

    def __init__(self, time, raw, truth, masks, weights, max_lag, base_time, raw_noise_rms=None):
        self.time, raw, truth = check_record(time, raw, truth)
        n = raw.size
        # Every score is a ratio or a time: scale the signals into [-1, 1] by a power of two
        # (exact in floating point) so that squares and filters cannot overflow or underflow.
        self.scale = unit_scale(raw, truth)
        self.raw = raw * self.scale
        self.fs = uniform_sample_rate(self.time)
        self.weights = weights or ScoreWeights()
        self.seg = as_segmentation(masks, n, self.raw, self.fs)
        self.steady = self.seg.steady
        if truth is not None:
            self.truth = truth * self.scale
            self.noise_ref = self.truth
            self.ref = self.truth
        else:
            self.truth = None
            self.noise_ref = moving_average(self.raw, odd(1.0 * self.fs))
            self.ref = median_filter(self.raw, size=odd(0.02 * self.fs), mode="nearest")
        if raw_noise_rms is None:
            self.raw_noise = self._rms(self.raw - self.noise_ref)
        else:  # the raw signal's noise measured at its full rate, per analysis sample
            self.raw_noise = self._rms(np.asarray(raw_noise_rms, float) * self.scale)
        self.segments = self.seg.transient_segments()
        # At least a sample each way: a lag searched over none was NaN.
        self.max_lag = max(
            round(require_positive("max_lag", max_lag, "s", single=True) * self.fs), 1
        )
        nb = max(round(require_positive("base_time", base_time, "s", single=True) * self.fs), 1)
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
        s = require_finite("smoothed", smoothed)
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
    scorer = Scorer(time, raw, truth, masks, weights, max_lag, base_time)
    return scorer.score(smoothed)
