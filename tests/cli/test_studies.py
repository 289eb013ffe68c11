"""``rollerrig study run|show|list``: progress, the store, tables, figures, resume, errors."""

import json
import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rollerrig.cli import app
from rollerrig.output import figure_provenance


def _run_local(runner, study, out, **options):
    """``rollerrig study run STUDY --executor local --out OUT``."""
    return runner.invoke(
        app, ["study", "run", str(study), "--executor", "local", "--out", str(out)], **options
    )


def test_the_study_table_gives_every_metric_its_unit_and_the_overshoots_in_percent(
    tmp_path, runner
):
    # The headers release_overshoot and true_release_overshoot had no unit and their values
    # read 0.4702 where simulate says "overshoot 47.0%": now in % with [%], as the frame study
    # prints them; the files keep the fraction, headed [-].
    out = tmp_path / "out"
    result = _run_local(runner, "lag", out)
    assert result.exit_code == 0, result.output
    text = result.output
    assert "release_overshoot [%]" in text and "true_release_overshoot [%]" in text
    assert "settling_time [s]" in text
    row = next(line for line in text.splitlines() if "tau = 0.3635 s" in line)
    doc = json.loads((out / "study-lag.json").read_text())
    value = next(r for r in doc["rows"] if r["label"] == "tau = 0.3635 s")["release_overshoot [-]"]
    assert 0.0 < value < 1.0 and f"{100 * value:.4g}" in row


@pytest.mark.slow  # ~10 s: a local dask cluster of 2 workers starts
def test_a_bundled_study_on_a_local_cluster_of_two_workers(tmp_path, runner):
    out = tmp_path / "out"
    result = runner.invoke(app, ["study", "run", "lag", "--workers", "2", "--out", str(out)])
    assert result.exit_code == 0, result.output
    text = result.output
    assert "on a local dask cluster of 2 workers" in text
    assert "6/6 points" in text and "points/s on 2 workers" in text
    assert "tau = 0.3635 s" in text  # one row per point
    assert (out / "study-lag.zarr" / "zarr.json").is_file()
    doc = json.loads((out / "study-lag.json").read_text())
    assert doc["status_counts"] == {"ok": 6} and doc["workers"] == 2
    assert "sweep_settings" in doc["solver"]  # what integrated the points, in the summary
    assert doc["points_per_second"] > 0 and len(doc["rows"]) == 6
    assert doc["sensitivity"]["release_overshoot"]["main_effects"]
    png = out / "study-lag-release_overshoot-line.png"
    assert png.stat().st_size > 10_000 and figure_provenance(png)["parameters"]["study"] == "lag"
    assert (out / "study-lag-points.csv").is_file() and (out / "study-lag-run.json").is_file()
    modes = {stat.S_IMODE(p.stat().st_mode) for p in out.rglob("*") if p.is_file()}
    assert modes <= {0o644, 0o664}


def test_run_again_resumes_and_restart_starts_again(tmp_path, runner):
    args = ["study", "run", "stiffness", "--executor", "local", "--out", str(tmp_path)]
    first = runner.invoke(app, args)
    assert first.exit_code == 0, first.output
    assert "6 points computed" in first.output
    again = runner.invoke(app, args)
    assert again.exit_code == 0, again.output
    assert "all 6 points were already in" in " ".join(again.output.split())
    restarted = runner.invoke(app, [*args, "--restart"])
    assert restarted.exit_code == 0 and "6 points computed" in restarted.output


def test_another_study_into_the_same_store_is_refused(tmp_path, runner):
    study = tmp_path / "lag.toml"
    study.write_text("name = 'lag'\n[grid]\n'drive.roller_lag' = [0.0, 0.2]\n", encoding="utf-8")
    out = tmp_path / "out"
    assert runner.invoke(app, ["study", "run", "lag", "--executor", "local", "--out",
                               str(out)]).exit_code == 0  # fmt: skip
    result = _run_local(runner, study, out)
    assert result.exit_code == 2
    assert "holds another study" in result.output and "--restart" in result.output


