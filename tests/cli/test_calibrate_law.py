"""``rollerrig calibrate --law``: the creep law of the fitted twin as a choice (issue 19,
point 2): the help shows it, a key of another law is one clear error naming the law's keys,
and a recording of the modified FASTSIM is calibrated with its ``fastsim.*`` keys, the console
and ``calibration.json`` naming the law."""

import dataclasses
import json

import pytest

from rollerrig.cli import app


def _flat(text: str) -> str:
    return " ".join(text.split())


def test_help_shows_the_law(runner):
    result = runner.invoke(app, ["calibrate", "--help"])
    assert result.exit_code == 0, result.output
    text = _flat(result.output)
    assert "--law" in text and "modified-fastsim" in text and "fastsim.k0" in text


def test_list_keys_lists_the_law_s_keys(runner):
    result = runner.invoke(app, ["calibrate", "--list-keys", "--law", "modified-fastsim"])
    assert result.exit_code == 0, result.output
    keys = result.output.split()
    assert "fastsim.k0" in keys and "fastsim.beta" in keys and "stiffness.roller_shaft" in keys
    assert not any(k.startswith("polach.") for k in keys)


def test_a_key_of_another_law_is_one_error_before_anything_is_read(runner, tmp_path):
    out = tmp_path / "o"
    result = runner.invoke(
        app,
        ["calibrate", "missing.tdms", "--law", "modified-fastsim", "--free",
         "inertia.roller,polach.static_friction,polach.k_adhesion", "--out", str(out)],
    )  # fmt: skip
    assert result.exit_code == 2, result.output
    text = _flat(result.output)
    assert text.startswith(
        "error: free parameter(s) 'polach.static_friction' (did you mean "
        "'fastsim.static_friction'?), 'polach.k_adhesion': not parameters of the creep law "
        "'modified-fastsim', whose keys are fastsim.static_friction, fastsim.limit_ratio, "
        "fastsim.friction_decay, fastsim.k0, fastsim.alpha_inf, fastsim.beta; they are keys "
        "of the law 'polach'"
    ), text
    assert "Traceback" not in result.output and not out.exists()
    # and the other way round, with Polach's law (the default)
    result = runner.invoke(app, ["calibrate", "missing.tdms", "--free", "fastsim.k0"])
    assert result.exit_code == 2 and "of the law 'modified-fastsim'" in _flat(result.output)


@pytest.mark.slow
def test_calibrate_a_modified_fastsim_recording_names_the_law(runner, tmp_path):
    from rollerrig.calibrate.problem import friction_parameters
    from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
    from rollerrig.recordings.synthetic import synthetic_recording
    from rollerrig.recordings.writers import write_recording
    from rollerrig.rig.model import DriveConfig
    from rollerrig.solve.simulation import Simulation

    truth = dataclasses.replace(friction_parameters("dry", "modified-fastsim"), k0=0.6)
    protocol = Protocol.from_steps(
        "cli-calibration-law",
        [Hold(1.0), RampTorque(650.0, 2.5), ReleaseTorque(), Hold(2.0)],
        normal_load=4300.0,
        roller_speed=30 / 3.6,
    )
    sim = Simulation(
        None, protocol, drives=DriveConfig(law="modified-fastsim"), friction_sets={"dry": truth}
    )
    rec, _ = synthetic_recording(sim.run(), seed=3)
    path = tmp_path / "law.tdms"
    write_recording(rec, path)
    out = tmp_path / "cal"
    result = runner.invoke(
        app,
        ["calibrate", str(path), "--law", "modified-fastsim", "--free", "fastsim.k0",
         "--out", str(out)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    text = _flat(result.output)
    assert "modified-fastsim creep law" in text and "fastsim.k0" in text
    doc = json.loads((out / "calibration.json").read_text())
    assert doc["law"] == "modified-fastsim"
    assert doc["provenance"]["parameters"]["law"] == "modified-fastsim"
    k0 = doc["parameters"]["fastsim.k0"]
    assert abs(k0["value"] - 0.6) <= 4.0 * k0["standard_error"], k0
