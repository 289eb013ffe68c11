"""The shared numeric rules of the signal modules: sample checks, rates, scales, JSON numbers."""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.signal._numeric import (
    check_samples,
    finite_or_none,
    odd,
    power_of_two_scale,
    tidy_rate,
    uniform_sample_rate,
)


def test_check_samples_names_the_first_bad_sample_of_one_or_several_channels():
    x = np.ones(10)
    check_samples(x, 0, 1e100, "why")  # a clean chunk passes
    check_samples(np.zeros(0), 0, 1e100, "why")  # so does an empty one
    x[4], x[7] = np.nan, 1e120
    with pytest.raises(ParameterError, match=r"^torque has .* \(nan\) at sample 104;"):
        check_samples(x, 100, 1e100, "why", "torque")
    x[4] = 0.0
    with pytest.raises(ParameterError, match=r"reaches 1e\+120 at sample 107, beyond 1e\+100: why"):
        check_samples(x, 100, 1e100, "why")
    two = np.zeros((6, 2))
    two[3, 1] = -np.inf
    with pytest.raises(ParameterError, match=r"\(-inf\) at sample 3;"):
        check_samples(two, 0, 1e100, "why")


def test_uniform_sample_rate_names_the_step_that_breaks_it():
    t = np.arange(100) / 250.0
    assert uniform_sample_rate(t) == pytest.approx(250.0, rel=1e-12)
    assert tidy_rate(uniform_sample_rate(np.arange(100) / 19200.0)) == 19200.0
    gap = np.concatenate([t[:50], t[50:] + 0.1])
    with pytest.raises(ParameterError, match=r"non-uniform.*step 0\.104 s at t = 0\.196 s"):
        uniform_sample_rate(gap)
    with pytest.raises(ParameterError, match="strictly increasing"):
        uniform_sample_rate(t[::-1])
    with pytest.raises(ParameterError, match="at least 2 samples"):
        uniform_sample_rate(t[:1])


@pytest.mark.parametrize("peak", [1e-300, 3.0e-5, 1.0, 400.0, 1e300])
def test_power_of_two_scale_brings_the_peak_into_half_to_one_exactly(peak):
    s = power_of_two_scale(peak)
    assert 0.5 <= s * peak < 1.0
    assert np.frexp(s)[0] == 0.5  # a power of two: scaling by it is exact
    assert power_of_two_scale(0.0) == 1.0


def test_finite_or_none_and_odd():
    assert [finite_or_none(v) for v in (1, np.float32(2.5), np.nan, -np.inf, None)] == [
        1.0,
        2.5,
        None,
        None,
        None,
    ]
    assert [odd(n) for n in (0, 3, 4, 110.4, 110.6)] == [3, 3, 5, 111, 111]
    assert odd(0.2, 1) == 1
