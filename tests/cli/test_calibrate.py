"""``rollerrig calibrate``: help that keeps its units, clear errors, and end to end on a
synthetic recording (calibrate, then ``analyze --rig calibrated-rig.toml``)."""

import json

import pytest

from rollerrig.cli import app
from rollerrig.output import file_sha256


def _flat(text: str) -> str:
    return " ".join(text.split())


@pytest.fixture(scope="module")
def synthetic_tdms(tmp_path_factory):
    """A short synthetic test of the twin with altered roller-shaft stiffness and bearing
    friction, written as NI TDMS."""
    from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
    from rollerrig.recordings.synthetic import synthetic_recording
    from rollerrig.recordings.writers import write_recording
    from rollerrig.rig.parameters import default_rig
    from rollerrig.solve.simulation import Simulation

    rig = default_rig().with_overrides(
        {"stiffness.roller_shaft": 47850.0, "bearing.friction_coefficient": 0.0091}
    )
    protocol = Protocol.from_steps(
        "cli-calibration",
        [Hold(1.0), RampTorque(650.0, 2.5), ReleaseTorque(), Hold(2.0)],
        normal_load=4300.0,
        roller_speed=30 / 3.6,
    )
    rec, _ = synthetic_recording(Simulation(rig, protocol).run(), seed=2)
    path = tmp_path_factory.mktemp("calibrate") / "altered.tdms"
    write_recording(rec, path)
    return path


def test_help_keeps_the_units_in_brackets(runner):
    result = runner.invoke(app, ["calibrate", "--help"])
    assert result.exit_code == 0, result.output
    text = _flat(result.output)
    for fragment in (
        "standard errors [SI]",
        "Noise of the torque sensor [N.m]",
        "per stage [-]",
        "<dry|wet>",
        "--free",
        "calibrated-rig.toml",
        "--list-keys",
        "delay against the encoders [ms]",
    ):
        assert fragment in text, fragment
    assert "Traceback" not in result.output
    # --free and the recording are required unless --list-keys is given: the help says so
    # (omitting --free had failed with an error the help never announced).
    assert "--free <str> [required, except with --list-keys] Free parameters" in text
    assert "recording <path> [required, except with --list-keys] Recording" in text


def test_list_keys_and_missing_or_unknown_keys(runner, tmp_path):
    result = runner.invoke(app, ["calibrate", "x.tdms", "--list-keys"])
    assert result.exit_code == 0
    keys = result.output.split()
    assert "stiffness.roller_shaft" in keys and "polach.k_slip" in keys
    # Issue 24, point 9: --list-keys needs no recording.
    alone = runner.invoke(app, ["calibrate", "--list-keys"])
    assert alone.exit_code == 0, alone.output
    assert alone.output.split() == keys
    neither = runner.invoke(app, ["calibrate", "--out", str(tmp_path / "o")])
    assert neither.exit_code == 2, neither.output
    assert _flat(neither.output) == (
        "error: give the RECORDING to calibrate to (rollerrig calibrate RECORDING --free KEYS), "
        "or --list-keys to list the keys --free accepts"
    )
    result = runner.invoke(app, ["calibrate", "x.tdms", "--out", str(tmp_path / "o")])
    assert result.exit_code == 2 and _flat(result.output).startswith(
        "error: --free is required: name the parameters to fit"
    )  # the package's error format, not click's "Error:"
    result = runner.invoke(
        app, ["calibrate", "x.tdms", "--free", "inertia.rolller", "--out", str(tmp_path / "o")]
    )
    assert result.exit_code == 2, result.output
    text = _flat(result.output)
    assert "'inertia.rolller' (did you mean 'inertia.roller'" in text
    assert not (tmp_path / "o").exists()


def test_a_recording_without_torque_request_is_one_clear_error(runner, tmp_path, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")
    rec.write_text(rec.read_text().replace("torque_request [N.m]", "setpoint [N.m]"))
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["calibrate", str(rec), "--free", "inertia.roller", "--out", str(out)]
    )
    assert result.exit_code == 2, result.output
    assert "torque_request" in result.output and "Traceback" not in result.output
    assert not out.exists()


