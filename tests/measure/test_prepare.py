"""A recording brought to a uniform time base at the analysis rate (rollerrig.measure.prepare).

References: linear interpolation is exact on a linear signal (gaps filled without error); the
anti-alias decimation keeps a 3 Hz tone and removes a 2.35 kHz one by >= 70 dB (the FIR's
stop band, rollerrig.signal.decimate).
"""

import numpy as np
import pytest

from rollerrig.measure.prepare import (
    ANALYSIS_RATE,
    DECIMATE_ABOVE,
    analysis_rate_facts,
    analysis_recording,
    fill_short_gaps,
    nominal_rate,
)
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.validate import MAX_INTERPOLATED_NAN_RUN
from rollerrig.recordings.writers import write_recording


def _with_gap(missing: int) -> Recording:
    t = np.arange(200) / 250.0
    keep = np.ones(t.size, dtype=bool)
    keep[100 : 100 + missing] = False
    return Recording(
        t[keep], {"torque": 3.0 + 2.0 * t[keep]}, {"torque": "N.m"}, {"source": "gappy.csv"}
    )


def test_short_gap_is_filled_exactly_and_noted():
    rec, notes = fill_short_gaps(_with_gap(MAX_INTERPOLATED_NAN_RUN))
    assert rec.time.size == 200
    np.testing.assert_allclose(np.diff(rec.time), 1 / 250.0, rtol=1e-9)
    np.testing.assert_allclose(rec["torque"], 3.0 + 2.0 * rec.time, rtol=0, atol=1e-12)
    assert len(notes) == 1 and notes[0].startswith("gappy.csv: gap of")
    assert f"about {MAX_INTERPOLATED_NAN_RUN} missing" in notes[0]
    assert rec.metadata["notes"][-1] == notes[0]


def test_long_gap_is_an_error_naming_it():
    with pytest.raises(RecordingError, match=r"gappy.csv: gap of .* too long to fill"):
        fill_short_gaps(_with_gap(MAX_INTERPOLATED_NAN_RUN + 1))


def test_uniform_recording_is_returned_as_it_is():
    rec = _with_gap(0)
    same, notes = fill_short_gaps(rec)
    assert same is rec and notes == []


def test_analysis_recording_streams_a_source_and_equals_the_whole_decimation(tmp_path):
    from rollerrig.recordings.source import open_recording

    t = np.arange(40_000) / 19_200.0
    torque = 100.0 + 10.0 * np.sin(2 * np.pi * 3.0 * t) + 2.0 * np.sin(2 * np.pi * 2350.0 * t)
    rec = Recording(t, {"torque": torque}, {"torque": "N.m"})
    path = write_recording(rec, tmp_path / "fast.tdms")
    whole, note = analysis_recording(rec)
    with open_recording(path) as src:
        streamed, streamed_note = analysis_recording(src)
    assert round(whole.sample_rate) == round(streamed.sample_rate) == ANALYSIS_RATE
    np.testing.assert_allclose(streamed["torque"], whole["torque"], rtol=0, atol=1e-9)
    assert "decimated first" in note and "while streaming it from the file" in streamed_note
    # the 2.35 kHz line is gone (>= 70 dB down), the 3 Hz one kept
    residual = whole["torque"] - (100.0 + 10.0 * np.sin(2 * np.pi * 3.0 * whole.time))
    assert np.max(np.abs(residual[50:-50])) < 2.0 * 10 ** (-70 / 20) + 1e-3
    same, none = analysis_recording(whole)
    assert same is whole and none is None
    facts = analysis_rate_facts(whole)
    assert facts["rate [Hz]"] == 1000.0 and facts["recording rate [Hz]"] == 19200.0
    assert facts["decimated above [Hz]"] == DECIMATE_ABOVE and facts["decimation"]


def test_nominal_rate_rounds_to_ten_digits():
    t = np.arange(5) * (1 / 19200.0 + 1e-18)
    assert nominal_rate(Recording(t, {}, {})) == 19200.0
    facts = analysis_rate_facts(Recording(np.arange(5) / 250.0, {}, {}))
    assert facts["decimation"] is None and "not faster than" in facts["decimation_null_because"]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rate": 5.0}, r"rate must lie in \[250, inf\)"),
        ({"rate": float("nan")}, "rate must be finite"),
        ({"above": -1.0}, "above must be > 0"),
    ],
)
def test_an_analysis_rate_below_the_rigs_modes_is_refused(kwargs, message):
    """5 Hz had returned 5 samples a second of a 19.2 kHz test; 1e-3 Hz tried to allocate
    6 GiB."""
    from rollerrig._validation import ParameterError

    t = np.arange(19200) / 19200.0
    rec = Recording(t, {"torque": 100.0 + t}, {"torque": "N.m"})
    with pytest.raises(ParameterError, match=message):
        analysis_recording(rec, **kwargs)
