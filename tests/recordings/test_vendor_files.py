"""Reading files as real acquisition software writes them (issue 7, item 5).

Each file is built by ``tests/vendor_files.py`` the way the tool writes it (LabVIEW and DAQmx
TDMS, INCA/CANape and CANedge MDF4, PicoScope, catman, DIAdem-style and CANape text exports,
LabVIEW .lvm, MATLAB v5 and v7.3, TwinCAT Scope CSV) from a known recording in SI units; the
reader, given the channel map a user would write, must give back that recording (same values
within the precision the tool stores, same rate, same clock), or one clear error that names the
file and what to do.
"""

import math

import numpy as np
import pytest

import vendor_files as vf
from rollerrig.recordings.readers import file_sha256, read_recording
from rollerrig.recordings.recording import RecordingError

RPM = 2 * math.pi / 60


def _read(v, cmap=None, **kwargs):
    """Read ``v`` with its map written beside it (as a user would), or with ``cmap`` (a dict)."""
    return read_recording(v.path, v.write_map() if cmap is None else cmap, **kwargs)


def _toml(text):
    import tomllib

    return tomllib.loads(text)


def _same(got, want, atol, rtol=0.0):
    np.testing.assert_allclose(np.asarray(got), np.asarray(want), atol=atol, rtol=rtol)


@pytest.fixture(scope="module")
def source():
    """1 s at 1 kHz with the 37 Hz line: the signals every text/binary fixture carries."""
    return vf.bench_recording(1.0, 1000.0, seed=5)


# ------------------------------------------------------------------------------ NI TDMS


def test_labview_waveform_tdms_reads_back_with_its_waveform_time(tmp_path, source):
    v = vf.labview_waveform_tdms(tmp_path, source)
    sha = file_sha256(v.path)
    rec = _read(v)
    assert rec.time.size == source.time.size
    assert rec.sample_rate == pytest.approx(1000.0, rel=1e-9)
    _same(rec.time, source.time, atol=1e-12)
    _same(rec["torque"], source["torque"], atol=1e-9)
    _same(rec["air_spring_pressure"], source["air_spring_pressure"], atol=1e-6)
    _same(rec["displacement_torque_sensor"], source["displacement_torque_sensor"], atol=1e-12)
    _same(rec["roller_encoder_counts"], source["roller_encoder_counts"], atol=0)
    assert file_sha256(v.path) == sha


def test_labview_tdms_start_time_is_kept_in_the_notes(tmp_path, source):
    v = vf.labview_waveform_tdms(tmp_path, source)
    notes = " ".join(_read(v).metadata["notes"])
    assert "2024-08-05T11:46:13" in notes


def test_a_stated_rate_contradicting_the_tdms_waveform_is_an_error(tmp_path, source):
    # The file says 1 kHz (wf_increment); a map saying 8 kHz is wrong by 8x (issue 7).
    v = vf.labview_waveform_tdms(tmp_path, source)
    cmap = _toml(v.channel_map)
    cmap["time"] = {"sample_rate_Hz": 8000.0}
    with pytest.raises(RecordingError) as err:
        _read(v, cmap)
    assert "8000" in str(err.value) and "1000" in str(err.value)