def test_calibrate_then_analyze_with_the_calibrated_rig(runner, tmp_path, synthetic_tdms):
    out = tmp_path / "cal"
    result = runner.invoke(
        app,
        [
            "calibrate",
            str(synthetic_tdms),
            "--free",
            "stiffness.roller_shaft,bearing.friction_coefficient,damping.wheel_shaft",
            "--out",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "calibrate-altered-run.json",
        "calibrated-rig.toml",
        "calibration-fit.nc",
        "calibration-fit.png",
        "calibration.json",
    ]
    text = _flat(result.output)
    assert "damping.wheel_shaft" in text and "not identified" in text
    doc = json.loads((out / "calibration.json").read_text())
    assert doc["provenance"]["inputs"]["recording"]["sha256"] == file_sha256(synthetic_tdms)
    assert doc["provenance"]["parameters"]["free"][0] == "stiffness.roller_shaft"
    assert doc["provenance"]["parameters"]["torque_delay_ms"] == 0.0  # the option's default
    stiffness = doc["parameters"]["stiffness.roller_shaft"]
    assert abs(stiffness["value"] - 47850.0) < 5 * stiffness["standard_error"] + 10.0
    assert doc["parameters"]["damping.wheel_shaft"]["value"] is None
    manifest = json.loads((out / "calibrate-altered-run.json").read_text())
    assert {f["file"] for f in manifest["files"]} == set(names) - {"calibrate-altered-run.json"}

    # The rig it was made on, recorded (issue 24, point 6).
    assert doc["rig"]["name"] == "pardubice-tram-roller-rig"
    assert doc["rig"]["sha256"] == doc["provenance"]["rig"]["sha256"]
    assert doc["rig"]["calibrated_keys"] == [
        "bearing.friction_coefficient",
        "stiffness.roller_shaft",
    ]
    assert doc["rig"]["parameters"]["stiffness.roller_shaft"] == 43500.0

    analysed = tmp_path / "analysed"
    calibrated_rig = str(out / "calibrated-rig.toml")
    result = runner.invoke(
        app,
        [
            "analyze",
            str(synthetic_tdms),
            "--rig",
            calibrated_rig,
            "--calibration",
            str(out / "calibration.json"),
            "--no-study",
            "--out",
            str(analysed),
        ],
    )
    assert result.exit_code == 0, result.output
    assert "warning:" not in result.output
    analysis = json.loads((analysed / "altered-analysis.json").read_text())
    assert analysis["provenance"]["rig"]["name"] == "pardubice-tram-roller-rig-calibrated"
    assert analysis["provenance"]["parameters"]["calibration_rig"] == "same rig"

    # On another rig: one error naming both rigs and what differs, nothing written ...
    from rollerrig.rig.parameters import default_rig, save_rig

    other = tmp_path / "other.toml"
    save_rig(default_rig().with_overrides({"stiffness.am_mount": 2.0e5}), other)
    args = ["analyze", str(synthetic_tdms), "--no-study", "--rig", str(other)]
    args += ["--calibration", str(out / "calibration.json"), "--out", str(tmp_path / "x")]
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    text = _flat(result.output)
    assert text.startswith(
        f"error: --calibration {out / 'calibration.json'}: rig: made on another rig: they differ "
        "in stiffness.am_mount (500000 there, 200000 here)"
    )
    assert f"(the bundled rig; sha256 {doc['rig']['parameters_sha256'][:12]})" in text
    assert f"--rig {other}; sha256" in text and "--allow-other-rig" in text
    assert "Traceback" not in result.output and not (tmp_path / "x").exists()
    # ... unless the user insists: a warning, recorded in every output's provenance.
    result = runner.invoke(app, [*args, "--allow-other-rig"])
    assert result.exit_code == 0, result.output
    assert "warning: --calibration" in result.output
    for path in (tmp_path / "x").glob("*.json"):
        record = json.loads(path.read_text())["provenance"]["parameters"]
        assert record["calibration_rig"] == "other rig", path.name
        assert "stiffness.am_mount (500000 there, 200000 here)" in record["calibration_rig_warning"]


@pytest.mark.parametrize(
    ("field", "edited", "line"),
    [
        (
            "standard_error",
            -1.0,
            "inertia.roller.standard_error: must be >= 0 [kg.m^2]; allowed 0, or [4.6e-11, 23]; "
            "got -1",
        ),
        ("value", "46", "inertia.roller.value: must be a number [kg.m^2]; got '46'"),
        (
            "value",
            1e300,
            "inertia.roller.value: not plausible: more than 1000 times away from the rig's "
            "value 45 [kg.m^2]; allowed [0.045, 45000]; got 1e+300",
        ),
    ],
)
def test_analyze_refuses_a_hand_edited_calibration_naming_the_field(
    runner, tmp_path, adhesion_csv, field, edited, line
):
    # Issue 24, point 8: these were internal errors (OverflowError) or named no field.
    rec = adhesion_csv(tmp_path / "test.csv")
    entry = {"value": 46.0, "standard_error": 0.5, field: edited}
    path = tmp_path / "calibration.json"
    path.write_text(json.dumps({"parameters": {"inertia.roller": entry}}))
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["analyze", str(rec), "--calibration", str(path), "--out", str(out)]
    )
    assert result.exit_code == 2, result.output
    assert _flat(result.output) == f"error: --calibration {path}: {line}"
    assert not out.exists()


