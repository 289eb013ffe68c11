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


# --------------------------------------------------------------------------------------------
# The creep law as a choice (issue 19, point 2)
# --------------------------------------------------------------------------------------------


def test_each_law_s_keys_are_its_parameter_set_s_fields():
    import dataclasses

    from rollerrig.calibrate.problem import FASTSIM_KEYS, law_keys
    from rollerrig.contact.creep import PolachParameters
    from rollerrig.contact.laws import FastsimParameters

    def fields(cls):
        return [f.name for f in dataclasses.fields(cls) if f.name not in ("name", "source")]

    assert [k.partition(".")[2] for k in law_keys("polach")] == fields(PolachParameters)
    assert [k.partition(".")[2] for k in law_keys("modified-fastsim")] == fields(FastsimParameters)
    # FASTSIM and FaStrip read no slope reduction: mu0, A, B only.
    assert law_keys("fastsim") == law_keys("fastrip") == FASTSIM_KEYS[:3]
    keys = free_parameter_catalogue(law="modified-fastsim")
    assert "fastsim.k0" in keys and not any(k.startswith("polach.") for k in keys)
    assert "stiffness.roller_shaft" in keys


def test_fastsim_keys_start_from_the_law_s_set_within_its_ranges():
    from rollerrig.calibrate.problem import FASTSIM_KEYS, friction_parameters
    from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM as E

    start = friction_parameters("wet", "modified-fastsim")  # mu0, A, B of Polach's wet set
    params = {p.key: p for p in free_parameters(FASTSIM_KEYS, default_rig(), start,
                                                law="modified-fastsim")}  # fmt: skip
    assert params["fastsim.static_friction"].initial == 0.3  # Polach (2005) wet
    assert params["fastsim.k0"].initial == E.k0
    assert params["fastsim.alpha_inf"].initial == E.alpha_inf
    assert params["fastsim.beta"].initial == E.beta
    assert params["fastsim.friction_decay"].unit == "s/m"
    for key, upper in (("fastsim.k0", 1.0), ("fastsim.alpha_inf", 1.0), ("fastsim.beta", None)):
        assert (params[key].lower, params[key].upper, params[key].kind) == (0.0, upper, "fastsim")
    # A named FASTSIM-family set is taken as it is.
    assert friction_parameters("eurosprinter-modified-fastsim", "modified-fastsim") == E


@pytest.mark.parametrize(
    ("keys", "law", "named", "other_law"),
    [
        (
            ["polach.static_friction", "polach.k_slip"],
            "modified-fastsim",
            "'polach.static_friction' (did you mean 'fastsim.static_friction'?), 'polach.k_slip'",
            "'polach'",
        ),
        (["fastsim.k0"], "polach", "'fastsim.k0'", "'modified-fastsim'"),
        (["fastsim.beta"], "fastsim", "'fastsim.beta'", "'modified-fastsim'"),
    ],
)
def test_a_key_of_another_law_is_one_error_naming_the_law_s_keys(keys, law, named, other_law):
    from rollerrig.calibrate.problem import friction_parameters, law_keys

    with pytest.raises(CalibrationError) as err:
        free_parameters(["stiffness.roller_shaft", *keys], default_rig(),
                        friction_parameters("dry", law), law=law)  # fmt: skip
    text = str(err.value)
    assert text.startswith(f"free parameter(s) {named}: not ")
    assert f"of the creep law {law!r}, whose keys are {', '.join(law_keys(law))}" in text
    assert f"of the law {other_law} (choose it with --law or law=...)" in text
    assert "stiffness.roller_shaft" not in text  # only what is wrong


def test_polach_s_law_refuses_a_set_without_k_a_and_an_unknown_law_is_named():
    from rollerrig.calibrate.problem import friction_parameters
    from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM

    with pytest.raises(CalibrationError, match="needs Polach's k_A, k_S"):
        friction_parameters(EUROSPRINTER_MODIFIED_FASTSIM, "polach")
    with pytest.raises(CalibrationError, match="did you mean 'modified-fastsim'"):
        free_parameter_catalogue(law="modified-fastsm")
