"""``rollerrig rig list`` and ``--rig NAME`` on the commands that take ``--rig``."""

from rollerrig.cli import app


def test_rig_list_names_every_bundled_set(runner):
    result = runner.invoke(app, ["rig", "list"])
    assert result.exit_code == 0, result.output
    for name in ("pardubice", "vt-fra-quarter-scale", "twin-disc-suros-type"):
        assert name in result.output


def test_rig_list_shows_each_file_once_with_its_names(runner):
    """The default rig loads as ``default`` and ``pardubice``: one block names both."""
    result = runner.invoke(app, ["rig", "list"])
    assert result.exit_code == 0, result.output
    assert result.output.count("default_rig.toml") == 1
    assert "pardubice (also: default)" in result.output


def test_rig_name_loads_the_set(runner, tmp_path):
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["contact", "--rig", "vt-fra-quarter-scale", "--load-kn", "5", "--out", str(out)]
    )
    assert result.exit_code == 0, result.output
    report = (out / "contact-report.json").read_text("utf-8")
    assert "vt-fra-quarter-scale" in report or "0.1143" in report


def test_a_misspelt_rig_name_is_one_usage_error_with_the_nearest(runner, tmp_path):
    result = runner.invoke(app, ["contact", "--rig", "pardubise", "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "did you mean 'pardubice'" in " ".join(result.output.split())
    assert "Traceback" not in result.output


def test_a_missing_rig_file_is_still_a_file_error(runner, tmp_path):
    result = runner.invoke(
        app, ["contact", "--rig", str(tmp_path / "no.toml"), "--out", str(tmp_path)]
    )
    assert result.exit_code == 2
    assert "rig file not found" in result.output