def test_allow_other_rig_needs_a_calibration(runner, tmp_path, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")
    result = runner.invoke(app, ["analyze", str(rec), "--allow-other-rig", "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "--allow-other-rig needs --calibration" in _flat(result.output)


def test_list_keys_lists_the_vf_settings_for_the_dq_drive_only(runner, tmp_path):
    # Issue 25 part 2: the V/f settings are free keys of the dq drive.
    lag = runner.invoke(app, ["calibrate", "--list-keys"]).output.split()
    dq = runner.invoke(app, ["calibrate", "--list-keys", "--roller-drive", "induction_dq"])
    assert dq.exit_code == 0, dq.output
    assert "roller_drive_vf.slip_compensation" in dq.output.split()
    assert not any(k.startswith("roller_drive_vf.") for k in lag)
    assert "induction_motor.response_lag_clp" in lag
    result = runner.invoke(
        app,
        [
            "calibrate",
            "x.tdms",
            "--free",
            "roller_drive_vf.slip_compensation",
            "--out",
            str(tmp_path / "o"),
        ],
    )
    assert result.exit_code == 2, result.output
    assert "--roller-drive induction_dq" in _flat(result.output)
    assert not (tmp_path / "o").exists()


def test_analyze_refuses_a_calibration_that_is_not_valid(runner, tmp_path, adhesion_csv):
    # Issue 25 part 2, item 4: a fit that did not converge is no calibration analyze uses.
    rec = adhesion_csv(tmp_path / "test.csv")
    entry = {"value": 46.0, "standard_error": 0.5}
    doc = {
        "parameters": {"inertia.roller": entry},
        "valid": False,
        "invalid_reasons": ["the fit did not converge within 3 iterations"],
    }
    path = tmp_path / "calibration.json"
    path.write_text(json.dumps(doc))
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["analyze", str(rec), "--calibration", str(path), "--out", str(out)]
    )
    assert result.exit_code == 2, result.output
    text = _flat(result.output)
    assert "not valid (the fit did not converge within 3 iterations)" in text
    assert not out.exists()


def test_the_torque_delay_reaches_the_calibration_and_its_provenance(
    runner, tmp_path, synthetic_tdms
):
    out = tmp_path / "cal"
    args = ["calibrate", str(synthetic_tdms), "--free", "stiffness.roller_shaft", "--out",
            str(out), "--torque-delay-ms", "2", "-q"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    doc = json.loads((out / "calibration.json").read_text())
    assert doc["provenance"]["parameters"]["torque_delay_ms"] == 2.0
    assert any("(torque_delay = 0.002 s" in n for n in doc["notes"])
    bad = runner.invoke(app, [*args[:-3], "--torque-delay-ms", "500"])
    assert bad.exit_code == 2 and "Traceback" not in bad.output