def test_show_writes_tables_and_figures_from_a_store(tmp_path, runner):
    out = tmp_path / "run"
    assert runner.invoke(app, ["study", "run", "drives", "--executor", "local", "--out",
                               str(out)]).exit_code == 0  # fmt: skip
    shown = tmp_path / "shown"
    result = runner.invoke(app, ["study", "show", str(out / "study-drives.zarr"), "--out",
                                 str(shown), "--figure-format", "svg"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "ideal speed source" in result.output
    assert (out / "study-drives-release_overshoot-cases.png").is_file()  # run: the default
    figure = shown / "study-drives-release_overshoot-cases.svg"
    assert figure_provenance(figure)["command"][1:3] == ["study", "show"]
    assert not list(shown.glob("*.png"))
    doc = json.loads((shown / "study-drives.json").read_text())
    assert doc["rows"][0]["label"] == "AM V/f with lag (rig today)"
    # --out inside the store wrote the tables and figures into it (a review, 2026-12-03)
    store = out / "study-drives.zarr"
    before = sorted(p.name for p in store.iterdir())
    for inside in (store, store / "sub"):
        result = runner.invoke(app, ["study", "show", str(store), "--out", str(inside)])
        assert result.exit_code == 2 and "is inside the input" in result.output, result.output
    assert sorted(p.name for p in store.iterdir()) == before


def test_list_shows_the_bundled_studies(runner):
    result = runner.invoke(app, ["study", "list"])
    assert result.exit_code == 0
    for name in ("stiffness", "lag", "drives", "joint", "sensitivity"):
        assert name in result.output


def test_run_help_names_every_bundled_study(runner):
    # The list had been written by hand and left out arm, which the tour runs.
    from rollerrig.studies.studyfile import bundled_studies

    result = runner.invoke(app, ["study", "run", "--help"])
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    assert "arm" in bundled_studies()
    assert f"a bundled study: {', '.join(bundled_studies())} (rollerrig study list)" in text


def test_show_of_the_out_folder_names_the_store_in_it(tmp_path, runner, tiny):
    # "GroupNotFoundError: No group found in store PosixPath(...)" had been the answer.
    out = tmp_path / "out"
    assert runner.invoke(app, _local(tiny, out)).exit_code == 0
    result = runner.invoke(app, ["study", "show", str(out), "--out", str(tmp_path / "shown")])
    assert result.exit_code == 2, result.output
    assert " ".join(result.output.split()) == (
        f"error: {out}: not a rollerrig study store but a folder holding study-tiny.zarr: give "
        f"{out / 'study-tiny.zarr'}"
    )
    result = runner.invoke(app, ["study", "show", str(tmp_path / "nothing.zarr")])
    assert result.exit_code == 2 and "Error" not in result.output, result.output
    assert "nothing.zarr: not a rollerrig study store: nothing there; give the" in result.output


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        ("[grid]\n'stiffness.roller_shaft' = { values = [1.0], unit = '[kN]' }", "unit"),
        ("[grid]\ncolour = [1]", "grid.colour"),
    ],
)
def test_a_bad_study_file_is_one_error_line_and_writes_nothing(tmp_path, runner, body, expected):
    study = tmp_path / "bad.toml"
    study.write_text(body, encoding="utf-8")
    out = tmp_path / "out"
    result = _run_local(runner, study, out)
    assert result.exit_code == 2, result.output
    assert expected in result.output and "Traceback" not in result.output
    assert not out.exists()


