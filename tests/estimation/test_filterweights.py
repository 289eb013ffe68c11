"""Weights of the correction's linear filters against the filters themselves.

Reference: rollerrig.signal.smoothing.savitzky_golay (tested against Savitzky & Golay 1964 and
MATLAB sgolayfilt) and rollerrig.measure.quantities.encoder_speed, applied to random signals.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from rollerrig._validation import ParameterError
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


@pytest.mark.parametrize("window", [6, 8, 52])
def test_savitzky_golay_matrix_refuses_an_even_window(window):
    """A Savitzky-Golay window is centred on its sample: an even one broke deep in numpy
    ("could not broadcast input array from shape (3,7) into shape (3,6)")."""
    message = "window must be an odd integer >= 1 [samples] (centred on its sample)"
    hint = f"; use {window + 1} or {window - 1}"
    with pytest.raises(ParameterError, match=re.escape(f"{message}, got {window}{hint}")):
        savitzky_golay_matrix(60, window, 3)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((30, 0, 0), "window must be an odd integer >= 1 [samples] (centred on its sample), got 0"),
        ((30, 7.5, 3), "window must be an odd integer >= 1 [samples]"),
        ((30, 5, 5), "order must be an integer in [0, window) = [0, 5), got 5"),
        ((30, 7, 2, 3), "deriv must be an integer in [0, order] = [0, 2], got 3"),
        ((5, 7, 3), "size must be an integer >= window = 7 [samples]"),
        ((30, 7, 3, 1, 0.0), "delta must be > 0 [s], got 0"),
    ],
)
def test_savitzky_golay_matrix_refuses_what_the_filter_refuses(args, message):
    with pytest.raises(ParameterError, match=re.escape(message)):
        savitzky_golay_matrix(*args)


@pytest.mark.parametrize("size", [1, 0, -1, 2.5])
def test_encoder_speed_matrix_needs_two_samples(size):
    """Row 0 repeats row 1, the difference of samples 0 and 1: one sample raised IndexError
    (as encoder_speed, which needs two samples)."""
    message = "size must be an integer >= 2 [samples] (a speed is a difference of two counts)"
    with pytest.raises(ParameterError, match=re.escape(f"{message}, got {size!r}")):
        encoder_speed_matrix(size, 250.0, 1e4)
    assert encoder_speed_matrix(2, 250.0, 1e4).shape == (2, 2)


def test_encoder_speed_matrix_refuses_non_physical_rates():
    with pytest.raises(ParameterError, match=re.escape("cpr must be > 0 [-], got 0")):
        encoder_speed_matrix(3, 250.0, 0)
    with pytest.raises(ParameterError, match=re.escape("fs must be finite [Hz], got nan")):
        encoder_speed_matrix(3, np.nan, 1e4)
