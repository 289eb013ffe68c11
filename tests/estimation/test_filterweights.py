"""Weights of the correction's linear filters against the filters themselves.

Reference: rollerrig.signal.smoothing.savitzky_golay (tested against Savitzky & Golay 1964 and
MATLAB sgolayfilt) and rollerrig.measure.quantities.encoder_speed, applied to random signals.
"""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig.estimation.filterweights import (
    BandedFilter,
    after_encoder_speed,
    encoder_speed_matrix,
    savitzky_golay_matrix,
)
from rollerrig.measure.quantities import encoder_speed
from rollerrig.signal.smoothing import savitzky_golay


@pytest.mark.parametrize(
    ("n", "window", "order", "deriv"),
    [(30, 7, 3, 0), (60, 51, 4, 1), (400, 171, 2, 0), (205, 201, 4, 1), (51, 51, 4, 2)],
)
def test_savitzky_golay_matrix_is_the_filter(n, window, order, deriv):
    x = np.random.default_rng(n).standard_normal(n)
    fs = 250.0
    W = savitzky_golay_matrix(n, window, order, deriv, 1.0 / fs)
    expected = savitzky_golay(x, window, order, deriv=deriv, sample_rate=fs if deriv else None)
    np.testing.assert_allclose(W @ x, expected, rtol=1e-10, atol=1e-9 * np.max(np.abs(expected)))


def test_encoder_speed_matrix_is_the_encoder_speed():
    counts = np.cumsum(np.random.default_rng(0).integers(100, 130, 40)).astype(float)
    t = np.arange(40) / 250.0
    np.testing.assert_allclose(
        encoder_speed_matrix(40, 250.0, 10000) @ counts, encoder_speed(counts, t, 10000)
    )


def test_banded_filter_norms_equal_the_full_matrix():
    """The banded rows (built with the sparse encoder product) against the dense product."""
    n, window = 300, 21
    full = savitzky_golay_matrix(n, window, 4, 1, 1 / 250) @ encoder_speed_matrix(n, 250.0, 1e4)
    banded = BandedFilter(
        lambda m: after_encoder_speed(savitzky_golay_matrix(m, window, 4, 1, 1 / 250), 250.0, 1e4),
        n,
        window // 2 + 1,
    )
    assert banded.full is None  # the banded form, not the whole matrix
    np.testing.assert_allclose(banded.row_norm2(), np.sum(full**2, axis=1), rtol=1e-12)
    for start, stop in ((0, 300), (0, 7), (5, 140), (120, 180), (290, 300), (150, 151)):
        expected = np.sum((full[start:stop].sum(axis=0) / (stop - start)) ** 2)
        assert banded.mean_norm2(start, stop) == pytest.approx(expected, rel=1e-10)


def test_the_mean_of_a_derivative_carries_little_noise():
    """The derivative weights telescope: a 2 s mean of α5 has far less quantisation than a
    sample (the mean speed change over the span, known to two counts)."""
    n, window = 1000, 51
    banded = BandedFilter(
        lambda m: (
            savitzky_golay_matrix(m, window, 4, 1, 1 / 250) @ encoder_speed_matrix(m, 250.0, 1e4)
        ),
        n,
        window // 2 + 1,
    )
    per_sample = banded.row_norm2()[500]
    assert banded.mean_norm2(200, 700) < 1e-3 * per_sample
