"""The ``rollerrig`` command: outputs written, numbers printed, clear errors for bad input.

The error boundary: a user-side problem ends with one ``error:`` line (exit code 2), anything
else with one ``internal error`` line (exit code 3); never a traceback, never a partial output.
Fixtures are tiny CSVs written here (an adhesion test of 10 s at 100 Hz built by hand).
"""

import json

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from rollerrig import __version__
from rollerrig.cli import app

runner = CliRunner()

COMMANDS = ("contact", "simulate", "study", "modes", "analyze", "spectrum", "filters", "demo")
HEADER = "time [s],torque [N.m],torque_request [N.m],wheel_speed [rad/s],roller_speed [rad/s]"


def _adhesion_csv(path, fs=100.0, duration=10.0, torque=None, nan_at=(), drop=()):
    """A hand-built adhesion test: ramp 2-5 s to 600 N.m, hold, sudden release; creep rising
    with the CoA; 30 km/h, 4.3 kN; ``torque`` replaces the measured torque if given; NaN at
    the samples ``nan_at``; the rows ``drop`` left out (a gap)."""
    rng = np.random.default_rng(0)
    t = np.arange(int(duration * fs)) / fs
    request = np.interp(t, [0, 2, 5, 5.5, 5.52, duration], [0, 0, 600, 600, 0, 0])
    # The induction motor's line (5 pole pairs x roller rotation at 30 km/h: 14.67 Hz) and noise.
    line = 3.0 * np.sin(2 * np.pi * 5 * (30 / 3.6) / (2 * np.pi * 0.452) * t)
    measured = request + line + rng.standard_normal(t.size) if torque is None else torque(t)
    rr, rw, load = 0.452, 0.348, 4300.0
    coa = np.clip(request / (rr * load), 0, None)
    creep = 0.02 * np.tan(np.clip(coa / 0.45, 0, 0.9) * np.pi / 2) / np.tan(0.45 * np.pi)
    omega_r = np.full(t.size, 30 / 3.6 / rr)
    omega_w = omega_r * rr * (1 + creep + 1e-4 * coa) / rw
    measured = np.array(measured, dtype=float)
    measured[list(nan_at)] = np.nan
    rows = [HEADER + ",normal_load [N]"]
    rows += [
        f"{a:.6f},{b!r},{c:.6f},{d:.9f},{e:.9f},{load}"
        for i, (a, b, c, d, e) in enumerate(
            zip(t, measured.tolist(), request, omega_w, omega_r, strict=True)
        )
        if i not in set(drop)
    ]
    path.write_text("\n".join(rows) + "\n")
    return path


def _no_traceback(result):
    assert "Traceback" not in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


def _files(folder):
    return sorted(p.name for p in folder.rglob("*")) if folder.exists() else []


def test_contact_report_writes_figures_and_summary(tmp_path):
    result = runner.invoke(app, ["contact", "--load-kn", "20", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "contact area" in result.output
    for name in ("contact-creep-curves.png", "contact-vs-roller-radius.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    summary = json.loads((tmp_path / "contact-report.json").read_text())
    assert summary["provenance"]["parameters"]["normal_load_N"] == 20e3
    roller, rail = summary["contact"]["roller"], summary["contact"]["tangent_rail"]
    # The roller's longitudinal curvature shrinks the contact (Kayaalp §2.5, Figs. 12-13).
    assert roller["area_m2"] < rail["area_m2"]
    assert not list(tmp_path.glob(".*"))  # no temporary files left behind


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--load-kn", "-5"], "normal_load"),
        (["--roller-radius-mm", "0"], "radius"),
        (["--poisson", "0.6"], "poisson"),
        (["--ka", "0.2", "--ks", "0.5"], "kS <= kA"),
    ],
)
def test_contact_rejects_nonphysical_input(tmp_path, args, message):
    result = runner.invoke(app, ["contact", "--out", str(tmp_path), *args])
    assert result.exit_code == 2
    assert message in result.output
    assert "Traceback" not in result.output


@pytest.mark.slow  # ~20-35 s on 2 shared cores (compiles and runs the twin twice)
def test_simulate_writes_results_figure_and_modes(tmp_path):
    args = ["simulate", "--experiment", "seed-10kmh-wet", "--out", str(tmp_path), "--format", "csv"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "13.84" in result.output  # the roller-shaft mode in the modal table
    assert "release at" in result.output
    for name in ("seed-10kmh-wet.csv", "seed-10kmh-wet.provenance.json", "seed-10kmh-wet.png"):
        assert (tmp_path / name).stat().st_size > 1000
    # Re-running replaces the outputs instead of failing.
    assert runner.invoke(app, args).exit_code == 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--experiment", "no-such-experiment"], "no-such-experiment"),
        (["--roller-drive", "steam"], "roller drive"),
        (["--roller-lag-s", "-1"], "roller_lag"),
        (["--format", "xlsx"], "format"),
    ],
)
def test_simulate_rejects_bad_options(tmp_path, args, message):
    result = runner.invoke(app, ["simulate", "--out", str(tmp_path), *args])
    assert result.exit_code == 2, result.output
    assert message in result.output


