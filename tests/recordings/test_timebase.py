"""The common time base of multi-rate channels: choice, anti-alias resampling, trimming.

References: sampling theorem (a tone above the new Nyquist frequency folds to |f - k·fs|); the
Kaiser window design (Kaiser 1974; Oppenheim & Schafer, Discrete-Time Signal Processing, 3rd ed.,
eq. 7.62-7.63): for A = 60 dB the pass-band ripple and stop-band gain are 10^(-60/20) = 1e-3.
Linear interpolation reproduces a linear function exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig.recordings.channels import ChannelSpec
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.timebase import ATTENUATION_DB, align_channels, resample_onto


def _amplitude(x: np.ndarray, t: np.ndarray, f: float) -> float:
    """Least-squares amplitude of the tone at ``f`` [Hz] in ``x`` sampled at ``t`` [s]."""
    a = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t), np.ones_like(t)])
    c, *_ = np.linalg.lstsq(a, x, rcond=None)
    return float(np.hypot(c[0], c[1]))


CASES = [
    # (input rate, output rate, offset of the output grid [s]) - QuantumX to 1 kHz, a 1 kHz
    # CAN raster to 10 Hz, a non-integer ratio, and a ratio close to 1
    (19200.0, 1000.0, 0.0),
    (19200.0, 1000.0, 0.00123),
    (1000.0, 10.0, 0.0371),
    (1000.0, 300.0, 0.00017),
    (1250.0, 1000.0, 0.0004),
]


@pytest.mark.parametrize("r_in, r_out, offset", CASES)
def test_in_band_tones_keep_their_amplitude(r_in, r_out, offset):
    t = np.arange(int(12 * r_in)) / r_in
    tt = 2.0 + offset + np.arange(int(8 * r_out)) / r_out
    rng = np.random.default_rng(3)
    for f in (0.05 * r_out, 0.2 * r_out, 0.4 * r_out):  # up to the pass-band edge 0.4 fs
        phase = rng.uniform(0, 2 * np.pi)
        y, how = resample_onto(np.sin(2 * np.pi * f * t + phase), t, tt)
        assert how["method"] == "fir_polyphase"
        assert _amplitude(y, tt, f) == pytest.approx(1.0, rel=0.01)
        # and in phase, on the output instants (not only the amplitude)
        np.testing.assert_allclose(y, np.sin(2 * np.pi * f * tt + phase), atol=0.01)


@pytest.mark.parametrize("r_in, r_out, offset", CASES)
def test_tones_above_the_new_nyquist_do_not_alias(r_in, r_out, offset):
    t = np.arange(int(12 * r_in)) / r_in
    tt = 2.0 + offset + np.arange(int(8 * r_out)) / r_out
    for f in (0.5 * r_out * 1.02, 0.7 * r_out, 0.93 * r_out, 3.3 * r_out):
        if f >= 0.5 * r_in:
            continue
        alias = abs(f - round(f / r_out) * r_out)  # where it would land
        y, _ = resample_onto(np.sin(2 * np.pi * f * t), t, tt)
        assert np.max(np.abs(y)) < 10 ** (-40 / 20)  # > 40 dB down, anywhere
        assert _amplitude(y, tt, alias) < 10 ** (-(ATTENUATION_DB - 3) / 20)


def test_naive_interpolation_would_alias():
    """The reference failure: sampling a 700 Hz tone at 1 kHz gives a full-size 300 Hz line."""
    t = np.arange(19200) / 19200.0
    tt = 0.2 + np.arange(600) / 1000.0
    x = np.sin(2 * np.pi * 700.0 * t)
    assert _amplitude(np.interp(tt, t, x), tt, 300.0) > 0.9
    assert _amplitude(resample_onto(x, t, tt)[0], tt, 300.0) < 1e-3


def test_upsampling_is_linear_and_exact_for_ramps():
    t = np.arange(40) / 10.0
    tt = 0.05 + np.arange(3000) / 1000.0
    y, how = resample_onto(3.0 + 2.0 * t, t, tt)
    assert how == {"from_rate_Hz": pytest.approx(10.0), "method": "linear"}
    np.testing.assert_allclose(y, 3.0 + 2.0 * tt, rtol=1e-12)


def test_jittered_source_is_regularised_first():
    # bus-logger masters: frame times jitter by up to 20 % of the interval
    rng = np.random.default_rng(5)
    t = np.arange(20000) / 1000.0 + rng.uniform(-2e-4, 2e-4, 20000)
    tt = 1.0 + np.arange(1800) / 100.0
    y, how = resample_onto(np.sin(2 * np.pi * 3.0 * t), t, tt)
    assert how["method"] == "fir_polyphase" and "regularised" in how
    np.testing.assert_allclose(y, np.sin(2 * np.pi * 3.0 * tt), atol=2e-3)


# --------------------------------------------------------------------------- align_channels


def _spec(name, unit="1"):
    return ChannelSpec(name, name.upper(), unit, canonical=False)


def _align(channels, *, time=None, resample_Hz=None, exact=True):
    """channels: list of (name, values, own time or None)."""
    loaded = [(_spec(n), v, "1", own) for n, v, own in channels]
    info = {"columns": {n: n.upper() for n, _, _ in channels}}
    notes: list[str] = []
    out = align_channels(
        time,
        loaded,
        [own for _, _, own in channels],
        own_time_exact=exact,
        info=info,
        notes=notes,
        where="f:",
        resample_Hz=resample_Hz,
    )
    return out, info, notes


def test_base_is_the_torque_channel_else_the_fastest():
    fast = np.arange(2000) / 1000.0
    slow = np.arange(20) / 10.0
    chans = [("speed", 5.0 + fast, fast), ("torque", 2.0 * slow, slow)]
    (time, ch, _), info, notes = _align(chans)
    np.testing.assert_allclose(time, slow[slow <= fast[-1]])
    assert info["resampled"]["onto"] == "time base of 'TORQUE'"
    assert "torque channel's rate" in notes[0]
    chans[1] = ("load", 2.0 * slow, slow)
    (time, ch, _), info, notes = _align(chans)
    assert time.size == 1901 and time[0] == 0.0 and time[-1] == pytest.approx(1.9)
    np.testing.assert_allclose(ch["load"], 2.0 * time, rtol=1e-12)
    assert "fastest channel's rate" in notes[0]
    assert any("trimmed" in n for n in notes)


def test_resample_Hz_wins_and_makes_a_uniform_grid():
    a = np.arange(3000) / 1000.0
    b = 0.013 + np.arange(300) / 100.0
    (time, ch, _), info, _ = _align([("torque", np.sin(a), a), ("load", b, b)], resample_Hz=250.0)
    assert time[0] == pytest.approx(0.013) and np.allclose(np.diff(time), 1 / 250.0)
    assert info["resampled"]["rate_Hz"] == pytest.approx(250.0)
    assert info["resampled"]["channels"]["torque"]["method"] == "fir_polyphase"
    assert info["resampled"]["channels"]["load"]["method"] == "linear"
    np.testing.assert_allclose(ch["load"], time, rtol=1e-12)


def test_single_base_is_left_alone_and_resample_at_own_rate_is_noted():
    a = np.arange(100) / 50.0
    (time, _, _), info, notes = _align([("x", a, a), ("y", -a, a.copy())])
    assert time is not None and "resampled" not in info and notes == []
    _, info, notes = _align([("x", a, a)], resample_Hz=50.0)
    assert "resampled" not in info and "own rate" in notes[0]


def test_time_column_keeps_index_alignment_unless_own_times_are_exact():
    time = np.arange(100) / 100.0
    stale = np.arange(100) * 1.0  # LabVIEW default wf_increment 1 beside a time column
    (_, ch, _), _, _ = _align([("x", time.copy(), stale)], time=time, exact=False)
    np.testing.assert_allclose(ch["x"], time)  # the time column rules
    with pytest.raises(RecordingError, match=r"do not overlap|overlap by less"):
        _align([("x", time.copy(), stale + 5.0)], time=time, exact=True)


def test_errors_name_the_column():
    t = np.arange(10) / 10.0
    with pytest.raises(RecordingError, match=r"'X'.*not strictly increasing"):
        _align([("x", t, t[::-1].copy()), ("y", t, t)])
    with pytest.raises(RecordingError, match=r"'Y'.*has 5 samples"):
        _align([("x", t, t), ("y", t[:5], None)], time=t)
    with pytest.raises(RecordingError, match=r"do not overlap.*X 0\.\.0\.9 s"):
        _align([("x", t, t), ("y", t, t + 10.0)])


def test_a_non_uniform_time_base_names_the_file_and_the_remedy():
    from rollerrig.recordings.recording import Recording, RecordingError
    from rollerrig.recordings.timebase import require_uniform_time

    t = np.arange(5000) / 250.0 + np.random.default_rng(0).normal(0, 2e-4, 5000)
    with pytest.raises(RecordingError) as info:
        require_uniform_time(t, "runs/jitter.csv", "the filter study")
    text = str(info.value)
    assert text.startswith("runs/jitter.csv: the filter study needs samples on a uniform")
    assert "resample_Hz = 250 in the channel map's [time] section (--channels)" in text

    from rollerrig.measure.prepare import fill_short_gaps

    rec = Recording(np.sort(t), {"torque": np.ones(5000)}, {"torque": "N.m"}, {"source": "j.csv"})
    uniform, notes = fill_short_gaps(rec)
    assert require_uniform_time(uniform.time, "j.csv", "x") == pytest.approx(250.0, rel=0.02)
    assert uniform.time[-1] <= rec.time[-1] and "irregular sample times" in notes[0]


def test_the_rate_of_rounded_time_stamps_is_the_spans():
    """600 Hz written with 5 decimals (0.00167, 0.00166, ... s): the median step said
    598.8 Hz, every frequency of a spectrum 0.2 % low; the span says 600 Hz to 1e-6. Written
    with 3 decimals the stamps are no uniform base, and the advice names 600 Hz, not the
    median step's 500 Hz."""
    from rollerrig.recordings.timebase import require_uniform_time
    from rollerrig.recordings.uniform import uniform_sample_rate

    t = np.round(np.arange(12_001) / 600.0, 5)
    assert uniform_sample_rate(t) == pytest.approx(600.0, rel=1e-6)
    with pytest.raises(RecordingError, match="resample_Hz = 600 "):
        require_uniform_time(np.round(np.arange(12_001) / 600.0, 3), "run.csv", "the spectrum")


