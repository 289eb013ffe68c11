"""``rollerrig frame``: the table, frame.json in SI units, two figures, clear errors."""

from __future__ import annotations

import json
import re

import pytest

from rollerrig.cli import app
from rollerrig.output import figure_provenance

pytest.importorskip("Pynite")


def test_frame_default_writes_json_and_figures(tmp_path, runner):
    out = tmp_path / "out"
    result = runner.invoke(app, ["frame", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "top horizontal deflection" in result.output and "~0.04" in result.output
    assert "note: the bundled frame's dimensions" in result.output
    doc = json.loads((out / "frame.json").read_text())
    for key in (
        "max_von_mises_stress",
        "top_horizontal_deflection",
        "strain_gauge_stresses",
        "natural_frequencies",
        "longitudinal_stiffness_at_contact",
        "provenance",
    ):
        assert key in doc, key
    assert doc["normal_load"] == 20e3 and doc["traction_force"] == 2e3  # kN -> N
    assert doc["units"]["top_horizontal_deflection"] == "m"
    assert 1e-6 < doc["top_horizontal_deflection"] < 1e-3  # metres, not millimetres
    assert 1e5 < doc["max_von_mises_stress"] < 1e9  # pascals
    assert len(doc["natural_frequencies"]) == 6
    assert doc["contact_dof"]["stiffness"] == doc["longitudinal_stiffness_at_contact"]
    assert doc["provenance"]["parameters"]["normal_load_N"] == 20e3
    for name in ("frame-deformed.png", "frame-modes.png"):
        assert (out / name).stat().st_size > 10_000
        assert figure_provenance(out / name)["parameters"]["traction_force_N"] == 2e3
    assert (out / "frame-run.json").exists()


def test_frame_loads_scale_the_gauges(tmp_path, runner):
    outs = []
    for args in (
        ["--vertical-kn", "10", "--horizontal-kn", "0"],
        ["--vertical-kn", "20", "--horizontal-kn", "0"],
    ):
        out = tmp_path / args[1]
        result = runner.invoke(app, ["frame", *args, "--modes", "1", "--out", str(out)])
        assert result.exit_code == 0, result.output
        outs.append(json.loads((out / "frame.json").read_text()))
    a, b = (o["strain_gauge_stresses"]["top_beam"] for o in outs)
    assert b == pytest.approx(2 * a) and a > 0


def test_frame_file_option_and_its_errors(tmp_path, runner):
    from importlib import resources

    text = resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text()
    good = tmp_path / "frame.toml"
    good.write_text(text)
    out = tmp_path / "out"
    result = runner.invoke(app, ["frame", "--frame", str(good), "--modes", "2", "--out", str(out)])
    assert result.exit_code == 0, result.output
    doc = json.loads((out / "frame.json").read_text())
    assert doc["frame_file"] == str(good)
    assert doc["provenance"]["inputs"]["frame"]["sha256"]
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('section = "brace"', 'section = "bracing"'))
    out2 = tmp_path / "out2"
    result = runner.invoke(app, ["frame", "--frame", str(bad), "--out", str(out2)])
    assert result.exit_code == 2
    assert "members.knee_brace_right.section: not a section of the frame" in result.output
    assert "Traceback" not in result.output
    assert not out2.exists() or list(out2.iterdir()) == []


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # the wheel-load bound and message of the other commands (it had taken 10 000 kN)
        (
            ["--vertical-kn", "-5"],
            "--vertical-kn must be in [0, 200] kN (a wheel load; a value typed in N?), got -5 kN",
        ),
        (
            ["--vertical-kn", "4300"],
            "--vertical-kn must be in [0, 200] kN (a wheel load; a value typed in N?), got 4300 kN",
        ),
        (["--horizontal-kn", "nan"], "--horizontal-kn must be a finite number [kN]"),
        (["--modes", "0"], "--modes must be in [1, 50]"),
        (["--vertical-kn", "1e6"], "--vertical-kn must be in [0, 200] kN"),
        (["--horizontal-kn", "-2e4"], "--horizontal-kn must be at most 10000 kN in magnitude"),
    ],
)
def test_frame_rejects_bad_options(tmp_path, runner, args, message):
    result = runner.invoke(app, ["frame", "--out", str(tmp_path), *args])
    assert result.exit_code == 2
    assert message in " ".join(result.output.split())
    assert list(tmp_path.iterdir()) == []