def test_a_tdms_cut_in_half_is_a_clear_error_or_a_shorter_recording(tmp_path, source):
    v = vf.labview_waveform_tdms(tmp_path, source, segments=4)
    data = v.path.read_bytes()
    cut = tmp_path / "cut.tdms"
    cut.write_bytes(data[: len(data) // 2])
    try:
        rec = read_recording(cut, v.write_map())
    except RecordingError as exc:
        assert "cut.tdms" in str(exc)
    else:
        assert 0 < rec.time.size < source.time.size
        _same(rec["torque"], source["torque"][: rec.time.size], atol=1e-9)


def test_daqmx_tasks_at_different_rates_and_start_times_share_one_clock(tmp_path):
    v = vf.daqmx_multitask_tdms(tmp_path, duration_s=1.0)
    f = v.facts
    rec = _read(v)
    # The common base is the torque's (19.2 kHz); the 10 Hz pressure is moved onto it.
    assert rec.sample_rate == pytest.approx(f["fast_rate_Hz"], rel=1e-6)
    resampled = rec.metadata["resampled"]["channels"]
    assert resampled["air_spring_pressure"]["from_rate_Hz"] == pytest.approx(10.0, rel=1e-6)
    # The pressure task started 0.35 s later (its own wf_start_time): on one clock, the pressure
    # at time t is the slow samples at t, not the slow samples index-aligned from 0.
    covered = rec.time >= f["slow_time_s"][0] - 1e-9
    assert covered.sum() > 0.5 * rec.time.size
    expected = np.interp(rec.time[covered], f["slow_time_s"], f["slow_pressure_Pa"])
    _same(rec["air_spring_pressure"][covered], expected, atol=1e-6 * expected.max())
    # Raw int16 codes with the DAQmx linear scale: within half a code (3000 N.m / 32767 / 2).
    src = f["source"]
    k = np.searchsorted(src.time, rec.time[0] - 1e-9)
    _same(rec["torque"], src["torque"][k : k + rec.time.size], atol=3000 / 32767 / 2 + 1e-9)


def test_daqmx_tasks_of_equal_length_but_different_rates_are_not_index_aligned(tmp_path):
    # Both tasks hold the same number of samples: 1 s at 19.2 kHz and 1920 s at 10 Hz. Index
    # alignment would squeeze 32 minutes of pressure into one second.
    v = vf.daqmx_multitask_tdms(tmp_path, duration_s=0.5, slow_samples=9600)
    f = v.facts
    rec = _read(v)
    assert "air_spring_pressure" in rec.metadata["resampled"]["channels"]
    covered = rec.time >= f["slow_time_s"][0] - 1e-9
    assert covered.any()
    expected = np.interp(rec.time[covered], f["slow_time_s"], f["slow_pressure_Pa"])
    _same(rec["air_spring_pressure"][covered], expected, atol=1e-6 * expected.max())


def test_daqmx_downsampled_to_a_stated_rate_with_an_anti_alias_filter(tmp_path):
    v = vf.daqmx_multitask_tdms(tmp_path, duration_s=1.0)
    cmap = _toml(v.channel_map)
    cmap["time"] = {"resample_Hz": 1000.0}
    rec = _read(v, cmap)
    assert rec.sample_rate == pytest.approx(1000.0, rel=1e-6)
    method = rec.metadata["resampled"]["channels"]["torque"]["method"]
    assert method != "linear"  # downsampling 19.2 kHz -> 1 kHz needs an anti-alias filter
    # The 37 Hz line (3 N.m) survives the anti-alias filter.
    x = rec["torque"] - rec["torque"].mean()
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size))) * 2 / np.hanning(x.size).sum()
    f = np.fft.rfftfreq(x.size, 1 / rec.sample_rate)
    assert spec[np.argmin(abs(f - 37.0))] == pytest.approx(3.0, rel=0.1)


# ------------------------------------------------------------------------------ MDF 4


def test_inca_canape_mdf_reads_the_fast_torque_named_by_its_raster(tmp_path, source):
    v = vf.inca_canape_mdf(tmp_path, source)
    rec = _read(v)
    assert rec.sample_rate == pytest.approx(1000.0, rel=1e-6)
    # The 1 kHz torque, not the 10 Hz copy in data group 0 resampled up.
    k = np.searchsorted(source.time, rec.time[0] - 0.0004 - 1e-9)
    _same(rec["torque"], source["torque"][k : k + rec.time.size], atol=1e-9)
    _same(rec["roller_speed"], source["roller_speed"][k : k + rec.time.size], atol=1e-9)


