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