def test_a_point_the_twin_cannot_resolve_is_failed_with_its_reason_not_ok(tmp_path, runner):
    # Stiffness 1e300 N.m/rad: the solver finishes but no metric has a value. It showed "ok"
    # with blank cells, the reason only in the JSON.
    study = tmp_path / "huge.toml"
    study.write_text("name = 'huge'\n[grid]\n'stiffness.roller_shaft' = { values = [43.5e3, "
                     "1e300], unit = 'N.m/rad' }\n", encoding="utf-8")  # fmt: skip
    out = tmp_path / "out"
    result = _run_local(runner, study, out, terminal_width=400)
    assert result.exit_code == 0, result.output
    row = next(line for line in result.output.splitlines() if "│" in line and "1e+300" in line)
    assert "solver failed" in row and "│ ok" not in row
    # and why, before the run: the shaft's torque is round-off at that stiffness
    assert "warning: stiffness.roller_shaft = 1e+300 N.m/rad: the twin resolves" in result.output
    (said,) = [line for line in result.output.splitlines() if line.startswith("note: stiff")]
    assert said.startswith("note: stiffness.roller_shaft = 1e+300 N.m/rad: solver failed: "
                           "the run gave no value of any metric (release_overshoot: the "
                           "experiment has no torque release")  # fmt: skip
    doc = json.loads((out / "study-huge.json").read_text())
    assert doc["status_counts"] == {"ok": 1, "solver failed": 1}
    assert doc["rows"][1]["release_overshoot [-]"] is None
    assert doc["rows"][1]["reason"] == said.split(": solver failed: ", 1)[1]
    csv = (out / "study-huge-points.csv").read_text().splitlines()
    assert csv[2].startswith("stiffness.roller_shaft = 1e+300 N.m/rad,1e+300,solver failed,")
    assert csv[2].endswith(",") and "nan" not in csv[2].lower()  # the value's cell empty


def test_an_ok_point_with_a_domain_warning_is_named_after_the_table(tmp_path, runner):
    # 1e14 N.m/rad: the run gives numbers (T56 resolved to 2.8 N.m), the point is ok; the
    # warning came before the table, and a note after it names the point again.
    study = tmp_path / "stiff.toml"
    study.write_text("name = 'stiff'\nexperiment = 'release-test'\n[grid]\n"
                     "'stiffness.roller_shaft' = { values = [43.5e3, 1e14], unit = 'N.m/rad' }\n"
                     "[outputs]\nmetrics = ['release_overshoot']\n",
                     encoding="utf-8")  # fmt: skip
    result = _run_local(runner, study, tmp_path / "out", terminal_width=400)
    assert result.exit_code == 0, result.output
    said = ("note: stiffness.roller_shaft = 1e+14 N.m/rad: ok, with warning: "
            "stiffness.roller_shaft = 1e+14 N.m/rad: the twin resolves")  # fmt: skip
    assert said in result.output
    assert "43500 N.m/rad: ok, with" not in result.output


def test_a_metric_without_a_value_at_points_that_ran_says_why_on_the_console(tmp_path, runner):
    # An experiment without a torque release: the CoA metrics have numbers (the points are
    # ok) but the overshoot has none: the table shows '-', and why was only in the JSON. (This
    # test had taken a roller shaft of 1e150 N.m/rad, whose overshoot is round-off: no number
    # in one environment, 1.5e12 in another; rollerrig now warns of that stiffness.)
    protocol = tmp_path / "ramp-hold.toml"
    protocol.write_text(
        '[experiment]\nname = "ramp-hold"\nnormal_load_kN = 4.3\nroller_speed_kmh = 30.0\n'
        'friction = "dry"\n[[step]]\naction = "hold"\nduration_s = 0.5\n[[step]]\n'
        'action = "ramp_torque"\nto_Nm = 600.0\nduration_s = 1.0\n[[step]]\n'
        'action = "hold"\nduration_s = 1.0\n',
        encoding="utf-8",
    )
    study = tmp_path / "half.toml"
    study.write_text("name = 'half'\nexperiment = 'ramp-hold.toml'\n[grid]\n"
                     "'stiffness.roller_shaft' = { values = [43.5e3, 63.5e3], unit = 'N.m/rad' }"
                     "\n[outputs]\nmetrics = ['release_overshoot', 'coa_bias_rms']\n",
                     encoding="utf-8")  # fmt: skip
    result = _run_local(runner, study, tmp_path / "out", terminal_width=400)
    assert result.exit_code == 0, result.output
    assert (
        "note: release_overshoot: no value at 2 of 2 points that ran ok: the experiment has "
        "no torque release from a positive force, or the run failed"
    ) in result.output
    assert "coa_bias_rms: no value" not in result.output