def test_inca_canape_mdf_group_by_index_and_by_file_group(tmp_path, source):
    v = vf.inca_canape_mdf(tmp_path, source)
    by_name = _read(v)["torque"]
    cmap = _toml(v.channel_map)
    cmap["channels"]["torque"]["column"] = v.facts["torque_by_index"]
    _same(_read(v, cmap)["torque"], by_name, atol=0)
    cmap["channels"]["torque"]["column"] = "Torque"
    cmap["file"] = {"group": v.facts["groups"][1]}
    _same(_read(v, cmap)["torque"], by_name, atol=0)


def test_a_name_in_two_mdf_groups_is_ambiguous_with_the_candidates(tmp_path, source):
    v = vf.inca_canape_mdf(tmp_path, source)
    cmap = _toml(v.channel_map)
    cmap["channels"]["torque"]["column"] = "Torque"
    with pytest.raises(RecordingError) as err:
        _read(v, cmap)
    msg = str(err.value)
    assert "ambiguous" in msg
    assert "100ms/Torque" in msg or "0/Torque" in msg
    assert "1ms/Torque" in msg or "1/Torque" in msg


def test_a_channel_of_an_empty_mdf_group_is_a_clear_error_or_a_note(tmp_path, source):
    v = vf.inca_canape_mdf(tmp_path, source)
    cmap = _toml(v.channel_map)
    cmap["extra"] = {"trigger": {"column": v.facts["empty_channel"], "unit": "1"}}
    with pytest.raises(RecordingError) as err:
        _read(v, cmap)
    assert "Trig_Flag" in str(err.value)
    cmap["extra"]["trigger"]["optional"] = True
    rec = _read(v, cmap)
    assert "trigger" not in rec
    assert any("Trig_Flag" in n for n in rec.metadata["notes"])


def test_a_catman_binary_file_asks_for_an_export_the_readers_take(tmp_path):
    # No reader of catman's own .BIN format: the error must say which export to use instead.
    path = tmp_path / "Haftversuch.BIN"
    path.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(RecordingError) as err:
        read_recording(path, {"channels": {"torque": {"column": "Drehmoment", "unit": "N.m"}}})
    msg = str(err.value)
    assert path.name in msg and "catman" in msg and "ASCII" in msg


def test_raw_can_frames_ask_for_a_dbc(tmp_path):
    v = vf.canedge_can_mdf(tmp_path)
    with pytest.raises(RecordingError) as err:
        _read(v)
    msg = str(err.value)
    assert "DBC" in msg and v.path.name in msg


# ------------------------------------------------------------------------------ text exports


def test_picoscope_csv_units_row_and_volts_scaled_by_the_map(tmp_path, source):
    v = vf.picoscope_csv(tmp_path, source)
    rec = _read(v)
    assert rec.sample_rate == pytest.approx(1000.0, rel=1e-6)
    _same(rec.time - rec.time[0], source.time, atol=1e-9)  # the file starts at -100 ms
    _same(rec["torque"], source["torque"], atol=300 * 5e-7 + 1e-9)
    _same(rec["displacement_torque_sensor"], source["displacement_torque_sensor"], atol=1e-9)


def test_picoscope_csv_is_sniffed_without_a_file_section(tmp_path, source):
    v = vf.picoscope_csv(tmp_path, source)
    rec = _read(v, _toml(vf.without_file_section(v.channel_map)))
    _same(rec["torque"], source["torque"], atol=300 * 5e-7 + 1e-9)


@pytest.mark.parametrize("time_column", ["absolute", "relative"])
def test_catman_ascii_export_with_preamble_units_row_and_decimal_commas(
    tmp_path, source, time_column
):
    v = vf.catman_ascii(tmp_path, source, time_column=time_column)
    rec = _read(v, format="csv")  # catman writes .txt
    assert rec.time.size == source.time.size
    _same(rec.time - rec.time[0], source.time, atol=1e-9)
    _same(rec["torque"], source["torque"], atol=1e-6)
    _same(rec["roller_speed"], source["roller_speed"], atol=1e-6 * RPM)
    _same(rec["air_spring_pressure"], source["air_spring_pressure"], atol=1e-6 * 1e5)


