"""Binary recordings as real acquisition software writes them: TDMS and MDF4 fixtures.

Every fixture is written here with the library the tools' files are read with (nptdms
``TdmsWriter``, asammdf ``MDF.append``), with the properties and layout of the tool it mimics
(each builder says which). Expected values follow from the fixture's construction: linear ramps
are reproduced exactly by linear interpolation, unit factors from the SI Brochure (1 kN.m =
1e3 N.m, 1 bar = 1e5 Pa).
"""

from __future__ import annotations

import hashlib
import os

import numpy as np
import pytest

from rollerrig.recordings.formats._table import apply_default_group
from rollerrig.recordings.formats.mdf import open_mdf
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import RecordingError
from rollerrig.recordings.source import open_recording

T0 = np.datetime64("2024-08-05T13:46:13.250000", "us")


def _fingerprint(path):
    st = os.stat(path)
    return hashlib.sha256(path.read_bytes()).hexdigest(), st.st_mtime_ns, st.st_size


# --------------------------------------------------------------------------- fixture builders


def labview_waveforms(path, *, n=2000, rate=1000.0, segments=4):
    """LabVIEW "Write to Measurement File"/TDMS Write of waveform data, one loop per segment.

    Mimics: every channel carries the waveform attributes LabVIEW writes (``wf_start_time`` as a
    TDMS timestamp, ``wf_start_offset`` 0, ``wf_increment``, ``wf_samples`` = samples per write),
    ``unit_string`` and ``NI_ChannelName``; the file grows by one segment per loop iteration.
    Group "Rig" holds torque (kN.m) and speed (rpm); both are linear ramps in time.
    """
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    per = n // segments
    t = np.arange(n) / rate
    torque = 0.5 + 0.1 * t  # kN.m
    speed = 300.0 + 10.0 * t  # rpm
    common = {
        "wf_start_time": T0,
        "wf_start_offset": 0.0,
        "wf_increment": 1.0 / rate,
        "wf_samples": per,
    }
    with TdmsWriter(str(path)) as w:
        for k in range(segments):
            s = slice(k * per, (k + 1) * per)
            w.write_segment(
                [
                    RootObject({"name": "run 12", "Author": "rig"}),
                    GroupObject("Rig"),
                    ChannelObject(
                        "Rig",
                        "Torque",
                        torque[s],
                        properties={
                            **common,
                            "unit_string": "kNm",
                            "NI_ChannelName": "Torque_Roller",
                        },
                    ),
                    ChannelObject(
                        "Rig",
                        "Speed",
                        speed[s],
                        properties={**common, "unit_string": "rpm", "NI_ChannelName": "n_roller"},
                    ),
                ]
            )
    return t, torque, speed


