"""Errors and help in the user's words (issue 23, point 7): a did-you-mean for every name a user
types, values answered in the unit typed, no pydantic or Python-API wording on the command
line, help texts that name every choice and no issue numbers."""

import re

import pytest

from rollerrig.cli import app


def _flat(text: str) -> str:
    return " ".join(text.split())


def _one_error(result) -> str:
    lines = [ln for ln in result.output.splitlines() if ln.lower().startswith("error")]
    assert len(lines) == 1, result.output
    assert "Traceback" not in result.output
    return lines[0]


PYDANTIC = ("Value error", "Input should be", "unable to parse", "pydantic")


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (
            ["simulate", "--roller-drive", "inductin"],
            "'inductin' is not one of induction, induction_linear, ideal_speed, servo, "
            "induction_dq; did you mean 'induction'?",
        ),
        (["simulate", "--roller-drive", "Induction_DQ"], "did you mean 'induction_dq'?"),
        (["simulate", "--solver", "fst"], "did you mean 'fast'?"),
        (["simulate", "--roller-lag-s", "abc"], "'abc' is not a number"),
        (["contact", "--load-kn", "x"], "'x' is not a number"),
        (["study", "run", "lag", "--workers", "1.5"], "'1.5' is not a whole number"),
        (["study", "run", "lag", "--workers", "0"], "must be >= 1, got 0"),
    ],
)
def test_a_bad_option_value_is_said_without_pydantic_wording(tmp_path, runner, args, expected):
    result = runner.invoke(app, [*args, "--out", str(tmp_path)])
    assert result.exit_code == 2, result.output
    line = _one_error(result)
    assert expected in line, line
    for words in PYDANTIC:
        assert words not in result.output, result.output
    assert list(tmp_path.iterdir()) == []


def test_a_bad_choice_keeps_its_brackets(tmp_path, runner):
    # Rich markup would eat "[kN]"; the value is shown as the user typed it.
    result = runner.invoke(app, ["simulate", "--roller-drive", "[kN]", "--out", str(tmp_path)])
    assert result.exit_code == 2, result.output
    assert "'[kN]' is not one of" in _one_error(result)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["simulate", "--experiment", "seed-10kmh-wte"], "did you mean 'seed-10kmh-wet'?"),
        (["simulate", "--experiment", "Release-Test"], "did you mean 'release-test'?"),
        (["study", "run", "drivs"], "did you mean 'drives'?"),
        (["study", "run", "stifness"], "did you mean 'stiffness'?"),
    ],
)
def test_a_misspelt_experiment_or_study_gets_a_did_you_mean(tmp_path, runner, args, expected):
    result = runner.invoke(app, [*args, "--out", str(tmp_path)])
    assert result.exit_code == 2, result.output
    line = _one_error(result)
    assert expected in line and "neither a bundled" in line, line


def test_a_name_far_from_every_bundled_one_gets_no_guess(tmp_path, runner):
    result = runner.invoke(app, ["study", "run", "zzzz", "--out", str(tmp_path)])
    assert result.exit_code == 2, result.output
    assert "did you mean" not in _one_error(result)


def test_a_free_key_typo_prints_the_near_keys_not_the_catalogue(tmp_path, runner):
    recording = tmp_path / "r.csv"
    recording.write_text("time [s],torque [N.m]\n0,0\n", encoding="utf-8")
    result = runner.invoke(
        app,
        [
            "calibrate",
            str(recording),
            "--free",
            "stiffness.roler_shaft,inertia.roller",
            "--out",
            str(tmp_path / "out"),
        ],
    )
    assert result.exit_code == 2, result.output
    line = _flat(result.output)
    assert "'stiffness.roler_shaft' (did you mean 'stiffness.roller_shaft'" in line, line
    assert "--list-keys" in line
    # the near matches only (at most 3), not the ~70 keys of the catalogue
    assert len(re.findall(r"'[a-z_]+\.[a-z_0-9]+'", line)) <= 4, line
    assert "inertia.am_stator" not in line


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (
            ["--load-kn", "-3"],
            "--load-kn must be in (0, 200] kN (a wheel load; a value typed in N?), got -3 kN",
        ),
        (["--load-kn", "nan"], "--load-kn must be a finite number (in kN), got nan"),
        (
            ["--speed-kmh", "0"],
            "--speed-kmh must be in (0, 300] km/h (a rolling speed), got 0 km/h",
        ),
        (
            ["--wheel-radius-mm", "-1"],
            "--wheel-radius-mm must be >= 5 mm (a radius; a value typed in m?), got -1 mm",
        ),
    ],
)
def test_a_value_is_answered_in_the_unit_typed(tmp_path, runner, args, expected):
    result = runner.invoke(app, ["contact", *args, "--out", str(tmp_path)])
    assert result.exit_code == 2, result.output
    line = _one_error(result)
    assert expected in line, line
    assert "[N]" not in line and "[m/s]" not in line and "[m]" not in line


def test_an_unknown_suffix_names_no_python_argument(tmp_path, runner):
    recording = tmp_path / "run.xyz"
    recording.write_text("time,torque\n0,0\n", encoding="utf-8")
    result = runner.invoke(app, ["analyze", str(recording), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    line = _one_error(result)
    assert "unsupported file suffix '.xyz'" in line and ".tdms" in line, line
    assert "format=" not in line and "rename" in line


def test_a_file_recognised_by_its_content_keeps_the_readers_own_words(tmp_path, runner):
    # an imc FAMOS file under '.dat': the reader names the vendor and the export to make
    export = tmp_path / "export.dat"
    export.write_bytes(b"|CF,2,1,1;|CK,1,3,1,1;\r\n|NO,1,  20,0,9,imc STUDIO,0,;\r\n")
    result = runner.invoke(app, ["analyze", str(export), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    line = _one_error(result)
    assert "imc FAMOS" in line and "unsupported file suffix" not in line, line


@pytest.mark.parametrize(
    "command",
    [
        "contact",
        "simulate",
        "modes",
        "frame",
        "analyze",
        "spectrum",
        "filters",
        "calibrate",
        "demo",
        "study run",
        "study show",
        "study list",
        "study frame",
        "study drive-dynamics",
    ],
)
def test_help_texts_name_no_issue_numbers(command, runner):
    result = runner.invoke(app, [*command.split(), "--help"])
    assert result.exit_code == 0, result.output
    assert not re.search(r"\bissue \d", result.output, re.IGNORECASE), command


def test_roller_drive_help_names_every_drive(runner):
    text = _flat(runner.invoke(app, ["simulate", "--help"]).output)
    help_text = text.split("--roller-drive", 1)[1].split("--roller-lag-s", 1)[0]
    for drive in ("induction", "induction_linear", "ideal_speed", "servo", "induction_dq"):
        # each named in the option's words, not only in the <choice|...> list
        assert help_text.count(drive) >= 2, (drive, help_text)


def test_simulate_list_says_what_each_experiment_is(runner):
    from rollerrig.experiment import bundled_protocols

    result = runner.invoke(app, ["simulate", "--list"])
    assert result.exit_code == 0, result.output
    lines = result.output.strip().splitlines()
    assert [ln.split()[0] for ln in lines] == list(bundled_protocols())
    for line in lines:
        _name, duration, unit, *words = line.split()
        assert unit == "s" and float(duration) > 0, line
        assert len(words) >= 5, line
    assert any("wet" in ln and ln.startswith("seed-10kmh-wet") for ln in lines)
