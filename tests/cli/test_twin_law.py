"""``rollerrig simulate --law``: the creep law of the twin's contact (issue 19, point 2)."""

from rollerrig.cli import app
from rollerrig.cli.twin import variant_stem


def test_a_law_other_than_polach_names_the_output():
    assert variant_stem("seed-30kmh-dry", law="polach") == "seed-30kmh-dry"
    assert variant_stem("seed-30kmh-dry", law="fastsim") == "seed-30kmh-dry_law-fastsim"


def test_an_unknown_law_is_refused_with_the_laws(tmp_path, runner):
    result = runner.invoke(app, ["simulate", "--out", str(tmp_path), "--law", "fastsimm"])
    assert result.exit_code == 2, result.output
    assert "modified-fastsim" in result.output
    assert list(tmp_path.iterdir()) == []


def test_the_law_option_is_documented(runner):
    result = runner.invoke(app, ["simulate", "--help"])
    assert result.exit_code == 0 and "--law" in result.output
