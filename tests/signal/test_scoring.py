"""Filter scores against constructed truths, and the seed's verdict (Kayaalp, 4.5.2.5-4.5.2.6)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from rollerrig._validation import ParameterError
from rollerrig.signal.scoring import (
    ScoreWeights,
    Segmentation,
    default_candidates,
    filter_study,
    prepare_study_signal,
    score_smoothing,
    seed_like_torque,
    steady_and_transient_masks,
    study_signal_from_chunks,
    study_signal_from_source,
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


# --- long and fast recordings: the study at its analysis rate ------------------------------
def test_fast_recording_is_studied_at_250_Hz_and_says_so():
    # 19.2 kHz (HBM QuantumX): the study runs on the signal decimated to the seed's 250 Hz,
    # where its windows were designed; the basis states rate, span and filter.
    sig = seed_like_torque(sample_rate=19200.0, duration=20.0)
    rows = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation)
    b = rows.basis
    assert (b.source_rate, b.analysis_rate, b.samples) == (19200.0, 250.0, 5000)
    assert b.start == 0.0 and abs(b.end - 19.996) < 1e-9
    assert "decimated from 19200 Hz to 250 Hz" in b.note() and "over 0.000-19.996 s" in b.note()
    assert b.as_dict()["analysis_rate_Hz"] == 250.0
    d = rows[0].as_dict()
    assert d["sample_rate_Hz"] == 250.0
    assert {p["window"] for m, p in default_candidates(250.0) if "window" in p} >= {
        r.params["window"] for r in rows if "window" in r.params
    }
    # the seed's verdict holds at 19.2 kHz (Kayaalp 4.5.2.5-4.5.2.6)
    kept = {(r.method, r.params.get("order"), r.params.get("window")): r.score for r in rows}
    assert abs(1 - kept[("savitzky_golay", 4, 111)].peak_kept) <= 0.04
    assert kept[("butterworth", 2, None)].peak_kept <= 0.94


def test_tuned_window_is_returned_at_the_recordings_rate():
    sig = seed_like_torque(sample_rate=2000.0, duration=20.0)
    order, window, table = tune_savitzky_golay(sig.time, sig.raw, None, sig.segmentation)
    best = table[0].params
    assert table.basis.analysis_rate == 250.0 and order == best["order"]
    assert window == (best["window"] - 1) * 8 + 1  # the same span in seconds at 2 kHz


def test_decimated_study_scores_the_smoothed_signal_like_the_full_rate_study():
    # The candidates keep nothing above a few hertz, so smoothing before or after the
    # anti-alias decimation gives the same kept peaks and lags; windows scale with the rate.
    sig = seed_like_torque(sample_rate=2000.0, duration=20.0, seed=1)
    cands = [("savitzky_golay", {"window": 111, "order": 4}), ("loess", {"window": 65}),
             ("butterworth", {"cutoff": 1.2, "order": 2, "zero_phase": False})]  # fmt: skip
    dec = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation, cands)
    full_cands = [(m, {**p, "window": 8 * (p["window"] - 1) + 1} if "window" in p else p)
                  for m, p in cands]  # same span in seconds at 2 kHz  # fmt: skip
    full = filter_study(sig.time, sig.raw, sig.truth, sig.segmentation, full_cands,
                        analysis_rate=None)  # fmt: skip
    assert full.basis.analysis_rate == 2000.0 and full.basis.decimation is None
    a = {r.method: r.score for r in dec}
    b = {r.method: r.score for r in full}
    for m in a:
        assert abs(a[m].peak_kept - b[m].peak_kept) < 0.01, m
        assert abs(a[m].lag - b[m].lag) < 2e-3, m
        # the raw noise is measured at the full rate, so noise_left keeps its meaning
        assert abs(a[m].noise_left / b[m].noise_left - 1) < 0.1, m


def test_study_signal_from_chunks_equals_the_array_path_and_honours_the_span():
    fs = 2000.0
    sig = seed_like_torque(sample_rate=fs, duration=20.0)
    t0 = 100.0
    chunks = (sig.raw[i : i + 3333] for i in range(0, sig.raw.size, 3333))
    streamed = study_signal_from_chunks(chunks, fs, start_time=t0, span=(102.0, 117.5))
    whole = prepare_study_signal(t0 + sig.time, sig.raw, span=(102.0, 117.5))
    assert streamed.basis == whole.basis
    assert (streamed.basis.start, streamed.basis.end) == (102.0, 117.5)
    assert_allclose(streamed.time, whole.time, rtol=0, atol=1e-9)
    assert_allclose(streamed.raw, whole.raw, rtol=0, atol=1e-10 * np.ptp(sig.raw))
    assert_allclose(streamed.raw_noise_rms, whole.raw_noise_rms, rtol=1e-9)
    # same rows either way
    assert [r.label for r in streamed.filter_study()] == [r.label for r in whole.filter_study()]


def test_masks_given_at_the_source_rate_follow_the_decimation():
    sig = seed_like_torque(sample_rate=2000.0, duration=20.0)
    s = prepare_study_signal(sig.time, sig.raw, masks=sig.segmentation)
    ref = seed_like_torque(sample_rate=250.0, duration=20.0).segmentation
    # the boundaries move by at most one analysis sample
    assert np.sum(s.masks.steady != ref.steady) <= 2 * len(ref.steady_segments())
    assert np.sum(s.masks.transient != ref.transient) <= 2 * len(ref.transient_segments())


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


def test_analysis_rate_choices_and_errors():
    sig = seed_like_torque(sample_rate=2000.0, duration=4.0)
    assert prepare_study_signal(sig.time, sig.raw, analysis_rate=None).basis.analysis_rate == 2000
    assert prepare_study_signal(sig.time, sig.raw, analysis_rate=1000.0).raw.size == 4000
    assert prepare_study_signal(sig.time, sig.raw, analysis_rate=5000.0).basis.decimation is None
    slow = seed_like_torque(sample_rate=400.0, duration=4.0)
    assert prepare_study_signal(slow.time, slow.raw).basis.analysis_rate == 400.0
    with pytest.raises(ParameterError, match="analysis_rate"):
        prepare_study_signal(sig.time, sig.raw, analysis_rate="fast")
    with pytest.raises(ParameterError, match="span"):
        prepare_study_signal(sig.time, sig.raw, span=(10.0, 12.0))
    with pytest.raises(ParameterError, match="holds 0 samples"):
        study_signal_from_chunks([sig.raw], 2000.0, span=(50.0, 60.0))


@settings(max_examples=40, deadline=None)
@given(bits=st.lists(st.booleans(), min_size=1, max_size=300), reach=st.integers(0, 40))
def test_mask_widening_equals_binary_dilation(bits, reach):
    # the O(n) cumulative-sum widening used by steady_and_transient_masks is scipy's binary
    # dilation by 2·reach + 1 ones (border False), which needs O(n·reach) time and memory
    from scipy.ndimage import binary_dilation

    from rollerrig.signal.scoring import _dilate

    mask = np.array(bits)
    ref = binary_dilation(mask, np.ones(2 * reach + 1, bool)) if reach else mask
    assert np.array_equal(_dilate(mask, reach), ref)


def test_study_of_an_open_source_reads_the_span_in_chunks(tmp_path):
    # open_recording (measure/source.py) gives the channel chunk by chunk; the study signal is
    # the one of the same samples in memory
    from rollerrig.measure.recording import Recording
    from rollerrig.measure.source import open_recording
    from rollerrig.measure.writers import write_recording

    fs = 2000.0
    sig = seed_like_torque(sample_rate=fs, duration=20.0)
    rec = Recording(5.0 + sig.time, {"torque": sig.raw}, {"torque": "N.m"})
    path = write_recording(rec, tmp_path / "run.parquet")
    with open_recording(path) as src:
        got = study_signal_from_source(src, "torque", span=(7.0, 22.0), chunk_samples=5000)
    ref = prepare_study_signal(rec.time, rec["torque"], span=(7.0, 22.0))
    assert got.basis == ref.basis
    assert_allclose(got.raw, ref.raw, rtol=0, atol=1e-10 * np.ptp(sig.raw))
    assert_allclose(got.raw_noise_rms, ref.raw_noise_rms, rtol=1e-9)


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
