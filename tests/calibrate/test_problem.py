"""The calibration problem: free keys, their bounds and starting values."""

import pytest

from rollerrig.calibrate.problem import (
    POLACH_KEYS,
    CalibrationError,
    free_parameter_catalogue,
    free_parameters,
)
from rollerrig.contact.creep import POLACH_DRY
from rollerrig.rig.parameters import default_rig


def test_catalogue_holds_the_rig_floats_and_the_friction_law():
    keys = free_parameter_catalogue()
    for key in (
        "stiffness.roller_shaft",
        "damping.roller_shaft",
        "induction_motor.response_lag_clp",
        "bearing.friction_coefficient",
        "inertia.roller",
        *POLACH_KEYS,
    ):
        assert key in keys
    # Names, integers and the DAQ are not parameters of the fit.
    for key in ("meta.name", "pmsm.pole_pairs", "sensors.daq_rate", "induction_motor.connection"):
        assert key not in keys
    # Every rig key is one with_overrides accepts.
    rig = default_rig()
    for key in keys:
        if not key.startswith("polach."):
            section, _, name = key.partition(".")
            rig.with_overrides({key: getattr(getattr(rig, section), name)})


def test_free_parameters_bounds_units_and_starting_values():
    params = free_parameters(
        "stiffness.roller_shaft, polach.k_adhesion,induction_motor.breakdown_torque_ratio",
        default_rig(),
        POLACH_DRY,
    )
    by_key = {p.key: p for p in params}
    assert by_key["stiffness.roller_shaft"].unit == "N.m/rad"
    assert by_key["stiffness.roller_shaft"].initial == 43500.0
    assert by_key["polach.k_adhesion"].upper == 1.0  # 0 < kA <= 1 (Polach 2005)
    assert by_key["polach.k_adhesion"].z_upper == pytest.approx(0.0)
    # z = ln(p - p_low): the breakdown torque ratio must stay above 1.
    ratio = by_key["induction_motor.breakdown_torque_ratio"]
    assert ratio.lower == 1.0 and ratio.value(ratio.z_initial) == pytest.approx(2.5)
    assert ratio.value(-5.0) > 1.0


def test_unknown_keys_are_named_with_the_valid_ones():
    with pytest.raises(CalibrationError) as err:
        free_parameters(["inertia.rollr", "sensors.daq_rate"], default_rig(), POLACH_DRY)
    text = str(err.value)
    assert "['inertia.rollr', 'sensors.daq_rate']" in text
    assert "inertia.roller" in text and "polach.static_friction" in text
