"""Filter scores against constructed truths, and the seed's verdict (Kayaalp, 4.5.2.5-4.5.2.6)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from rollerrig.signal.scoring import (
    ScoreWeights,
    Segmentation,
    default_candidates,
    filter_study,
    score_smoothing,
    seed_like_torque,
    steady_and_transient_masks,
    tune_savitzky_golay,
)
from rollerrig.signal.smoothing import smooth

FS = 250.0


def _pulse_record(n=3000):
    t = np.arange(n) / FS
    x = 50.0 + 100.0 * np.exp(-0.5 * ((t - 6.0) / 0.15) ** 2)
    seg = Segmentation.from_ranges(n, steady=[(0, 1000), (2000, n)], transient=[(1300, 1700)])
    return t, x, seg


@settings(max_examples=25, deadline=None)
@given(d=st.integers(-40, 40), use_truth=st.booleans())
def test_pure_delay_of_d_samples_is_lag_d_over_fs(d, use_truth):
    t, x, seg = _pulse_record()
    delayed = np.roll(x, d)
    s = score_smoothing(t, x, delayed, truth=x if use_truth else None, masks=seg)
    assert abs(s.lag - d / FS) < 0.05 / FS
    if use_truth:
        assert abs(s.peak_time_error - d / FS) < 1e-12
        assert_allclose(s.peak_kept, 1.0)


def test_identity_and_constant_smoothers_bound_the_noise_score():
    sig = seed_like_torque()
    same = score_smoothing(sig.time, sig.raw, sig.raw, sig.truth, sig.segmentation)
    exact = score_smoothing(sig.time, sig.raw, sig.truth, sig.truth, sig.segmentation)
    assert_allclose(same.noise_left, 1.0)
    assert exact.noise_left == 0.0 and exact.peak_kept == 1.0 and abs(exact.lag) < 1e-3
    assert exact.cost < 1e-2


def test_causal_butterworth_lag_on_a_ramp_is_its_dc_group_delay():
    # A ramp through a unity-gain low-pass comes out shifted by τ(0) = 1/(Ω_c sin(π/2n))
    # (see test_smoothing); the least-squares lag of the scores must report it.
    n = int(60 * FS)
    t = np.arange(n) / FS
    x = np.clip(t - 10.0, 0.0, 40.0)
    seg = Segmentation.from_ranges(
        n, steady=[(0, int(9 * FS))], transient=[(int(20 * FS), int(45 * FS))]
    )
    for order in (1, 2, 3):
        omega_c = 2 * FS * np.tan(np.pi * 1.2 / FS)
        tau0 = 1.0 / (omega_c * np.sin(np.pi / (2 * order)))
        y = smooth(x, "butterworth", sample_rate=FS, cutoff=1.2, order=order, zero_phase=False)
        s = score_smoothing(t, x, y, truth=x, masks=seg, max_lag=1.0)
        assert_allclose(s.lag, tau0, rtol=2e-3)


def test_masks_from_torque_request_and_from_raw_find_the_transients():
    sig = seed_like_torque()
    for source in (sig.torque_request, sig.raw):
        seg = steady_and_transient_masks(source, sig.sample_rate)
        t = sig.time
        # ramp, peak and release (4-10 s) and the ramp down (14-16 s) are transient
        for when in (5.0, 9.9, 10.05, 15.0):
            assert seg.transient[np.searchsorted(t, when)], when
        # the middle of each steady part is steady
        for when in (2.0, 12.5, 18.0):
            assert seg.steady[np.searchsorted(t, when)], when
        assert not np.any(seg.steady & seg.transient)


def test_masks_as_index_ranges_equal_boolean_masks():
    sig = seed_like_torque()
    seg = sig.segmentation
    y = smooth(sig.raw, "savitzky_golay", window=111, order=4)
    ranges = {"steady": seg.steady_segments(), "transient": seg.transient_segments()}
    a = score_smoothing(sig.time, sig.raw, y, sig.truth, ranges)
    b = score_smoothing(sig.time, sig.raw, y, sig.truth, (seg.steady, seg.transient))
    assert a == b


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
    assert costs == sorted(costs)
    assert [r.rank for r in rows] == list(range(1, len(rows) + 1))
    # no Butterworth at 1.2 Hz among the better half (the seed rejects them)
    assert all(r.method != "butterworth" for r in rows[: len(rows) // 2])
    assert rows[0].as_dict()["rank"] == 1


def test_default_windows_scale_with_the_sample_rate():
    w250 = [p["window"] for m, p in default_candidates(250.0) if m == "savitzky_golay"]
    w500 = [p["window"] for m, p in default_candidates(500.0) if m == "savitzky_golay"]
    assert 111 in w250 and 223 in w500


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
