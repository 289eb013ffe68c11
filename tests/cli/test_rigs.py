"""``rollerrig rig list``, ``rig show`` and ``--rig NAME`` on the commands that take ``--rig``."""

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


def test_rig_show_gives_each_value_with_its_unit_and_basis(runner):
    # A set's values had been visible only by opening its file (a user's review, 2026-12-03).
    result = runner.invoke(app, ["rig", "show", "default", "--section", "stiffness"])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "stiffness.roller_shaft" in text and "43500" in text and "N.m/rad" in text
    assert "source: Kayaalp" in text and "inertia." not in text


def test_rig_show_names_a_misspelt_set_or_section(runner):
    result = runner.invoke(app, ["rig", "show", "default", "--section", "stifness"])
    assert result.exit_code == 2 and "did you mean 'stiffness'" in result.output
    result = runner.invoke(app, ["rig", "show", "defualt"])
    assert result.exit_code == 2 and "did you mean 'default'" in " ".join(result.output.split())
