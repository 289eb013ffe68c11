"""The filter study: score a grid of smoothing filters on one recording and tune Savitzky-Golay.

The source dissertation (Kayaalp, sections 4.5.2.5-4.5.2.6) judges smoothing filters on the
roller-shaft torque by eye; :func:`filter_study` turns its criteria into numbers and ranks the
seed's filter grid by cost, and :func:`tune_savitzky_golay` searches the Savitzky-Golay order and
window the seed tuned by hand. The parts live in modules by concern:

* :mod:`rollerrig.signal.filter_score` -- the scores (``noise_left``, ``peak_kept``,
  ``peak_time_error``, ``lag``, ``cost``), their weights, :func:`score_smoothing`;
* :mod:`rollerrig.signal.steady_transient` -- the steady and transient parts the scores use;
* :mod:`rollerrig.signal.filter_candidates` -- the seed's filter grid and the tuning grid;
* :mod:`rollerrig.signal.study_signal` -- the signal a study scores, at 250 Hz for recordings
  faster than 500 Hz, from arrays, chunks or an open recording;
* :mod:`rollerrig.signal.study_table` -- the ranked result with its basis and unscored notes;
* :mod:`rollerrig.signal.synthetic_torque` -- a seed-like torque with known truth.

Their public names are importable from here as well.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from rollerrig.signal.filter_candidates import SEED_SAMPLE_RATE, default_candidates
from rollerrig.signal.filter_score import FilterScore, ScoreWeights, score_smoothing
from rollerrig.signal.steady_transient import Segmentation, steady_and_transient_masks
from rollerrig.signal.study_signal import (
    ANALYSIS_RATE_LIMIT,
    StudySignal,
    prepare_study_signal,
    study_signal_from_chunks,
    study_signal_from_source,
)
from rollerrig.signal.study_table import StudyBasis, StudyRow, StudyTable
from rollerrig.signal.synthetic_torque import SyntheticTorque, seed_like_torque

__all__ = [
    "ANALYSIS_RATE_LIMIT",
    "SEED_SAMPLE_RATE",
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
    time, raw, truth, masks, weights, analysis_rate, span
        As in :func:`filter_study` (times [s], signals [N·m], masks at the rate of ``time``).
    orders : iterable of int
        Polynomial orders to try.
    windows : iterable of int, optional
        Odd windows [samples at the analysis rate]; default 11, 21, ..., 201 at 250 Hz, scaled
        to the analysis rate (0.04-0.8 s).

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
