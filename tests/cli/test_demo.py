"""``rollerrig demo``: the README's main job end to end, then its files through the other
commands; every output carries the provenance of what it was computed from."""

import json

import pytest

from rollerrig.cli import app
from rollerrig.output import figure_provenance, file_sha256


@pytest.mark.slow
def test_demo_runs_end_to_end_and_its_outputs_analyse_again(tmp_path, runner):
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
    # A, not identifiable, has no distance in standard errors that are no uncertainty
    assert fit["truth_distance"]["A"]["sigma"] is None
    assert "not identifiable" in fit["truth_distance"]["A"]["why"]
    assert fit["stderr"]["mu0"] > fit["stderr_statistical"]["mu0"]  # keyed as the values
    assert (tmp_path / "seed-30kmh-dry-report.html").stat().st_size > 100_000
    # Coherence of shaft displacement and torque: high at the roller order (the run-out's own
    # line), low at the induction motor's line (not mechanical; Kayaalp §4.5.2.4).
    spectra = json.loads((tmp_path / "free-rolling-spectra.json").read_text())
    coh = {
        r["source"].split(" (")[0]: r["coherence"]
        for r in spectra["coherence_torque_displacement_30kmh"]
    }
    assert coh["roller order ×1"] > 0.9 and coh["AM electrical ×1"] < 0.2

    # Provenance (issue 8): the analysis names the recording the demo wrote, by its final path
    # and the hash of the file as it lies in --out; so does every figure of the analysis.
    tdms = tmp_path / "seed-30kmh-dry.tdms"
    for record in (summary["provenance"], spectra["provenance"]):
        recording = record["inputs"]["recording"]
        assert recording["sha256"] == file_sha256(tdms)
        assert recording["path"] == str(tdms.resolve())
        assert record["inputs"]["truth"]["sha256"] == file_sha256(
            tmp_path / "seed-30kmh-dry-truth.nc"
        )
        assert record["rig"]["sha256"] and record["command"][1] == "demo"
    assert figure_provenance(tmp_path / "order-map.png")["inputs"]["free_rolling_30kmh"]
    assert figure_provenance(tmp_path / "twin-seed-30kmh-dry.png")["command"][1] == "demo"
    manifest = json.loads((tmp_path / "demo-run.json").read_text())
    listed = {f["file"]: f["sha256"] for f in manifest["files"]}
    assert listed["seed-30kmh-dry.tdms"] == file_sha256(tdms)
    assert set(listed) | {"demo-run.json"} == {p.name for p in tmp_path.iterdir()}
    from nptdms import TdmsFile

    assert TdmsFile.read(tdms).properties["name"] == "seed-30kmh-dry"  # not the temporary name

    recordings = sorted(tmp_path.glob("free-rolling-*.mf4"))
    assert len(recordings) == 4
    out = tmp_path / "again"
    args = ["spectrum", *map(str, recordings[:2]), "--coherence", "displacement_torque_sensor"]
    r = runner.invoke(app, [*args, "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert (out / "order-map.png").exists()
    assert "coherence torque–displacement_torque_sensor at the peaks" in r.output
    r = runner.invoke(app, ["filters", str(tdms), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "Savitzky-Golay tuned" in r.output
    truth = tmp_path / "seed-30kmh-dry-truth.nc"
    args = ["analyze", str(tdms), "--no-study", "--out", str(out), "--truth", str(truth)]
    r = runner.invoke(app, args)
    assert r.exit_code == 0, r.output
    assert (out / "seed-30kmh-dry-report.html").exists()


def test_demo_names_the_extra_before_it_simulates(tmp_path, monkeypatch):
    # With only the twin extra the demo used to simulate for 15 s, then fail writing TDMS.
    import sys

    from typer.testing import CliRunner

    from rollerrig.cli import app

    monkeypatch.setitem(sys.modules, "nptdms", None)  # import fails as if not installed
    result = CliRunner().invoke(app, ["demo", "--out", str(tmp_path / "out")])
    assert result.exit_code == 2
    assert (
        result.output.strip() == "error: rollerrig demo needs nptdms: pip install 'rollerrig[all]'"
    )
    assert not (tmp_path / "out").exists()
