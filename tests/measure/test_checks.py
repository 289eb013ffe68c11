"""Refusals of recordings an analysis cannot compute with (rollerrig.measure.checks): each names
the file, the channel, its file column and map entry, and what to change."""

import numpy as np
import pytest

from rollerrig.measure.checks import (
    check_channel_values,
    require_adhesion_test,
    require_analysis_inputs,
)
from rollerrig.measure.segmentation import segment_test
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.rig.parameters import default_rig


def _recording(torque, **extra) -> Recording:
    t = np.arange(2000) / 250.0
    channels = {"torque": np.broadcast_to(torque, t.shape), "normal_load": 4300.0 + 0 * t}
    channels.update(extra)
    units = {"torque": "N.m", "normal_load": "N", **{k: "rad/s" for k in extra}}
    return Recording(t, channels, units, {"source": "flat.csv", "columns": {"torque": "Tq"}})


def test_values_beyond_the_torque_sensor_range_are_refused():
    rig = default_rig()
    with pytest.raises(RecordingError, match="torque sensor's range"):
        check_channel_values(_recording(5e5), ["torque"], rig)
    check_channel_values(_recording(500.0), ["torque", "absent"], rig)


def test_nan_and_overflowing_values_name_the_column_and_map_entry():
    x = np.full(2000, 100.0)
    x[7] = np.nan
    with pytest.raises(RecordingError, match=r"flat.csv: channel 'torque' \(map entry "):
        check_channel_values(_recording(x), ["torque"])
    with pytest.raises(RecordingError, match=r"file column 'Tq'\).*squares overflow"):
        check_channel_values(_recording(1e300), ["torque"])


def test_a_derived_channel_is_named_as_derived_with_what_to_check():
    """A recording whose normal load is 0 (a pressure channel scaled to 0): the CoA the
    analysis computes is NaN; the message said "map entry [channels.coa]" (no such entry)
    and suggested --lenient, which cannot help."""
    from rollerrig.measure.quantities import derive_quantities

    rec = _recording(500.0)
    rec = Recording(rec.time, {**rec.channels, "normal_load": 0.0 * rec.time}, rec.units,
                    rec.metadata)  # fmt: skip
    derived = derive_quantities(rec, default_rig())
    with pytest.raises(RecordingError, match=r"derived channel 'coa' \(from the torque") as err:
        check_channel_values(derived, ["coa"])
    assert "map entry" not in str(err.value) and "--lenient" not in str(err.value)
    assert "normal load is <= 0 N" in str(err.value)


def test_missing_inputs_name_the_map_entries_to_add():
    with pytest.raises(RecordingError) as err:
        require_analysis_inputs(_recording(1.0))
    text = str(err.value)
    assert text.startswith("flat.csv: an adhesion-test analysis needs")
    assert "[channels.roller_speed] or [channels.roller_encoder_counts]" in text
    assert "normal load" not in text  # that one is there
    speeds = {"roller_speed": np.ones(2000), "wheel_speed": np.ones(2000)}
    require_analysis_inputs(_recording(1.0, **speeds))


def test_a_torque_without_a_ramp_is_no_adhesion_test():
    flat = _recording(100.0)
    with pytest.raises(RecordingError, match=r"no adhesion test found.*'torque'.*'Tq'"):
        require_adhesion_test(flat, segment_test(flat))
    t = flat.time
    ramp = _recording(np.interp(t, [0, 2, 5, 5.1, 8], [0, 0, 600, 0, 0]))
    require_adhesion_test(ramp, segment_test(ramp))
