"""Readers and writers: round trips through the real libraries, validation at the boundary.

Each foreign file is written here with the library itself (pandas, pyarrow, nptdms TdmsWriter,
asammdf MDF.append, scipy.io.savemat, h5py) in non-SI units, then read with a channel map; the
expected SI values follow from the unit definitions (1 rpm = 2π/60 rad/s, 1 bar = 1e5 Pa,
1 kN = 1e3 N, 1 mm = 1e-3 m, 1 ms = 1e-3 s; BIPM SI Brochure, 9th ed., Tables 7-8).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import sys

import numpy as np
import pandas as pd
import pytest

from rollerrig.recordings.channels import ChannelMap
from rollerrig.recordings.readers import FORMATS, detect_format, read_recording
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.writers import write_recording

RATE = 250.0
N = 2000
RPM = 2 * math.pi / 60


@pytest.fixture
def raw():
    """Raw DAQ values in the units the rig's LabVIEW export uses."""
    t = np.arange(N) / RATE
    return {
        "t_ms": t * 1e3,
        "Torque_Roller": 0.5 + 0.1 * np.sin(2 * np.pi * 3 * t),  # kN.m
        "n_roller": 300 + 10 * t,  # rpm
        "p_air": 2.0 + 0.01 * t,  # bar
        "Fz": 10.0 + 0.0 * t,  # kN
        "laser3": 0.05 * np.cos(t),  # mm
    }


MAP = {
    "time": {"column": "t_ms", "unit": "ms"},
    "channels": {
        "torque": {"column": "Torque_Roller", "unit": "kN.m"},
        "roller_speed": {"column": "n_roller", "unit": "rpm"},
        "air_spring_pressure": {"column": "p_air", "unit": "bar"},
        "normal_load": {"column": "Fz", "unit": "kN"},
        "displacement_torque_sensor": {"column": "laser3", "unit": "mm"},
    },
}


def _check_si(rec: Recording, raw: dict, *, time=True) -> None:
    if time:
        np.testing.assert_allclose(rec.time, raw["t_ms"] * 1e-3, rtol=0, atol=1e-12)
    np.testing.assert_allclose(rec["torque"], raw["Torque_Roller"] * 1e3, rtol=1e-12)
    np.testing.assert_allclose(rec["roller_speed"], raw["n_roller"] * RPM, rtol=1e-12)
    np.testing.assert_allclose(rec["air_spring_pressure"], raw["p_air"] * 1e5, rtol=1e-12)
    np.testing.assert_allclose(rec["normal_load"], raw["Fz"] * 1e3, rtol=1e-12)
    np.testing.assert_allclose(
        rec["displacement_torque_sensor"], raw["laser3"] * 1e-3, rtol=1e-12, atol=1e-18
    )
    assert rec.units["torque"] == "N.m" and rec.units["roller_speed"] == "rad/s"
    assert rec.units["air_spring_pressure"] == "Pa" and rec.units["normal_load"] == "N"
    assert rec.units["displacement_torque_sensor"] == "m"


def _fingerprint(path):
    st = os.stat(path)
    return hashlib.sha256(path.read_bytes()).hexdigest(), st.st_mtime_ns, st.st_size


# --------------------------------------------------------------------------- foreign files


