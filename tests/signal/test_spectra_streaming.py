"""Streaming Welch spectra, cross spectra and coherence against scipy, and bounded memory.

References: :func:`scipy.signal.welch`, :func:`scipy.signal.csd` and
:func:`scipy.signal.coherence` on the concatenated signal (same segments, window, detrending
and scaling); the old peak interpolation (an outer product of offsets and window samples) for
the scalloping correction.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal as sps

from rollerrig._validation import ParameterError
from rollerrig.signal.peaks import find_spectral_peaks, window_response
from rollerrig.signal.welch import (
    Spectrum,
    coherence,
    coherence_stream,
    cross_spectra_stream,
    power_spectrum,
    welch_stream,
)

FS = 250.0
RNG = np.random.default_rng(11)
X = RNG.standard_normal(20_011) + 3.0 * np.sin(2 * np.pi * 14.67 * np.arange(20_011) / FS)
X += 1e-3 * np.arange(X.size)  # a trend for the detrending to remove
Y = np.roll(X, 5) + 0.7 * RNG.standard_normal(X.size)


def _pieces(x, sizes):
    """Split x at the cumulative sizes (cycled), empty pieces included."""
    out, start, k = [], 0, 0
    while start < x.size:
        size = sizes[k % len(sizes)]
        out.append(x[start : start + size])
        start += size
        k += 1
    return out


@settings(max_examples=40, deadline=None)
@given(
    sizes=st.lists(st.integers(min_value=0, max_value=3000), min_size=1, max_size=6).filter(
        lambda s: sum(s) > 0
    ),
    nperseg=st.sampled_from([64, 255, 1000, 2048]),
    overlap=st.sampled_from([None, 0, 17]),
)
def test_welch_stream_equals_scipy_for_any_chunking(sizes, nperseg, overlap):
    f, p = sps.welch(X, FS, nperseg=nperseg, noverlap=overlap, detrend="linear", scaling="spectrum")
    s = welch_stream(_pieces(X, sizes), FS, nperseg, overlap)
    np.testing.assert_allclose(s.frequency, f)
    np.testing.assert_allclose(s.power, p, rtol=1e-9, atol=1e-12 * p.max())
    assert s.n_segments == (X.size - s.noverlap) // (nperseg - s.noverlap)


@pytest.mark.parametrize("detrend", ["linear", "constant", False])
@pytest.mark.parametrize("scaling", ["spectrum", "density"])
@pytest.mark.parametrize("window", ["hann", "blackmanharris"])
def test_cross_spectra_and_coherence_equal_scipy(detrend, scaling, window):
    kw = {"nperseg": 1000, "noverlap": 300, "detrend": detrend, "window": window}
    pairs = list(zip(_pieces(X, [777]), _pieces(Y, [777]), strict=True))
    cs = cross_spectra_stream(pairs, FS, scaling=scaling, **kw)
    _, pxx = sps.welch(X, FS, scaling=scaling, **kw)
    _, pyy = sps.welch(Y, FS, scaling=scaling, **kw)
    _, pxy = sps.csd(X, Y, FS, scaling=scaling, **kw)
    _, gamma = sps.coherence(X, Y, FS, **kw)
    np.testing.assert_allclose(cs.x.power, pxx, rtol=1e-9, atol=1e-12 * pxx.max())
    np.testing.assert_allclose(cs.y.power, pyy, rtol=1e-9, atol=1e-12 * pyy.max())
    np.testing.assert_allclose(cs.cross, pxy, rtol=1e-9, atol=1e-12 * np.abs(pxy).max())
    np.testing.assert_allclose(cs.coherence.coherence, gamma, atol=1e-10)
    streamed = coherence_stream(pairs, FS, **kw)
    np.testing.assert_allclose(streamed.coherence, gamma, atol=1e-10)
    assert streamed.nperseg == 1000 and streamed.noverlap == 300


def test_array_front_ends_equal_scipy():
    _, p = sps.welch(X, FS, nperseg=4096, detrend="linear", scaling="spectrum")
    s = power_spectrum(X, FS, nperseg=4096)
    np.testing.assert_allclose(s.power, p, rtol=1e-9, atol=1e-12 * p.max())
    assert (s.noverlap, s.detrend) == (2048, "linear")
    _, g = sps.coherence(X, Y, FS, nperseg=512, detrend="linear")
    np.testing.assert_allclose(coherence(X, Y, FS, nperseg=512).coherence, g, atol=1e-10)


def test_errors_name_the_signal_and_the_sample():
    bad = X.copy()
    bad[12_345] = np.nan
    with pytest.raises(ParameterError, match=r"torque.*non-finite.*sample 12345"):
        welch_stream(_pieces(bad, [1000]), FS, 512, name="torque")
    with pytest.raises(ParameterError, match=r"torque is constant \(0"):
        welch_stream([np.zeros(5000)], FS, 512, name="torque")
    with pytest.raises(ParameterError, match=r"torque is constant \(4.2"):
        welch_stream([np.full(5000, 4.2)], FS, 512, name="torque")
    with pytest.raises(ParameterError, match=r"torque reaches 1e\+300 at sample 7.*scale"):
        welch_stream([np.r_[np.ones(7), 1e300, np.ones(5000)]], FS, 512, name="torque")
    with pytest.raises(ParameterError, match="no variation beyond its linear trend"):
        welch_stream([np.linspace(0.0, 1.0, 5000)], FS, 512, name="torque")
    with pytest.raises(ParameterError, match="fewer than one segment"):
        welch_stream([X[:100]], FS, 512)
    with pytest.raises(ParameterError, match="equal length"):
        cross_spectra_stream([(X[:10], Y[:11])], FS, 64)
    with pytest.raises(ParameterError, match="noverlap"):
        welch_stream([X], FS, 64, noverlap=64)
    with pytest.raises(ParameterError, match="window"):
        welch_stream([X], FS, 64, window="no-such-window")


def test_streaming_memory_does_not_grow_with_the_record():
    # 2**24 samples (128 MB as one array) streamed in 64 k chunks: the estimator holds one
    # chunk, one segment of history and a batch of segments (measured ~20 MB).
    nperseg, chunk = 8192, 1 << 16

    def chunks():
        rng = np.random.default_rng(0)
        for _ in range((1 << 24) // chunk):
            yield rng.standard_normal(chunk)

    tracemalloc.start()
    s = welch_stream(chunks(), 19_200.0, nperseg)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert s.n_segments == ((1 << 24) - nperseg // 2) // (nperseg // 2)
    assert peak < 64e6
    # white noise, unit variance: 2 σ² Σw² / (Σw)² = 3 / nperseg per bin (Hann)
    assert np.median(s.power[1:-1]) == pytest.approx(3.0 / nperseg, rel=0.05)


def test_peak_finding_memory_is_independent_of_candidates_times_segment():
    # 2**20-sample segments and ~2000 candidate maxima: the old outer product of offsets and
    # window samples needed candidates x nperseg x 16 B (~34 GB); the window response is now
    # evaluated once on a fixed grid.
    nperseg = 1 << 20
    rng = np.random.default_rng(3)
    power = rng.exponential(1.0, nperseg // 2 + 1)
    f = np.fft.rfftfreq(nperseg, 1.0 / 19_200.0)
    spec = Spectrum(f, power, "spectrum", "welch", 19_200.0, nperseg, 8, "hann", 0.0)
    tracemalloc.start()
    peaks = find_spectral_peaks(spec, min_prominence=0.0, min_snr=9.0, floor_bins=31)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert len(peaks) > 500
    assert peak < 400e6


def test_window_response_equals_the_direct_sum():
    w = sps.get_window("hann", 1000)
    d = np.linspace(0.0, 0.5, 11)
    direct = np.abs(np.exp(-2j * np.pi * np.outer(d, np.arange(w.size)) / w.size) @ w) ** 2
    np.testing.assert_allclose(window_response(w, 0.0, 0.5, 11), direct / w.sum() ** 2, rtol=1e-12)