def test_a_nan_time_stamp_or_values_of_another_length_are_refused():
    """A NaN stamp had given a rate of NaN or of 250 Hz; a series half as long as its time had
    been resampled as if it spanned it (40 % off on the FIR path, silently)."""
    from rollerrig._validation import ParameterError
    from rollerrig.recordings.timebase import resample_onto
    from rollerrig.recordings.uniform import uniform_sample_rate

    for time in ([0, 0.004, 0.008, np.nan], [0, 0.004, np.nan, 0.012]):
        with pytest.raises(ParameterError, match="strictly increasing"):
            uniform_sample_rate(time)
    t = np.arange(2000) / 1000.0
    for target in (np.arange(100, 900) / 250.0 / 4, np.arange(10, 90) / 100.0):
        with pytest.raises(ParameterError, match=r"values \(1000,\) and time \(2000,\)"):
            resample_onto(np.linspace(0.0, 1.0, 1000), t, target)


def test_stamps_rounded_to_whole_microseconds_are_a_uniform_base():
    """19.2 kHz written to whole µs steps by 52 and 53 µs, 1.9 % apart: the in-memory check
    refused it as jitter while the streamed reader took it at the median step's 19 231 Hz
    (0.16 % off, silently; a review, 2026-12-03). Every stamp lies within 0.5 µs of the
    19 200 Hz grid: a uniform base at the span's rate. The same resolution on stamps that
    jitter by 20 µs stays non-uniform."""
    from rollerrig.recordings.timebase import require_uniform_time
    from rollerrig.recordings.uniform import print_resolution, rounded_grid

    t = np.round(np.arange(50_000) / 19_200.0, 6)
    assert np.ptp(np.diff(t)) > 0.018 * np.median(np.diff(t))  # not uniform by its steps
    assert print_resolution(t) == 1e-6 and rounded_grid(t)
    assert require_uniform_time(t, "run.csv", "the spectrum") == pytest.approx(19_200.0, rel=1e-6)
    assert Recording(t, {"torque": np.zeros(t.size)}, {"torque": "N.m"}).sample_rate == (
        pytest.approx(19_200.0, rel=1e-6)
    )
    jitter = np.round(np.arange(5000) / 250.0 + np.random.default_rng(1).normal(0, 2e-5, 5000), 6)
    assert not rounded_grid(jitter)
    with pytest.raises(RecordingError, match="non-uniform"):
        require_uniform_time(jitter, "run.csv", "the spectrum")
    # A resolution coarser than ROUNDED_GRID_LIMIT of a step is not taken for rounding.
    assert not rounded_grid(np.round(np.arange(12_001) / 600.0, 3))


