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
    "savitzky_golay_standing",
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


SAVITZKY_GOLAY_BASIS = (
    "analyze smooths the torque and both speeds with a Savitzky-Golay filter, the seed's method "
    "(Kayaalp, tuned there by eye to order 4-5, window 111 at 250 Hz), so only its order "
    "and window are tuned, on the ranking's cost, over a finer grid than the ranking's; the "
    "ranking compares every filter family at the seed's windows and does not choose the "
    "analysis's filter"
)
"""Why the analysis smooths with the tuned Savitzky-Golay filter, not the ranking's best."""


def savitzky_golay_standing(grid: StudyTable, ranking: StudyTable) -> dict:
    """Where the tuned Savitzky-Golay filter (``grid[0]``) would stand in a filter study's ranking.

    Both tables score on one study signal with one cost (:meth:`StudySignal.filter_study` and
    :meth:`StudySignal.tune_savitzky_golay` of the same signal, default weights), so the tuned
    filter's cost places it among the ranked filters (:meth:`StudyTable.rank_of`). Tables of
    different bases (rate or span) are not comparable: ``would_rank`` is then None.

    Parameters
    ----------
    grid : StudyTable
        The tuning table of :func:`tune_savitzky_golay` (ranked, the tuned filter first).
    ranking : StudyTable
        The ranked study of :func:`filter_study` on the same signal.

    Returns
    -------
    dict
        ``label``, ``order``, ``window [samples at analysis rate]``, ``cost``, ``would_rank``
        (None where not comparable), ``of`` (rows ranked), ``best_in_ranking``, ``best_cost``,
        ``basis`` (:data:`SAVITZKY_GOLAY_BASIS`) and ``note`` (one sentence for outputs).

    Examples
    --------
    >>> torque = seed_like_torque(duration=20.0)
    >>> sig = prepare_study_signal(torque.time, torque.raw)
    >>> grid = sig.tune_savitzky_golay(orders=[2], windows=[111])[2]
    >>> ranking = sig.filter_study([("moving_average", {"window": 33}),
    ...                             ("savitzky_golay", {"order": 2, "window": 111})])
    >>> standing = savitzky_golay_standing(grid, ranking)
    >>> standing["would_rank"] == [r.label for r in ranking].index("SG order 2 w111") + 1
    True
    """
    best = grid[0]
    top = ranking[0]
    comparable = grid.basis is None or ranking.basis is None or grid.basis == ranking.basis
    rank = ranking.rank_of(best.score.cost) if comparable else None
    if rank is None:
        where = "not comparable with the ranking (another rate or span)"
    elif rank == 1:
        where = f"it would rank 1 of {len(ranking)} above"
    else:
        where = (
            f"it would rank {rank} of {len(ranking)} above, behind {top.label} "
            f"(cost {top.score.cost:.3f})"
        )
    return {
        "label": best.label,
        "order": best.params["order"],
        "window [samples at analysis rate]": best.params["window"],
        "cost": float(best.score.cost),
        "would_rank": rank,
        "of": len(ranking),
        "best_in_ranking": top.label,
        "best_cost": float(top.score.cost),
        "basis": SAVITZKY_GOLAY_BASIS,
        "note": f"the tuned {best.label} costs {best.score.cost:.3f}: {where}; "
        + SAVITZKY_GOLAY_BASIS,
    }
