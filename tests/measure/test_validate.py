"""Validation of a recording at the boundary (rollerrig.measure.validate), on samples built here:
time strictly increasing, NaN/inf runs (strict: an error naming them; lenient: short runs
interpolated, exact on a linear signal), gaps (an interval over GAP_FACTOR x the median)."""

import numpy as np
import pytest

from rollerrig.measure.recording import RecordingError
from rollerrig.measure.validate import (
    GAP_FACTOR,
    MAX_INTERPOLATED_NAN_RUN,
    describe_gap,
    find_gaps,
    validate_samples,
)

T = np.arange(20) / 100.0


def test_gaps_are_intervals_beyond_the_factor_with_their_missing_samples():
    t = np.concatenate([T[:10], T[13:]])  # samples 10, 11, 12 dropped
    step, gaps = find_gaps(t)
    assert step == pytest.approx(0.01)
    (gap,) = gaps
    assert (gap["sample"], gap["missing_samples"]) == (9, 3)
    assert gap["duration_s"] == pytest.approx(0.04) and gap["start_s"] == pytest.approx(0.09)
    assert describe_gap(gap) == "0.04 s after t = 0.09 s (sample 9, about 3 missing sample(s))"
    jitter = T + np.r_[0, (GAP_FACTOR - 1.05) * 0.01, np.zeros(18)]  # just under the factor
    assert find_gaps(jitter)[1] == []


def test_strict_refuses_gaps_and_nan_naming_where():
    t = np.concatenate([T[:10], T[13:]])
    with pytest.raises(RecordingError, match=r"f: gap \(dropped samples\) between sample 9"):
        validate_samples(t, {"x": np.zeros(t.size)}, "strict", "f:")
    x = np.ones(T.size)
    x[4:6] = np.nan
    with pytest.raises(RecordingError, match=r"channel 'x' has 2 NaN/inf samples in 1 run"):
        validate_samples(T, {"x": x}, "strict", "f:")


def test_lenient_interpolates_short_runs_exactly_and_keeps_gaps():
    x = 2.0 + 3.0 * T
    x[4 : 4 + MAX_INTERPOLATED_NAN_RUN] = np.inf
    x[0] = np.nan  # at the edge: held
    out, report = validate_samples(T, {"x": x}, "lenient", "f:")
    np.testing.assert_allclose(out["x"][1:], (2.0 + 3.0 * T)[1:], rtol=1e-12)
    assert out["x"][0] == out["x"][1]
    methods = [(r["first_sample"], r["last_sample"], r["method"]) for r in report["interpolated"]]
    assert methods == [(0, 0, "held (edge)"), (4, 3 + MAX_INTERPOLATED_NAN_RUN, "linear")]
    t = np.concatenate([T[:10], T[13:]])
    _, report = validate_samples(t, {"x": np.zeros(t.size)}, "lenient", "f:")
    assert [g["sample"] for g in report["gaps"]] == [9]


def test_long_runs_and_bad_time_are_errors_in_either_mode():
    x = np.ones(T.size)
    x[2 : 3 + MAX_INTERPOLATED_NAN_RUN] = np.nan
    with pytest.raises(RecordingError, match="too long to interpolate"):
        validate_samples(T, {"x": x}, "lenient", "f:")
    back = T.copy()
    back[5] = back[3]
    with pytest.raises(RecordingError, match=r"time goes backwards at sample 5"):
        validate_samples(back, {}, "lenient", "f:")
    with pytest.raises(RecordingError, match="need at least 2"):
        validate_samples(T[:1], {}, "strict", "f:")