def test_frame_help_keeps_the_units(runner):
    result = runner.invoke(app, ["frame", "--help"])
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    for fragment in ("[kN], 0 to 200", "contact [kN]", "--frame", "frame.json"):
        assert fragment in text, fragment


def _hostile(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            (
                'spring_plate = { value = [0.0, 0.0, 2.00], unit = "m",',
                'spring_plate = { value = [0.0, 0.0, 1e200], unit = "m",',
            ),
            "nodes.spring_plate.value: outside the plausible range (a rig frame lies within 1 km "
            "of its origin) [m]; allowed [-1000, 1000]",
        ),
        (
            ("youngs_modulus = { value = 210.0,", "youngs_modulus = { value = 1e-300,"),
            "materials.steel.youngs_modulus.value: outside the plausible range",
        ),
        ("members", "members: too many entries for the frame analysis"),
    ],
)
def test_hostile_frame_files_are_one_clear_error(tmp_path, runner, change, message):
    from importlib import resources

    text = resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text()
    if change == "members":  # 20 000 more members (joining the same two nodes)
        text += "".join(
            f'\n[members.extra{i}]\nnodes = ["base_front_left", "base_rear_left"]\n'
            'section = "column"\n'
            for i in range(20_000)
        )
    else:
        text = _hostile(text, *change)
    path = tmp_path / "hostile.toml"
    path.write_text(text)
    out = tmp_path / "out"
    result = runner.invoke(app, ["frame", "--frame", str(path), "--out", str(out)])
    assert result.exit_code == 2, result.output
    assert message in " ".join(result.output.split())
    assert "Traceback" not in result.output and "mechanism" not in result.output
    assert not out.exists() or list(out.iterdir()) == []


def test_frame_without_traction_is_refused_before_the_analysis(tmp_path, runner):
    from importlib import resources

    text = resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text()
    path = tmp_path / "f.toml"
    no_traction = re.sub(r"(?m)^traction = \[.*\]$", "traction = [0, 0, 0]", text)
    assert no_traction.count("traction = [0, 0, 0]") == 5
    path.write_text(no_traction)
    out = tmp_path / "out"
    result = runner.invoke(app, ["frame", "--frame", str(path), "--out", str(out)])
    assert result.exit_code == 2, result.output
    assert "load_points: every load point's traction is [0, 0, 0]" in result.output
    assert "internal error" not in result.output


def test_few_modes_still_find_the_contacts_dominant_mode(tmp_path, runner):
    """Review: ``--modes 2`` wrote 'mode 2, 37.79 Hz, modal mass 8.55e+06 kg, share 0.000' to
    frame.json (the default run: mode 4, 1551 kg, share 0.710). The two modes asked for are
    reported and drawn, the contact's mode 4 with them."""
    out = tmp_path / "out"
    result = runner.invoke(app, ["frame", "--modes", "2", "--out", str(out)])
    assert result.exit_code == 0, result.output
    doc = json.loads((out / "frame.json").read_text())
    assert len(doc["natural_frequencies"]) == 2 and doc["modes_computed"] >= 4
    contact = doc["contact_dof"]
    assert contact["mode"] == 4
    assert contact["modal_mass"] == pytest.approx(1551.0, rel=1e-3)
    assert contact["participation"] == pytest.approx(0.710, abs=1e-3)
    assert "mode 4 (computed beyond --modes 2)" in result.output
    assert "natural frequency 3" not in result.output


def test_an_unestablished_dominant_mode_is_said_not_guessed(tmp_path, runner, monkeypatch):
    """When even the most modes computed leave the dominant one open, the table and
    frame.json say 'not established' with why, and the run still writes its outputs."""
    from rollerrig.frame import analysis

    monkeypatch.setattr(analysis, "MAX_CONTACT_MODES", 2)
    out = tmp_path / "out"
    result = runner.invoke(app, ["frame", "--modes", "2", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "not established" in result.output
    doc = json.loads((out / "frame.json").read_text())
    assert doc["contact_dof"]["dominant_mode"] == "not established"
    assert "compute more modes" in doc["contact_dof"]["why"]
    assert "mode" not in doc["contact_dof"]
    assert (out / "frame-modes.png").exists()
