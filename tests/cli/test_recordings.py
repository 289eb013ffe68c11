"""``rollerrig analyze``, ``spectrum`` and ``filters`` on hand-built recordings: results with
provenance, clear errors naming the channel or map entry, --lenient reported everywhere, fast
and long recordings decimated or streamed and said so."""

import json

import numpy as np
import pytest
import xarray as xr

from rollerrig.cli import app
from rollerrig.output import figure_provenance, file_sha256

HEADER = "time [s],torque [N.m],torque_request [N.m],wheel_speed [rad/s],roller_speed [rad/s]"


def _no_traceback(result):
    assert "Traceback" not in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


def _files(folder):
    return sorted(p.name for p in folder.rglob("*")) if folder.exists() else []


def test_analyze_reports_missing_channels_clearly(tmp_path, runner):
    bad = tmp_path / "bad.csv"
    bad.write_text("time [s],torque [N.m]\n0,1\n0.004,2\n0.008,3\n")
    result = runner.invoke(app, ["analyze", str(bad), "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "lacks channel" in result.output or "needs" in result.output
    assert "Traceback" not in result.output


def test_analyze_names_the_file_of_a_nan_time_stamp(tmp_path, runner):
    rows = [f"{k / 250:.3f},{k * 0.5:.2f},0,1,1" for k in range(40)]
    rows[20] = "nan,10,0,1,1"
    rec = tmp_path / "nantime.csv"
    rec.write_text(HEADER + "\n" + "\n".join(rows) + "\n")
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    _no_traceback(result)
    assert f"{rec}: time stamp 20 (of 40) is nan" in " ".join(result.output.split())


def test_failure_while_writing_leaves_no_partial_output(
    tmp_path, monkeypatch, runner, adhesion_csv
):
    from rollerrig.report.html import HtmlReport

    def fail(self, path):
        raise RuntimeError("disk full (simulated)")

    monkeypatch.setattr(HtmlReport, "write", fail)
    rec = adhesion_csv(tmp_path / "test.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", "--out", str(out)])
    assert result.exit_code == 3, result.output
    assert "disk full (simulated)" in result.output
    # The JSON and NetCDF were written before the report failed: neither is left, nor any
    # staging folder.
    assert not out.exists()
    assert _files(tmp_path) == ["test.csv"]


def test_analyze_without_a_test_names_the_torque_channel(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "flat.csv", torque=lambda t: 100.0 + 0 * t)
    rec.write_text(rec.read_text().replace("torque_request [N.m]", "setpoint [N.m]"))
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "no adhesion test found" in result.output
    assert "channel 'torque'" in result.output and "[channels.torque]" in result.output
    _no_traceback(result)
    assert not (tmp_path / "out").exists()


def test_analyze_huge_torque_names_the_channel(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "huge.csv", torque=lambda t: 1e300 * (1 + 0.1 * np.sin(t)))
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "channel 'torque'" in result.output and "1e+300" in result.output
    _no_traceback(result)
    rec = adhesion_csv(tmp_path / "kilo.csv", torque=lambda t: 1e6 + 0 * t)  # N.m as mN.m?
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "torque sensor's range" in result.output


def test_analyze_truth_of_another_length_or_not_netcdf(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")
    out = ["--out", str(tmp_path / "out")]
    not_nc = tmp_path / "truth.nc"
    not_nc.write_text("this is not NetCDF")
    result = runner.invoke(app, ["analyze", str(rec), "--truth", str(not_nc), *out])
    assert result.exit_code == 2, result.output
    assert "--truth" in result.output and "not a NetCDF file" in result.output
    _no_traceback(result)
    # An analysis' NetCDF has a 'coa' (the measured one): it was taken as the truth.
    analysis = tmp_path / "x-analysis.nc"
    zeros = ("time", np.zeros(10))
    coords = {"time": np.arange(10) / 100}
    xr.Dataset({"coa": zeros, "coa_corrected": zeros}, coords=coords).to_netcdf(
        analysis, engine="h5netcdf"
    )
    result = runner.invoke(app, ["analyze", str(rec), "--truth", str(analysis), *out])
    assert result.exit_code == 2, result.output
    assert "an analysis' output" in result.output
    _no_traceback(result)
    short = tmp_path / "short.nc"  # a truth needs 'coa' over 'time' only (another model's)
    xr.Dataset({"coa": zeros}, coords=coords).to_netcdf(short, engine="h5netcdf")
    result = runner.invoke(app, ["analyze", str(rec), "--truth", str(short), *out])
    assert result.exit_code == 2, result.output
    assert "10 samples, the recording 1000" in result.output
    _no_traceback(result)


def test_filters_refuses_a_table_of_no_rows(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")  # --top -5 printed all rows but 5 (a slice)
    result = runner.invoke(app, ["filters", str(rec), "--top", "-5", "--out", str(tmp_path / "o")])
    assert result.exit_code == 2 and "--top" in result.output
    assert not (tmp_path / "o").exists()


def test_filters_on_a_csv_with_a_header_and_no_rows(tmp_path, runner):
    empty = tmp_path / "empty.csv"
    empty.write_text(HEADER + "\n")
    result = runner.invoke(app, ["filters", str(empty), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "empty.csv" in result.output
    _no_traceback(result)


def test_filters_does_not_need_unrelated_sensors_of_the_map(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")
    cmap = tmp_path / "map.toml"
    cmap.write_text(
        '[time]\ncolumn = "time [s]"\nunit = "s"\n'
        '[channels.torque]\ncolumn = "torque [N.m]"\nunit = "N.m"\n'
        '[channels.air_spring_pressure]\ncolumn = "p_bar"\nunit = "bar"\n'
    )
    out = tmp_path / "out"
    result = runner.invoke(app, ["filters", str(rec), "--channels", str(cmap), "--out", str(out)])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "test-filters.json").read_text())
    assert any("air_spring_pressure" in n for n in summary["recording"]["notes"])
    assert "lag [ms]" in result.output  # table headers keep their units
    # The tuned Savitzky-Golay filter is placed in the ranking, and why it is used is said.
    sg = summary["savitzky_golay"]
    assert 1 <= sg["would_rank"] <= sg["of"] == len(summary["ranking"])
    text = " ".join(result.output.split())
    assert f"costs {sg['cost']:.3f}: it would rank {sg['would_rank']} of {sg['of']}" in text
    assert "analyze smooths with it" in text and "the seed's method" in text


def test_lenient_reports_interpolated_runs_in_every_output(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv", nan_at=(150, 151), drop=(900, 901))
    out = tmp_path / "out"
    strict = runner.invoke(app, ["filters", str(rec), "--out", str(out)])
    assert strict.exit_code == 2 and "gap" in strict.output  # strict by default
    result = runner.invoke(app, ["analyze", str(rec), "--lenient", "--no-study", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "samples 150..151" in result.output  # console
    # the spectrum's window and phase are printed beside its caption
    spectrum = json.loads((out / "test-analysis.json").read_text())["spectrum"]
    assert spectrum["window_note"] in " ".join(result.output.split())
    summary = json.loads((out / "test-analysis.json").read_text())  # JSON
    (run,) = summary["recording"]["interpolated"]
    assert (run["channel"], run["first_sample"], run["last_sample"]) == ("torque", 150, 151)
    assert summary["recording"]["notes"]
    (gap,) = summary["recording"]["gaps"]  # rows 900-901 left out: a 0.03 s step
    assert gap["missing_samples"] == 2 and "gap kept" in result.output
    assert any("filled by linear interpolation" in n for n in summary["recording"]["notes"])
    ds = xr.open_dataset(out / "test-analysis.nc", engine="h5netcdf")  # NetCDF attributes
    try:
        assert json.loads(ds.attrs["interpolated"])[0]["first_sample"] == 150
        assert json.loads(ds.attrs["gaps"])[0]["missing_samples"] == 2
        assert json.loads(ds.attrs["recording_notes"]) == summary["recording"]["notes"]
    finally:
        ds.close()
    html = (out / "test-report.html").read_text()  # HTML report
    assert "samples 150..151" in html and "The recording as read" in html
    assert "gap kept" in html
    # The fit says over which slip velocities A and B are constrained, and tests its residuals.
    fit = summary["polach_fit_corrected_coa"]
    assert fit["slip_velocity_coverage"]["slip_velocity_range [m/s]"][1] > 0
    assert "durbin_watson" in fit["residual_structure"]
    assert "How far the Polach fit can be trusted" in html
    result = runner.invoke(app, ["filters", str(rec), "--lenient", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "samples 150..151" in result.output
    filt = json.loads((out / "test-filters.json").read_text())  # filters JSON
    assert filt["recording"]["interpolated"][0]["first_sample"] == 150
    assert filt["recording"]["gaps"][0]["missing_samples"] == 2
    assert filt["recording"]["notes"] == summary["recording"]["notes"]


def test_a_gap_too_long_to_fill_is_named(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv", drop=range(300, 320))
    for command in ("analyze", "filters"):
        result = runner.invoke(app, [command, str(rec), "--lenient", "--out", str(tmp_path / "o")])
        assert result.exit_code == 2, result.output
        assert "gap of 0.21 s after t = 2.99 s" in result.output and "too long" in result.output
    assert not (tmp_path / "o").exists()


def test_analyze_of_a_fast_recording_decimates_and_says_so_whole_or_streamed(
    tmp_path, monkeypatch, runner, fast_test
):
    import rollerrig.cli as cli

    rec, t, coa = fast_test(tmp_path / "fast.tdms")
    truth = tmp_path / "fast-truth.nc"
    xr.Dataset({"coa": ("time", coa)}, coords={"time": t}).to_netcdf(truth, engine="h5netcdf")
    summaries = []
    for name, limit in (("whole", cli._SPECTRUM_IN_MEMORY), ("streamed", 1000)):
        monkeypatch.setattr(cli, "_SPECTRUM_IN_MEMORY", limit)  # 1000: the file counts as long
        out = tmp_path / name
        args = ["analyze", str(rec), "--no-study", "--truth", str(truth), "--out", str(out)]
        result = runner.invoke(app, args)
        assert result.exit_code == 0, result.output
        assert "analysed at 1000 Hz" in result.output
        summary = json.loads((out / "fast-analysis.json").read_text())
        rate = summary["analysis_rate"]
        assert (rate["rate [Hz]"], rate["recording rate [Hz]"]) == (1000.0, 19200.0)
        assert rate["decimation"]["stopband_attenuation_dB"] >= 70.0
        notes = summary["recording"]["notes"]
        assert any(n.startswith("decimated from 19200 Hz to 1000 Hz") for n in notes)
        assert any("analysed at 1000 Hz" in n for n in summary["notes"])
        smoothing = summary["smoothing"]
        assert smoothing["samples at [Hz]"] == 1000.0 and smoothing["tuned at [Hz]"] == 250.0
        assert summary["truth_errors"]["corrected_coa_vs_true_rms [-]"] < 0.05
        summaries.append(summary)
    whole, streamed = summaries
    assert "streaming it from the file" in " ".join(streamed["notes"])
    # The streamed decimation equals the one-shot one (to rounding): the same results.
    assert [p["start [s]"] for p in whole["phases"]] == [p["start [s]"] for p in streamed["phases"]]
    assert whole["polach_fit_corrected_coa"]["mu0"] == pytest.approx(
        streamed["polach_fit_corrected_coa"]["mu0"], rel=1e-6
    )


def test_filters_on_a_fast_recording_states_its_basis_whole_or_streamed(
    tmp_path, monkeypatch, runner, fast_test
):
    import rollerrig.cli as cli

    rec, _, _ = fast_test(tmp_path / "fast.parquet", duration=6.0)
    rankings = []
    for name, limit in (("whole", cli._SPECTRUM_IN_MEMORY), ("streamed", 1000)):
        monkeypatch.setattr(cli, "_SPECTRUM_IN_MEMORY", limit)
        out = tmp_path / name
        result = runner.invoke(app, ["filters", str(rec), "--out", str(out)])
        assert result.exit_code == 0, result.output
        assert "filter study computed at 250 Hz" in result.output
        summary = json.loads((out / "fast-filters.json").read_text())
        basis = summary["basis"]
        assert (basis["source_rate_Hz"], basis["analysis_rate_Hz"]) == (19200.0, 250.0)
        assert basis["decimation"].startswith("decimated from 19200 Hz to 250 Hz")
        sg = summary["savitzky_golay"]
        assert sg["tuned at [Hz]"] == 250.0 and sg["samples at [Hz]"] == 19200.0
        assert sg["window [s]"] == pytest.approx(sg["window [samples]"] / 19200.0)
        assert isinstance(summary["unscored"], dict)
        assert all(r["sample_rate_Hz"] == 250.0 for r in summary["ranking"])
        rankings.append([r["label"] for r in summary["ranking"]])
    assert rankings[0] == rankings[1]


def test_lenient_on_a_long_file_reads_it_whole_and_says_so(
    tmp_path, monkeypatch, runner, adhesion_csv
):
    import rollerrig.cli as cli

    monkeypatch.setattr(cli, "_SPECTRUM_IN_MEMORY", 100)
    rec = adhesion_csv(tmp_path / "test.csv", nan_at=(150,))
    result = runner.invoke(app, ["filters", str(rec), "--out", str(tmp_path / "a")])
    assert result.exit_code == 2, result.output  # streamed strictly: the NaN is an error
    assert "'torque' has a NaN/inf sample at sample 150" in result.output
    assert "on the command line: --lenient" in result.output
    result = runner.invoke(app, ["filters", str(rec), "--lenient", "--out", str(tmp_path / "b")])
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "b" / "test-filters.json").read_text())
    assert any("read whole for --lenient" in n for n in summary["recording"]["notes"])
    assert summary["recording"]["interpolated"][0]["first_sample"] == 150


def test_every_output_of_analyze_and_filters_carries_the_inputs_hashes(
    tmp_path, runner, adhesion_csv
):
    rec = adhesion_csv(tmp_path / "test.csv")
    cmap = tmp_path / "map.toml"
    cmap.write_text(
        '[time]\ncolumn = "time [s]"\nunit = "s"\n'
        '[channels.torque]\ncolumn = "torque [N.m]"\nunit = "N.m"\n'
        '[channels.torque_request]\ncolumn = "torque_request [N.m]"\nunit = "N.m"\n'
        '[channels.wheel_speed]\ncolumn = "wheel_speed [rad/s]"\nunit = "rad/s"\n'
        '[channels.roller_speed]\ncolumn = "roller_speed [rad/s]"\nunit = "rad/s"\n'
        '[channels.normal_load]\ncolumn = "normal_load [N]"\nunit = "N"\n'
    )
    out = tmp_path / "out"
    common = ["--channels", str(cmap), "--out", str(out)]
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", *common])
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["filters", str(rec), *common])
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["spectrum", str(rec), *common])
    assert result.exit_code == 0, result.output
    sha, map_sha = file_sha256(rec), file_sha256(cmap)

    def check(record, what):
        assert record["inputs"]["recording"]["sha256"] == sha, what
        assert record["channel_map"]["sha256"] == map_sha, what
        assert record["command"][1] in ("analyze", "filters", "spectrum"), what
        assert record["commit"] or record["commit_note"], what

    for path in out.glob("*.json"):
        check(json.loads(path.read_text())["provenance"], path.name)
    for path in out.glob("*.png"):
        check(figure_provenance(path), path.name)
    ds = xr.open_dataset(out / "test-analysis.nc", engine="h5netcdf")
    try:
        check(json.loads(ds.attrs["provenance"]), "test-analysis.nc")
    finally:
        ds.close()
    names = {p.name for p in out.iterdir()}
    assert {"analyze-test-run.json", "filters-test-run.json", "spectrum-run.json"} <= names
    assert file_sha256(rec) == sha  # the input was only read


def test_analyze_with_a_calibration_uses_it_and_refuses_a_bad_file(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")
    bad = tmp_path / "calibration.json"
    bad.write_text('{"free": []}')
    out = tmp_path / "out"
    result = runner.invoke(app, ["analyze", str(rec), "--calibration", str(bad), "--out", str(out)])
    assert result.exit_code == 2, result.output
    assert "--calibration" in result.output and "parameters" in result.output
    _no_traceback(result)
    assert not out.exists()

    good = tmp_path / "good.json"
    calibration = {"parameters": {"inertia.roller": {"value": 60.0, "standard_error": 0.5}}}
    good.write_text(json.dumps(calibration))
    args = ["analyze", str(rec), "--no-study", "--calibration", str(good), "--out", str(out)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "expanded uncertainty" in result.output
    summary = json.loads((out / "test-analysis.json").read_text())
    inputs = summary["coa_uncertainty"]["inputs"]
    assert "inertia.roller" in json.dumps(inputs)
    run = json.loads((out / "analyze-test-run.json").read_text())
    assert "calibration" in run["provenance"]["inputs"]
    html = (out / "test-report.html").read_text()
    assert "The calibrated twin this analysis used" in html and "inertia.roller" in html


def test_analyze_writes_channels_whose_names_netcdf_cannot_hold(tmp_path, runner, adhesion_csv):
    """Issue 24, point 4: a slash, brackets or an accent in a column name used to fail the
    NetCDF writer at the very end (exit 3, nothing written)."""
    rec = adhesion_csv(tmp_path / "odd.csv")
    extra = {
        "oil temp/bearing [degC]": "oil_temp_bearing",
        "Group/Channel [N/mm]": "Group_Channel",
        "[bold]x[/bold] [1]": "bold_x_bold",
        "Öl-Temp [degC]": "Ol_Temp",
        "oil temp_bearing [degC]": "oil_temp_bearing_2",
    }
    lines = rec.read_text().splitlines()
    rows = [lines[0] + "," + ",".join(extra)]
    rows += [f"{line},{40 + i / 1000},{i},1,2,3" for i, line in enumerate(lines[1:])]
    rec.write_text("\n".join(rows) + "\n")
    out = tmp_path / "out"
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", "--out", str(out)])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out / "odd-analysis.nc", engine="h5netcdf") as ds:
        for header, stored in extra.items():
            original = header.rsplit(" [", 1)[0]
            assert ds[stored].attrs["original_name"] == original
        assert ds["Group_Channel"].values[3] == pytest.approx(3e3)  # N/mm -> N/m
        assert "original_name" not in ds["torque"].attrs


def test_a_full_disk_names_the_file_and_what_to_do(tmp_path, monkeypatch, runner, adhesion_csv):
    """Issue 24, point 9: the disk filling up while the NetCDF is written."""
    import errno

    from rollerrig.output import tables

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(tables, "_nc", full)
    rec = adhesion_csv(tmp_path / "test.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", "--out", str(out)])
    _no_traceback(result)
    assert result.exit_code != 0
    assert "test-analysis.nc: cannot write the file: No space left on device" in result.output
    assert "the disk is full" in result.output and "--out" in result.output
    assert not out.exists() and _files(tmp_path) == ["test.csv"]


def test_unicode_names_keep_their_outputs_apart(tmp_path, runner, adhesion_csv):
    one = adhesion_csv(tmp_path / "试验一.csv")
    two = adhesion_csv(tmp_path / "试验二.csv")
    same = adhesion_csv(tmp_path / "a_b.csv")
    other = adhesion_csv(tmp_path / "a b.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["spectrum", str(one), str(two), "--out", str(out), "-q"])
    assert result.exit_code == 0, result.output
    assert {"试验一-spectrum.png", "试验二-spectrum.png"} <= set(_files(out))
    result = runner.invoke(app, ["spectrum", str(same), str(other), "--out", str(out), "-q"])
    assert result.exit_code == 0, result.output  # the same once made safe: numbered
    assert {"a_b-1-spectrum.png", "a_b-2-spectrum.png"} <= set(_files(out))
    for rec in (one, two):
        result = runner.invoke(app, ["filters", str(rec), "--out", str(out), "-q"])
        assert result.exit_code == 0, result.output
    names = set(_files(out))
    for stem in ("试验一", "试验二"):
        assert {f"{stem}-filters.json", f"filters-{stem}-run.json"} <= names
    bad = adhesion_csv(tmp_path / "x:y.csv")  # analyze: the run file follows the same rule
    result = runner.invoke(app, ["analyze", str(bad), "--no-study", "--out", str(out), "-q"])
    assert result.exit_code == 0, result.output
    assert {"x_y-analysis.json", "analyze-x_y-run.json"} <= set(_files(out))


def _jittered(path, adhesion_csv, sigma=0.0002):
    """The hand-built test at 100 Hz with N(0, sigma) noise on its time stamps."""
    src = adhesion_csv(path)
    lines = src.read_text().splitlines()
    rng = np.random.default_rng(1)
    out = [lines[0]]
    for k, line in enumerate(lines[1:]):
        _, rest = line.split(",", 1)
        out.append(f"{k / 100.0 + (rng.normal(0, sigma) if k else 0.0):.6f},{rest}")
    path.write_text("\n".join(out) + "\n")
    return path


def test_jittered_time_stamps_are_put_on_a_uniform_base_and_said_so(tmp_path, runner, adhesion_csv):
    rec = _jittered(tmp_path / "jitter.csv", adhesion_csv)
    for command in (["filters"], ["spectrum"], ["analyze", "--no-study"]):
        out = tmp_path / command[0]
        result = runner.invoke(app, [*command, str(rec), "--out", str(out)])
        assert result.exit_code == 0, (command, result.output)
        text = " ".join(result.output.split())
        assert "irregular sample times" in text, command
        assert "resample_Hz = 100" in text, command


def test_constant_torque_is_refused_by_filters_and_a_warning_of_analyze(
    tmp_path, runner, adhesion_csv
):
    rec = adhesion_csv(tmp_path / "const.csv", torque=lambda t: np.full(t.size, 12.5))
    result = runner.invoke(app, ["filters", str(rec), "--out", str(tmp_path / "f")])
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert f"{rec}: channel 'torque' is constant (12.5 in all 1000 samples)" in text
    assert "check that the channel is connected" in text
    result = runner.invoke(app, ["spectrum", str(rec), "--out", str(tmp_path / "s")])
    assert result.exit_code == 2 and "is constant (12.5" in result.output
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", "--out", str(tmp_path / "a")])
    text = " ".join(result.output.split())
    assert "warning:" in text and "channel 'torque' is constant (12.5" in text, text


def test_analyze_and_filters_note_an_empty_tdms_channel_they_can_do_without(
    tmp_path, runner, adhesion_csv
):
    """A TDMS file whose torque_request channel was created but never written (a spare input
    of the acquisition task): without a channel map, analyze (which falls back to the torque
    for the phases) and filters (which needs only the torque) run and note the empty channel;
    it stopped both with 'holds no samples'."""
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsFile, TdmsWriter

    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.writers import write_recording

    full = tmp_path / "full.tdms"
    write_recording(read_recording(adhesion_csv(tmp_path / "test.csv")), full)
    src = TdmsFile.read(full)
    rec = tmp_path / "spare.tdms"
    with TdmsWriter(rec) as writer:
        objects = [RootObject(src.properties)]
        for group in src.groups():
            objects.append(GroupObject(group.name, group.properties))
            for ch in group.channels():
                data = np.array([], dtype=float) if ch.name == "torque_request" else ch[:]
                objects.append(ChannelObject(group.name, ch.name, data, properties=ch.properties))
        writer.write_segment(objects)
    for command in (["analyze", "--no-study"], ["filters"]):
        out = tmp_path / command[0]
        result = runner.invoke(app, [command[0], str(rec), *command[1:], "--out", str(out)])
        _no_traceback(result)
        assert result.exit_code == 0, result.output
        results = " ".join(p.read_text() for p in out.glob("spare-*.json"))
        assert "torque_request' (not needed here) not read" in results
        assert "holds no samples" in results


def test_a_table_cell_shows_no_negative_zero():
    # The filters table had shown a lag of -0.2 ms as "-0.000" [s]; it is in ms now.
    from rollerrig.cli.recordings import _cell

    assert _cell(-0.0002) == "0.000"
    assert _cell(-0.04, 1) == "0.0"
    assert _cell(-0.26, 1) == "-0.3"
    assert _cell(float("nan")) == "–"


def test_the_fit_table_shows_no_sigma_for_a_parameter_at_a_bound():
    # A fit whose A ends at its bound 1 has a one-sided interval: "(at a bound)", where the
    # table had printed hundreds of thousands of σ from the truth.
    import warnings

    from rollerrig.cli.recordings import _fit_cell
    from rollerrig.contact.creep import PolachParameters
    from rollerrig.fit.model import PARAMETER_NAMES, polach_coa
    from rollerrig.fit.polach import fit_polach

    flat = PolachParameters(0.36, 1.0, 0.0, 0.27, 0.08)
    load, stiffness = 4300.0, 3.2e6
    s = np.linspace(5e-4, 0.02, 200)
    w = s * 10 / 3.6
    y = polach_coa(s, w, load, stiffness, flat)
    y = y + 0.002 * np.random.default_rng(1).standard_normal(s.size)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fit_polach(s, y, load, stiffness, slip_velocity=w)
    truth = dict(zip(PARAMETER_NAMES, (0.36, 0.4, 0.2, 0.27, 0.08), strict=True))
    assert "limit_ratio" in fit.at_bound
    assert _fit_cell(fit, "limit_ratio", truth).endswith("at a bound)")
    assert _fit_cell(fit, "static_friction", truth).endswith(" σ)")


def test_the_fit_table_gives_no_error_bar_where_a_and_b_are_not_identifiable():
    # Creep to 1 % at 30 km/h: the slip velocities do not reach where μ(w) falls, and the
    # table had printed A as 0.7553 ± 0.0066 (53.5 σ from a truth of 0.4) beside "A and B NOT
    # identifiable".
    import warnings

    from rollerrig.cli.recordings import _fit_cell
    from rollerrig.contact.creep import PolachParameters
    from rollerrig.fit.model import PARAMETER_NAMES, polach_coa
    from rollerrig.fit.polach import fit_polach

    true = PolachParameters(0.36, 0.4, 0.2, 0.27, 0.08)
    load, stiffness = 4300.0, 3.2e6
    s = np.linspace(2e-4, 0.01, 150)
    w = s * 30 / 3.6
    y = polach_coa(s, w, load, stiffness, true)
    y = y + 0.002 * np.random.default_rng(2).standard_normal(s.size)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fit_polach(s, y, load, stiffness, slip_velocity=w)
    assert not fit.coverage.a_and_b_identifiable
    truth = dict(zip(PARAMETER_NAMES, true.as_tuple(), strict=True))
    for key in ("limit_ratio", "friction_decay"):
        cell = _fit_cell(fit, key, truth)
        assert "not identifiable" in cell and "±" not in cell and "σ" not in cell
        assert fit.truth_distance(truth)[key]["sigma"] is None
    assert "±" in _fit_cell(fit, "static_friction", truth)


def test_analyze_warns_of_another_rig_than_the_recordings_and_an_implausible_coa(
    tmp_path, runner, adhesion_csv
):
    # `analyze seed-30kmh-dry.tdms --rig vt-fra-quarter-scale` had printed a hold's CoA of 2.37
    # (rig) without a word. Now a warning names both rigs, and one names a CoA above 1.0.
    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.writers import write_recording
    from rollerrig.rig.parameters import default_rig

    def with_rig(name, **kwargs):
        csv = read_recording(adhesion_csv(tmp_path / f"{name}-plain.csv", **kwargs))
        channels = {key: csv[key] for key in csv.channels}
        own = Recording(csv.time, channels, csv.units, {"rig": default_rig().to_dict()})
        return write_recording(own, tmp_path / f"{name}.csv")

    rec = with_rig("own")
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", "--out", str(tmp_path / "o")])
    assert result.exit_code == 0, result.output
    assert "warning:" not in result.output, result.output  # its own rig: nothing to say

    def five_times(t):  # the hold at 3000 N.m: a CoA of 1.5 on either rig
        return 5 * np.interp(t, [0, 2, 5, 5.5, 5.52, 10], [0, 0, 600, 600, 0, 0])

    rec = with_rig("test", torque=five_times)
    out = tmp_path / "out"
    args = ["analyze", str(rec), "--no-study", "--out", str(out)]
    result = runner.invoke(app, [*args, "--rig", "vt-fra-quarter-scale"])
    assert result.exit_code == 0, result.output
    _no_traceback(result)
    text = " ".join(result.output.split())
    assert (
        "warning: " + str(rec) + ": the recording states it was made on rig "
        "'pardubice-tram-roller-rig'" in text
    ), text
    assert "the analysis uses rig 'vt-fra-quarter-scale-roller-rig'" in text
    assert "geometry.roller_radius_x (0.452 there, 0.5715 here)" in text
    assert "warning: " + str(rec) + ": implausible CoA: the" in text
    assert "wrong rig file" in text and "air-spring area" in text
    assert text.count("the recording states it was made on rig") == 1  # no note repeating it
    notes = json.loads((out / "test-analysis.json").read_text())["notes"]
    assert any(n.startswith("the recording states it was made on rig") for n in notes)
    assert any(n.startswith("implausible CoA") for n in notes)