def test_catman_ascii_is_sniffed_without_a_file_section(tmp_path, source):
    v = vf.catman_ascii(tmp_path, source, time_column="relative")
    rec = _read(v, _toml(vf.without_file_section(v.channel_map)), format="csv")
    _same(rec["torque"], source["torque"], atol=1e-6)


@pytest.mark.parametrize("dialect", ["date_format", "dayfirst", "sniffed"])
def test_german_bench_dates_are_day_first_across_midnight_and_day_12_to_13(tmp_path, dialect):
    v = vf.german_bench_csv(tmp_path)
    cmap = _toml(v.channel_map)
    if dialect == "dayfirst":
        del cmap["file"]["date_format"]
    elif dialect == "sniffed":
        del cmap["file"]
    rec = _read(v, cmap)
    n = v.facts["n_samples"]
    # One sample a second for 180 s, through 00:00:00 of the 13th: no jump, no reordering.
    np.testing.assert_allclose(rec.time - rec.time[0], np.arange(n), atol=1e-9)
    _same(rec["roller_speed"], v.facts["roller_speed_rpm"] * RPM, atol=0.05 * RPM)
    _same(rec["air_spring_pressure"], v.facts["pressure_bar"] * 1e5, atol=0.5e-3 * 1e5)


def test_canape_csv_export_with_units_row(tmp_path, source):
    v = vf.canape_ascii_csv(tmp_path, source)
    rec = _read(v)
    _same(rec.time, source.time, atol=1e-9)
    _same(rec["torque"], source["torque"], atol=1e-6)
    _same(rec["wheel_speed"], source["wheel_speed"], atol=1e-6)


def test_labview_lvm_two_segments_read_as_one_recording(tmp_path, source):
    v = vf.labview_lvm(tmp_path, source)
    rec = _read(v)
    assert rec.time.size == source.time.size
    _same(rec.time, source.time, atol=1e-6)
    _same(rec["torque"], source["torque"], atol=1e-6)
    _same(rec["air_spring_pressure"], source["air_spring_pressure"], atol=1e-6 * 1e5)
    _same(rec["wheel_encoder_counts"], source["wheel_encoder_counts"], atol=0)


# ------------------------------------------------------------------------------ MATLAB


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_matlab_struct_of_signals(tmp_path, source, version):
    v = vf.matlab_struct_mat(tmp_path, source, version=version)
    sha = file_sha256(v.path)
    rec = _read(v)
    _same(rec.time, source.time, atol=1e-12)
    _same(rec["torque"], source["torque"], atol=1e-9)
    _same(rec["roller_speed"], source["roller_speed"], atol=1e-9)
    _same(rec["air_spring_pressure"], source["air_spring_pressure"], atol=1e-6)
    assert file_sha256(v.path) == sha


# ------------------------------------------------------------------------------ the fixtures


def test_every_builder_documents_its_tool_and_sources():
    for name in vf.__all__:
        obj = getattr(vf, name)
        if callable(obj) and name not in ("VendorFile", "without_file_section"):
            doc = obj.__doc__ or ""
            assert len(doc) > 200, name
            if name not in ("bench_recording", "adhesion_recording"):
                assert "Source" in doc, name


def test_maps_are_valid_toml_and_drop_their_file_section(tmp_path, source):
    v = vf.catman_ascii(tmp_path, source)
    assert "file" in _toml(v.channel_map)
    assert "file" not in _toml(vf.without_file_section(v.channel_map))
    assert v.write_map().read_text(encoding="utf-8") == v.channel_map


def test_the_fixture_recordings_say_what_was_injected():
    rec = vf.bench_recording(0.5, 250.0)
    lines = rec.metadata["injected_lines"]
    assert any(line["frequency [Hz]"] == vf.EXTRA_LINE_HZ for line in lines)
    assert any("INJECTED" in note for note in rec.metadata["notes"])


# ------------------------------------------------------------------------------ chunked access

