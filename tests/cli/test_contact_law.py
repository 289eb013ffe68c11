"""``rollerrig contact --law``: the FASTSIM family in the contact command."""

import json

import pytest

from rollerrig.cli import app


def test_help_names_the_laws_and_keeps_units(runner):
    result = runner.invoke(app, ["contact", "--help"], terminal_width=200)
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    for law in ("polach", "fastsim", "modified-fastsim", "fastrip"):
        assert law in text
    assert "[kN]" in text and "[mu0, A, B in s/m]" in text  # Rich markup off
    assert "--friction-set <name>" in text and "<list[" not in text  # not typer's list[str]


@pytest.mark.parametrize("law", ["fastsim", "modified-fastsim", "fastrip"])
def test_law_writes_curves_and_traction_figure(tmp_path, runner, law):
    result = runner.invoke(app, ["contact", "--law", law, "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    for name in (
        "contact-creep-curves.png",
        "contact-traction.png",
        "contact-vs-roller-radius.png",
    ):
        assert (tmp_path / name).stat().st_size > 10_000
    summary = json.loads((tmp_path / "contact-report.json").read_text())
    assert summary["law"] == law
    assert summary["provenance"]["parameters"]["law"] == law


def test_friction_set_by_name_and_did_you_mean(tmp_path, runner):
    result = runner.invoke(
        app,
        [
            "contact",
            "--law",
            "fastsim",
            "--friction-set",
            "eurosprinter-coulomb",
            "--out",
            str(tmp_path / "a"),
        ],
    )
    assert result.exit_code == 0, result.output
    assert "eurosprinter-coulomb" in result.output
    result = runner.invoke(
        app, ["contact", "--friction-set", "polach-drie", "--out", str(tmp_path / "b")]
    )
    assert result.exit_code == 2
    assert "did you mean 'polach-dry'" in result.output
    result = runner.invoke(app, ["contact", "--law", "fastsm", "--out", str(tmp_path / "c")])
    assert result.exit_code == 2
    result = runner.invoke(
        app, ["contact", "--law", "fastsim", "--ka", "0.5", "--out", str(tmp_path / "d")]
    )
    assert result.exit_code == 2 and "--law polach only" in result.output