def test_csv_written_by_pandas(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    before = _fingerprint(f)
    rec = read_recording(f, MAP, channels=("torque", "roller_speed"))
    _check_si(rec, raw)
    assert _fingerprint(f) == before
    md = rec.metadata
    assert md["format"] == "csv" and md["sha256"] == before[0]
    assert md["columns"]["torque"] == "Torque_Roller" and md["source_units"]["torque"] == "kN.m"
    assert md["channel_map"]["channels"]["torque"]["unit"] == "kN.m"
    assert md["gaps"] == [] and md["interpolated"] == []


def test_csv_semicolon_decimal_comma(tmp_path, raw):
    f = tmp_path / "de.csv"
    pd.DataFrame(raw).to_csv(f, index=False, sep=";", decimal=",")
    rec = read_recording(f, MAP)
    _check_si(rec, raw)
    assert any("decimal commas" in n for n in rec.metadata["notes"])


def test_csv_headers_with_units_need_no_map(tmp_path, raw):
    f = tmp_path / "units.csv"
    pd.DataFrame(
        {
            "time [ms]": raw["t_ms"],
            "torque [kN.m]": raw["Torque_Roller"],
            "roller_speed [rpm]": raw["n_roller"],
            "air_spring_pressure [bar]": raw["p_air"],
            "normal_load [kN]": raw["Fz"],
            "displacement_torque_sensor [mm]": raw["laser3"],
            "comment": ["x"] * N,
        }
    ).to_csv(f, index=False)
    rec = read_recording(f)
    _check_si(rec, raw)
    assert "comment" not in rec


def test_csv_map_column_matches_header_without_unit(tmp_path, raw):
    f = tmp_path / "h.csv"
    pd.DataFrame({"t_ms [ms]": raw["t_ms"], "n_roller [rpm]": raw["n_roller"]}).to_csv(
        f, index=False
    )
    cmap = {"time": MAP["time"], "channels": {"roller_speed": MAP["channels"]["roller_speed"]}}
    rec = read_recording(f, cmap)
    np.testing.assert_allclose(rec["roller_speed"], raw["n_roller"] * RPM)


def test_csv_with_sample_rate_and_scale_offset(tmp_path):
    volts = np.linspace(0.0, 5.0, 500)
    f = tmp_path / "ai.csv"
    pd.DataFrame({"ai0": volts}).to_csv(f, index=False)
    cmap = {
        "time": {"sample_rate_Hz": 250},
        "channels": {"torque": {"column": "ai0", "unit": "N.m", "scale": 200.0, "offset": -500}},
    }
    rec = read_recording(f, cmap)
    np.testing.assert_allclose(rec.time, np.arange(500) / 250.0)
    np.testing.assert_allclose(rec["torque"], 200.0 * volts - 500.0)


def test_csv_absolute_timestamps(tmp_path):
    stamps = pd.date_range("2024-05-01 10:00:00", periods=100, freq="4ms")
    f = tmp_path / "abs.csv"
    pd.DataFrame({"Time": stamps.astype(str), "T": np.arange(100.0)}).to_csv(f, index=False)
    rec = read_recording(
        f, {"time": {"column": "Time"}, "channels": {"torque": {"column": "T", "unit": "N.m"}}}
    )
    np.testing.assert_allclose(rec.time, np.arange(100) * 0.004, atol=1e-12)
    assert any("absolute timestamps" in n for n in rec.metadata["notes"])


def test_parquet_written_by_pandas(tmp_path, raw):
    f = tmp_path / "run.parquet"
    pd.DataFrame(raw).to_parquet(f)
    before = _fingerprint(f)
    rec = read_recording(f, MAP)
    _check_si(rec, raw)
    assert _fingerprint(f) == before


def _tdms(path, raw, *, time_channel=False, group="Measured"):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    wf = {"wf_increment": 1 / RATE, "wf_start_offset": 0.0}
    objects = [RootObject(), GroupObject(group)]
    if time_channel:
        objects.append(ChannelObject(group, "Time", raw["t_ms"], properties={"unit_string": "ms"}))
    for name in ("Torque_Roller", "n_roller", "p_air", "Fz", "laser3"):
        objects.append(ChannelObject(group, name, raw[name], properties=wf))
    with TdmsWriter(str(path)) as w:
        w.write_segment(objects)


def test_tdms_waveform_time_from_wf_increment(tmp_path, raw):
    f = tmp_path / "run.tdms"
    _tdms(f, raw)
    before = _fingerprint(f)
    cmap = {
        "channels": {
            name: {**spec, "column": f"Measured/{spec['column']}"}
            for name, spec in MAP["channels"].items()
        }
    }
    rec = read_recording(f, cmap)
    _check_si(rec, raw)
    assert rec.sample_rate == pytest.approx(RATE)
    assert _fingerprint(f) == before


def test_tdms_time_channel_and_short_names(tmp_path, raw):
    f = tmp_path / "run.tdms"
    _tdms(f, raw, time_channel=True)
    cmap = {**MAP, "time": {"column": "Measured/Time", "unit": "ms"}}
    rec = read_recording(f, cmap)  # channel names without group resolve when unique
    _check_si(rec, raw)


def test_tdms_ambiguous_channel_name(tmp_path, raw):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    f = tmp_path / "two.tdms"
    wf = {"wf_increment": 1 / RATE}
    with TdmsWriter(str(f)) as w:
        w.write_segment(
            [
                RootObject(),
                GroupObject("A"),
                GroupObject("B"),
                ChannelObject("A", "Fz", raw["Fz"], properties=wf),
                ChannelObject("B", "Fz", raw["Fz"], properties=wf),
            ]
        )
    with pytest.raises(RecordingError, match=r"'Fz', which is ambiguous.*A/Fz.*B/Fz"):
        read_recording(f, {"channels": {"normal_load": {"column": "Fz", "unit": "kN"}}})
    rec = read_recording(f, {"channels": {"normal_load": {"column": "B/Fz", "unit": "kN"}}})
    np.testing.assert_allclose(rec["normal_load"], 1e4)


def test_mdf4_two_rasters_are_resampled(tmp_path):
    from asammdf import MDF, Signal

    t_fast = np.arange(4000) / 1000.0  # 1 kHz torque
    t_slow = np.arange(1000) / 250.0  # 250 Hz speed
    f = tmp_path / "qx.mf4"
    mdf = MDF(version="4.10")
    mdf.append([Signal(0.2 + 0.1 * t_fast, t_fast, name="T_Roll", unit="kNm")])
    mdf.append([Signal(100.0 * t_slow, t_slow, name="n_roll", unit="rpm")])
    mdf.save(f, overwrite=True)
    mdf.close()
    before = _fingerprint(f)
    cmap = {
        "channels": {
            "torque": {"column": "T_Roll", "unit": "kN.m"},
            "roller_speed": {"column": "n_roll"},  # unit from the file
        }
    }
    rec = read_recording(f, cmap)
    assert _fingerprint(f) == before
    # onto the raster of the first mapped channel, trimmed to the common span
    assert rec.sample_rate == pytest.approx(1000.0)
    assert rec.time[0] == 0.0 and rec.time[-1] == pytest.approx(t_slow[-1])
    np.testing.assert_allclose(rec["torque"], (0.2 + 0.1 * rec.time) * 1e3, rtol=1e-12)
    # a linear signal is reproduced exactly by linear interpolation
    np.testing.assert_allclose(rec["roller_speed"], 100.0 * rec.time * RPM, atol=1e-9)
    res = rec.metadata["resampled"]
    assert list(res["channels"]) == ["roller_speed"]
    assert res["channels"]["roller_speed"]["from_rate_Hz"] == pytest.approx(250.0)
    assert rec.metadata["source_units"]["roller_speed"] == "rpm"


def test_mat_v5_written_by_savemat(tmp_path, raw):
    from scipy.io import savemat

    f = tmp_path / "run.mat"
    savemat(f, {"t_ms": raw["t_ms"].reshape(-1, 1), "meas": {k: v for k, v in raw.items()}})
    before = _fingerprint(f)
    cmap = {
        "time": MAP["time"],
        "channels": {n: {**s, "column": f"meas.{s['column']}"} for n, s in MAP["channels"].items()},
    }
    rec = read_recording(f, cmap)
    _check_si(rec, raw)
    assert _fingerprint(f) == before


def test_mat_v73_written_by_h5py(tmp_path, raw):
    import h5py

    f = tmp_path / "run73.mat"
    with h5py.File(f, "w") as h:
        for name, values in raw.items():
            ds = h.create_dataset(name, data=values.reshape(1, -1))
            ds.attrs["MATLAB_class"] = np.bytes_("double")
    before = _fingerprint(f)
    rec = read_recording(f, MAP)
    _check_si(rec, raw)
    assert _fingerprint(f) == before


# --------------------------------------------------------------------------- our writers


@pytest.fixture
def recording():
    t = 0.5 + np.arange(1500) / RATE
    return Recording(
        t,
        {
            "torque": 400.0 * np.sin(t),
            "roller_speed": 5.0 + t,
            "normal_load": np.full(t.size, 1e4),
            "slip_velocity": 0.01 * t,
        },
        {"torque": "N.m", "roller_speed": "rad/s", "normal_load": "N", "slip_velocity": "m/s"},
        {"generator": "test", "seed": np.int64(7), "nested": {"a": [1, 2]}},
    )


CASES = [("csv", {}), ("parquet", {}), ("tdms", {}), ("mf4", {}), ("mat", {})]
CASES.append(("mat", {"mat_version": "7.3"}))


@pytest.mark.parametrize(("fmt", "kw"), CASES)
def test_writer_reader_round_trip(tmp_path, recording, fmt, kw):
    f = tmp_path / f"run.{fmt}"
    assert write_recording(recording, f, **kw) == f
    before = _fingerprint(f)
    rec = read_recording(f)
    assert _fingerprint(f) == before
    # Binary formats keep the values; CSV text their 12 significant digits (no float noise).
    rtol = 5e-12 if fmt == "csv" else 0.0
    np.testing.assert_allclose(rec.time, recording.time, rtol=rtol, atol=0.0)
    assert set(rec.channels) == set(recording.channels)
    for name in recording.channels:
        np.testing.assert_allclose(rec[name], recording[name], rtol=rtol, atol=0.0)
        assert rec.units[name] == recording.units[name]
    assert rec.metadata["stored_metadata"] == {
        "generator": "test",
        "seed": 7,
        "nested": {"a": [1, 2]},
    }
    assert rec.metadata["format"] == fmt
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_csv_writer_headers_and_sidecar(tmp_path, recording):
    f = tmp_path / "run.csv"
    write_recording(recording, f)
    header = f.read_text().splitlines()[0]
    assert (
        header == "time [s],torque [N.m],roller_speed [rad/s],normal_load [N],slip_velocity [m/s]"
    )
    assert json.loads((tmp_path / "run.metadata.json").read_text())["generator"] == "test"


def test_tdms_writer_layout(tmp_path, recording):
    from nptdms import TdmsFile

    f = tmp_path / "run.tdms"
    write_recording(recording, f)
    tdms = TdmsFile.read(f)
    group = tdms["rollerrig"]
    assert group.channels()[0].name == "time"
    props = group["torque"].properties
    assert props["unit_string"] == "N.m"
    assert props["wf_increment"] == pytest.approx(1 / RATE)
    assert props["wf_start_offset"] == pytest.approx(0.5)
    # a foreign map without a time column uses the waveform properties
    rec = read_recording(f, {"channels": {"torque": {"column": "rollerrig/torque", "unit": "N.m"}}})
    np.testing.assert_allclose(rec.time, recording.time, atol=1e-12)


def test_mat73_writer_header_and_layout(tmp_path, recording):
    import h5py
    from scipy.io.matlab import matfile_version

    f = tmp_path / "run.mat"
    write_recording(recording, f, mat_version="7.3")
    assert f.read_bytes()[:10] == b"MATLAB 7.3"
    assert matfile_version(str(f)) == (2, 0)
    with h5py.File(f, "r") as h:
        assert h["torque"].shape == (1, recording.time.size)  # MATLAB n x 1 column vector
        assert h["torque"].attrs["MATLAB_class"] == b"double"


def test_writer_refuses_to_overwrite(tmp_path, recording):
    f = tmp_path / "run.parquet"
    write_recording(recording, f)
    before = _fingerprint(f)
    with pytest.raises(FileExistsError, match="overwrite=True"):
        write_recording(recording, f)
    assert _fingerprint(f) == before
    shorter = recording.select(0.0, 1.0)
    write_recording(shorter, f, overwrite=True)
    assert read_recording(f).time.size == shorter.time.size
    assert [p.name for p in tmp_path.iterdir()] == ["run.parquet"]


def test_csv_writer_refuses_existing_sidecar(tmp_path, recording):
    (tmp_path / "run.metadata.json").write_text("{}")
    with pytest.raises(FileExistsError, match=r"run\.metadata\.json"):
        write_recording(recording, tmp_path / "run.csv")
    assert not (tmp_path / "run.csv").exists()


def test_writer_errors(tmp_path, recording):
    with pytest.raises(RecordingError, match=r"not written as Excel workbooks.*CSV"):
        write_recording(recording, tmp_path / "run.xlsx")
    with pytest.raises(RecordingError, match=r"unsupported file suffix '\.sav'"):
        write_recording(recording, tmp_path / "run.sav")
    with pytest.raises(RecordingError, match="mat_version"):
        write_recording(recording, tmp_path / "run.mat", mat_version="6")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("suffix", "kw"),
    [("csv", {}), ("parquet", {}), ("tdms", {}), ("mf4", {}), ("mat", {}), ("mat", {"v": "7.3"})],
)
def test_names_a_format_cannot_hold_come_back_as_written(tmp_path, recording, suffix, kw):
    """Names from DAQ software (slashes, brackets, accents, a leading digit) are written under
    names the format stores (MAT: identifiers) and read back under the names they had."""
    names = ["oil temp/bearing", "Group/Channel", "[bold]x[/bold]", "Öl-Temp", "2nd", "units"]
    n = recording.time.size
    odd = Recording(
        recording.time,
        {**recording.channels, **{k: np.full(n, float(i)) for i, k in enumerate(names)}},
        {**recording.units, **dict.fromkeys(names, "1")},
    )
    path = write_recording(odd, tmp_path / f"run.{suffix}", mat_version=kw.get("v", "5"))
    back = read_recording(path)
    for i, name in enumerate(names):
        assert back[name].tolist() == [float(i)] * n, name