SINGLE_RATE = {
    "labview-tdms": lambda d, r: vf.labview_waveform_tdms(d, r),
    "picoscope": lambda d, r: vf.picoscope_csv(d, r),
    "catman": lambda d, r: vf.catman_ascii(d, r, name="catman.csv", time_column="relative"),
    "canape-csv": lambda d, r: vf.canape_ascii_csv(d, r),
    "lvm": lambda d, r: vf.labview_lvm(d, r),
    "mat5": lambda d, r: vf.matlab_struct_mat(d, r, version="5"),
    "mat73": lambda d, r: vf.matlab_struct_mat(d, r, version="7.3"),
    "twincat": lambda d, r: vf.twincat_scope_csv(d, r),
}


@pytest.mark.parametrize("kind", sorted(SINGLE_RATE))
def test_chunks_of_a_vendor_file_are_the_whole_read(tmp_path, source, kind):
    from rollerrig.recordings.source import open_recording

    v = SINGLE_RATE[kind](tmp_path, source)
    cmap = v.write_map()
    whole = read_recording(v.path, cmap)
    with open_recording(v.path, cmap) as src:
        assert src.n_samples == whole.time.size
        chunks = list(src.iter_chunks(chunk_samples=77))
    assert {len(c) for c in chunks[:-1]} == {77}
    _same(np.concatenate([c.time for c in chunks]), whole.time, atol=1e-12)
    for name in whole.channels:
        _same(np.concatenate([c[name] for c in chunks]), whole[name], atol=1e-9)


@pytest.mark.parametrize("kind", ["daqmx", "inca-mdf"])
def test_chunks_of_a_multi_rate_vendor_file_or_a_pointer_to_read_recording(tmp_path, kind):
    from rollerrig.recordings.source import open_recording

    if kind == "daqmx":
        v = vf.daqmx_multitask_tdms(tmp_path, duration_s=0.5)
    else:
        v = vf.inca_canape_mdf(tmp_path, vf.bench_recording(1.0, 250.0))
    cmap = v.write_map()
    try:
        with open_recording(v.path, cmap) as src:
            chunks = list(src.iter_chunks(chunk_samples=1000))
    except RecordingError as exc:
        assert "read_recording" in str(exc) and v.path.name in str(exc)
    else:
        whole = read_recording(v.path, cmap)
        _same(np.concatenate([c["torque"] for c in chunks]), whole["torque"], atol=1e-9)


# ------------------------------------------------------------------------------ TwinCAT Scope


@pytest.mark.parametrize(
    "dialect",
    [
        {},  # tab, decimal comma, a time column per channel, EOF line
        {"separator": ";", "decimal": ".", "shared_time": True, "eof": False},
        {"separator": ",", "decimal": "."},
    ],
    ids=["tab-comma-eof", "semicolon-shared-time", "comma-point"],
)
def test_twincat_scope_export_reads_each_channel_on_its_time_columns(tmp_path, source, dialect):
    """Without a [file] or [time] section: the channels' header under the file header, a key
    above each time column (ms), ragged rows below the slow channel's end, an EOF line."""
    v = vf.twincat_scope_csv(tmp_path, source, **dialect)
    rec = _read(v)
    assert rec.time.size == source.time.size
    _same(rec.time, source.time - source.time[0], atol=1e-9)
    _same(rec["torque"], source["torque"], atol=1e-6)
    _same(rec["wheel_speed"], source["wheel_speed"], atol=1e-6 * RPM)
    _same(rec["roller_speed"], source["roller_speed"], atol=1e-6 * RPM)
    notes = " ".join(rec.metadata["notes"])
    # the export's start: FILETIME of vf.START, in UTC
    assert "2024-08-05T11:46:13.250Z" in notes
    assert "different sample times" in notes  # the pressure at 10 ms, not in the map


