"""The study's table: ties, scores a signal cannot give, filters that cannot run on it."""

from __future__ import annotations

import re

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.signal.filter_candidates import default_candidates
from rollerrig.signal.scoring import filter_study, tune_savitzky_golay
from rollerrig.signal.study_table import COST_TIE
from rollerrig.signal.synthetic_torque import seed_like_torque

FS = 250.0


def test_scores_a_signal_cannot_give_are_none_with_the_reason():
    # a constant torque (no test in it): nothing to score but the cost; the row dicts carry
    # None, never NaN, and the table says why
    t = np.arange(5000) / FS
    rows = filter_study(t, np.full(t.size, 150.0), candidates=[("moving_average", {"window": 33})])
    d = rows[0].as_dict()
    assert d["noise_left"] is None and d["peak_kept"] is None and d["lag_s"] is None
    assert np.isfinite(d["cost"])
    assert set(rows.unscored) == {"noise_left", "peak_kept", "peak_time_error_s", "lag_s"}
    assert "no noise" in rows.unscored["noise_left"]
    assert "no transient" in rows.unscored["lag_s"]
    sig = seed_like_torque(duration=20.0)
    full = filter_study(sig.time, sig.raw, candidates=[("moving_average", {"window": 33})])
    assert full.unscored == {}
    assert None not in full[0].as_dict().values()


def test_slow_recording_ranks_the_filters_that_exist_and_lists_the_others():
    # A 10 Hz export of a ramp-hold-release test: the seed's windows (samples at 250 Hz) shrink
    # below what LOWESS/LOESS accept; those are listed as not run, the rest is still ranked.
    t = np.arange(301) / 10.0
    x = np.interp(t, [0, 5, 10, 10.1, 30], [0, 0, 500, 0, 0])
    x = x + np.random.default_rng(3).normal(0.0, 2.0, t.size)
    table = filter_study(t, x)
    assert 0 < len(table) < len(default_candidates(10.0))
    assert "cannot run on this signal" in table.unscored["not_run"]
    assert "LOESS w5" in table.unscored["not_run"]
    order, window, _ = tune_savitzky_golay(t, x)
    assert 2 <= order < window


def test_a_signal_no_filter_can_run_on_is_one_clear_error():
    t = np.arange(4) / 10.0
    with pytest.raises(ParameterError, match="no filter of the study can run on this signal"):
        filter_study(t, np.array([0.0, 1.0, 0.0, 1.0]), candidates=[("lowess", {"window": 5})])


def test_equal_filters_rank_in_the_order_of_the_candidates():
    # Savitzky-Golay of orders 2 and 3 is one filter away from the ends (Savitzky & Golay 1964:
    # the odd term adds nothing at the window centre); the segments leave the ends out, so the
    # costs agree to rounding and the candidates' order decides, not the rounding.
    sig = seed_like_torque(seed=3)
    pair = [("savitzky_golay", {"window": 33, "order": p}) for p in (2, 3)]
    for cands in (pair, pair[::-1]):
        rows = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation, cands)
        assert abs(rows[0].score.cost - rows[1].score.cost) <= COST_TIE * rows[0].score.cost
        assert [r.params["order"] for r in rows] == [p["order"] for _, p in cands]


@pytest.mark.parametrize(
    ("candidates", "message"),
    [
        ([], "candidates must hold at least one (method, params) pair"),
        (["moving_average"], "each candidate must be a (method, params) pair"),
        ([("moving_average", 33)], "each candidate must be a (method, params) pair"),
        # A misspelt parameter had raised a bare KeyError from the candidate's label.
        ([("moving_average", {"windw": 33})],
         "MA w? (method 'moving_average' takes parameters ['window'], got ['windw'])"),
    ],
)  # fmt: skip
def test_a_study_names_what_is_wrong_with_its_candidates(candidates, message):
    t = np.arange(2500) / FS
    with pytest.raises(ParameterError, match=re.escape(message)):
        filter_study(t, np.sin(t), candidates=candidates)


def test_masks_of_the_wrong_kind_are_named():
    t = np.arange(2500) / FS
    with pytest.raises(ParameterError, match=r"masks must be a Segmentation, a .* got str"):
        filter_study(t, np.sin(t), masks="steady", candidates=[("moving_average", {"window": 5})])


def test_the_tuned_savitzky_golay_is_placed_in_the_ranking_on_the_same_cost():
    # The filters command had said "Savitzky-Golay tuned for this recording: order 2, window
    # 171" below a ranking whose best was rLOWESS and which never listed window 171: the tuned
    # filter's cost now places it in the ranking, and the basis of the choice is said.
    from rollerrig.signal.scoring import prepare_study_signal, savitzky_golay_standing

    sig = seed_like_torque(duration=20.0)
    study = prepare_study_signal(sig.time, sig.raw)
    _, _, grid = study.tune_savitzky_golay(orders=[2, 4], windows=[33, 171])
    ranking = study.filter_study(
        [("moving_average", {"window": 131}), ("savitzky_golay", {"order": 2, "window": 33}),
         ("savitzky_golay", {"order": 4, "window": 171}),
         ("savitzky_golay", {"order": 2, "window": 171})]
    )  # fmt: skip
    standing = savitzky_golay_standing(grid, ranking)
    # the tuned filter is one of the ranked ones here: its rank is its own
    own = next(r for r in ranking if r.label == grid[0].label)
    assert standing["would_rank"] == own.rank and standing["of"] == 4
    assert standing["cost"] == pytest.approx(own.score.cost)
    assert ranking.rank_of(ranking[-1].score.cost + 1.0) == 5
    assert "seed's method" in standing["basis"] and "does not choose" in standing["basis"]
    assert standing["note"].startswith(f"the tuned {grid[0].label} costs ")
    # a table on another span is not comparable
    other = prepare_study_signal(sig.time, sig.raw, span=(0.0, 15.0))
    assert savitzky_golay_standing(grid, other.filter_study())["would_rank"] is None