def daqmx_two_tasks(path, *, seconds=2.0, fast=19200.0, slow=10.0, start_lag_s=0.0125):
    """DAQmx TDMS logging of two tasks: torque at 19.2 kHz (HBM QuantumX rate) and pressure at
    10 Hz, one group per task, each task started on its own (the pressure task
    ``start_lag_s`` later, so its ``wf_start_time`` differs), data logged every 0.5 s.

    The torque holds a 50 Hz tone and a 3 kHz tone (above the Nyquist frequency of a 1 kHz
    common base); the pressure is a ramp in bar.
    """
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    n_fast, n_slow = int(seconds * fast), int(seconds * slow)
    t_fast = np.arange(n_fast) / fast
    t_slow = start_lag_s + np.arange(n_slow) / slow
    torque = 0.2 * np.sin(2 * np.pi * 50.0 * t_fast) + 0.05 * np.sin(2 * np.pi * 3000.0 * t_fast)
    pressure = 2.0 + 0.1 * t_slow  # bar
    lag = np.timedelta64(round(start_lag_s * 1e6), "us")
    wf_fast = {"wf_start_time": T0, "wf_start_offset": 0.0, "wf_increment": 1.0 / fast}
    wf_slow = {"wf_start_time": T0 + lag, "wf_start_offset": 0.0, "wf_increment": 1.0 / slow}
    blocks = 4
    with TdmsWriter(str(path)) as w:
        for k in range(blocks):
            f = slice(k * n_fast // blocks, (k + 1) * n_fast // blocks)
            s = slice(k * n_slow // blocks, (k + 1) * n_slow // blocks)
            w.write_segment(
                [
                    RootObject({"name": "daqmx"}),
                    GroupObject("Torque Task"),
                    GroupObject("Pressure Task"),
                    ChannelObject(
                        "Torque Task",
                        "T56",
                        torque[f],
                        properties={
                            **wf_fast,
                            "wf_samples": f.stop - f.start,
                            "unit_string": "kNm",
                            "NI_ChannelName": "cDAQ1Mod1/ai0",
                        },
                    ),
                    ChannelObject(
                        "Pressure Task",
                        "p_air",
                        pressure[s],
                        properties={
                            **wf_slow,
                            "wf_samples": s.stop - s.start,
                            "unit_string": "bar",
                            "NI_ChannelName": "cDAQ1Mod2/ai0",
                        },
                    ),
                ]
            )
    return t_fast, torque, t_slow, pressure


def inca_multigroup(path):
    """INCA / CANape MDF4 measurement: one data group per acquisition raster.

    Mimics: every group has its own master channel named ``time``; the raster is the group's
    acquisition name ("1ms", "100ms"), the comment names the raster, the source names the ECU
    / device; ``Torque`` is recorded in two rasters (1 kHz and 10 Hz); a third raster group
    was configured but recorded nothing (zero records), as INCA writes for an unused raster.
    Signals are ramps: Torque = 0.2 + 0.1 t [kNm], n_roll = 100 t [rpm], p_air = 2 + t [bar].
    """
    from asammdf import MDF, Signal
    from asammdf.blocks import v4_constants as v4c
    from asammdf.blocks.source_utils import Source

    t1 = np.arange(3000) / 1000.0
    t2 = np.arange(30) / 10.0
    mdf = MDF(version="4.10")
    ecu = Source("QuantumX", "QX/1", "HBM QuantumX", v4c.SOURCE_ECU, v4c.BUS_TYPE_NONE)
    mdf.append(
        [
            Signal(0.2 + 0.1 * t1, t1, name="Torque", unit="kNm"),
            Signal(100.0 * t1, t1, name="n_roll", unit="rpm"),
        ],
        acq_name="1ms",
        acq_source=ecu,
        comment="raster 1 ms",
    )
    mdf.append(
        [
            Signal(0.2 + 0.1 * t2, t2, name="Torque", unit="kNm"),
            Signal(2.0 + t2, t2, name="p_air", unit="bar"),
        ],
        acq_name="100ms",
        comment="raster 100 ms",
    )
    mdf.append(
        [Signal(np.zeros(0), np.zeros(0), name="T_motor", unit="Nm")],
        acq_name="10ms",
        comment="raster 10 ms (unused)",
    )
    mdf.save(path, overwrite=True)
    mdf.close()
    return t1, t2


def canedge_bus_log(path, *, with_signal=False):
    """CANedge-style bus logging: raw CAN frames (``CAN_DataFrame`` with ID, DLC, DataBytes) in a
    bus-event channel group whose source is a CAN bus, no decoded signals.

    ``with_signal`` adds a decoded analogue signal group beside it (a logger with an analogue
    input), as mixed files are written.
    """
    from asammdf import MDF, Signal
    from asammdf.blocks import v4_constants as v4c
    from asammdf.blocks.source_utils import Source

    n = 50
    t = np.cumsum(np.full(n, 0.01))
    dtype = np.dtype(
        [
            ("CAN_DataFrame.BusChannel", "u1"),
            ("CAN_DataFrame.ID", "<u4"),
            ("CAN_DataFrame.DLC", "u1"),
            ("CAN_DataFrame.DataLength", "u1"),
            ("CAN_DataFrame.DataBytes", "u1", (8,)),
        ]
    )
    frames = np.zeros(n, dtype=dtype)
    frames["CAN_DataFrame.BusChannel"] = 1
    frames["CAN_DataFrame.ID"] = 0x123
    frames["CAN_DataFrame.DLC"] = 8
    frames["CAN_DataFrame.DataLength"] = 8
    frames["CAN_DataFrame.DataBytes"] = np.arange(8)
    bus = Source("CAN1", "CAN1", "CANedge", v4c.SOURCE_BUS, v4c.BUS_TYPE_CAN)
    mdf = MDF(version="4.11")
    mdf.append([Signal(frames, t, name="CAN_DataFrame")], acq_name="CAN1", acq_source=bus)
    mdf.groups[0].channel_group.flags |= v4c.FLAG_CG_BUS_EVENT
    if with_signal:
        mdf.append([Signal(2.0 + t, t, name="p_air", unit="bar")], acq_name="AIN")
    mdf.save(path, overwrite=True)
    mdf.close()


# --------------------------------------------------------------------------- TDMS


def test_labview_waveform_time_units_and_ni_channel_name(tmp_path):
    f = tmp_path / "labview.tdms"
    t, torque, speed = labview_waveforms(f)
    before = _fingerprint(f)
    rec = read_recording(
        f,
        {
            "channels": {
                "torque": {"column": "Torque_Roller"},  # NI_ChannelName; unit from the file
                "roller_speed": {"column": "Rig/Speed", "unit": "rpm"},
            }
        },
    )
    np.testing.assert_allclose(rec.time, t, atol=1e-12)
    np.testing.assert_allclose(rec["torque"], torque * 1e3, rtol=1e-12)
    np.testing.assert_allclose(rec["roller_speed"], speed * 2 * np.pi / 60, rtol=1e-12)
    assert any("2024-08-05T13:46:13.250000" in n for n in rec.metadata["notes"])
    assert "resampled" not in rec.metadata
    assert _fingerprint(f) == before


def test_daqmx_tasks_on_one_absolute_clock(tmp_path):
    f = tmp_path / "daqmx.tdms"
    _, _, t_slow, _ = daqmx_two_tasks(f)
    rec = read_recording(
        f,
        {
            "channels": {
                "torque": {"column": "T56"},
                "air_spring_pressure": {"column": "p_air"},
            }
        },
    )
    # common base: the torque's own 19.2 kHz, trimmed to the span the pressure covers
    assert rec.sample_rate == pytest.approx(19200.0)
    assert rec.time[0] == pytest.approx(t_slow[0], abs=1 / 19200)
    assert rec.time[-1] <= t_slow[-1] + 1e-12
    # the pressure started 12.5 ms later (wf_start_time): a ramp lands exactly on its clock
    np.testing.assert_allclose(rec["air_spring_pressure"], (2.0 + 0.1 * rec.time) * 1e5, rtol=1e-9)
    res = rec.metadata["resampled"]
    assert res["channels"]["air_spring_pressure"]["method"] == "linear"
    assert res["channels"]["air_spring_pressure"]["from_rate_Hz"] == pytest.approx(10.0)
    assert any("wf_start_time" in n and "+0.0125 s" in n for n in rec.metadata["notes"])


def test_daqmx_resample_onto_1kHz_filters_what_would_alias(tmp_path):
    f = tmp_path / "daqmx.tdms"
    daqmx_two_tasks(f)
    rec = read_recording(
        f,
        {
            "time": {"resample_Hz": 1000.0},
            "channels": {"torque": {"column": "T56", "unit": "kN.m"}},
        },
    )
    assert rec.sample_rate == pytest.approx(1000.0)
    how = rec.metadata["resampled"]["channels"]["torque"]
    assert how["method"] == "fir_polyphase" and (how["up"], how["down"]) == (5, 96)
    # away from the ends: the 50 Hz tone is kept (within 1 %), the 3 kHz tone (it would alias to
    # 0 Hz... 500 Hz) is gone: the residual is below 1 % of its 0.05 kN.m amplitude (> 40 dB)
    mid = (rec.time > 0.2) & (rec.time < 1.8)
    t = rec.time[mid]
    expected = 0.2e3 * np.sin(2 * np.pi * 50.0 * t)
    residual = rec["torque"][mid] - expected
    assert np.max(np.abs(residual)) < 0.01 * 0.05e3
    assert np.max(np.abs(rec["torque"][mid])) == pytest.approx(0.2e3, rel=0.01)


def test_tdms_equal_length_different_increment_is_not_index_aligned(tmp_path):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    # two channels of 1000 samples each: 1 kHz and 100 Hz (LabVIEW waveforms of equal size)
    f = tmp_path / "rates.tdms"
    x = np.arange(1000, dtype=float)
    with TdmsWriter(str(f)) as w:
        w.write_segment(
            [
                RootObject(),
                GroupObject("G"),
                ChannelObject("G", "fast", x, properties={"wf_increment": 1e-3}),
                ChannelObject("G", "slow", x, properties={"wf_increment": 1e-2}),
            ]
        )
    rec = read_recording(
        f,
        {
            "channels": {
                "torque": {"column": "fast", "unit": "N.m"},
                "normal_load": {"column": "slow", "unit": "N"},
            }
        },
    )
    # on the torque's 1 kHz base: slow sample k is at 0.01 k s, so its value is 100 t
    np.testing.assert_allclose(rec["normal_load"], 100.0 * rec.time, atol=1e-9)
    np.testing.assert_allclose(rec["torque"], 1000.0 * rec.time, atol=1e-9)


def test_tdms_truncated_and_garbage_are_clear_errors(tmp_path):
    f = tmp_path / "labview.tdms"
    labview_waveforms(f, segments=1)  # one segment: a cut lands inside it
    data = f.read_bytes()
    cut = tmp_path / "cut.tdms"
    cut.write_bytes(data[: len(data) // 2])
    before = _fingerprint(cut)
    cmap = {"channels": {"torque": {"column": "Rig/Torque"}}}
    with pytest.raises(RecordingError, match=r"cut\.tdms: the TDMS file is truncated"):
        read_recording(cut, cmap)
    assert _fingerprint(cut) == before
    tiny = tmp_path / "tiny.tdms"
    tiny.write_bytes(data[:40])  # the lead-in only
    with pytest.raises(RecordingError, match=r"tiny\.tdms"):
        read_recording(tiny, cmap)
    junk = tmp_path / "junk.tdms"
    junk.write_bytes(np.random.default_rng(1).bytes(3000))
    with pytest.raises(RecordingError, match=r"junk\.tdms: not a readable TDMS file"):
        read_recording(junk, cmap)


def _plain_tdms(path, channels, *, index_file=False, rate=250.0):
    """A one-group TDMS file ("g") of waveform channels {name: (values, unit)} (nptdms)."""
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    objects = [RootObject({}), GroupObject("g")]
    for name, (values, unit) in channels.items():
        props = {"unit_string": unit}
        if len(values):
            props["wf_increment"] = 1.0 / rate
        objects.append(ChannelObject("g", name, np.asarray(values, dtype=float), properties=props))
    with TdmsWriter(str(path), index_file=index_file) as w:
        w.write_segment(objects)


def test_tdms_stale_index_file_is_ignored_and_noted(tmp_path):
    full = tmp_path / "run.tdms"
    x = np.arange(7501, dtype=float)
    _plain_tdms(full, {"torque": (x, "N.m"), "speed": (2 * x, "rpm")})
    old = tmp_path / "old.tdms"  # an older, shorter run: its index left beside the new file
    _plain_tdms(old, {"torque": (x[:2500], "N.m")}, index_file=True)
    (tmp_path / "old.tdms_index").rename(tmp_path / "run.tdms_index")
    cmap = {"channels": {"torque": {"column": "torque"}}}
    rec = read_recording(full, cmap)
    assert rec.time.size == 7501
    np.testing.assert_array_equal(rec["torque"], x)
    notes = " ".join(rec.metadata["notes"])
    assert "'run.tdms_index'" in notes and "ignored" in notes and "stale" in notes
    assert "'g/torque' 2500 in the index, 7501 in the file" in notes
    # chunked reading goes through the same reader
    with open_recording(full, cmap, channels=["torque"]) as src:
        parts = [c["torque"] for c in src.iter_chunks(["torque"], 1000)]
    np.testing.assert_array_equal(np.concatenate(parts), x)


def test_tdms_agreeing_index_file_is_noted(tmp_path):
    f = tmp_path / "run.tdms"
    _plain_tdms(f, {"torque": (np.arange(100.0), "N.m")}, index_file=True)
    assert (tmp_path / "run.tdms_index").is_file()
    rec = read_recording(f, {"channels": {"torque": {"column": "torque"}}})
    assert rec.time.size == 100
    assert any("index agrees with the file" in n for n in rec.metadata["notes"])


def test_tdms_empty_channel_nobody_needs_is_skipped(tmp_path):
    f = tmp_path / "spare.tdms"
    x = np.arange(500.0)
    _plain_tdms(f, {"torque": (x, "N.m"), "Spare AI7": ([], "V")})
    rec = read_recording(f)  # no map: every column of the file is looked at
    np.testing.assert_array_equal(rec["torque"], x)
    assert any("'g/Spare AI7'" in n and "without samples" in n for n in rec.metadata["notes"])
    # a map entry that is needed and names the empty channel stays an error
    for column in ("Spare AI7", "g/Spare AI7"):
        with pytest.raises(RecordingError, match=r"'g/Spare AI7' holds no samples"):
            read_recording(f, {"channels": {"torque": {"column": column, "unit": "N.m"}}})


def test_tdms_empty_canonical_channel_is_an_error(tmp_path):
    f = tmp_path / "empty_torque.tdms"
    _plain_tdms(f, {"torque": ([], "N.m"), "normal_load": (np.arange(50.0), "N")})
    with pytest.raises(RecordingError, match=r"'g/torque' holds no samples"):
        read_recording(f)


def test_tdms_empty_canonical_channel_the_caller_does_not_need_is_a_note(tmp_path):
    """A command that needs only the torque (``rollerrig filters``, ``spectrum``) reads a file
    whose canonical torque_request channel was created but never written: the empty channel
    is noted, not an error (it stopped those commands); a caller needing it still gets the
    error."""
    f = tmp_path / "empty_request.tdms"
    x = np.arange(50.0)
    _plain_tdms(f, {"torque": (x, "N.m"), "torque_request": ([], "N.m")})
    rec = read_recording(f, channels=["torque"])
    np.testing.assert_array_equal(rec["torque"], x)
    assert "torque_request" not in rec.channels
    assert any(
        "'g/torque_request' (not needed here) not read" in n and "holds no samples" in n
        for n in rec.metadata["notes"]
    )
    with pytest.raises(RecordingError, match=r"'g/torque_request' holds no samples"):
        read_recording(f, channels=["torque", "torque_request"])


# --------------------------------------------------------------------------- MDF4


def test_inca_plain_name_in_two_groups_is_ambiguous(tmp_path):
    f = tmp_path / "inca.mf4"
    inca_multigroup(f)
    with pytest.raises(RecordingError, match=r"'Torque', which is ambiguous.*'1ms/Torque'.*"):
        read_recording(f, {"channels": {"torque": {"column": "Torque"}}})
    with pytest.raises(RecordingError, match=r"100ms/Torque"):
        read_recording(f, {"channels": {"torque": {"column": "Torque"}}})


@pytest.mark.parametrize(
    "column, rate",
    [
        ("1ms/Torque", 1000.0),  # acquisition name
        ("0/Torque", 1000.0),  # data-group index
        ("raster 1 ms/Torque", 1000.0),  # group comment
        ("QuantumX/Torque", 1000.0),  # source name
        ("100ms/Torque", 10.0),
        ("1/Torque", 10.0),
    ],
)
def test_inca_group_qualified_names(tmp_path, column, rate):
    f = tmp_path / "inca.mf4"
    inca_multigroup(f)
    rec = read_recording(f, {"channels": {"torque": {"column": column}}})
    assert rec.sample_rate == pytest.approx(rate)
    np.testing.assert_allclose(rec["torque"], (0.2 + 0.1 * rec.time) * 1e3, rtol=1e-12)
    assert rec.metadata["source_units"]["torque"] == "kNm"


def test_inca_rasters_onto_the_torque_base(tmp_path):
    f = tmp_path / "inca.mf4"
    inca_multigroup(f)
    # torque from the 100 ms raster: the 1 kHz speed is low-pass filtered and decimated onto it
    rec = read_recording(
        f,
        {
            "channels": {
                "torque": {"column": "100ms/Torque"},
                "roller_speed": {"column": "n_roll"},
                "air_spring_pressure": {"column": "p_air"},
            }
        },
    )
    assert rec.sample_rate == pytest.approx(10.0)
    how = rec.metadata["resampled"]["channels"]["roller_speed"]
    assert how["method"] == "fir_polyphase" and how["from_rate_Hz"] == pytest.approx(1000.0)
    assert "air_spring_pressure" not in rec.metadata["resampled"]["channels"]
    # a ramp passes the (unit-gain, linear-phase) filter unchanged away from the ends
    mid = slice(5, -5)
    np.testing.assert_allclose(
        rec["roller_speed"][mid], 100.0 * rec.time[mid] * 2 * np.pi / 60, rtol=1e-3
    )
    # torque from the 1 ms raster: the 10 Hz pressure is interpolated onto 1 kHz
    rec = read_recording(
        f,
        {
            "channels": {
                "torque": {"column": "1ms/Torque"},
                "air_spring_pressure": {"column": "p_air"},
            }
        },
    )
    assert rec.sample_rate == pytest.approx(1000.0)
    assert rec.metadata["resampled"]["channels"]["air_spring_pressure"]["method"] == "linear"
    np.testing.assert_allclose(rec["air_spring_pressure"], (2.0 + rec.time) * 1e5, rtol=1e-12)
    assert rec.time[-1] == pytest.approx(2.9)  # trimmed to the 100 ms raster's span


def test_inca_empty_group_is_a_clear_error(tmp_path):
    f = tmp_path / "inca.mf4"
    inca_multigroup(f)
    with pytest.raises(RecordingError, match=r"'T_motor' is in data group 2 .*no samples"):
        read_recording(f, {"channels": {"torque": {"column": "T_motor"}}})


def test_inca_file_group_makes_plain_names_resolve(tmp_path):
    f = tmp_path / "inca.mf4"
    inca_multigroup(f)
    for group, n in (("100ms", 30), (1, 30), ("1ms", 3000)):
        with open_mdf(f) as table:
            apply_default_group(table, group, f"{f}:")
            (name,) = table.aliases["Torque"]
            assert table.load(name).values.size == n
    with open_mdf(f) as table, pytest.raises(RecordingError, match=r"group = 'fast'.*'100ms'"):
        apply_default_group(table, "fast", f"{f}:")
    # through the channel map: names the group lacks still resolve in the file
    cmap = {
        "file": {"group": "100ms"},
        "channels": {"torque": {"column": "Torque"}, "roller_speed": {"column": "n_roll"}},
    }
    rec = read_recording(f, cmap)
    assert rec.sample_rate == pytest.approx(10.0)
    assert rec.metadata["columns"]["torque"] == "100ms/Torque"
    assert any("[file] group" in n for n in rec.metadata["notes"])


def test_canedge_raw_frames_say_decode_first(tmp_path):
    f = tmp_path / "canedge.mf4"
    canedge_bus_log(f)
    with pytest.raises(
        RecordingError, match=r"raw bus logging.*extract_bus_logging.*CAN_DataFrame"
    ):
        read_recording(f, {"channels": {"torque": {"column": "Torque"}}})
    mixed = tmp_path / "mixed.mf4"
    canedge_bus_log(mixed, with_signal=True)
    rec = read_recording(mixed, {"channels": {"air_spring_pressure": {"column": "p_air"}}})
    assert rec["air_spring_pressure"][0] == pytest.approx(2.01e5)
    with pytest.raises(RecordingError, match=r"not readable: \['raw bus frames"):
        read_recording(mixed, {"channels": {"torque": {"column": "Torque"}}})


# --------------------------------------------------------------------------- damaged files


def _good_file(tmp_path, fmt):
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.writers import write_recording

    t = np.arange(4000) / 250.0
    rec = Recording(t, {"torque": np.sin(t)}, {"torque": "N.m"})
    kw = {"mat_version": "7.3"} if fmt == "mat73" else {}
    suffix = {"mat73": ".mat", "mat5": ".mat"}.get(fmt, f".{fmt}")
    f = tmp_path / f"good{suffix}"
    write_recording(rec, f, **kw)
    return f


@pytest.mark.parametrize("fmt", ["tdms", "mf4", "parquet", "mat5", "mat73"])
@pytest.mark.parametrize("damage", ["half", "garbage", "empty"])
def test_damaged_files_are_recording_errors(tmp_path, fmt, damage):
    good = _good_file(tmp_path, fmt)
    data = good.read_bytes()
    bad = tmp_path / f"bad{good.suffix}"
    if damage == "half":
        bad.write_bytes(data[: len(data) // 2])
    elif damage == "garbage":
        bad.write_bytes(np.random.default_rng(7).bytes(len(data)))
    else:
        bad.write_bytes(b"")
    before = _fingerprint(bad)
    with pytest.raises(RecordingError, match=r"bad\."):
        read_recording(bad)
    assert _fingerprint(bad) == before


@pytest.mark.parametrize("suffix", [".tdms", ".mf4", ".mat", ".parquet", ".lvm"])
def test_an_empty_file_says_so(tmp_path, suffix):
    path = tmp_path / f"empty{suffix}"
    path.write_bytes(b"")
    with pytest.raises(RecordingError, match=r"the file is empty \(0 bytes\)"):
        read_recording(path, {"channels": {"torque": {"column": "T", "unit": "N.m"}}})


def test_mdf_samples_flagged_invalid_are_nan_where_they_were_logged(tmp_path):
    """MDF4 invalidation bits (a logger's 'this sample is not valid'): the samples stay in
    place as NaN, so strict reading names them and lenient reading interpolates them; asammdf
    drops them by default, which left the channel shorter than its time base (refused as a
    damaged file)."""
    from asammdf import MDF, Signal

    t = np.arange(2000) * 1e-3
    flagged = np.zeros(2000, dtype=bool)
    flagged[100:103] = True
    mdf = MDF(version="4.10")
    sig = Signal(np.sin(t), t, name="T", unit="N.m", invalidation_bits=flagged)
    mdf.append([sig], acq_name="fast")
    path = tmp_path / "flagged.mf4"
    mdf.save(path, overwrite=True)
    cmap = {"channels": {"torque": {"column": "T"}}}
    with pytest.raises(RecordingError, match=r"3 NaN/inf samples .* samples 100\.\.102"):
        read_recording(path, cmap)
    rec = read_recording(path, cmap, validate="lenient")
    assert rec["torque"].size == 2000
    np.testing.assert_allclose(rec["torque"][99:104], np.sin(t[99:104]), atol=1e-6)
    np.testing.assert_array_equal(rec["torque"][:100], np.sin(t[:100]))


def test_mdf_invalid_sample_of_a_slower_raster_is_checked_on_its_own_time_base(tmp_path):
    """One sample flagged invalid in the 100 ms group is one NaN sample of the file: it is
    checked and (lenient) interpolated on the group's own time base before the channel is
    resampled; resampled first, it had been a run of 199 NaN samples on the 1 ms base, which
    lenient reading refused as too long to interpolate."""
    from asammdf import MDF, Signal

    t1, t2 = np.arange(4000) * 1e-3, np.arange(40) * 0.1
    bad1, bad2 = np.zeros(t1.size, bool), np.zeros(t2.size, bool)
    bad1[2000] = bad2[20] = True
    mdf = MDF(version="4.10")
    mdf.append([Signal(100 + t1, t1, name="Trq", unit="Nm", invalidation_bits=bad1)], "1ms")
    mdf.append([Signal(3 + 0 * t2, t2, name="pAir", unit="bar", invalidation_bits=bad2)], "100ms")
    path = tmp_path / "invalid.mf4"
    mdf.save(path, overwrite=True)
    sha = hashlib.sha256(path.read_bytes()).hexdigest()
    cmap = {"channels": {"torque": {"column": "Trq"}, "air_spring_pressure": {"column": "pAir"}}}
    rec = read_recording(path, cmap, validate="lenient")
    assert np.isfinite(rec["air_spring_pressure"]).all()
    np.testing.assert_allclose(rec["air_spring_pressure"], 3e5)
    runs = {r["channel"]: r for r in rec.metadata["interpolated"]}
    assert (runs["air_spring_pressure"]["first_sample"], runs["torque"]["first_sample"]) == (
        20,
        2000,
    )
    assert "own time base" in runs["air_spring_pressure"]["time_base"]
    # resampled onto 200 Hz: strict names the one sample of the file, lenient reads
    resampled = {**cmap, "time": {"resample_Hz": 200}}
    with pytest.raises(
        RecordingError, match=r"1 NaN/inf samples .* samples 2000\.\.2000 of its own"
    ):
        read_recording(path, resampled)
    rec = read_recording(path, resampled, validate="lenient")
    assert rec.sample_rate == pytest.approx(200.0)
    assert np.isfinite(rec["torque"]).all() and np.isfinite(rec["air_spring_pressure"]).all()
    assert hashlib.sha256(path.read_bytes()).hexdigest() == sha


@pytest.mark.parametrize("same", [True, False], ids=["same-value", "other-value"])
def test_mdf_event_group_with_a_repeated_time_stamp(tmp_path, same):
    """Two CAN frames logged with one time stamp: the refusal 'its time base is not strictly
    increasing' named neither the group, the sample nor the time. A repeat of the stamp and
    the value is dropped (noted); another value is an error naming group, sample, time and
    what to do."""
    from asammdf import MDF, Signal

    t1 = np.arange(2000) * 1e-3
    tc = np.arange(200) * 0.01 + 0.0005
    tc[50] = tc[49]
    speed = np.full(tc.size, 600.0)
    if not same:
        speed[50] = 601.0
    mdf = MDF(version="4.10")
    mdf.append([Signal(100 + t1, t1, name="Trq", unit="Nm")], acq_name="1ms")
    mdf.append([Signal(speed, tc, name="nRoll", unit="rpm")], acq_name="CAN1")
    path = tmp_path / "can_dup.mf4"
    mdf.save(path, overwrite=True)
    sha = hashlib.sha256(path.read_bytes()).hexdigest()
    cmap = {"channels": {"torque": {"column": "Trq"}, "roller_speed": {"column": "nRoll"}}}
    if same:
        rec = read_recording(path, cmap)
        np.testing.assert_allclose(rec["roller_speed"], 600 * 2 * np.pi / 60)
        note = next(n for n in rec.metadata["notes"] if "repeating the time stamp" in n)
        assert "'CAN1'" in note and "sample 50" in note and "0.4905 s" in note
    else:
        with pytest.raises(
            RecordingError,
            match=r"'nRoll' in group .*'CAN1'.* repeats t = 0\.4905 s at sample 50 .*correct the",
        ):
            read_recording(path, cmap)
    assert hashlib.sha256(path.read_bytes()).hexdigest() == sha


def test_tdms_timestamp_time_channel_keeps_labview_resolution(tmp_path):
    """A time channel of LabVIEW timestamps (seconds since 1904 and 2^-64 s fractions, as
    DAQmx logging writes them) at 51.2 kS/s: the sample k is at exactly k/51200 s. Read as
    numpy's datetime64[us] (nptdms' default) the steps were 19 and 20 µs and the rate 50 000
    Hz; the stored fractions give k/51200 to the float. Its ``unit_string`` ("UTC") is no time
    unit of the seconds it becomes."""
    from nptdms import ChannelObject, TdmsWriter
    from nptdms.timestamp import TimestampArray

    rate, n = 51200.0, 5120
    start = 3_805_703_173  # 2024-08-05 11:46:13 in seconds since 1904-01-01
    frac = [(k << 64) // 51200 for k in range(n)]  # exact: 2^64 k / 51200, below one second
    stamps = np.zeros(n, dtype=[("second_fractions", "<u8"), ("seconds", "<i8")])
    stamps["seconds"] = start
    stamps["second_fractions"] = np.array(frac, dtype=np.uint64)
    torque = np.sin(2 * np.pi * 37 * np.arange(n) / rate)
    path = tmp_path / "daqmx.tdms"
    with TdmsWriter(path) as writer:
        writer.write_segment([
            ChannelObject("Log", "Time", TimestampArray(stamps), properties={"unit_string": "UTC"}),
            ChannelObject("Log", "Torque", torque, properties={"unit_string": "N.m"}),
        ])  # fmt: skip
    before = _fingerprint(path)
    rec = read_recording(path, {"time": {"column": "Log/Time"}, "channels": {
        "torque": {"column": "Log/Torque"}}})  # fmt: skip
    assert _fingerprint(path) == before
    np.testing.assert_allclose(rec.time, np.arange(n) / rate, rtol=0, atol=1e-15)
    assert rec.sample_rate == pytest.approx(rate, rel=1e-12)
    assert any("2024-08-05T11:46:13" in note for note in rec.metadata["notes"])


def test_mdf_unit_held_by_the_conversion_rule_is_the_channel_unit(tmp_path):
    """INCA and CANape often leave a channel's own unit empty and write it in its conversion
    rule (ASAM MDF 4: the rule's unit applies then): raw int16 counts x 0.001 in kN.m. It was
    refused ("got ''")."""
    from asammdf import MDF, Signal

    t = np.arange(300) / 1000.0
    raw = (np.arange(300) % 100).astype(np.int16)
    mdf = MDF(version="4.10")
    conversion = {"a": 0.001, "b": 0.0, "unit": "kNm"}
    mdf.append([Signal(raw, t, name="Trq", unit="", conversion=conversion)], acq_name="1ms")
    path = tmp_path / "inca.mf4"
    mdf.save(path, overwrite=True)
    rec = read_recording(path, {"channels": {"torque": {"column": "Trq"}}})
    np.testing.assert_allclose(rec["torque"], raw * 1.0)  # 0.001 kN.m = 1 N.m a count


def test_mdf_master_that_is_not_time_is_no_time_base(tmp_path):
    """An angle master (cn_sync_type 2, an engine bench recording over crank angle, 0.5 deg a
    record) was taken as seconds: 2 Hz. It is no time base now: the map must give one."""
    import struct

    from asammdf import MDF, Signal

    angle = np.arange(400) * 0.5
    mdf = MDF(version="4.10")
    mdf.append([Signal(np.sin(np.deg2rad(angle)), angle, name="Trq", unit="N.m")])
    path = tmp_path / "angle.mf4"
    mdf.save(path, overwrite=True)
    buf = bytearray(path.read_bytes())
    at = buf.find(b"##CN")
    while at >= 0:  # the CN blocks: the master (cn_type 2) gets cn_sync_type 2, an angle
        links = struct.unpack_from("<Q", buf, at + 16)[0]
        data = at + 24 + 8 * links
        if buf[data] == 2:
            buf[data + 1] = 2
        at = buf.find(b"##CN", at + 4)
    path.write_bytes(bytes(buf))
    with pytest.raises(RecordingError, match=r"no time.*0 \(angle\).*not time"):
        read_recording(path, {"channels": {"torque": {"column": "Trq"}}})
    rec = read_recording(path, {"time": {"sample_rate_Hz": 1000.0}, "channels": {
        "torque": {"column": "Trq"}}})  # fmt: skip
    assert rec.sample_rate == pytest.approx(1000.0)


def test_parquet_timestamps_with_a_time_zone_are_utc_instants(tmp_path):
    """Timestamps stored with a time zone (Europe/Berlin, across the end of summer time):
    seconds between the UTC instants, 1 ms a sample through the repeated hour. They were
    read through pandas' Timestamp objects (correct, but 42 s for 2 million rows)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    start = np.datetime64("2024-10-27T00:59:58.5", "ns").astype(np.int64)  # 02:59:58.5 CEST
    stamps = pa.array(start + np.arange(4000) * 1_000_000, pa.timestamp("ns", tz="Europe/Berlin"))
    path = tmp_path / "berlin.parquet"
    pq.write_table(pa.table({"time": stamps, "torque [N.m]": np.arange(4000.0)}), path)
    rec = read_recording(path, {"time": {"column": "time"}, "channels": {
        "torque": {"column": "torque"}}})  # fmt: skip
    np.testing.assert_allclose(rec.time, np.arange(4000) * 1e-3, rtol=0, atol=1e-12)
    assert rec.time.dtype == float


def diadem_groups(path, *, n_fast=1000, n_slow=1000, slow_times=("Time",)):
    """A DIAdem / LabVIEW TDMS file whose groups each hold their own time channel (no
    waveform timing): "Fast" (Time, Torque at 1 kHz) and "Slow" (Time, Pressure at 100 Hz,
    3 bar + 1 bar/s)."""
    from nptdms import ChannelObject, TdmsWriter

    objects = [
        ChannelObject("Fast", "Time", np.arange(n_fast) / 1000.0, properties={"unit_string": "s"}),
        ChannelObject("Fast", "Torque", np.full(n_fast, 100.0), properties={"unit_string": "N·m"}),
    ]
    for name in slow_times:
        t = np.arange(n_slow) / 100.0
        objects.append(ChannelObject("Slow", name, t, properties={"unit_string": "s"}))
    pressure = 3.0 + np.arange(n_slow) / 100.0
    objects.append(ChannelObject("Slow", "Pressure", pressure, properties={"unit_string": "bar"}))
    with TdmsWriter(str(path)) as w:
        w.write_segment(objects)


DIADEM_MAP = {
    "time": {"column": "Fast/Time"},
    "channels": {
        "torque": {"column": "Fast/Torque"},
        "air_spring_pressure": {"column": "Slow/Pressure"},
    },
}


@pytest.mark.parametrize("n_slow", [1000, 300], ids=["same-length", "shorter"])
def test_tdms_group_with_its_own_time_channel_is_put_on_the_time_column(tmp_path, n_slow):
    """A channel of another group than the [time] column's, whose group holds its own Time
    channel, is sampled at that Time: it was lined up by sample index on the fast clock (at
    t = 0.5 s 8.0 bar instead of 3.5, no note), and of another length it was an error that
    only said the lengths differ."""
    path = tmp_path / "diadem.tdms"
    diadem_groups(path, n_slow=n_slow)
    before = _fingerprint(path)
    rec = read_recording(path, DIADEM_MAP)
    assert _fingerprint(path) == before
    np.testing.assert_allclose(rec.time, np.arange(1000) / 1000.0)
    # 3 bar + 1 bar/s: linear interpolation reproduces the ramp
    np.testing.assert_allclose(rec["air_spring_pressure"], (3.0 + rec.time) * 1e5, rtol=1e-12)
    assert rec["air_spring_pressure"][500] == pytest.approx(3.5e5)
    notes = " ".join(rec.metadata["notes"])
    assert "'Slow/Time', the time channel of their own group" in notes
    assert "resampled: air_spring_pressure 100 Hz (linear interpolation)" in notes
    # the other way round: the slow group's time, the fast torque filtered down onto it
    rec = read_recording(path, {**DIADEM_MAP, "time": {"column": "Slow/Time"}})
    assert rec.sample_rate == pytest.approx(100.0)
    np.testing.assert_allclose(rec["torque"], 100.0, rtol=1e-3)
    np.testing.assert_allclose(rec["air_spring_pressure"], (3.0 + rec.time) * 1e5, rtol=1e-12)
    assert any(
        "'Fast/Time', the time channel of their own group" in n for n in rec.metadata["notes"]
    )


def test_tdms_group_time_channels_in_the_chunked_reader(tmp_path):
    """The chunked reader reads one time base: a channel on its group's own Time is another
    (it had been index-aligned with the time column, as read_recording did)."""
    path = tmp_path / "diadem.tdms"
    diadem_groups(path)
    with pytest.raises(RecordingError, match=r"on its group's time channel 'Slow/Time'.*use read_"):
        open_recording(path, DIADEM_MAP)
    with open_recording(path, DIADEM_MAP, channels=["torque"]) as src:
        assert src.names == ("torque",)
        assert src.sample_rate == pytest.approx(1000.0)


def test_tdms_group_with_two_time_channels_is_a_clear_error(tmp_path):
    path = tmp_path / "diadem.tdms"
    diadem_groups(path, slow_times=("Time", "Timestamp"))
    with pytest.raises(
        RecordingError,
        match=r"'Slow/Pressure' is in a group with several time channels \['Slow/Time', "
        r"'Slow/Timestamp'\].*map as \[time\] column the time channel of its group",
    ):
        read_recording(path, DIADEM_MAP)
    # a group without a time channel of its own, of another length: the error says what to do
    from nptdms import ChannelObject, TdmsWriter

    bare = tmp_path / "bare.tdms"
    with TdmsWriter(str(bare)) as w:
        w.write_segment([
            ChannelObject("Fast", "Time", np.arange(1000) / 1000.0),
            ChannelObject("Fast", "Torque", np.full(1000, 100.0)),
            ChannelObject("Slow", "Pressure", np.ones(300), properties={"unit_string": "bar"}),
        ])  # fmt: skip
    with pytest.raises(RecordingError, match=r"300 samples, time has 1000; it was sampled at "
                       r"another rate .*sample_rate_Hz = its rate"):  # fmt: skip
        read_recording(bare, {**DIADEM_MAP, "channels": {
            "torque": {"column": "Fast/Torque", "unit": "N.m"},
            "air_spring_pressure": {"column": "Slow/Pressure"}}})  # fmt: skip
    # in the time column's group, the channels are sampled with it
    rec = read_recording(path, {"time": {"column": "Slow/Time"}, "channels": {
        "air_spring_pressure": {"column": "Slow/Pressure"}}})  # fmt: skip
    np.testing.assert_allclose(rec["air_spring_pressure"], (3.0 + rec.time) * 1e5, rtol=1e-12)