def test_a_number_without_a_unit_is_said_once_with_the_unit_taken(tmp_path, runner):
    study = tmp_path / "bare.toml"
    study.write_text("name = 'bare'\n[grid]\n'stiffness.roller_shaft' = [43.5e3, 143.5e3]\n"
                     "'drive.roller_lag' = { values = [0.0, 0.2], unit = 's' }\n"
                     "[outputs]\nmetrics = ['release_overshoot', 'coa_bias_rms']\n",
                     encoding="utf-8")  # fmt: skip
    result = _run_local(runner, study, tmp_path / "out", terminal_width=400)
    assert result.exit_code == 0, result.output
    (said,) = [line for line in result.output.splitlines() if "without a unit" in line]
    assert said.startswith(f"note: {study}: numbers without a unit taken in SI: "
                           "grid.stiffness.roller_shaft in N.m/rad; if another unit was meant, "
                           "give it")  # fmt: skip
    assert "drive.roller_lag" not in said  # given with its unit


def test_local_executor_refuses_dask_options(tmp_path, runner):
    result = runner.invoke(app, ["study", "run", "lag", "--executor", "local", "--workers", "2",
                                 "--out", str(tmp_path)])  # fmt: skip
    assert result.exit_code == 2 and "--executor dask" in result.output


def test_study_frame_prints_the_verdict_and_writes_json_and_figure(tmp_path, runner):
    result = runner.invoke(app, ["study", "frame", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "does not explain the oscillation" in " ".join(result.output.split())
    assert "overshoot T56/r_r [%]" in result.output  # the unit in the header, as study run's
    doc = json.loads((tmp_path / "study-frame.json").read_text())
    assert [c["frame"] for c in doc["cases"]] == ["rigid frame", "frame (FE)", "frame 10x softer"]
    assert doc["frame_matters"] is False
    assert (tmp_path / "study-frame.png").stat().st_size > 10_000


def test_simulate_with_a_flexible_frame_names_its_outputs(tmp_path, runner):
    result = runner.invoke(app, ["simulate", "-e", "release-test", "--frame", "flexible",
                                 "--format", "csv", "--out", str(tmp_path)])  # fmt: skip
    assert result.exit_code == 0, result.output
    csv = tmp_path / "release-test_frame-flexible.csv"
    assert "frame_displacement" in csv.read_text().splitlines()[0]


@pytest.mark.slow  # ~30 s: ~1000 linearisations of the dq twin and six lag fits
def test_study_drive_dynamics_answers_the_question(tmp_path, runner):
    result = runner.invoke(app, ["study", "drive-dynamics", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "Thevenin, lag c_lp (rig)" in text and "dq default" in text
    # 100 % slip compensation with a 0.05 s slip filter is lightly damped at every speed too
    # (not only 150 %), an estimate 50 % high acts as 150 %, 150 % with 0.05 s grows.
    assert "dq slip comp 1.0, 0.05 s: lightly damped mode in 1-1.7 Hz at every speed" in text
    assert "dq slip comp 1.5, 0.05 s: unstable at" in text
    assert "depends on" in text and "holds over the assumed ranges" in text
    doc = json.loads((tmp_path / "study-drive-dynamics.json").read_text())
    by = {v["drive"]: v for v in doc["verdicts"]}
    same = ("dq slip comp 1.0, 0.1 s, R_R est. 1.5", "dq slip comp 1.5, 0.1 s")
    assert by[same[0]]["frequency [Hz]"] == pytest.approx(by[same[1]]["frequency [Hz]"])
    assert doc["seed_lag [s]"] == pytest.approx(0.3635, abs=1e-3)
    assert all(h["tau [s]"] < 0.1 for h in doc["lag_held_speed"])  # 38-81 ms
    assert (tmp_path / "study-drive-dynamics.png").stat().st_size > 10_000


# --------------------------------------------------------------------------------------------
# Issue 24: --restart, names, lost chunk files, --scheduler, Ctrl-C on dask
# --------------------------------------------------------------------------------------------

TINY = "name = 'tiny'\n[grid]\n'drive.roller_lag' = [0.0, 0.2]\n"


@pytest.fixture
def tiny(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY, encoding="utf-8")
    return path


def _local(study, out, *extra):
    return ["study", "run", str(study), "--executor", "local", "--out", str(out), *extra]


def _plant(kind, path, elsewhere):
    """Something at ``path`` that is not tiny's store; returns a file that must survive."""
    import zarr

    from rollerrig.studies.store import StudyStore

    if kind == "foreign zarr store":
        zarr.open_group(path, mode="w").create_array("x", shape=(2,), dtype="f8")[:] = [1, 2]
        return path / "x" / "zarr.json"
    if kind == "plain folder":
        path.mkdir()
        (path / "notes.txt").write_text("keep me")
        return path / "notes.txt"
    if kind == "file":
        path.write_text("keep me")
        return path
    if kind == "symlink":
        elsewhere.mkdir()
        (elsewhere / "zarr.json").write_text("{}")
        (elsewhere / "notes.txt").write_text("keep me")
        path.symlink_to(elsewhere, target_is_directory=True)
        return elsewhere / "notes.txt"
    StudyStore.create(path, attrs={"study": "other", "study_sha256": "x"}, parameters={},
                      labels=["a"], metrics={"release_overshoot": {"units": "1"}})  # fmt: skip
    return path / "zarr.json"


@pytest.mark.parametrize(
    "kind", ["foreign zarr store", "plain folder", "file", "symlink", "another study's store"]
)
def test_restart_refuses_and_keeps_whatever_is_not_this_studys_store(tmp_path, runner, tiny, kind):
    out = tmp_path / "out"
    out.mkdir()
    store = out / "study-tiny.zarr"
    witness = _plant(kind, store, tmp_path / "elsewhere")
    result = runner.invoke(app, _local(tiny, out, "--restart"))
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert f"error: {store}: " in text and "nothing was removed" in text
    assert "Traceback" not in text and witness.exists()


def test_a_hostile_study_name_is_refused_and_writes_nothing(tmp_path, runner):
    study = tmp_path / "a" / "b" / "evil.toml"
    study.parent.mkdir(parents=True)
    study.write_text('name = "x/../../../escaped"\n' + TINY.split("\n", 1)[1], encoding="utf-8")
    out = tmp_path / "a" / "b" / "out"
    result = runner.invoke(app, _local(study, out))
    assert result.exit_code == 2, result.output
    assert "name: not a study name" in result.output
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a", "b", "evil.toml"]


def test_a_study_named_by_an_odd_file_name_writes_safe_names_into_out(tmp_path, runner):
    study = tmp_path / "my study [v2].toml"
    study.write_text(TINY.split("\n", 1)[1], encoding="utf-8")  # no name: the file's stem
    out = tmp_path / "out"
    result = runner.invoke(app, _local(study, out))
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "study-my_study__v2_-points.csv",
        "study-my_study__v2_-points.metadata.json",
        "study-my_study__v2_-release_overshoot-line.png",
        "study-my_study__v2_-run.json",
        "study-my_study__v2_.json",
        "study-my_study__v2_.zarr",
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["my study [v2].toml", "out"]


def test_a_lost_chunk_file_is_reported_damaged_and_computed_again(tmp_path, runner, tiny):
    out = tmp_path / "out"
    assert runner.invoke(app, _local(tiny, out)).exit_code == 0
    store = out / "study-tiny.zarr"
    (store / "release_overshoot" / "c" / "0").unlink()  # a partial copy, a sync tool
    shown = runner.invoke(app, ["study", "show", str(store), "--out", str(tmp_path / "shown")])
    assert shown.exit_code == 0, shown.output
    text = " ".join(shown.output.split())
    assert "2 of 2 points are damaged" in text and "release_overshoot/c/0" in text
    doc = json.loads((tmp_path / "shown" / "study-tiny.json").read_text())
    assert doc["status_counts"] == {"damaged": 2}
    assert "release_overshoot/c/0" in doc["failures"][0]["reason"]
    again = runner.invoke(app, _local(tiny, out))
    assert again.exit_code == 0, again.output
    text = " ".join(again.output.split())
    assert "2 points of" in text and "had lost their results" in text
    assert "2 points computed" in text and "nothing to compute" not in text
    doc = json.loads((out / "study-tiny.json").read_text())
    assert doc["status_counts"] == {"ok": 2} and doc["damaged_recomputed"] == 2
    assert all(r["release_overshoot [-]"] > 0 for r in doc["rows"])


@pytest.mark.parametrize(
    "address", ["not an address", "tcp://", "999.1.1.1:99999", "tcp://host:0", "http://h:8786"]
)
def test_a_scheduler_that_is_not_an_address_is_refused_naming_the_option(tmp_path, runner, address):
    out = tmp_path / "out"
    result = runner.invoke(app, ["study", "run", "lag", "--scheduler", address, "--out", str(out)])
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert f"error: --scheduler {address!r}: not a dask scheduler address" in text
    assert "internal error" not in text and not out.exists()


def test_a_scheduler_nobody_listens_at_is_an_error_naming_the_address(
    tmp_path, runner, tiny, monkeypatch
):
    pytest.importorskip("distributed")
    import socket

    from rollerrig.studies import runner as study_runner

    monkeypatch.setattr(study_runner, "SCHEDULER_TIMEOUT", 1.0)
    with socket.socket() as s:  # a loopback port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"127.0.0.1:{port}"
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["study", "run", str(tiny), "--scheduler", address, "--out", str(out)]
    )
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert f"error: --scheduler {address!r}: cannot reach the dask scheduler" in text
    # No point ran: the store it created is gone (an empty study-tiny.zarr had stayed).
    assert not (out / "study-tiny.zarr").exists()
    # A store that held points before is kept: here two points lost their results (a chunk
    # file), so the run has points to compute and fails at the scheduler before any.
    assert runner.invoke(app, _local(tiny, out)).exit_code == 0
    store = out / "study-tiny.zarr"
    (store / "release_overshoot" / "c" / "0").unlink()
    kept = sorted(p.relative_to(store) for p in store.rglob("*"))
    command = ["study", "run", str(tiny), "--scheduler", address, "--out", str(out)]
    result = runner.invoke(app, command)
    assert result.exit_code == 2, result.output
    assert sorted(p.relative_to(store) for p in store.rglob("*")) == kept
    # --restart removed the old store on purpose; the new one, without a point, goes too.
    result = runner.invoke(app, [*command, "--restart"])
    assert result.exit_code == 2, result.output
    assert not store.exists()


def _ignores_sigint(pid: int) -> bool:
    """Whether process ``pid`` has its own SIGINT disposition: ignored or caught by the study's
    worker preload (Linux: the SigIgn and SigCgt masks in /proc)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    bit = 1 << (signal.SIGINT - 1)
    masks = [
        int(line.split()[1], 16)
        for line in status.splitlines()
        if line.startswith(("SigIgn", "SigCgt"))
    ]
    return any(mask & bit for mask in masks)


def _worker_processes(pid: int) -> list[int]:
    """The dask worker processes that ``pid`` started (multiprocessing's spawned children)."""
    kids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
                command = (entry / "cmdline").read_bytes()
            except (OSError, IndexError, ValueError):
                continue
            if parent == pid and b"spawn_main" in command:
                kids.append(int(entry.name))
    return kids


@pytest.mark.slow  # ~30 s: a local dask cluster of 2 workers and a first batch of 32 points
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_ctrl_c_during_a_dask_study_prints_one_line(tmp_path):
    pytest.importorskip("distributed")
    study = tmp_path / "many.toml"
    # Enough points that the study is still running when the first batch is in: 128 points
    # took 2.4 s on 2 workers once sweeps ran at their own settings, and had finished before
    # the signal in two of three runs (2026-12-03).
    study.write_text("name = 'many'\n[grid]\n'drive.roller_lag' = { start = 0, stop = 0.4, "
                     "num = 4096 }\n", encoding="utf-8")  # fmt: skip
    out = tmp_path / "out"
    command = [sys.executable, "-m", "rollerrig.cli", "study", "run", str(study), "--workers",
               "2", "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)  # fmt: skip
    try:
        # Wait (no fixed delay) until the workers are up and the first batch is in the store:
        # the study is then in its loop over results, with batches running on both workers.
        status_chunk = out / "study-many.zarr" / "status" / "c" / "0"
        for _ in range(3000):
            workers = _worker_processes(proc.pid)
            if status_chunk.is_file() and sum(map(_ignores_sigint, workers)) == 2:
                break
            if proc.poll() is not None:
                break
            time.sleep(0.1)
        assert proc.poll() is None, proc.communicate()
        os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C: every process of the group
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert proc.returncode == 128 + signal.SIGINT
    assert err.splitlines() == [
        "error: interrupted by SIGINT; --out holds no partial output of this run"
    ]
