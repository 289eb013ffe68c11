"""Chunked smoothing equals whole-array smoothing (to rounding, or within a stated bound)."""

from __future__ import annotations

import re

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy import signal as sps

from rollerrig._validation import ParameterError
from rollerrig.signal.chunked import (
    filter_array_chunked,
    filter_chunks,
    iter_chunks,
    zero_phase_padding,
)
from rollerrig.signal.smoothing import butterworth_sos, smooth

FS = 250.0


@pytest.fixture(scope="module")
def walk():
    rng = np.random.default_rng(0)
    return np.cumsum(rng.standard_normal(30_000)) + rng.standard_normal(30_000)


FIR_CASES = [
    ("moving_average", {"window": 111}),
    ("moving_average", {"window": 10}),
    ("gaussian", {"window": 131}),
    ("lowess", {"window": 131}),
    ("loess", {"window": 33}),
    ("savitzky_golay", {"window": 111, "order": 4}),
    ("savitzky_golay", {"window": 31, "order": 3, "deriv": 1}),
]


@pytest.mark.parametrize(("method", "params"), FIR_CASES)
@pytest.mark.parametrize("chunk_size", [1, 7, 1000, 4096, 100_000])
def test_finite_support_filters_stream_exactly(walk, method, params, chunk_size):
    x = walk if chunk_size >= 1000 else walk[:3000]
    whole = smooth(x, method, sample_rate=FS, **params)
    chunked = filter_array_chunked(x, method, chunk_size=chunk_size, sample_rate=FS, **params)
    # same arithmetic up to where FFT blocks and running sums start: rounding only
    assert_allclose(chunked, whole, rtol=0, atol=1e-13 * np.ptp(x))


@pytest.mark.parametrize("order", [1, 2, 3])
@pytest.mark.parametrize("chunk_size", [1, 333, 4096])
def test_causal_butterworth_streams_bit_for_bit_with_carried_state(walk, order, chunk_size):
    params = {"cutoff": 1.2, "order": order, "zero_phase": False}
    x = walk if chunk_size > 1 else walk[:3000]
    whole = smooth(x, "butterworth", sample_rate=FS, **params)
    chunked = filter_array_chunked(
        x, "butterworth", chunk_size=chunk_size, sample_rate=FS, **params
    )
    assert_array_equal(chunked, whole)


@pytest.mark.parametrize("order", [1, 2, 3])
@pytest.mark.parametrize("tolerance", [1e-4, 1e-9])
def test_zero_phase_butterworth_streams_within_the_stated_bound(walk, order, tolerance):
    params = {"cutoff": 1.2, "order": order}
    whole = smooth(walk, "butterworth", sample_rate=FS, **params)
    chunks = iter_chunks(walk, 2500)
    got = np.concatenate(
        list(filter_chunks(chunks, "butterworth", sample_rate=FS, tolerance=tolerance, **params))
    )
    assert np.max(np.abs(got - whole)) <= tolerance * np.ptp(walk)


def test_zero_phase_padding_bounds_the_impulse_response_tail():
    for order in (1, 2, 3):
        pad = zero_phase_padding(FS, 1.2, order, 1e-9)
        impulse = np.zeros(10 * pad)
        impulse[0] = 1.0
        h = np.abs(sps.sosfilt(butterworth_sos(FS, 1.2, order), impulse))
        assert h[pad:].sum() <= 1e-9 < h[pad - 1 :].sum()


def test_multichannel_chunks_filter_each_column(walk):
    x = np.stack([walk, -2.0 * walk, walk[::-1]], axis=1)
    got = filter_array_chunked(x, "savitzky_golay", chunk_size=3000, window=111, order=5)
    for j in range(3):
        assert_allclose(got[:, j], smooth(x[:, j], "savitzky_golay", window=111, order=5),
                        rtol=0, atol=1e-12 * np.ptp(x[:, j]))  # fmt: skip


def test_streaming_emits_before_the_input_ends_and_holds_bounded_history():
    consumed = []

    def source():
        for k in range(50):
            consumed.append(k)
            yield np.random.default_rng(k).standard_normal(1000)

    stream = filter_chunks(source(), "savitzky_golay", window=111, order=4)
    first = next(stream)
    assert len(consumed) == 1 and first.size == 1000 - 55
    sizes = [first.size] + [c.size for c in stream]
    assert sum(sizes) == 50_000
    assert max(sizes) <= 1000


def test_robust_methods_are_refused():
    with pytest.raises(ParameterError, match="median of all"):
        list(filter_chunks([np.zeros(100)], "rloess", window=11))
    with pytest.raises(ParameterError, match="sample_rate"):
        list(filter_chunks([np.zeros(100)], "butterworth", cutoff=1.0))


@pytest.mark.parametrize(
    ("sample_rate", "cutoff", "tolerance", "needs"),
    [
        (19200.0, 1e-6, 1e-9, "1.19e+11"),  # had tried to allocate 890 GiB
        (1e12, 1.2, 1e-9, "5.18e+12"),  # 38 TiB
        (19200.0, 1e-300, 1e-9, "inf"),  # the pole rounds onto the unit circle: OverflowError
    ],
)
def test_zero_phase_padding_refuses_an_impulse_response_beyond_the_memory_limit(
    sample_rate, cutoff, tolerance, needs
):
    message = (
        f"cutoff {cutoff:g} Hz is too low for zero-phase streaming at sample_rate "
        f"{sample_rate:g} Hz (order 2, tolerance {tolerance:g}): the impulse response needs about "
        f"{needs} samples to decay, more than MAX_PADDING = 16777216 samples (memory); decimate "
        "first, or raise cutoff or tolerance"
    )
    with pytest.raises(ParameterError, match=re.escape(message)):
        zero_phase_padding(sample_rate, cutoff, 2, tolerance)
    with pytest.raises(ParameterError, match="too low for zero-phase streaming"):
        list(filter_chunks([np.zeros(10)], "butterworth", sample_rate=sample_rate, cutoff=cutoff))


def test_zero_phase_padding_of_a_tiny_tolerance_is_finite():
    """tol·1e-3 underflowed to 0 for the smallest tolerance: log(0) gave an OverflowError."""
    assert zero_phase_padding(FS, 1.2, 2, 5e-324) < 100_000


@pytest.mark.parametrize("order", [33, 100, 1000, 10**9, 0, 2.5, True])
def test_zero_phase_padding_refuses_orders_scipy_cannot_design(order):
    """Order 10**9 had asked 7.5 GiB, 1000 raised a LinAlgError, 56 at 0.01 Hz / 19.2 kHz
    silently had DC gain 0."""
    message = (
        "order must be an integer in [1, 32] (scipy's Butterworth sections lose their gain at "
        f"higher orders), got {order!r}"
    )
    with pytest.raises(ParameterError, match=re.escape(message)):
        zero_phase_padding(FS, 1.2, order)
    assert zero_phase_padding(FS, 1.2, 32) > zero_phase_padding(FS, 1.2, 3)
