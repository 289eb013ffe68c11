"""Streaming anti-alias decimation: equal to one-shot; pass and stop bands as stated; zero phase."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy import signal as sps

import rollerrig.signal.decimate as dec
from rollerrig._validation import ParameterError
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.signal.decimate import (
    decimate,
    decimate_chunks,
    decimate_recording,
    decimated_time,
    design_decimation,
)


def _walk(n, channels=None, seed=0):
    rng = np.random.default_rng(seed)
    shape = (n,) if channels is None else (n, channels)
    return np.cumsum(rng.standard_normal(shape), axis=0) + 50.0


def _split(x, sizes):
    """Consecutive pieces of x with the given sizes (cycled), the last one shorter."""
    out, i, k = [], 0, 0
    while i < x.shape[0]:
        out.append(x[i : i + sizes[k % len(sizes)]])
        i += sizes[k % len(sizes)]
        k += 1
    return out


def _reference(x, spec):
    """y[m] = Σ_j x_ext[j] h[m·down − j·up + K·up], summed term by term (no upfirdn)."""
    k, up, down, h = spec.half_length, spec.up, spec.down, spec.taps
    n = x.size
    head, tail = x[: min(k + 1, n)], x[n - min(k + 1, n) :]

    def line(samples, at):
        i = np.arange(samples.size)
        slope, icpt = np.polyfit(i, samples, 1) if samples.size > 1 else (0.0, samples[0])
        return icpt + slope * at

    ext = np.concatenate([line(head, np.arange(-k, 0)), x, line(tail, tail.size + np.arange(k))])
    y = np.empty(spec.output_length(n))
    for m in range(y.size):
        j = np.arange(-k, n + k)
        idx = m * down - j * up + k * up
        ok = (idx >= 0) & (idx < h.size)
        y[m] = np.sum(ext[j[ok] + k] * h[idx[ok]])
    return y


# --- streaming equals one-shot ------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(
    sizes=st.lists(st.integers(1, 2500), min_size=1, max_size=6),
    block=st.sampled_from([1, 97, 1000, 1 << 18]),
    rates=st.sampled_from([(2000.0, 100.0), (19200.0, 1000.0), (3000.0, 1200.0), (900.0, 300.0)]),
    n=st.integers(1, 6000),
    channels=st.sampled_from([None, 3]),
)
def test_streaming_equals_one_shot_for_any_chunking(sizes, block, rates, n, channels):
    x = _walk(n, channels)
    spec = design_decimation(*rates)
    whole = decimate(x, spec)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(dec, "_BLOCK", block)  # small blocks: the buffer is cut many times
        pieces = list(decimate_chunks(_split(x, sizes), spec))
    got = np.concatenate(pieces, axis=0)
    assert got.shape == whole.shape == (spec.output_length(n), *x.shape[1:])
    assert_allclose(got, whole, rtol=0, atol=1e-12 * (1 + np.max(np.abs(x))))


@pytest.mark.parametrize(("rates", "n"), [((2000.0, 100.0), 3001), ((19200.0, 1000.0), 2500),
                                          ((900.0, 300.0), 50), ((2000.0, 250.0), 7)])  # fmt: skip
def test_one_shot_equals_the_defining_sum(rates, n):
    x = _walk(n, seed=n)
    spec = design_decimation(*rates)
    assert_allclose(decimate(x, spec), _reference(x, spec), rtol=0, atol=1e-11 * np.ptp(x))


@pytest.mark.parametrize("rates", [(2000.0, 100.0), (19200.0, 250.0), (19200.0, 1000.0)])
def test_interior_equals_scipy_resample_poly_with_the_same_taps(rates):
    # scipy.signal.resample_poly pads with zeros at the ends; away from them (K input samples)
    # it must give our samples exactly: same taps, same phase convention (peer-library check).
    spec = design_decimation(*rates)
    x = _walk(40 * spec.taps.size // spec.up)
    ours = decimate(x, spec)
    ref = sps.resample_poly(x, spec.up, spec.down, window=spec.taps / spec.up)
    edge = spec.half_length * spec.up // spec.down + 2
    assert_allclose(ours[edge:-edge], ref[edge : ours.size - edge], rtol=0, atol=1e-10)


def test_streaming_emits_before_the_input_ends_and_holds_bounded_history(monkeypatch):
    monkeypatch.setattr(dec, "_BLOCK", 4096)
    consumed = []

    def source():
        for k in range(40):
            consumed.append(k)
            yield _walk(5000, seed=k)

    stream = decimate_chunks(source(), 19200.0, 1000.0)
    next(stream)
    assert len(consumed) <= 2
    spec = design_decimation(19200.0, 1000.0)
    assert sum(1 for _ in stream) > 30
    assert spec.output_length(200_000) == 10_417


# --- filter: stated bands, tested -----------------------------------------------------------
def _amplitude(y, t, f):
    """Least-squares amplitude of a sine at f [Hz] in y(t)."""
    a = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t), np.ones_like(t)])
    c = np.linalg.lstsq(a, y, rcond=None)[0]
    return float(np.hypot(c[0], c[1]))


@pytest.mark.parametrize(("fs", "target"), [(19200.0, 1000.0), (19200.0, 250.0), (2000.0, 100.0)])
def test_in_band_tone_kept_within_0p1_percent_and_alias_attenuated_60_dB(fs, target):
    spec = design_decimation(fs, target)
    t = np.arange(int(6 * fs)) / fs
    nyq = spec.rate / 2
    ty = decimated_time(t.size, spec)
    edge = spec.half_length * spec.up // spec.down + 2  # outputs the end lines reach
    inner = slice(edge, -edge)
    for f in (0.05 * nyq, 0.5 * nyq, spec.passband_edge):
        y = decimate(np.sin(2 * np.pi * f * t + 0.3), spec)
        assert abs(_amplitude(y[inner], ty[inner], f) - 1.0) <= 1e-3, f
    # above the new Nyquist frequency: just above it, its double and near the input Nyquist
    for f in (1.003 * nyq, 1.5 * nyq, 2.0 * nyq + 1.0, 0.97 * fs / 2):
        y = decimate(np.sin(2 * np.pi * f * t + 0.3), spec)
        assert np.max(np.abs(y[inner])) <= 1e-3, f  # >= 60 dB down, wherever it would alias


def test_stated_ripple_and_attenuation_match_an_independent_frequency_response():
    for fs, target in [(19200.0, 1000.0), (19200.0, 250.0), (1000.0, 250.0)]:
        spec = design_decimation(fs, target)
        assert spec.passband_ripple <= 1e-3 and spec.stopband_attenuation_dB >= 60.0
        fs_up = fs * spec.up
        f_pass = np.linspace(0, spec.passband_edge, 2000)
        f_stop = np.linspace(spec.stopband_edge, fs_up / 2, 20000)
        _, hp = sps.freqz(spec.taps / spec.up, worN=f_pass, fs=fs_up)
        _, hs = sps.freqz(spec.taps / spec.up, worN=f_stop, fs=fs_up)
        assert np.max(np.abs(np.abs(hp) - 1)) <= spec.passband_ripple * 1.01 + 1e-12
        assert -20 * np.log10(np.max(np.abs(hs))) >= spec.stopband_attenuation_dB - 0.05
        assert spec.describe().startswith(f"decimated from {fs:g} Hz to {target:g} Hz")


def test_zero_phase_keeps_a_pulse_centred_and_ramps_and_constants_exact():
    fs, target = 19200.0, 1000.0
    spec = design_decimation(fs, target)
    t = np.arange(int(4 * fs)) / fs
    pulse = np.exp(-0.5 * ((t - 2.0) / 0.01) ** 2)
    y = decimate(pulse, spec)
    ty = decimated_time(t.size, spec)
    k = int(np.argmax(y))
    # parabolic peak time: zero delay to a small fraction of an output sample
    c0, c1, c2 = y[k - 1 : k + 2]
    peak = ty[k] + 0.5 * (c0 - c2) / (c0 - 2 * c1 + c2) / spec.rate
    assert abs(peak - 2.0) < 1e-6
    # least-squares end lines and unit-gain polyphase branches: a constant passes exactly, ends
    # included; a ramp exactly for an integer factor, to 1e-7 of its range for 5/96
    assert_allclose(decimate(np.full(t.size, 7.5), spec), 7.5, rtol=0, atol=1e-12)
    assert_allclose(decimate(3.0 - 2.0 * t, spec), 3.0 - 2.0 * ty, rtol=0, atol=1e-7 * 8.0)
    t2 = np.arange(8000) / 2000.0
    spec2 = design_decimation(2000.0, 100.0)
    y2 = decimate(3.0 - 2.0 * t2, spec2)
    assert_allclose(y2, 3.0 - 2.0 * decimated_time(t2.size, spec2), rtol=0, atol=1e-12)


def test_rational_ratio_and_output_instants():
    spec = design_decimation(19200.0, 250.0)
    assert (spec.up, spec.down, spec.rate) == (5, 384, 250.0)
    assert (design_decimation(1000.0, 250.0).up, design_decimation(1000.0, 250.0).down) == (1, 4)
    # a rate measured from float time stamps is taken as the exact ratio
    assert design_decimation(19200.000000001, 1000.0).rate == 1000.0
    assert_allclose(decimated_time(19200, spec, 5.0), 5.0 + np.arange(250) / 250.0)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: design_decimation(1000.0, 1000.0), "below the sample rate"),
        (lambda: design_decimation(1000.0, 2000.0), "below the sample rate"),
        (lambda: design_decimation(1000.0, 1000.0 / 1.0077), "not reachable"),
        (lambda: design_decimation(1000.0, 100.0, attenuation_dB=10), "attenuation_dB"),
        (lambda: design_decimation(1000.0, 100.0, passband=1.0), "passband"),
        (lambda: decimate(np.array([1.0, np.nan, 2.0]), 1000.0, 100.0), "non-finite"),
        (lambda: list(decimate_chunks([np.zeros(5), np.zeros((5, 2))], 1000.0, 100.0)),
         "same channels"),
        (lambda: decimate(np.zeros(10), 1000.0), "target_rate"),
    ],
)  # fmt: skip
def test_invalid_requests_raise_named_errors(call, match):
    with pytest.raises(ParameterError, match=match):
        call()


@pytest.mark.parametrize(
    ("sample_rate", "target_rate", "kw", "taps"),
    [
        (19200.0, 0.1, {}, "8298069"),  # had asked 4 GiB for the response's FFT
        (1e6, 1.0, {}, "43219101"),  # 32 GiB
        (19200.0, 1e-9, {}, "about 8.3e+14"),  # 5.9 PiB
        (1e300, 1e-300, {}, "over 1e308"),  # a factor of 1e600: OverflowError in the ratio
        (19200.0, 1000.0, {"passband": 1 - 1e-15}, "811006333626836961"),  # 5.6 EiB
    ],
)
def test_design_decimation_refuses_filters_beyond_the_tap_limit(sample_rate, target_rate, kw, taps):
    band = kw.get("passband", 0.8)
    message = (
        f"target_rate {target_rate:g} Hz is too far below sample_rate {sample_rate:g} Hz for one "
        f"anti-alias filter with attenuation_dB 70 and passband {band!r}: it needs {taps} taps, "
        f"more than MAX_TAPS = {dec.MAX_TAPS} (memory); decimate in stages (to a rate between the "
        "two first), or lower attenuation_dB or passband"
    )
    with pytest.raises(ParameterError, match=re.escape(message)):
        design_decimation(sample_rate, target_rate, **kw)


def test_a_steep_decimation_is_done_in_stages_within_the_tap_limit():
    """19.2 kHz to 0.1 Hz in one filter needs 8.3 M taps; 19.2 kHz -> 100 Hz -> 0.1 Hz fits."""
    first, second = design_decimation(19200.0, 100.0), design_decimation(100.0, 0.1)
    assert max(first.taps.size, second.taps.size) <= dec.MAX_TAPS
    assert second.rate == pytest.approx(0.1)


# --- recordings ---------------------------------------------------------------------------
def test_decimate_recording_notes_the_operation_and_keeps_units():
    fs = 19200.0
    t = 10.0 + np.arange(int(3 * fs)) / fs
    counts = np.floor(t * 2000.0)  # an encoder at 2000 counts/s
    rec = Recording(
        t,
        {"torque": 100 + 5 * np.sin(2 * np.pi * 14.7 * t), "roller_encoder_counts": counts},
        {"torque": "N.m", "roller_encoder_counts": "1"},
        {"source": "run.tdms", "notes": ["read by the TDMS reader"]},
    )
    out = decimate_recording(rec, 1000.0)
    assert out.time.size == 3000 and out.time[0] == 10.0
    assert dict(out.units) == dict(rec.units)
    assert out.metadata["notes"][0] == "read by the TDMS reader"
    assert "decimated from 19200 Hz to 1000 Hz" in out.metadata["notes"][-1]
    assert out.metadata["decimated"]["rate_Hz"] == 1000.0
    assert out.metadata["source"] == "run.tdms"
    # the counts' slope (the speed) survives: 2000 counts/s
    slope = np.diff(out["roller_encoder_counts"][100:-100]) * 1000.0
    assert_allclose(slope, 2000.0, rtol=0.03)
    assert abs(_amplitude(out["torque"][200:-200], out.time[200:-200], 14.7) - 5.0) < 5e-3


def test_decimate_recording_refuses_non_uniform_time_naming_the_source():
    t = np.r_[np.arange(1000), np.arange(1100, 2000)] / 1000.0
    rec = Recording(t, {"torque": np.zeros(t.size)}, {"torque": "N.m"}, {"source": "gap.csv"})
    with pytest.raises(RecordingError, match=r"gap\.csv.*non-uniform"):
        decimate_recording(rec, 100.0)
    ok = Recording(t[:1000], {"torque": np.zeros(1000)}, {"torque": "N.m"}, {"source": "a.csv"})
    with pytest.raises(RecordingError, match=r"a\.csv.*below the sample rate"):
        decimate_recording(ok, 5000.0)


def test_decimate_recording_streams_an_open_source_like_the_recording_in_memory(tmp_path):
    # open_recording (measure/source.py) reads the file in chunks; the result must equal the
    # decimation of the whole recording read at once, with the source's notes kept.
    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.source import open_recording
    from rollerrig.recordings.writers import write_recording

    fs = 19200.0
    t = np.arange(int(2.5 * fs)) / fs
    rec = Recording(
        t,
        {"torque": 200 + 10 * np.sin(2 * np.pi * 3.0 * t), "air_spring_pressure": 8e4 + t},
        {"torque": "N.m", "air_spring_pressure": "Pa"},
    )
    path = write_recording(rec, tmp_path / "run.parquet")
    whole = decimate_recording(read_recording(path), 1000.0)
    with open_recording(path) as src:
        streamed = decimate_recording(src, 1000.0, chunk_samples=7000)
        one = decimate_recording(src, 1000.0, names="torque")
    assert list(one.channels) == ["torque"]
    assert_allclose(streamed.time, whole.time, rtol=0, atol=1e-12)
    for name in ("torque", "air_spring_pressure"):
        assert_allclose(streamed[name], whole[name], rtol=1e-13)
        assert streamed.units[name] == rec.units[name]
    assert streamed.metadata["decimated"] == whole.metadata["decimated"]
    assert "decimated from 19200 Hz to 1000 Hz" in streamed.metadata["notes"][-1]
