"""Steady and transient parts found from the torque request or the measured torque."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig.signal.steady_transient import steady_and_transient_masks
from rollerrig.signal.synthetic_torque import seed_like_torque


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


@settings(max_examples=40, deadline=None)
@given(bits=st.lists(st.booleans(), min_size=1, max_size=300), reach=st.integers(0, 40))
def test_mask_widening_equals_binary_dilation(bits, reach):
    # the O(n) cumulative-sum widening used by steady_and_transient_masks is scipy's binary
    # dilation by 2·reach + 1 ones (border False), which needs O(n·reach) time and memory
    from scipy.ndimage import binary_dilation

    from rollerrig.signal.steady_transient import _dilate

    mask = np.array(bits)
    ref = binary_dilation(mask, np.ones(2 * reach + 1, bool)) if reach else mask
    assert np.array_equal(_dilate(mask, reach), ref)


def test_settings_that_would_mark_everything_steady_or_transient_are_refused():
    """k_sigma NaN had marked every sample steady, -1 every sample transient."""
    import pytest

    from rollerrig._validation import ParameterError

    r = seed_like_torque(duration=8.0)
    fs = 1.0 / (r.time[1] - r.time[0])
    assert 0 < steady_and_transient_masks(r.raw, fs).transient.sum() < r.raw.size
    for kwargs, message in (
        ({"k_sigma": np.nan}, "k_sigma must be finite"),
        ({"k_sigma": -1.0}, "k_sigma must be > 0"),
        ({"margin": -0.1}, "margin must be >= 0"),
        ({"smoothing_time": np.nan}, "smoothing_time must be finite"),
    ):
        with pytest.raises(ParameterError, match=message):
            steady_and_transient_masks(r.raw, fs, **kwargs)
    with pytest.raises(ParameterError, match="at least 3 samples"):
        steady_and_transient_masks(r.raw[:1], fs)