def test_a_recordings_rate_is_its_uniform_bases_not_its_median_step():
    """600 Hz written with 5 decimals: Recording.sample_rate, which the spectrum and the
    streamed analysis use, was 1 over the median step, 598.8 Hz (a 100 Hz tone at 99.8 Hz,
    a review, 2026-12-03); a base with jitter keeps the median step's rate."""
    t = np.round(np.arange(12_001) / 600.0, 5)
    rec = Recording(t, {"torque": np.zeros(t.size)}, {"torque": "N.m"})
    assert 1.0 / np.median(np.diff(t)) == pytest.approx(598.8, abs=0.05)
    assert rec.sample_rate == pytest.approx(600.0, rel=1e-6)
    jittered = np.arange(5000) / 250.0 + np.random.default_rng(0).normal(0, 2e-4, 5000)
    rec = Recording(np.sort(jittered), {"torque": np.zeros(5000)}, {"torque": "N.m"})
    assert rec.sample_rate == pytest.approx(1.0 / np.median(np.diff(np.sort(jittered))))


def test_jittered_epoch_stamps_are_not_taken_for_a_rounded_grid():
    """Unrounded ``time.time()`` floats near 1.7e9 s: their round-off (0.24 µs) made every
    finer resolution "fit", and a jitter of 7 µs at 1 kHz passed as a rounded uniform grid
    (a review, 2026-12-03). The floats cannot show a resolution their round-off exceeds."""
    from rollerrig.recordings.uniform import print_resolution, rounded_grid

    rng = np.random.default_rng(0)
    for rate in (1000.0, 5000.0):
        t = 1.7e9 + np.arange(5000) / rate + rng.normal(0.0, 7e-6, 5000)
        assert print_resolution(t) == 0.0 and not rounded_grid(t)
