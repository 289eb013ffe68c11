"""The filter study, Savitzky-Golay tuning and the seed's verdict (Kayaalp, 4.5.2.5-4.5.2.6)."""

from __future__ import annotations

from itertools import pairwise

import pytest
from numpy.testing import assert_allclose

from rollerrig.signal.filter_candidates import default_candidates
from rollerrig.signal.filter_score import ScoreWeights
from rollerrig.signal.scoring import filter_study, tune_savitzky_golay
from rollerrig.signal.study_table import COST_TIE
from rollerrig.signal.synthetic_torque import seed_like_torque


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("with_truth", [True, False])
def test_seed_verdict_savitzky_golay_keeps_peaks_butterworth_does_not(seed, with_truth):
    # Kayaalp 4.5.2.5: Butterworth 2-3 at 1.2 Hz "did not catch the spikes"; 4.5.2.6: SG order
    # 4-5, window 111 keeps them. Measured on this signal (seeds 0-3): SG 4/5 w111 keeps
    # 0.97-0.99 (truth-free reference) / 1.02-1.03 (truth) of the peak excursion; Butterworth
    # 2-3 @ 1.2 Hz keeps 0.83-0.88 / 0.87-0.93 (zero-phase or causal).
    sig = seed_like_torque(seed=seed)
    truth = sig.truth if with_truth else None
    candidates = [("savitzky_golay", {"window": 111, "order": p}) for p in (4, 5)] + [
        ("butterworth", {"cutoff": 1.2, "order": o, "zero_phase": z})
        for o in (2, 3)
        for z in (True, False)
    ]
    rows = filter_study(sig.time, sig.raw, truth, sig.segmentation, candidates)
    kept = {(r.method, r.params.get("order"), r.params.get("zero_phase")): r.score for r in rows}
    for p in (4, 5):
        assert abs(1 - kept[("savitzky_golay", p, None)].peak_kept) <= 0.04
    for o in (2, 3):
        for z in (True, False):
            assert kept[("butterworth", o, z)].peak_kept <= (0.94 if with_truth else 0.90)
    worst_sg = max(abs(1 - kept[("savitzky_golay", p, None)].peak_kept) for p in (4, 5))
    best_bw = min(abs(1 - s.peak_kept) for k, s in kept.items() if k[0] == "butterworth")
    assert worst_sg < best_bw
    # the causal ones are also late by about their DC group delay (0.19 s, 0.27 s)
    assert kept[("butterworth", 2, False)].lag > 0.15
    assert kept[("butterworth", 3, False)].lag > 0.22


def test_filter_study_covers_the_seed_grid_and_ranks_by_cost():
    sig = seed_like_torque()
    cands = default_candidates(sig.sample_rate)
    methods = {m for m, _ in cands}
    assert methods == {"butterworth", "moving_average", "gaussian", "lowess", "loess",
                       "rlowess", "rloess", "savitzky_golay"}  # fmt: skip
    assert ("loess", {"window": 131}) in cands
    assert {(p["order"], p["window"]) for m, p in cands if m == "savitzky_golay"} >= {
        (o, 111) for o in range(2, 8)
    }
    rows = filter_study(sig.time, sig.raw, None, sig.segmentation)
    assert len(rows) == len(cands)
    costs = [r.score.cost for r in rows]
    # by cost; ties (equal to COST_TIE, e.g. SG orders 2 and 3) in the grid's order
    assert all(b - a >= -COST_TIE * a for a, b in pairwise(costs))
    assert [r.rank for r in rows] == list(range(1, len(rows) + 1))
    # no Butterworth at 1.2 Hz among the better half (the seed rejects them)
    assert all(r.method != "butterworth" for r in rows[: len(rows) // 2])
    assert rows[0].as_dict()["rank"] == 1


def test_tune_savitzky_golay_returns_the_table_minimum():
    sig = seed_like_torque()
    order, window, table = tune_savitzky_golay(sig.time, sig.raw, None, sig.segmentation)
    assert (order, window) == (table[0].params["order"], table[0].params["window"])
    assert table[0].score.cost == min(r.score.cost for r in table)
    assert len(table) == 6 * 20
    assert 2 <= order <= 7


def test_weights_change_the_ranking_as_documented():
    sig = seed_like_torque()
    noise_only = ScoreWeights(noise=1.0, peak=0.0, timing=0.0)
    rows = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation, weights=noise_only)
    for r in rows:
        assert_allclose(r.score.cost, r.score.noise_left)


@pytest.mark.parametrize("scale", [1e300, 1e-300, -3.0])
def test_scores_are_invariant_to_the_signal_scale_even_near_the_float_limits(scale):
    # every score is a ratio or a time; a torque in the wrong unit by 1e300 still gets a study
    sig = seed_like_torque(duration=20.0)
    cands = [("savitzky_golay", {"window": 111, "order": 4}), ("rloess", {"window": 33}),
             ("butterworth", {"cutoff": 1.2, "order": 2})]  # fmt: skip
    ref = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation, cands)
    got = filter_study(sig.time, scale * sig.raw, scale * sig.truth, sig.segmentation, cands)
    for a, b in zip(ref, got, strict=True):
        assert a.label == b.label
        for name in ("noise_left", "peak_kept", "lag"):
            assert_allclose(getattr(b.score, name), getattr(a.score, name), rtol=1e-9)
