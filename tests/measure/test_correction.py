"""Dynamics correction of the rig's CoA, against the twin's true contact CoA.

Reference: the roller's equation of motion F_x r_r = T56 + J5 α5 + R05 (DESIGN.md §3), which
the twin satisfies exactly (tests/rig/test_model.py); here it is applied to what the rig
measures (torque sensor, encoder speed) and compared with the twin's true CoA.
"""

import numpy as np
import pytest

from rollerrig.measure.correction import corrected_adhesion
from rollerrig.measure.quantities import derive_quantities
from rollerrig.recordings.synthetic import DisturbanceModel, synthetic_recording
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation


@pytest.fixture(scope="module")
def measured():
    rig = default_rig()
    ds = Simulation(experiment="seed-30kmh-dry", output_rate=1000.0).run()
    rec, truth = synthetic_recording(ds, disturbances=DisturbanceModel(), sample_rate=250.0)
    return rig, derive_quantities(rec, rig), truth


def test_correction_brings_the_rig_coa_to_the_contact_coa(measured):
    rig, rec, truth = measured
    b = rig.bearing
    coa, _ = corrected_adhesion(
        rec["torque"],
        rec["roller_speed"],
        rec["normal_load"],
        rec.sample_rate,
        roller_radius=rig.geometry.roller_radius_x,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        regularisation_speed=b.regularisation_speed,
        load_transfer=rig.arm.transfer_ratio,
        dead_weight=rig.arm.dead_weight,
    )
    true = truth["coa"].values
    raw_error = np.sqrt(np.mean((rec["coa"] - true) ** 2))
    corrected_error = np.sqrt(np.mean((coa - true) ** 2))
    # Measured on the default rig's dry test with the default disturbances: 0.038 -> 0.0089.
    assert corrected_error < 0.012
    assert corrected_error < raw_error / 3


def test_constant_speed_adds_only_the_bearing_loss():
    n = np.full(1000, 1e4)
    coa, alpha = corrected_adhesion(
        np.full(1000, 100.0),
        np.full(1000, 20.0),
        n,
        250.0,
        roller_radius=0.5,
        roller_inertia=45.0,
        bearing_friction=0.007,
        bearing_radius=0.065,
        roller_weight=5000.0,
    )
    np.testing.assert_allclose(alpha, 0.0, atol=1e-9)
    # (100 + 0.007·0.065·15000·tanh(400)) / (0.5·1e4)
    np.testing.assert_allclose(coa, (100 + 0.007 * 0.065 * 15000) / 5000, rtol=1e-9)


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("bearing_friction", float("nan"), "bearing_friction must be finite"),  # all CoA NaN
        ("bearing_friction", -0.5, "bearing_friction must be >= 0"),  # CoA -0.066
        ("roller_weight", -1e7, "roller_weight must be >= 0"),  # CoA -0.96
        ("regularisation_speed", 0.0, "regularisation_speed must be > 0"),
        ("bearing_radius", float("inf"), "bearing_radius must be finite"),
    ],
)
def test_bearing_parameters_that_make_no_bearing_are_refused(key, value, message):
    from rollerrig._validation import ParameterError
    from rollerrig.measure.correction import correction_terms

    kwargs = {
        "roller_radius": 0.5, "roller_inertia": 45.0, "bearing_friction": 0.007,
        "bearing_radius": 0.065, "roller_weight": 5000.0, key: value,
    }  # fmt: skip
    with pytest.raises(ParameterError, match=message):
        correction_terms(np.full(500, 100.0), np.full(500, 20.0), np.full(500, 1e4), 250.0,
                         **kwargs)  # fmt: skip