@pytest.mark.slow
def test_demo_runs_end_to_end_and_its_outputs_analyse_again(tmp_path):
    # The README's main job, then the files it wrote through the other commands.
    result = runner.invoke(app, ["demo", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    # No line is injected into the demo's recordings any more, so none is "found" by hand.
    assert "no line is injected into the demo's recordings" in result.output
    assert "1.333 Hz" not in result.output.split("speed-independent lines in the free")[-1]
    # The fit says where A and B are constrained, that they are not here, and how far it
    # misses the twin's truth (the demo's test runs at one speed).
    assert "A and B NOT identifiable" in result.output
    assert "misses the twin's true Polach set" in result.output
    summary = json.loads((tmp_path / "seed-30kmh-dry-analysis.json").read_text())
    fit = summary["polach_fit_corrected_coa"]
    assert fit["identifiable"] is False and fit["A_B_identifiable"] is False
    assert fit["truth_distance"]["limit_ratio"]["beyond_warn_sigma"] is True
    assert (tmp_path / "seed-30kmh-dry-report.html").stat().st_size > 100_000
    # Coherence of shaft displacement and torque: high at the roller order (the run-out's own
    # line), low at the induction motor's line (not mechanical; Kayaalp §4.5.2.4).
    spectra = json.loads((tmp_path / "free-rolling-spectra.json").read_text())
    coh = {
        r["source"].split(" (")[0]: r["coherence"]
        for r in spectra["coherence_torque_displacement_30kmh"]
    }
    assert coh["roller order ×1"] > 0.9 and coh["AM electrical ×1"] < 0.2
    recordings = sorted(tmp_path.glob("free-rolling-*.mf4"))
    assert len(recordings) == 4
    out = tmp_path / "again"
    args = ["spectrum", *map(str, recordings[:2]), "--coherence", "displacement_torque_sensor"]
    r = runner.invoke(app, [*args, "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert (out / "order-map.png").exists()
    assert "coherence torque–displacement_torque_sensor at the peaks" in r.output
    r = runner.invoke(app, ["filters", str(tmp_path / "seed-30kmh-dry.tdms"), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "Savitzky-Golay tuned" in r.output
    r = runner.invoke(
        app,
        [
            "analyze",
            str(tmp_path / "seed-30kmh-dry.tdms"),
            "--no-study",
            "--out",
            str(out),
            "--truth",
            str(tmp_path / "seed-30kmh-dry-truth.nc"),
        ],
    )
    assert r.exit_code == 0, r.output
    assert (out / "seed-30kmh-dry-report.html").exists()


def test_analyze_reports_missing_channels_clearly(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("time [s],torque [N.m]\n0,1\n0.004,2\n0.008,3\n")
    result = runner.invoke(app, ["analyze", str(bad), "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "lacks channel" in result.output or "needs" in result.output
    assert "Traceback" not in result.output


@pytest.mark.slow  # ~10-18 s: three twin runs
def test_study_writes_table_figure_and_json(tmp_path):
    result = runner.invoke(app, ["study", "drives", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "ideal speed source" in result.output
    assert (tmp_path / "study-drives.png").stat().st_size > 10_000
    assert runner.invoke(app, ["study", "colour", "--out", str(tmp_path)]).exit_code == 2


# --- Help, version, markup ------------------------------------------------------------------


@pytest.mark.parametrize("command", COMMANDS)
def test_help_of_every_command_keeps_units_in_brackets(command):
    result = runner.invoke(app, [command, "--help"])
    assert result.exit_code == 0, result.output
    _no_traceback(result)
    assert "Usage:" in result.output
    # Every "[" of the help survives: Rich markup would have eaten "[kN]" and friends.
    expected = {
        "contact": ["Normal load [kN]", "[km/h]", "[mm]", "Poisson's ratio [-]"],
        "simulate": ["Roller-drive lag τ [s]"],
        "analyze": ["--lenient"],
        "filters": ["--lenient"],
    }
    for text in expected.get(command, []):
        assert text in " ".join(result.output.split()), text


def test_root_help_and_version():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for command in COMMANDS:
        assert command in result.output
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0, result.output
    assert result.output.strip() == f"rollerrig {__version__}"


def test_error_messages_keep_brackets(tmp_path):
    # A channel map entry and the extra to install are named with brackets: both survive.
    rec = _adhesion_csv(tmp_path / "test.csv")
    cmap = tmp_path / "map.toml"
    cmap.write_text('[time]\ncolumn = "time [s]"\nunit = "s"\n[channels.torque]\ncolumn = "Tq"\n')
    result = runner.invoke(app, ["filters", str(rec), "--channels", str(cmap)])
    assert result.exit_code == 2, result.output
    assert "[channels.torque]" in result.output
    _no_traceback(result)


# --- The error boundary ---------------------------------------------------------------------


def test_missing_file_is_one_error_line(tmp_path):
    missing = tmp_path / "nope.tdms"
    for args in (["analyze", str(missing)], ["filters", str(missing)]):
        result = runner.invoke(app, [*args, "--out", str(tmp_path / "out")])
        assert result.exit_code == 2, result.output
        assert result.output.startswith("error:") and "nope.tdms" in result.output
        assert len(result.output.strip().splitlines()) == 1
        _no_traceback(result)
    assert not (tmp_path / "out").exists()


def test_missing_optional_package_names_the_extra(tmp_path, monkeypatch):
    import rollerrig.measure.readers as readers

    def no_nptdms(*args, **kwargs):
        raise ModuleNotFoundError("No module named 'nptdms'", name="nptdms")

    monkeypatch.setattr(readers, "read_recording", no_nptdms)
    result = runner.invoke(app, ["filters", str(tmp_path / "x.tdms")])
    assert result.exit_code == 2, result.output
    assert "pip install 'rollerrig[io]'" in result.output
    _no_traceback(result)


def test_internal_error_is_one_line_exit_3_and_debug_shows_the_traceback(tmp_path, monkeypatch):
    import rollerrig.contact.curves as curves

    def broken(*args, **kwargs):
        raise ZeroDivisionError("something inside broke")

    monkeypatch.setattr(curves, "polach_creep_curve", broken)
    args = ["contact", "--out", str(tmp_path)]
    result = runner.invoke(app, args)
    assert result.exit_code == 3, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith("internal error: ZeroDivisionError: something inside broke")
    assert "please report" in line
    _no_traceback(result)
    assert _files(tmp_path) == []
    # --debug (or ROLLERRIG_DEBUG=1) shows the traceback as well, same exit code.
    result = runner.invoke(app, ["--debug", *args])
    assert result.exit_code == 3
    assert "Traceback" in result.output and "ZeroDivisionError" in result.output
    monkeypatch.setenv("ROLLERRIG_DEBUG", "1")
    result = runner.invoke(app, args)
    assert result.exit_code == 3 and "Traceback" in result.output


def test_out_that_is_a_file_is_a_clear_error(tmp_path):
    rec = _adhesion_csv(tmp_path / "test.csv")
    blocker = tmp_path / "out"
    blocker.write_text("not a folder")
    result = runner.invoke(app, ["filters", str(rec), "--out", str(blocker)])
    assert result.exit_code == 2, result.output
    assert "is a file, not a folder" in result.output
    assert blocker.read_text() == "not a folder"


def test_failure_while_writing_leaves_no_partial_output(tmp_path, monkeypatch):
    from rollerrig.report.html import HtmlReport

    def fail(self, path):
        raise RuntimeError("disk full (simulated)")

    monkeypatch.setattr(HtmlReport, "write", fail)
    rec = _adhesion_csv(tmp_path / "test.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["analyze", str(rec), "--no-study", "--out", str(out)])
    assert result.exit_code == 3, result.output
    assert "disk full (simulated)" in result.output
    # The JSON and NetCDF were written before the report failed: neither is left, nor any
    # staging folder.
    assert not out.exists()
    assert _files(tmp_path) == ["test.csv"]


# --- analyze, filters: bad inputs -----------------------------------------------------------


def test_analyze_without_a_test_names_the_torque_channel(tmp_path):
    rec = _adhesion_csv(tmp_path / "flat.csv", torque=lambda t: 100.0 + 0 * t)
    rec.write_text(rec.read_text().replace("torque_request [N.m]", "setpoint [N.m]"))
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "no adhesion test found" in result.output
    assert "channel 'torque'" in result.output and "[channels.torque]" in result.output
    _no_traceback(result)
    assert not (tmp_path / "out").exists()


def test_analyze_huge_torque_names_the_channel(tmp_path):
    rec = _adhesion_csv(tmp_path / "huge.csv", torque=lambda t: 1e300 * (1 + 0.1 * np.sin(t)))
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "channel 'torque'" in result.output and "1e+300" in result.output
    _no_traceback(result)
    rec = _adhesion_csv(tmp_path / "kilo.csv", torque=lambda t: 1e6 + 0 * t)  # N.m as mN.m?
    result = runner.invoke(app, ["analyze", str(rec), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "torque sensor's range" in result.output


def test_analyze_truth_of_another_length_or_not_netcdf(tmp_path):
    rec = _adhesion_csv(tmp_path / "test.csv")
    not_nc = tmp_path / "truth.nc"
    not_nc.write_text("this is not NetCDF")
    result = runner.invoke(app, ["analyze", str(rec), "--truth", str(not_nc)])
    assert result.exit_code == 2, result.output
    assert "--truth" in result.output and "not a NetCDF file" in result.output
    _no_traceback(result)
    short = tmp_path / "short.nc"
    xr.Dataset({"coa": ("time", np.zeros(10))}, coords={"time": np.arange(10) / 100}).to_netcdf(
        short, engine="h5netcdf"
    )
    result = runner.invoke(app, ["analyze", str(rec), "--truth", str(short)])
    assert result.exit_code == 2, result.output
    assert "10 samples, the recording 1000" in result.output
    _no_traceback(result)


def test_filters_on_a_csv_with_a_header_and_no_rows(tmp_path):
    empty = tmp_path / "empty.csv"
    empty.write_text(HEADER + "\n")
    result = runner.invoke(app, ["filters", str(empty), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "empty.csv" in result.output
    _no_traceback(result)


def test_filters_does_not_need_unrelated_sensors_of_the_map(tmp_path):
    rec = _adhesion_csv(tmp_path / "test.csv")
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
    assert "lag [s]" in result.output  # table headers keep their units


# --- --lenient: every output says what was interpolated -------------------------------------


def test_lenient_reports_interpolated_runs_in_every_output(tmp_path):
    rec = _adhesion_csv(tmp_path / "test.csv", nan_at=(150, 151), drop=(900, 901))
    out = tmp_path / "out"
    strict = runner.invoke(app, ["filters", str(rec), "--out", str(out)])
    assert strict.exit_code == 2 and "gap" in strict.output  # strict by default
    result = runner.invoke(app, ["analyze", str(rec), "--lenient", "--no-study", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "samples 150..151" in result.output  # console
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


def test_staged_outputs_commit_together_or_not_at_all(tmp_path):
    from rollerrig.cli import staged_outputs

    out = tmp_path / "a" / "b"
    with staged_outputs(out) as stage:
        stage.path("x.json").write_text("{}")
        (stage.dir / "sub").mkdir()
        (stage.dir / "sub" / "y.txt").write_text("y")
        assert not out.exists()  # nothing visible before the end
    assert sorted(p.relative_to(out).as_posix() for p in stage.written) == ["sub/y.txt", "x.json"]
    with pytest.raises(RuntimeError), staged_outputs(out) as stage:
        stage.path("x.json").write_text("new")
        stage.path("z.json").write_text("z")
        raise RuntimeError("failed half-way")
    assert (out / "x.json").read_text() == "{}" and not (out / "z.json").exists()
    assert _files(tmp_path) == ["a", "b", "sub", "x.json", "y.txt"]  # no staging folder left


def test_output_names_from_user_data_stay_inside_out(tmp_path):
    # An experiment named "../escaped" or with 300 characters (issue 8): the file lands in
    # --out under a plain, shortened name; nothing is written next to it.
    from rollerrig.cli import MAX_OUTPUT_STEM, staged_outputs

    out = tmp_path / "out"
    with staged_outputs(out) as stage:
        stage.path("../escaped.nc").write_text("e")
        stage.path("x" * 300 + ".png").write_text("x")
    names = sorted(p.name for p in stage.written)
    assert names == ["_escaped.nc", "x" * MAX_OUTPUT_STEM + ".png"]
    assert _files(tmp_path) == sorted(["out", *names])


def test_an_output_name_taken_by_a_folder_is_one_error_and_nothing_moves(tmp_path):
    from rollerrig.cli import UserError, staged_outputs

    out = tmp_path / "out"
    (out / "report.html").mkdir(parents=True)
    with pytest.raises(UserError, match=r"report.html is a folder"), staged_outputs(out) as st:
        st.path("a.json").write_text("{}")
        st.path("report.html").write_text("<html>")
    assert _files(tmp_path) == ["out", "report.html"]  # a.json was not moved in either


def test_a_gap_too_long_to_fill_is_named(tmp_path):
    rec = _adhesion_csv(tmp_path / "test.csv", drop=range(300, 320))
    for command in ("analyze", "filters"):
        result = runner.invoke(app, [command, str(rec), "--lenient", "--out", str(tmp_path / "o")])
        assert result.exit_code == 2, result.output
        assert "gap of 0.21 s after t = 2.99 s" in result.output and "too long" in result.output
    assert not (tmp_path / "o").exists()


# --- fast and long recordings: decimated, streamed, stated ----------------------------------


def _fast_test(path, fs=19_200.0, duration=8.0):
    """The hand-built adhesion test of ``_adhesion_csv`` at the QuantumX rate (19.2 kHz), with
    an inverter line at 2.35 kHz (far above the analysis band: decimation must not alias it),
    written with the package's writer (format from the suffix); returns the path and the true
    CoA on the file's time axis."""
    from rollerrig.measure.recording import Recording
    from rollerrig.measure.writers import write_recording

    rng = np.random.default_rng(1)
    t = np.arange(int(duration * fs)) / fs
    request = np.interp(t, [0, 2, 5, 5.5, 5.52, duration], [0, 0, 600, 600, 0, 0])
    line = 3.0 * np.sin(2 * np.pi * 14.67 * t) + 2.0 * np.sin(2 * np.pi * 2350.0 * t)
    rr, rw, load = 0.452, 0.348, 4300.0
    coa = np.clip(request / (rr * load), 0, None)
    creep = 0.02 * np.tan(np.clip(coa / 0.45, 0, 0.9) * np.pi / 2) / np.tan(0.45 * np.pi)
    omega_r = np.full(t.size, 30 / 3.6 / rr)
    channels = {
        "torque": request + line + rng.standard_normal(t.size),
        "torque_request": request,
        "wheel_speed": omega_r * rr * (1 + creep + 1e-4 * coa) / rw,
        "roller_speed": omega_r,
        "normal_load": np.full(t.size, load),
    }
    units = {"torque": "N.m", "torque_request": "N.m", "wheel_speed": "rad/s"}
    units |= {"roller_speed": "rad/s", "normal_load": "N"}
    write_recording(Recording(t, channels, units), path)
    return path, t, coa


def test_analyze_of_a_fast_recording_decimates_and_says_so_whole_or_streamed(tmp_path, monkeypatch):
    import rollerrig.cli as cli

    rec, t, coa = _fast_test(tmp_path / "fast.tdms")
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


def test_filters_on_a_fast_recording_states_its_basis_whole_or_streamed(tmp_path, monkeypatch):
    import rollerrig.cli as cli

    rec, _, _ = _fast_test(tmp_path / "fast.parquet", duration=6.0)
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


def test_lenient_on_a_long_file_reads_it_whole_and_says_so(tmp_path, monkeypatch):
    import rollerrig.cli as cli

    monkeypatch.setattr(cli, "_SPECTRUM_IN_MEMORY", 100)
    rec = _adhesion_csv(tmp_path / "test.csv", nan_at=(150,))
    result = runner.invoke(app, ["filters", str(rec), "--out", str(tmp_path / "a")])
    assert result.exit_code == 2, result.output  # streamed strictly: the NaN is an error
    assert "'torque' has a NaN/inf sample at sample 150" in result.output
    assert "on the command line: --lenient" in result.output
    result = runner.invoke(app, ["filters", str(rec), "--lenient", "--out", str(tmp_path / "b")])
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "b" / "test-filters.json").read_text())
    assert any("read whole for --lenient" in n for n in summary["recording"]["notes"])
    assert summary["recording"]["interpolated"][0]["first_sample"] == 150
