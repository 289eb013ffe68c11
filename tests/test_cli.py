"""The ``rollerrig`` command: outputs written, numbers printed, clear errors for bad input."""

import json

import pytest
from typer.testing import CliRunner

from rollerrig.cli import app

runner = CliRunner()


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


def test_demo_runs_end_to_end_and_its_outputs_analyse_again(tmp_path):
    # The README's main job, then the files it wrote through the other commands.
    result = runner.invoke(app, ["demo", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "speed-independent lines in the free-rolling spectra: 1.3" in result.output
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


def test_study_writes_table_figure_and_json(tmp_path):
    result = runner.invoke(app, ["study", "drives", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "ideal speed source" in result.output
    assert (tmp_path / "study-drives.png").stat().st_size > 10_000
    assert runner.invoke(app, ["study", "colour", "--out", str(tmp_path)]).exit_code == 2
