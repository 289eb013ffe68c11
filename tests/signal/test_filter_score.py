"""Filter scores against constructed truths: delays, identity, the Butterworth group delay."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from rollerrig.signal.filter_score import score_smoothing
from rollerrig.signal.smoothing import smooth
from rollerrig.signal.steady_transient import Segmentation
from rollerrig.signal.synthetic_torque import seed_like_torque

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


def test_masks_as_index_ranges_equal_boolean_masks():
    sig = seed_like_torque()
    seg = sig.segmentation
    y = smooth(sig.raw, "savitzky_golay", window=111, order=4)
    ranges = {"steady": seg.steady_segments(), "transient": seg.transient_segments()}
    a = score_smoothing(sig.time, sig.raw, y, sig.truth, ranges)
    b = score_smoothing(sig.time, sig.raw, y, sig.truth, (seg.steady, seg.transient))
    assert a == b


def test_a_smoothed_signal_with_a_gap_or_a_lag_of_nothing_is_refused():
    """A NaN at the smoothed signal's end had made its noise score NaN; max_lag 0 its lag."""
    import pytest

    from rollerrig._validation import ParameterError

    r = seed_like_torque(duration=8.0)
    sm = smooth(r.raw, "moving_average", window=25)
    sm[-1] = np.nan
    with pytest.raises(ParameterError, match="smoothed must be finite"):
        score_smoothing(r.time, r.raw, sm, r.truth)
    with pytest.raises(ParameterError, match="max_lag must be > 0"):
        score_smoothing(r.time, r.raw, r.raw, r.truth, max_lag=0.0)
