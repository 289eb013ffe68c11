"""The seed's filter grid and the Savitzky-Golay tuning grid (Kayaalp, 4.5.2.5-4.5.2.6)."""

from __future__ import annotations

import pytest

from rollerrig._validation import ParameterError
from rollerrig.signal.filter_candidates import (
    default_candidates,
    filter_label,
    savitzky_golay_candidates,
)


def test_default_windows_scale_with_the_sample_rate():
    w250 = [p["window"] for m, p in default_candidates(250.0) if m == "savitzky_golay"]
    w500 = [p["window"] for m, p in default_candidates(500.0) if m == "savitzky_golay"]
    assert 111 in w250 and 223 in w500


def test_savitzky_golay_grid_is_every_order_below_its_window_scaled_to_the_rate():
    grid = savitzky_golay_candidates(250.0)
    windows = sorted({p["window"] for _, p in grid})
    assert windows == list(range(11, 202, 10)) and len(grid) == 6 * 20  # 0.04-0.8 s at 250 Hz
    fast = {p["window"] for _, p in savitzky_golay_candidates(2000.0)}
    assert min(fast) == 89 and max(fast) == 1609  # the same spans at 2 kHz, made odd
    given = savitzky_golay_candidates(250.0, orders=[2, 6], windows=[5, 7])
    assert given == [
        ("savitzky_golay", {"window": 5, "order": 2}),
        ("savitzky_golay", {"window": 7, "order": 2}),
        ("savitzky_golay", {"window": 7, "order": 6}),
    ]
    with pytest.raises(ParameterError, match="order < window"):
        savitzky_golay_candidates(250.0, orders=[7], windows=[5, 7])


def test_labels_name_the_method_and_its_parameters():
    assert filter_label("savitzky_golay", {"window": 111, "order": 4}) == "SG order 4 w111"
    assert filter_label("butterworth", {"cutoff": 1.2, "order": 2, "zero_phase": False}) == (
        "Butterworth 2 @ 1.2 Hz causal"
    )
    assert [filter_label(m, p) for m, p in default_candidates()[6:8]] == ["MA w11", "MA w33"]


def test_a_label_shows_a_parameter_left_out_as_a_question_mark():
    assert filter_label("savitzky_golay", {"window": 111}) == "SG order ? w111"
    assert filter_label("butterworth", {}) == "Butterworth 2 @ ? Hz zero-phase"
    assert filter_label("moving_average", {"windw": 3}) == "MA w?"
