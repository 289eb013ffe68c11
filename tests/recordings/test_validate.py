"""Validation of a recording at the boundary (rollerrig.recordings.validate), on samples built here:
time strictly increasing, NaN/inf runs (strict: an error naming them; lenient: short runs
interpolated, exact on a linear signal), gaps (an interval over GAP_FACTOR x the median)."""

import numpy as np
import pytest

from rollerrig.recordings.recording import RecordingError
from rollerrig.recordings.validate import (
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


# ----------------------------------------------------- absurd rates (issue 24, point 7)


def _picosecond_csv(path, n=1000):
    """A time column in picoseconds written as seconds: 1e12 Hz."""
    rows = ["time [s],torque [N.m]"] + [f"{k * 1e-12!r},{np.sin(k / 10)}" for k in range(n)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_a_rate_above_the_limit_is_refused_naming_the_limit(tmp_path):
    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.source import open_recording
    from rollerrig.recordings.validate import MAX_SAMPLE_RATE_HZ

    path = _picosecond_csv(tmp_path / "ps.csv")
    for read in (read_recording, open_recording):
        with pytest.raises(RecordingError, match=r"sampling rate 1e\+12 Hz .* limit of 1e\+08"):
            read(path)
    assert MAX_SAMPLE_RATE_HZ == 1e8


@pytest.mark.parametrize("key", ["sample_rate_Hz", "resample_Hz"])
def test_a_channel_map_stating_an_absurd_rate_is_refused_before_reading(tmp_path, key):
    from rollerrig._validation import ParameterError
    from rollerrig.recordings.channels import load_channel_map

    cmap = tmp_path / "map.toml"
    time = f"{key} = 1e12" if key == "sample_rate_Hz" else f'column = "t"\n{key} = 1e12'
    cmap.write_text(f'[time]\n{time}\n[channels.torque]\ncolumn = "T"\nunit = "N.m"\n')
    with pytest.raises(ParameterError, match=rf"time\.{key}: must be <= 100000000 \[Hz\]"):
        load_channel_map(cmap)


def test_no_time_base_is_built_beyond_the_grid_limit():
    from rollerrig.recordings.validate import MAX_GRID_SAMPLES, check_grid

    assert check_grid(10.0, 1000.0, "x:", "test") == 10_001
    with pytest.raises(RecordingError, match=r"would hold 1e\+12 samples, above the limit of"):
        check_grid(1e4, 1e8, "x:", "[time] resample_Hz")
    assert MAX_GRID_SAMPLES == 2**28


def test_resampling_onto_a_grid_beyond_the_limit_is_refused_before_allocating(tmp_path):
    """A 1 kHz and a 100 Hz channel resampled onto 1e8 Hz over 1e4 s: 1e12 samples (8 TB)."""
    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.writers import write_recording

    t = np.arange(10_001) * 1.0  # 1 Hz over 1e4 s
    rec = Recording(t, {"torque": np.sin(t)}, {"torque": "N.m"})
    path = write_recording(rec, tmp_path / "long.csv")
    cmap = {"time": {"column": "time", "unit": "s", "resample_Hz": 1e8},
            "channels": {"torque": {"column": "torque", "unit": "N.m"}}}  # fmt: skip
    with pytest.raises(RecordingError, match=r"1e\+08 Hz time base over 10000 s .*MAX_GRID"):
        read_recording(path, cmap)


def test_a_time_without_a_unit_that_looks_like_ms_is_a_warning_naming_the_file(tmp_path):
    import warnings

    from rollerrig._warnings import DomainWarning
    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.source import open_recording

    rows = [f"{4 * k},{k % 7}" for k in range(3000)]  # 250 Hz in ms, header without a unit
    ms = tmp_path / "ms_nounit.csv"
    ms.write_text("time,torque [N.m]\n" + "\n".join(rows) + "\n")
    for read in (read_recording, open_recording):
        with pytest.warns(DomainWarning, match="looks like milliseconds") as caught:
            got = read(ms)
            if read is open_recording:
                got.close()
        text = str(caught[0].message)
        assert str(ms) in text and 'unit = "ms"' in text and '"time [ms]"' in text
    stated = tmp_path / "ms_unit.csv"
    stated.write_text("time [ms],torque [N.m]\n" + "\n".join(rows) + "\n")
    seconds = tmp_path / "s_nounit.csv"
    seconds.write_text(
        "time,torque [N.m]\n" + "\n".join(f"{k / 250},{k % 7}" for k in range(3000)) + "\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", DomainWarning)
        assert read_recording(stated).time[-1] == pytest.approx(11.996)
        assert read_recording(seconds).time[-1] == pytest.approx(11.996)
        assert read_recording(ms, {"time": {"column": "time", "unit": "s"},
            "channels": {"torque": {"column": "torque"}}}).time[-1] == 11996  # fmt: skip


def test_a_recording_leaves_its_callers_arrays_writable():
    """Recording froze the caller's float arrays (setflags on them, not on a view)."""
    from rollerrig.recordings.recording import Recording

    x, t = np.zeros(5), np.arange(5) / 250.0
    rec = Recording(t, {"x": x}, {"x": "N.m"})
    x[0] = np.nan  # and what the caller writes later does not reach the checked recording
    t[2] = np.nan
    assert not rec["x"].flags.writeable and not rec.time.flags.writeable
    assert np.all(np.isfinite(rec["x"])) and np.all(np.isfinite(rec.time))
    frozen = np.arange(5.0)
    frozen.setflags(write=False)  # a reader's read-only array is shared, not copied
    assert np.shares_memory(Recording(np.arange(5) / 250.0, {"x": frozen},
                                      {"x": "N.m"})["x"], frozen)  # fmt: skip


def test_find_gaps_refuses_time_that_is_not_strictly_increasing():
    """Unsorted time had given a wrong median and a "gap" over a step back, silently; a
    repeated instant a median of 0 and a ZeroDivisionError."""
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape(
        "time must be strictly increasing [s]; got time[2] = 0.1 after time[1] = 0.5"
    )):  # fmt: skip
        find_gaps(np.array([0.0, 0.5, 0.1, 0.2, 0.3]))
    with pytest.raises(ParameterError, match=re.escape("got time[1] = 0 after time[0] = 0")):
        find_gaps(np.array([0.0, 0.0, 0.0, 0.1]))
    with pytest.raises(ParameterError, match=re.escape("time must be finite [s]")):
        find_gaps(np.array([0.0, np.nan, 0.2]))
    with pytest.raises(ParameterError, match=re.escape("time must hold at least 2 samples")):
        find_gaps(np.array([0.0]))  # no interval: a NaN median had come back, with a warning


def test_a_recording_refuses_complex_values_naming_the_channel():
    """A complex channel (or time) had lost its imaginary part in the conversion to float,
    silently; one whose imaginary parts are all zero is taken as real."""
    import re

    from rollerrig._validation import ParameterError
    from rollerrig.recordings.recording import Recording

    t = np.arange(5) / 250.0
    x = np.array([1.0, 2.0, 3.0 + 0.5j, 4.0, 5.0])
    with pytest.raises(ParameterError, match=re.escape(
        "channel 'x' must be real, got complex values: (3+0.5j) at sample 2 (1 of 5 samples "
        "with an imaginary part)"
    )):  # fmt: skip
        Recording(t, {"x": x}, {"x": "N.m"})
    with pytest.raises(ParameterError, match=re.escape("time must be real, got complex values")):
        Recording(t + 1e-3j, {"x": x.real}, {"x": "N.m"})
    real = x.real + 0j
    rec = Recording(t + 0j, {"x": real}, {"x": "N.m"})
    assert rec["x"].dtype == float and rec.time.dtype == float
    assert rec["x"].tolist() == [1.0, 2.0, 3.0, 4.0, 5.0]
    real[0] = 9.0  # a writable array given is copied, as a float one is
    assert rec["x"][0] == 1.0 and real.flags.writeable
    with pytest.raises(ParameterError, match="channel 'x' must hold numbers"):
        Recording(t, {"x": ["a"] * 5}, {"x": "N.m"})
