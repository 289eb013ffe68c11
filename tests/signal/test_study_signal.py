"""The study signal of long and fast recordings: the study at its analysis rate."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from rollerrig._validation import ParameterError
from rollerrig.signal.filter_candidates import default_candidates
from rollerrig.signal.scoring import filter_study, tune_savitzky_golay
from rollerrig.signal.study_signal import (
    prepare_study_signal,
    study_signal_from_chunks,
    study_signal_from_source,
)
from rollerrig.signal.synthetic_torque import seed_like_torque


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


def test_study_of_an_open_source_reads_the_span_in_chunks(tmp_path):
    # open_recording (measure/source.py) gives the channel chunk by chunk; the study signal is
    # the one of the same samples in memory
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.source import open_recording
    from rollerrig.recordings.writers import write_recording

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