# --------------------------------------------------------------------------- bad files


def _csv(tmp_path, t, **cols):
    f = tmp_path / "bad.csv"
    pd.DataFrame({"time [s]": t, **{f"{k} [N.m]": v for k, v in cols.items()}}).to_csv(
        f, index=False
    )
    return f


def test_missing_column_suggests_close_match(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    cmap = {**MAP, "channels": {"torque": {"column": "Torque_Roler", "unit": "kN.m"}}}
    with pytest.raises(RecordingError) as err:
        read_recording(f, cmap)
    msg = str(err.value)
    assert "labview.csv" in msg and "[channels.torque]" in msg and "'Torque_Roler'" in msg
    assert "close matches: ['Torque_Roller']" in msg and "available columns" in msg


def test_non_monotonic_time(tmp_path):
    t = np.arange(20) / RATE
    t[10], t[11] = t[11], t[10]
    with pytest.raises(RecordingError, match=r"bad.csv: time goes backwards at sample 11"):
        read_recording(_csv(tmp_path, t, torque=np.zeros(20)))


def test_duplicated_time(tmp_path):
    t = np.arange(20) / RATE
    t[7] = t[6]
    with pytest.raises(RecordingError, match=r"time duplicated at sample 7: t\[6\] = 0.024 s"):
        read_recording(_csv(tmp_path, t, torque=np.zeros(20)), validate="lenient")


def test_nan_run_strict_names_channel_count_and_run(tmp_path):
    t = np.arange(100) / RATE
    v = t.copy()
    v[40:42] = np.nan
    v[70] = np.inf
    f = _csv(tmp_path, t, torque=v)
    with pytest.raises(
        RecordingError,
        match=r"channel 'torque' has 3 NaN/inf samples in 2 run\(s\); first run: samples 40..41 "
        r"\(t = 0.16 s .. 0.164 s, 2 samples\)",
    ):
        read_recording(f)


def test_nan_run_lenient_interpolates_short_runs(tmp_path):
    t = np.arange(100) / RATE
    v = 3.0 * t + 1.0
    v[40:43] = np.nan
    v[0] = np.nan
    rec = read_recording(_csv(tmp_path, t, torque=v), validate="lenient")
    np.testing.assert_allclose(rec["torque"][1:], (3.0 * t + 1.0)[1:], rtol=1e-12)
    assert rec["torque"][0] == pytest.approx(3.0 * t[1] + 1.0)  # edge: held
    runs = rec.metadata["interpolated"]
    assert [(r["first_sample"], r["last_sample"], r["method"]) for r in runs] == [
        (0, 0, "held (edge)"),
        (40, 42, "linear"),
    ]


def test_nan_run_lenient_long_run_still_errors(tmp_path):
    t = np.arange(100) / RATE
    v = t.copy()
    v[50:60] = np.nan
    with pytest.raises(RecordingError, match=r"too long to interpolate.*samples 50..59"):
        read_recording(_csv(tmp_path, t, torque=v), validate="lenient")


def test_gap_strict_and_lenient(tmp_path):
    t = np.arange(100) / RATE
    t[60:] += 5 / RATE  # five dropped samples between 59 and 60
    f = _csv(tmp_path, t, torque=np.zeros(100))
    with pytest.raises(
        RecordingError,
        match=r"gap \(dropped samples\) between sample 59 \(t = 0.236 s\) and 60 "
        r"\(t = 0.26 s\): 0.024 s, about 5 missing",
    ):
        read_recording(f)
    rec = read_recording(f, validate="lenient")
    assert rec.metadata["gaps"] == [
        {
            "sample": 59,
            "start_s": pytest.approx(0.236),
            "end_s": pytest.approx(0.26),
            "duration_s": pytest.approx(0.024),
            "missing_samples": 5,
        }
    ]


def test_unknown_unit_in_map_and_in_header(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    cmap = {**MAP, "channels": {"normal_load": {"column": "Fz", "unit": "furlong"}}}
    # the map entry and the unit are named ([channels.normal_load] or channels.normal_load.unit)
    with pytest.raises(RecordingError, match=r"channels\.normal_load\b.*'furlong'"):
        read_recording(f, cmap)
    g = tmp_path / "hdr.csv"
    pd.DataFrame({"time [s]": [0.0, 0.1], "torque [lbf.ft]": [1.0, 2.0]}).to_csv(g, index=False)
    with pytest.raises(RecordingError, match=r"hdr.csv.*'torque \[lbf.ft\]'.*'lbf.ft'"):
        read_recording(g)


def test_map_unit_conflicting_with_header(tmp_path):
    f = tmp_path / "c.csv"
    pd.DataFrame({"t [s]": [0.0, 0.1, 0.2], "n [rad/s]": [1.0, 2.0, 3.0]}).to_csv(f, index=False)
    cmap = {"time": {"column": "t"}, "channels": {"roller_speed": {"column": "n", "unit": "rpm"}}}
    with pytest.raises(RecordingError, match=r"map says unit 'rpm' but the file says 'rad/s'"):
        read_recording(f, cmap)


def test_unknown_canonical_name(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    cmap = {**MAP, "channels": {"roller_sped": {"column": "n_roller", "unit": "rpm"}}}
    with pytest.raises(RecordingError, match=r"'roller_sped' is not a canonical.*'roller_speed'"):
        read_recording(f, cmap)


def test_extra_channels(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame({**raw, "I_AM": np.ones(N)}).to_csv(f, index=False)
    cmap = ChannelMap.from_dict(
        {**MAP, "extra": {"motor_current": {"column": "I_AM", "unit": "A"}}}
    )
    rec = read_recording(f, cmap)
    assert rec.units["motor_current"] == "A"


def test_missing_required_channel(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    with pytest.raises(RecordingError, match=r"required channel\(s\) \['wheel_speed'\]"):
        read_recording(f, MAP, channels=("torque", "wheel_speed"))


def test_missing_files_and_suffixes(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    with pytest.raises(FileNotFoundError, match="channel map file not found"):
        read_recording(f, tmp_path / "missing.toml")
    with pytest.raises(FileNotFoundError, match="recording file not found"):
        read_recording(tmp_path / "nope.csv", MAP)
    (tmp_path / "run.sav").write_bytes(b"x")
    with pytest.raises(RecordingError, match=r"unsupported file suffix '.sav'"):
        read_recording(tmp_path / "run.sav")
    # a folder had been "unsupported file suffix ''; ... rename it"
    (tmp_path / "runs").mkdir()
    with pytest.raises(RecordingError, match=r"runs is a folder, not a recording file; give"):
        read_recording(tmp_path / "runs")
    with pytest.raises(RecordingError, match=r"unsupported format 'hdf'"):
        read_recording(f, format="hdf")
    with pytest.raises(RecordingError, match="validate must be"):
        read_recording(f, MAP, validate="loose")


def test_map_from_toml_file(tmp_path, raw):
    f = tmp_path / "labview.csv"
    pd.DataFrame(raw).to_csv(f, index=False)
    m = tmp_path / "map.toml"
    m.write_text(
        '[time]\ncolumn = "t_ms"\nunit = "ms"\n'
        '[channels.roller_speed]\ncolumn = "n_roller"\nunit = "rpm"\n'
    )
    rec = read_recording(f, m)
    assert rec.metadata["channel_map"]["source"] == str(m)
    np.testing.assert_allclose(rec["roller_speed"], raw["n_roller"] * RPM)


def test_format_override_and_detection(tmp_path, raw):
    f = tmp_path / "export.txt"
    pd.DataFrame(raw).to_csv(f, index=False)
    _check_si(read_recording(f, MAP, format="csv"), raw)
    assert {detect_format(f"x{s}") for ss in FORMATS.values() for s in ss} == set(FORMATS)


def test_non_numeric_entries_are_named(tmp_path):
    f = tmp_path / "txt.csv"
    pd.DataFrame({"time [s]": [0.0, 0.1, 0.2], "torque [N.m]": ["1", "ERR", "3"]}).to_csv(
        f, index=False
    )
    with pytest.raises(RecordingError, match=r"1 non-numeric entries, first at row 1: 'ERR'"):
        read_recording(f)


def test_no_time_anywhere(tmp_path):
    f = tmp_path / "nt.csv"
    pd.DataFrame({"T": [1.0, 2.0]}).to_csv(f, index=False)
    with pytest.raises(RecordingError, match=r"no time"):
        read_recording(f, {"channels": {"torque": {"column": "T", "unit": "N.m"}}})


@pytest.mark.parametrize(
    ("suffix", "module"),
    [
        ("tdms", "nptdms"),
        ("mf4", "asammdf"),
        ("parquet", "pyarrow.parquet"),
        ("parquet", "pandas"),
        ("csv", "pandas"),
    ],
)
def test_missing_optional_reader_names_the_extra(tmp_path, recording, monkeypatch, suffix, module):
    f = tmp_path / f"run.{suffix}"
    write_recording(recording, f)
    monkeypatch.setitem(sys.modules, module, None)
    with pytest.raises(
        ImportError, match=rf"{module.split('.')[0]}.*pip install 'rollerrig\[io\]'"
    ):
        read_recording(f)


def test_recording_as_dataset_without_xarray_names_the_extra(recording, monkeypatch):
    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ImportError, match=r"xarray: pip install 'rollerrig\[io\]'"):
        recording.to_dataset()


# ------------------------------------------------------- vendor files not read (issue 24, 9)

# The start of an imc FAMOS raw file as imc documents the format ("FAMOS file format", imc
# Test & Measurement): the keys |CF (format version 2, processor 1) and |CK, then |NO (origin).
FAMOS_HEAD = b"|CF,2,1,1;|CK,1,3,1,1;\r\n|NO,1,  20,0,9,imc STUDIO,0,;\r\n"
# Dewesoft 7 / X data files start with the text DEWESOFT, then binary header fields.
DEWESOFT_HEAD = b"DEWESOFT\x00\x00\x00\x00" + bytes(range(32))


@pytest.mark.parametrize(
    ("name", "head", "vendor", "export"),
    [
        ("run.raw", FAMOS_HEAD, "imc FAMOS", "in imc FAMOS or imc STUDIO export"),
        ("run.dxd", DEWESOFT_HEAD, "Dewesoft", "in Dewesoft X use Export"),
        ("run.d7d", DEWESOFT_HEAD, "Dewesoft", "ASAM MDF4"),
        ("run.dxz", DEWESOFT_HEAD, "Dewesoft", "MATLAB"),
        # misnamed: the content tells the vendor, not a parse error of the suffix's format
        ("famos.csv", FAMOS_HEAD, "imc FAMOS", "recognised by its content; named '.csv'"),
        ("dewesoft.mf4", DEWESOFT_HEAD, "Dewesoft", "recognised by its content; named '.mf4'"),
        ("export.dat", FAMOS_HEAD, "imc FAMOS", "recognised by its content"),
    ],
)
def test_vendor_files_not_read_name_the_vendor_and_the_export(tmp_path, name, head, vendor, export):
    from rollerrig.recordings.source import open_recording

    path = tmp_path / name
    path.write_bytes(head)
    for read in (read_recording, open_recording):
        with pytest.raises(RecordingError) as info:
            read(path)
        message = str(info.value)
        assert vendor in message and export in message, message
        assert "unsupported file suffix" not in message
