"""``rollerrig contact``: the table, two figures and a summary, each with provenance."""

import json

import pytest

from rollerrig.cli import app
from rollerrig.output import figure_provenance


def test_contact_report_writes_figures_and_summary(tmp_path, runner):
    result = runner.invoke(app, ["contact", "--load-kn", "20", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "contact area" in result.output
    for name in ("contact-creep-curves.png", "contact-vs-roller-radius.png"):
        assert (tmp_path / name).stat().st_size > 10_000
        record = figure_provenance(tmp_path / name)
        assert record["parameters"]["normal_load_N"] == 20e3
        assert record["command"][1:] == ["contact", "--load-kn", "20", "--out", str(tmp_path)]
        assert record["rig"]["name"] == "pardubice-tram-roller-rig" and record["rig"]["sha256"]
    summary = json.loads((tmp_path / "contact-report.json").read_text())
    assert summary["provenance"]["parameters"]["normal_load_N"] == 20e3
    roller, rail = summary["contact"]["roller"], summary["contact"]["tangent_rail"]
    # The roller's longitudinal curvature shrinks the contact (Kayaalp §2.5, Figs. 12-13).
    assert roller["area_m2"] < rail["area_m2"]
    # the ratio column is rail / roller, as transfer's factor F_rail/F_roller
    row = next(line for line in result.output.splitlines() if "contact area" in line)
    assert f"{rail['area_m2'] / roller['area_m2']:.3f}" in row
    assert "rail / roller" in result.output
    assert not list(tmp_path.glob(".*"))  # no temporary files, no lock left behind
    assert (tmp_path / "contact-run.json").exists()


def test_contact_with_a_rig_file_records_its_hash(tmp_path, runner):
    from importlib import resources

    from rollerrig.output import file_sha256

    with resources.as_file(resources.files("rollerrig.rig") / "data") as data:
        rig_file = sorted(data.glob("*.toml"))[0]
        out = tmp_path / "out"
        result = runner.invoke(app, ["contact", "--rig", str(rig_file), "--out", str(out)])
        assert result.exit_code == 0, result.output
        summary = json.loads((out / "contact-report.json").read_text())
        assert summary["provenance"]["inputs"]["rig"]["sha256"] == file_sha256(rig_file)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--load-kn", "-5"], "--load-kn must be in (0, 200] kN"),
        # a load typed in N, a speed far beyond any rig, a radius typed in m: refused, named
        (["--load-kn", "4300"], "(a wheel load; a value typed in N?), got 4300 kN"),
        (["--speed-kmh", "1000"], "--speed-kmh must be in (0, 300] km/h"),
        (["--roller-radius-mm", "0.452"], "(a radius; a value typed in m?), got 0.452 mm"),
        (["--roller-radius-mm", "0"], "radius"),
        (["--poisson", "0.6"], "--poisson must be in (0, 0.5), got 0.6"),
        (["--ka", "0.2", "--ks", "0.5"], "kS <= kA"),
    ],
)
def test_contact_rejects_nonphysical_input(tmp_path, runner, args, message):
    result = runner.invoke(app, ["contact", "--out", str(tmp_path), *args])
    assert result.exit_code == 2
    assert message in result.output
    assert "Traceback" not in result.output
    assert list(tmp_path.iterdir()) == []
