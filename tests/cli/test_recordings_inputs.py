"""What ``analyze``, ``spectrum`` and ``filters`` say about their inputs before any analysis: a
missing file at once, the twin's results given for a recording, a mistyped ``--channel``, a
recording without a roller speed, and what to do where the Savitzky-Golay grid's optimum is on
its edge (a review of the command line, 2026-12-03)."""

import json
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from rollerrig.cli import app


def _text(result) -> str:
    return " ".join(result.output.split())


def _twin_csv(path):
    """The shape of ``rollerrig simulate --format csv``: the twin's states and its measured_*
    columns, no ``torque``."""
    t = np.arange(500) / 100.0
    rows = ["time [s],t56 [N.m],measured_t56 [N.m],roller_speed [rad/s],wheel_speed [rad/s]"]
    rows += [f"{x:.3f},{np.sin(x):.6f},{np.sin(x):.6f},18.4,23.9" for x in t]
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("command", ["analyze", "spectrum", "filters"])
def test_the_twins_csv_results_are_not_a_recording_and_the_error_says_how_to_get_one(
    tmp_path, runner, command
):
    # analyze had asked for [channels.torque] though the file has measured_t56, spectrum and
    # filters for a channel-map entry: none said it is the twin's output, nor what to do.
    csv = _twin_csv(tmp_path / "seed-30kmh-dry.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, [command, str(csv), "--out", str(out)])
    assert result.exit_code == 2, result.output
    text = _text(result)
    assert "the twin's results (`rollerrig simulate`: it has 'measured_t56'" in text
    assert "`rollerrig demo` writes the seed test's" in text
    nc = tmp_path / "seed-30kmh-dry.nc"  # where simulate's default format would have put it
    assert f"rollerrig.synthetic_recording(xarray.load_dataset('{nc}'))" in text
    assert "rollerrig.write_recording(rec, 'seed-30kmh-dry.tdms')" in text
    assert not out.exists()


def test_the_twins_netcdf_results_are_named_as_such_not_as_an_unknown_suffix(tmp_path, runner):
    import xarray as xr

    nc = tmp_path / "seed-30kmh-dry.nc"
    t = np.arange(100) / 250.0
    xr.Dataset({"t56": ("time", np.sin(t))}, coords={"time": t}).to_netcdf(nc, engine="h5netcdf")
    result = runner.invoke(app, ["spectrum", str(nc), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    text = _text(result)
    assert "unsupported file suffix" not in text
    assert f"{nc}: NetCDF (.nc) is what rollerrig writes (the twin's results" in text
    assert f"rollerrig.synthetic_recording(xarray.load_dataset('{nc}'))" in text


def test_the_python_route_the_error_gives_makes_a_recording_spectrum_reads(tmp_path, runner):
    # What the message tells the user to run must work on simulate's own output.
    import xarray as xr

    import rollerrig
    from rollerrig.solve.results import save_dataset
    from rollerrig.solve.simulation import Simulation

    nc = save_dataset(Simulation(experiment="release-test").solve(), tmp_path / "release.nc")
    rec, _ = rollerrig.synthetic_recording(xr.load_dataset(nc))
    tdms = rollerrig.write_recording(rec, tmp_path / "release.tdms")
    result = runner.invoke(app, ["spectrum", str(tdms), "--out", str(tmp_path / "out"), "-q"])
    assert result.exit_code == 0, result.output


@pytest.mark.parametrize(
    ("command", "option", "typed", "hint"),
    [
        ("spectrum", "--channel", "torqe", " (did you mean 'torque'?)"),
        ("filters", "--channel", "torqe", " (did you mean 'torque'?)"),
        ("spectrum", "--coherence", "rollr_speed", " (did you mean 'roller_speed'?)"),
        ("spectrum", "--channel", "laser", ""),  # nothing close: the channels, no guess
    ],
)
def test_a_mistyped_channel_is_named_by_its_option_with_the_nearest(
    tmp_path, runner, adhesion_csv, command, option, typed, hint
):
    rec = adhesion_csv(tmp_path / "rec.csv")
    result = runner.invoke(app, [command, str(rec), option, typed, "--out", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    text = _text(result)
    assert f"{rec}: {option} {typed!r}: no such channel{hint}; the recording has [" in text
    assert "'torque'" in text and "--channels" in text


def test_a_recording_without_a_roller_speed_names_the_channel_map_not_a_speed_option(
    tmp_path, runner
):
    # "(or give the speed)": spectrum has no speed option.
    rec = tmp_path / "torque-only.csv"
    t = np.arange(2000) / 250.0
    rows = ["time [s],torque [N.m]"] + [f"{x:.3f},{np.sin(9 * x):.6f}" for x in t]
    rec.write_text("\n".join(rows) + "\n")
    result = runner.invoke(app, ["spectrum", str(rec), "--out", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    text = _text(result)
    assert (
        "map a roller_speed or roller_encoder_counts channel in a channel map (--channels" in text
    )
    assert "give the speed" not in text and "roller_speed=" not in text


_RUN = """
import atexit, json, sys
record = sys.argv[1]
atexit.register(lambda: open(record, "w").write(json.dumps(sorted(sys.modules))))
sys.argv = ["rollerrig", *sys.argv[2:]]
from rollerrig.cli import main
main()
"""


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["analyze", "{missing}"], "error: file not found: {missing}"),
        (["analyze", "{rec}", "--truth", "{missing}"], "error: --truth {missing}: file not found"),
        (["spectrum", "{rec}", "{missing}"], "error: file not found: {missing}"),
        (["filters", "{rec}", "--channels", "{missing}"], "--channels {missing}: file not found"),
        (["analyze", "{rec}", "--rig", "{missing}"], "{missing}: rig file not found"),
    ],
)
def test_a_missing_input_is_said_before_the_analysis_is_imported(
    tmp_path, adhesion_csv, args, message
):
    # It had come after 3-5 s of imports on a loaded machine.
    rec = adhesion_csv(tmp_path / "rec.csv")
    names = {"missing": tmp_path / "no-such.csv", "rec": rec}
    record = tmp_path / "modules.json"
    done = subprocess.run(
        [sys.executable, "-c", _RUN, str(record), *(a.format(**names) for a in args)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert message.format(**names) in " ".join((done.stdout + done.stderr).split())
    modules = set(json.loads(record.read_text()))
    heavy = {"scipy", "xarray", "rollerrig.analysis", "rollerrig.signal", "rollerrig.recordings"}
    assert not {m.split(".")[0] for m in modules} & heavy
    assert not {".".join(m.split(".")[:2]) for m in modules} & heavy


def _grid(order_best, window_best):
    """A ranked Savitzky-Golay table over orders 2-7 x windows 11-201, best first."""
    rows = [
        SimpleNamespace(params={"order": o, "window": w})
        for o in range(2, 8)
        for w in range(11, 202, 10)
        if (o, w) != (order_best, window_best)
    ]
    rows.insert(0, SimpleNamespace(params={"order": order_best, "window": window_best}))
    table = SimpleNamespace(basis=SimpleNamespace(analysis_rate=250.0))
    return type("Table", (list,), {"basis": table.basis})(rows)


def test_an_optimum_on_the_grid_edge_says_what_the_user_can_do():
    # The figure says "widen the grid"; no option of filters does.
    from rollerrig.cli.recordings import _grid_edge_note

    assert _grid_edge_note(_grid(4, 111)) is None  # inside: nothing to say
    text = _grid_edge_note(_grid(2, 171))
    assert "order 2 is the smallest tried" in text
    assert "orders 2-7 and windows 11-201 samples at 250 Hz, a fixed grid" in text
    assert "tune_savitzky_golay(time, torque, orders=..., windows=...)" in text
    assert "moving average" in text  # below order 2: what the ranking already scores
    text = _grid_edge_note(_grid(5, 201))
    assert "window 201 is the largest tried" in text and "moving average" not in text


@pytest.mark.parametrize("command", ["analyze", "spectrum", "filters", "calibrate", "transfer"])
def test_a_folder_given_for_a_recording_is_named_a_folder(tmp_path, runner, command):
    # "somedir: unsupported file suffix ''; ... rename it" (analyze, spectrum, filters,
    # calibrate) and "somedir: no such file" (transfer) of a folder that exists.
    folder = tmp_path / "somedir"
    folder.mkdir()
    extra = ["--free", "inertia.roller"] if command == "calibrate" else []
    result = runner.invoke(app, [command, str(folder), *extra, "--out", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    what = "a curve file" if command == "transfer" else "a recording file"
    assert f"{folder} is a folder, not {what}; give" in _text(result)
    assert "suffix" not in result.output and "no such file" not in result.output
    assert "Traceback" not in result.output