def test_twincat_scope_slow_channel_on_a_common_time_base(tmp_path, source):
    """The pressure at 10 ms beside the 1 ms channels: each on its own time base, put on one by
    the map's resample_Hz, never aligned by index (the rows below its last sample are short)."""
    v = vf.twincat_scope_csv(tmp_path, source)
    cmap = _toml(v.channel_map)
    cmap["channels"]["air_spring_pressure"] = {"column": "fPressureAirSpring", "unit": "bar"}
    cmap["time"] = {"resample_Hz": 1000.0}
    rec = _read(v, cmap)
    # the common span ends at the slow channel's last sample (990 ms): 991 samples at 1 kHz
    assert rec.time.size == 991
    _same(rec.time, source.time[:991] - source.time[0], atol=1e-9)
    _same(rec["torque"], source["torque"][:991], atol=1e-6)
    # interpolated linearly between its own samples: through them at every 10 ms
    _same(rec["air_spring_pressure"][::10], source["air_spring_pressure"][:991:10], atol=0.1)
    assert rec.metadata["resampled"]["channels"]["air_spring_pressure"]["from_rate_Hz"] == (
        pytest.approx(100.0)
    )


def test_twincat_scope_export_separated_by_spaces_is_refused_with_what_to_do(tmp_path, source):
    v = vf.twincat_scope_csv(tmp_path, source, separator=" ", decimal=".")
    with pytest.raises(RecordingError, match=r"separated by spaces.*tab"):
        _read(v)


def test_twincat_scope_sample_time_split_by_a_comma_separator_leaves_the_values(tmp_path):
    """TwinCAT writes the header's sample time in the PC's locale (0,5) even under a ','
    separator: that row, and the unit row beside it, get more cells than the names. The units
    are then not read (said in a note), the samples are."""
    path = tmp_path / "scope.csv"
    header = [
        "Name,rig",
        "",
        "Name,fTorque,Name,fFast",
        "SampleTime[ms],1,SampleTime[ms],0,5",
        "Unit,Nm (Torque),Unit,V (Voltage)",
        "",
    ]
    rows = [f"{k},{10.0 * k},{0.5 * k},{-k}" for k in range(4)]
    rows += [f" , ,{0.5 * k},{-k}" for k in range(4, 8)]
    path.write_text("\n".join(header + rows) + "\n", encoding="utf-8")
    cmap = {"channels": {"torque": {"column": "fTorque", "unit": "N.m"}}}
    rec = read_recording(path, cmap)
    _same(rec.time, [0.0, 1e-3, 2e-3, 3e-3], atol=1e-12)
    _same(rec["torque"], [0.0, 10.0, 20.0, 30.0], atol=0)
    assert any("'SampleTime[ms]' row not read" in n for n in rec.metadata["notes"])


def test_twincat_scope_cell_that_is_no_number_names_its_line_and_channel(tmp_path, source):
    v = vf.twincat_scope_csv(tmp_path, source, decimal=".", eof=False)
    lines = v.path.read_text(encoding="utf-8").splitlines()
    at = next(i for i, t in enumerate(lines) if t.startswith("0\t")) + 5
    cells = lines[at].split("\t")
    cells[1] = "#WERT!"
    lines[at] = "\t".join(cells)
    v.path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(RecordingError, match=rf"line {at + 1}, channel 'fTorqueT56'.*#WERT!"):
        _read(v)


def _scope_text(names: list[str], rows: list[str], *, start: str = "133673319732500000") -> str:
    """A small TwinCAT Scope export: a time column per channel, tab-separated."""
    header = ["Name\tscope", f"Starttime of export\t{start}\tMontag\t13:46:13.250", "", ""]
    header.append("\t".join(f"Name\t{n}" for n in names))
    header.append("\t".join("SampleTime[ms]\t1" for _ in names))
    header.append("\t".join("Unit\tNm (Torque)" for _ in names))
    return "\n".join([*header, "", *rows]) + "\n"


