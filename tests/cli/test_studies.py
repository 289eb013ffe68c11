"""``rollerrig study run|show|list``: progress, the store, tables, figures, resume, errors."""

import json
import stat

import pytest

from rollerrig.cli import app
from rollerrig.output import figure_provenance


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
    result = runner.invoke(app, ["study", "run", str(study), "--executor", "local", "--out",
                                 str(out)])  # fmt: skip
    assert result.exit_code == 2
    assert "holds another study" in result.output and "--restart" in result.output


def test_show_writes_tables_and_figures_from_a_store(tmp_path, runner):
    out = tmp_path / "run"
    assert runner.invoke(app, ["study", "run", "drives", "--executor", "local", "--out",
                               str(out)]).exit_code == 0  # fmt: skip
    shown = tmp_path / "shown"
    result = runner.invoke(app, ["study", "show", str(out / "study-drives.zarr"), "--out",
                                 str(shown)])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "ideal speed source" in result.output
    assert (shown / "study-drives-release_overshoot-cases.png").is_file()
    doc = json.loads((shown / "study-drives.json").read_text())
    assert doc["rows"][0]["label"] == "AM V/f with lag (rig today)"


def test_list_shows_the_bundled_studies(runner):
    result = runner.invoke(app, ["study", "list"])
    assert result.exit_code == 0
    for name in ("stiffness", "lag", "drives", "joint", "sensitivity"):
        assert name in result.output


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
    result = runner.invoke(app, ["study", "run", str(study), "--executor", "local", "--out",
                                 str(out)])  # fmt: skip
    assert result.exit_code == 2, result.output
    assert expected in result.output and "Traceback" not in result.output
    assert not out.exists()


def test_local_executor_refuses_dask_options(tmp_path, runner):
    result = runner.invoke(app, ["study", "run", "lag", "--executor", "local", "--workers", "2",
                                 "--out", str(tmp_path)])  # fmt: skip
    assert result.exit_code == 2 and "--executor dask" in result.output


def test_study_frame_prints_the_verdict_and_writes_json_and_figure(tmp_path, runner):
    result = runner.invoke(app, ["study", "frame", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "does not explain the oscillation" in " ".join(result.output.split())
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


@pytest.mark.slow  # ~10 s: 84 linearisations of the dq twin and four lag fits
def test_study_drive_dynamics_answers_the_question(tmp_path, runner):
    result = runner.invoke(app, ["study", "drive-dynamics", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "Thevenin, lag c_lp (rig)" in text and "dq default" in text
    # Only slip compensation 1.5 gives a lightly damped 1-1.7 Hz mode at every speed.
    assert "at every speed: dq slip comp 1.5" in text
    doc = json.loads((tmp_path / "study-drive-dynamics.json").read_text())
    assert doc["seed_lag [s]"] == pytest.approx(0.3635, abs=1e-3)
    assert all(h["tau [s]"] < 0.1 for h in doc["lag_held_speed"])  # 37-60 ms
    assert (tmp_path / "study-drive-dynamics.png").stat().st_size > 10_000
