"""Calibration with the creep law as a choice (issue 19, point 2): a recording the twin made
with the modified FASTSIM and a parameter set the calibration is not told, fitted with that
law's ``fastsim.*`` keys; the result names the law and reproduces with it.

Measured on this test (seed 4, 7.5 s, the rig known; k0 and μ0 free with the two nuisance
parameters): k0 = 0.6012 ± 0.0020 for 0.6 (+0.62 standard errors), μ0 = 0.51967 ± 0.00054 for
0.52 (−0.60), 2 iterations, 127 simulations, 6.6 s (Polach's law on the same test with k_A and
μ0 free: 103 simulations, 5.0 s).
"""

import dataclasses

import numpy as np
import pytest

from rollerrig.calibrate import (
    CALIBRATED_RIG_NAME,
    CALIBRATION_JSON_NAME,
    calibrate,
    read_calibration,
    write_calibration,
)
from rollerrig.calibrate.problem import friction_parameters
from rollerrig.contact.laws import FastsimParameters
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation

from .conftest import TRUTH, make_recording, short_test

LAW = "modified-fastsim"
START = friction_parameters("dry", LAW)  # mu0, A, B of Polach's dry set; k0, alpha, beta E's
TRUE_LAW = dataclasses.replace(START, static_friction=0.52, k0=0.60)
FREE = ["fastsim.k0", "fastsim.static_friction"]


@pytest.fixture(scope="module")
def rig():
    return default_rig().with_overrides(TRUTH)


@pytest.fixture(scope="module")
def calibration(rig):
    rec, _ = make_recording(seed=4, friction=TRUE_LAW, law=LAW)
    return calibrate(rec, FREE, rig=rig, law=LAW)


def test_the_modified_fastsim_parameters_are_recovered_within_their_standard_errors(
    calibration,
):
    # Coverage-like: one fit, two parameters, 3 standard errors (it fails for about 1 fit in
    # 200 if the stated errors are honest); the start was 10 % (k0) and 6 % (mu0) off.
    assert calibration.valid and calibration.law == LAW
    for key in FREE:
        true = getattr(TRUE_LAW, key.partition(".")[2])
        p = calibration.parameters[key]
        assert p.identified, key
        assert abs(p.value - true) <= 3.0 * p.standard_error, (key, p.value, p.standard_error)
        # The recording's own precision; the total adds the load sensor's classes, which move
        # k0 by 1.4-1.7 % each (2026-12-03: statistical 0.33 %, total 2.2 %).
        assert 0.0 < p.standard_error_statistical < 0.01 * true, key


def test_the_result_names_the_law_and_its_fitted_parameters(calibration, tmp_path):
    doc = calibration.to_json()
    assert doc["law"] == LAW and doc["friction"]["law"] == LAW
    assert doc["experiment"]["drives"]["law"] == LAW
    for key in FREE:
        entry = doc["parameters"][key]
        assert entry["value"] == calibration.parameters[key].value
        assert entry["standard_error"] > 0 and key in doc["covariance"]["keys"]
    # The friction law of the result: the fitted values in the law's own set.
    assert isinstance(calibration.friction, FastsimParameters)
    assert calibration.friction.k0 == calibration.parameters["fastsim.k0"].value
    assert calibration.friction.beta == START.beta  # not free: kept
    assert doc["fit"]["finite_difference_step_z_law"] == {k: 3e-4 for k in FREE}
    text = repr(calibration)
    assert f"creep law {LAW}" in text and "fastsim.k0: 0.60" in text

    paths = write_calibration(calibration, tmp_path)
    assert {p.name for p in paths} >= {CALIBRATION_JSON_NAME, CALIBRATED_RIG_NAME}
    back = read_calibration(tmp_path / CALIBRATION_JSON_NAME)
    assert back["law"] == LAW and set(back["values"]) == set(FREE)
    rig_text = (tmp_path / CALIBRATED_RIG_NAME).read_text(encoding="utf-8")
    assert "fastsim" not in rig_text  # the law is not a rig key


def test_the_calibrated_twin_reproduces_the_truth_with_the_same_law(calibration, rig):
    def force(friction):
        sim = Simulation(
            rig,
            short_test(),
            drives=DriveConfig(law=calibration.law),
            friction_sets={"dry": friction},
        )
        return sim.run()["contact_force"].values

    truth = force(TRUE_LAW)
    rms_start = float(np.sqrt(np.mean((force(START) - truth) ** 2)))
    rms_fitted = float(np.sqrt(np.mean((force(calibration.friction) - truth) ** 2)))
    # The load is fitted too (4291 N where the recording's was 4300 N: μN is what the
    # saturated force fixes), and this twin runs at 4300 N: 0.146 N RMS of a 2 kN force
    # against 1.64 N from the start (2026-12-03).
    assert rms_fitted < 0.1 * rms_start, (rms_fitted, rms_start)