def test_twincat_scope_a_name_given_twice_is_ambiguous_not_the_first(tmp_path):
    """Two channels of one name (two symbols scoped under one display name): the map's name
    alone is an error naming the candidates, as for a CSV, never the first column quietly."""
    path = tmp_path / "dup.csv"
    path.write_text(_scope_text(["T", "T"], [f"{k}\t{k}\t{k}\t{100 * k}" for k in range(5)]))
    with pytest.raises(RecordingError, match=r"2 columns of that name.*T\.1"):
        read_recording(path, {"channels": {"torque": {"column": "T", "unit": "N.m"}}})
    rec = read_recording(path, {"channels": {"torque": {"column": "T.1", "unit": "N.m"}}})
    _same(rec["torque"], [0.0, 100.0, 200.0, 300.0, 400.0], atol=0)


def test_twincat_scope_decimal_commas_first_seen_deep_in_the_file(tmp_path):
    """A channel that shows whole numbers for its first 500 samples (a torque of 0 before the
    run) and then 0,5: the decimal mark is sniffed from every row, not the first few."""
    path = tmp_path / "late.csv"
    rows = [f"{k}\t{0 if k < 500 else '0,5'}" for k in range(600)]
    path.write_text(_scope_text(["v"], rows))
    rec = read_recording(path, {"channels": {"torque": {"column": "v", "unit": "N.m"}}})
    assert rec["torque"][499] == 0.0 and rec["torque"][500] == 0.5


def test_twincat_scope_start_time_beyond_any_date_is_left_unsaid(tmp_path):
    path = tmp_path / "ovf.csv"
    rows = [f"{k}\t{k}" for k in range(3)]
    path.write_text(_scope_text(["T"], rows, start="9" * 40))
    rec = read_recording(path, {"channels": {"torque": {"column": "T", "unit": "N.m"}}})
    assert not any("started" in n for n in rec.metadata["notes"])
    path.write_text(_scope_text(["T"], rows))
    rec = read_recording(path, {"channels": {"torque": {"column": "T", "unit": "N.m"}}})
    assert any("started 2024-08-05T11:46:13.250Z" in n for n in rec.metadata["notes"])


def test_twincat_scope_cells_in_quotes(tmp_path, source):
    v = vf.twincat_scope_csv(tmp_path, source, eof=False)
    lines = v.path.read_text(encoding="utf-8").splitlines()
    quoted = ["\t".join(f'"{c}"' if c.strip() else c for c in t.split("\t")) for t in lines]
    v.path.write_text("\n".join(quoted) + "\n", encoding="utf-8")
    rec = _read(v)
    _same(rec["torque"], source["torque"], atol=1e-6)


def test_twincat_scope_export_cut_short_drops_its_last_line(tmp_path, source):
    """A copy cut mid-line (no EOF line, no line end): the cut row's cells may be cut numbers
    (12 of 12,5), so that row is dropped with a note, never read."""
    v = vf.twincat_scope_csv(tmp_path, source, eof=False, slow_every=1)
    text = v.path.read_text(encoding="utf-8")
    v.path.write_text(text[: text.rindex("\n", 0, len(text) - 1) + 7], encoding="utf-8")
    rec = _read(v)
    assert rec.time.size == source.time.size - 1
    _same(rec["torque"], source["torque"][:-1], atol=1e-6)
    assert any("without a line end" in n for n in rec.metadata["notes"])


# ------------------------------------------------------- a logger that lost power (NUL tail)


@pytest.mark.parametrize("builder", ["labview_lvm", "twincat_scope_csv"])
def test_a_nul_padded_tail_of_an_lvm_or_scope_export_is_left_out(tmp_path, source, builder):
    # A logger that loses power leaves the file's space zero-filled after the last line it
    # wrote. CSV files had their padding left out with a note; LabVIEW .lvm files and TwinCAT
    # Scope exports, which decode the whole file, had been refused as binary.
    v = getattr(vf, builder)(tmp_path, source)
    whole = _read(v)
    data = v.path.read_bytes()
    v.path.write_bytes(data + b"\x00" * 4096)
    padded = _read(v)
    _same(padded.time, whole.time, atol=0)
    _same(padded["torque"], whole["torque"], atol=0)
    assert any("NUL bytes" in n for n in padded.metadata["notes"])
