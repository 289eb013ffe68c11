"""The result of a filter study: ranked rows, where the study was computed, what it could not score.

:func:`rank_filters` runs every candidate filter on the study signal, scores it
(:class:`rollerrig.signal.filter_score.Scorer`) and returns a :class:`StudyTable`: the
:class:`StudyRow` list, lowest cost first, with its :class:`StudyBasis` (rate, span and method)
and ``unscored`` (why a score is missing: None in :meth:`StudyRow.as_dict`, never NaN; which
filters cannot run on the signal).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.signal._numeric import finite_or_none
from rollerrig.signal.filter_candidates import filter_label
from rollerrig.signal.filter_score import FilterScore, Scorer
from rollerrig.signal.smoothing import METHODS, smooth

__all__ = ["COST_TIE", "StudyBasis", "StudyRow", "StudyTable", "rank_filters"]

COST_TIE = 1e-9
"""Costs closer than this, relative, are a tie [-], ranked in the order of the candidates.

Savitzky-Golay of orders 2k and 2k + 1 is one filter away from the ends, so where the ends are not
scored the two costs agree to about 1e-13 and only rounding (of the convolution, of a chunked
read) would decide which comes first; distinct filters differed by 2.6e-7 or more on the
seed-like torque (250 Hz to 2 kHz, three seeds, the tuning grid). With the tie rule the lower
order ranks first, and the same recording read whole or in chunks gives the same ranking.
"""


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
            "noise_left": finite_or_none(s.noise_left),
            "peak_kept": finite_or_none(s.peak_kept),
            "peak_time_error_s": finite_or_none(s.peak_time_error),
            "lag_s": finite_or_none(s.lag),
            "cost": s.cost,
        }


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

    def rank_of(self, cost: float) -> int:
        """The rank a filter of ``cost`` would take in this table, scored on the same signal with
        the same weights: one more than the rows cheaper by more than :data:`COST_TIE` (a tie
        shares the tied row's rank).

        Examples
        --------
        >>> from rollerrig.signal.scoring import seed_like_torque, filter_study
        >>> sig = seed_like_torque(duration=20.0)
        >>> rows = filter_study(sig.time, sig.raw, candidates=[("moving_average", {"window": 33})])
        >>> rows.rank_of(rows[0].score.cost), rows.rank_of(rows[0].score.cost + 1.0)
        (1, 2)
        """
        cost = float(cost)
        return 1 + sum(1 for r in self if r.score.cost < cost - COST_TIE * abs(cost))

    def unscored_notes(self) -> list[str]:
        """One sentence per entry of :attr:`unscored`, for consoles and reports."""
        return [
            why if key == "not_run" else f"{key} not scored: {why}"
            for key, why in self.unscored.items()
        ]


def _unscored(scorer: Scorer) -> dict[str, str]:
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


def rank_filters(
    scorer: Scorer, candidates: Iterable[tuple[str, Mapping]], basis: StudyBasis
) -> StudyTable:
    """Smooth the scorer's signal with every candidate, score each and rank them by cost.

    Parameters
    ----------
    scorer : Scorer
        The study signal, scaled, with its reference and segments.
    candidates : iterable of (str, mapping)
        ``(method, params)`` pairs, windows in samples at ``scorer.fs``.
    basis : StudyBasis
        Where the study is computed (rates, span, method); ``analysis_rate`` is ``scorer.fs``.

    Returns
    -------
    StudyTable
        Lowest cost first (ties within :data:`COST_TIE` in the order of ``candidates``).
        Candidates that cannot run on the signal (a window longer than the signal, a LOWESS of
        fewer than 5 samples) are left out and listed in ``unscored``.

    Raises
    ------
    ParameterError
        An unknown method, or no candidate that can run on the signal.
    """
    results = []
    not_run: list[str] = []
    candidates = list(candidates)
    if not candidates:
        raise ParameterError("candidates must hold at least one (method, params) pair")
    for item in candidates:
        if not (isinstance(item, tuple | list) and len(item) == 2 and isinstance(item[1], Mapping)):
            raise ParameterError(
                f"each candidate must be a (method, params) pair with params a mapping, e.g. "
                f"('moving_average', {{'window': 33}}), got {item!r}"
            )
        method, params = item
        if method not in METHODS:
            raise ParameterError(f"unknown method {method!r}; known: {sorted(METHODS)}")
        try:
            y = smooth(scorer.raw, method, sample_rate=scorer.fs, **params)
        except ParameterError as exc:
            # The seed's windows scale with the rate: on a slow or short recording some
            # filters do not exist (a LOWESS of 5 samples, a window longer than the signal).
            # They are left out and listed; the others are still ranked.
            not_run.append(f"{filter_label(method, params)} ({exc})")
            continue
        results.append((len(results), method, dict(params), scorer.score_scaled(y)))
    if not results:
        raise ParameterError(
            f"no filter of the study can run on this signal ({scorer.raw.size} samples at "
            f"{scorer.fs:.6g} Hz): {'; '.join(not_run[:3])}"
            f"{' ...' if len(not_run) > 3 else ''}; a filter the signal is too short or too "
            "slow for needs a longer recording (several seconds) at a rate of at least about "
            "50 Hz"
        )
    rate = basis.analysis_rate
    rows = [
        StudyRow(i + 1, m, p, filter_label(m, p), s, rate)
        for i, (_, m, p, s) in enumerate(_by_cost(results))
    ]
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
    return StudyTable(rows, basis, why)


def _by_cost(results: list[tuple]) -> list[tuple]:
    """``(index, method, params, score)`` by cost; a run of ties (:data:`COST_TIE`) by index."""
    out: list[tuple] = []
    run: list[tuple] = []
    for r in sorted(results, key=lambda r: r[3].cost):
        if run and r[3].cost - run[0][3].cost > COST_TIE * abs(run[0][3].cost):
            out += sorted(run, key=lambda r: r[0])
            run = []
        run.append(r)
    return out + sorted(run, key=lambda r: r[0])
