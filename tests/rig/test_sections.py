"""The parameter sections: the bundled default against its sources, derived values, metadata.

Reference values: Kayaalp's dissertation (model-parameter table of section 4.5.1.5, Table 1,
Table 2); DESIGN.md §2 restates them.
"""

from __future__ import annotations

import math
import typing

import pytest

from rollerrig.rig.parameters import default_rig
from rollerrig.rig.sections import SECTIONS, MetaParameters, quantity_of, si_unit_of
from rollerrig.units import QUANTITIES

#: Section -> its values in file order (Kayaalp 4.5.1.5: J1..J7 [kg.m^2], k01..k70 [N.m/rad],
#: b01..b70 [N.m.s/rad], r_wx, r_wy, r_rx, r_ry [m]).
KAYAALP_SECTIONS = {
    "inertia": (3.0, 0.95, 5.1, 11.6, 45.0, 6.6, 35.0),
    "stiffness": (5e5, 3.85e5, 3.70e5, 0.435e5, 5e5),
    "damping": (1e5, 1.0, 1e3, 1.0, 1e5),
    "geometry": (0.348, 0.291, 0.452, 1.890),
}
#: "section.key" -> value [SI]: 4.5.1.5 (E, ν, f_g, W_r), Table 1 (PMSM), Table 2 (AM), 4.1.3.
KAYAALP_VALUES = {
    "material.youngs_modulus": 210e9,
    "material.poisson": 0.3,
    "bearing.friction_coefficient": 0.007,
    "bearing.roller_subsystem_weight": 5000.0,
    "pmsm.rated_power": 58e3,
    "pmsm.rated_torque": 852.0,
    "pmsm.rated_current": 122.0,
    "pmsm.flux_linkage": 0.2,
    "pmsm.pole_pairs": 22,
    "induction_motor.rated_power": 55e3,
    "induction_motor.rated_frequency": 50.0,
    "induction_motor.rated_torque": 891.0,
    "induction_motor.rated_current": 133.0,
    "induction_motor.rated_line_voltage": 380.0,
    "induction_motor.connection": "delta",
    "induction_motor.pole_pairs": 5,
    "induction_motor.response_lag_clp": 2.75,
    "sensors.daq_rate": 250.0,
}


def test_default_rig_values_match_kayaalp_4_5_1_5():
    rig = default_rig()
    for section, values in KAYAALP_SECTIONS.items():
        assert tuple(getattr(rig, section).model_dump().values()) == values, section
    for name, value in KAYAALP_VALUES.items():
        section, key = name.split(".")
        got = getattr(getattr(rig, section), key)
        assert got == value and type(got) is type(value), name
    assert rig.pmsm.rated_speed == pytest.approx(650 * 2 * math.pi / 60, rel=1e-15)  # 650 rpm


def test_default_rig_derived_nameplate_checks():
    rig = default_rig()
    im = rig.induction_motor
    # ω_sync = 2π·50/5; ω_N = P/T = 55e3/891; slip = 1 − ω_N/ω_sync ≈ 1.76 % (DESIGN.md §2).
    assert im.synchronous_speed == pytest.approx(62.8319, rel=1e-5)
    assert im.rated_speed == pytest.approx(61.7284, rel=1e-5)
    assert im.rated_slip == pytest.approx(0.0176, abs=5e-5)
    # PMSM: P = T·ω holds for Table 1 (852 N.m at 650 rpm = 58.0 kW) ...
    assert rig.pmsm.rated_torque * rig.pmsm.rated_speed == pytest.approx(58e3, rel=1e-3)
    # ... but 1.5·p·φ·I_N = 805.2 N.m, not 852 N.m: rated torque needs 129.1 A.
    assert rig.pmsm.torque_constant * rig.pmsm.rated_current == pytest.approx(805.2, rel=1e-12)
    assert rig.pmsm.rated_torque_current == pytest.approx(129.09, abs=0.01)
    assert rig.pmsm.max_current >= rig.pmsm.rated_torque_current
    assert rig.sensors.encoder_counts_per_revolution == 10000


def test_models_are_frozen():
    rig = default_rig()
    with pytest.raises(Exception):  # noqa: B017 - pydantic's ValidationError on frozen assignment
        rig.inertia.roller = 1.0


def test_every_field_states_its_quantity_and_si_unit():
    # Each value is SI in the unit of its quantity, and its description says that unit (the
    # dimensionless unit "1" written [-], the package's one spelling in text).
    for section, model in SECTIONS.items():
        if model is MetaParameters:
            continue
        for key, field in model.model_fields.items():
            assert quantity_of(field) in QUANTITIES, f"{section}.{key}"
            assert field.description, f"{section}.{key}"
            if typing.get_origin(field.annotation) is not typing.Literal:
                unit = si_unit_of(field)
                assert f"[{'-' if unit == '1' else unit}]" in field.description, f"{section}.{key}"


ACCURACY_KEYS = (
    "torque_sensor_accuracy",
    "pressure_sensor_range",
    "pressure_sensor_accuracy",
    "air_spring_area_uncertainty",
    "roller_radius_tolerance",
    "wheel_radius_tolerance",
    "roller_inertia_uncertainty",
    "bearing_loss_uncertainty",
)


def test_sensor_accuracies_default_to_the_bundled_values_so_old_rig_files_load(tmp_path):
    """A rig file written before the accuracy keys existed loads with the bundled values."""
    from importlib import resources

    from rollerrig.rig.parameters import load_rig
    from rollerrig.rig.sections import SensorParameters

    rig = default_rig()
    for key in ACCURACY_KEYS:
        assert SensorParameters.model_fields[key].default == getattr(rig.sensors, key), key
        assert rig.provenance[f"sensors.{key}"]  # with its source or assumption
    # DMP331: 0.35 % of the range (BD SENSORS data sheet), on a 10 bar range
    assert rig.sensors.pressure_sensor_accuracy * rig.sensors.pressure_sensor_range == 3500.0
    text = resources.files("rollerrig.rig").joinpath("data/default_rig.toml").read_text("utf-8")
    old = "\n".join(line for line in text.splitlines() if not line.startswith(ACCURACY_KEYS))
    path = tmp_path / "old-rig.toml"
    path.write_text(old, encoding="utf-8")
    loaded = load_rig(path)
    assert loaded.sensors == rig.sensors


# --------------------------------------------------------------------------------------------
# [roller_drive_vf]: every key has a plausible range checked when the file is read (issue 24,
# point 8: a current limit of 1e-9 ended in the steady-state solver's words)
# --------------------------------------------------------------------------------------------

_VF_KEYS = (
    "boost",
    "ir_compensation",
    "slip_compensation",
    "current_limit",
    "ramp_time",
    "current_filter_time",
    "slip_filter_time",
    "rotor_resistance_estimate",
    "filter_time",
)


def _rig_with_vf(table):
    """(sections, provenance) of the bundled rig file with its [roller_drive_vf] table replaced
    by ``table`` (read as :func:`rollerrig.rig.parameters.load_rig` reads a file)."""
    import tomllib
    from importlib import resources

    from rollerrig.rig.rigfile import read_sections

    text = resources.files("rollerrig.rig").joinpath("data/default_rig.toml").read_text("utf-8")
    data = tomllib.loads(text)
    data["roller_drive_vf"] = table
    return read_sections(data, "rig.toml")


@pytest.mark.parametrize(
    ("key", "value", "unit", "line"),
    [
        (
            "current_limit",
            1e-9,
            "1",
            "rig.toml: roller_drive_vf.current_limit: must be >= 1 "
            "[x induction_motor.rated_current]; allowed [1, 4]; got 1e-09",
        ),
        (
            "current_limit",
            10.0,
            "1",
            "rig.toml: roller_drive_vf.current_limit: must be <= 4 "
            "[x induction_motor.rated_current]; allowed [1, 4]; got 10",
        ),
        (
            "boost",
            3.0,
            "1",
            "rig.toml: roller_drive_vf.boost: must be <= 2.5 [U_0/(R_s.I_N)]; allowed [0, 2.5]; "
            "got 3",
        ),
        (
            "slip_compensation",
            2.0,
            "1",
            "rig.toml: roller_drive_vf.slip_compensation: must be <= 1.5 [x rated slip]; "
            "allowed [0, 1.5]; got 2",
        ),
        (
            "ir_compensation",
            -1.0,
            "1",
            "rig.toml: roller_drive_vf.ir_compensation: must be >= 0; allowed [0, 1]; got -1",
        ),
        (
            "ramp_time",
            1.0,
            "ns",
            "rig.toml: roller_drive_vf.ramp_time: must be >= 0.01 [s]; allowed [0.01, 650]; "
            "got 1e-09 (written 1 ns)",
        ),
        (
            "ramp_time",
            1e300,
            "s",
            "rig.toml: roller_drive_vf.ramp_time: must be <= 650 [s]; allowed [0.01, 650]; "
            "got 1e+300",
        ),
        (
            "slip_filter_time",
            1e-6,
            "s",
            "rig.toml: roller_drive_vf.slip_filter_time: must be 0 (the machine's default) or "
            "at least 1 ms [s]; allowed 0 or [0.001, 10]; got 1e-06",
        ),
        (
            "current_filter_time",
            11.0,
            "s",
            "rig.toml: roller_drive_vf.current_filter_time: must be <= 10 [s]; allowed [0, 10]; "
            "got 11",
        ),
        (
            "rotor_resistance_estimate",
            3.0,
            "1",
            "rig.toml: roller_drive_vf.rotor_resistance_estimate: must be <= 2 [x the "
            "machine's rotor resistance]; allowed [0.5, 2]; got 3",
        ),
    ],
)
def test_every_vf_key_is_checked_against_its_plausible_range(key, value, unit, line):
    from rollerrig.rig.rigfile import RigFileError

    table = {k: {"value": 0.0, "unit": "1", "assumption": "a"} for k in ("ir_compensation",)}
    table[key] = {"value": value, "unit": unit, "assumption": "a"}
    with pytest.raises(RigFileError) as info:
        _rig_with_vf(table)
    assert info.value.problems == [line]


def test_the_vf_defaults_and_range_ends_are_accepted():
    from rollerrig.drives.vf import VF_SETTING_RANGES

    for key, (low, high) in VF_SETTING_RANGES.items():
        if key == "filter_time":  # deprecated: test_the_old_filter_time_is_read_as_both_filters
            continue
        for value in (low, high):
            unit = "s" if key.endswith("time") else "1"
            sections, _ = _rig_with_vf({key: {"value": value, "unit": unit, "source": "x"}})
            assert getattr(sections["roller_drive_vf"], key) == value
    sections, _ = _rig_with_vf({})  # a rig file without the table: the defaults
    assert sections["roller_drive_vf"] == default_rig().roller_drive_vf


def _vf_entries():
    from hypothesis import strategies as st

    number = (
        st.floats(allow_nan=True, allow_infinity=True)
        | st.integers(min_value=-(10**30), max_value=10**30)
        | st.booleans()
        | st.text(max_size=6)
        | st.none()
    )
    unit = st.sampled_from(["1", "s", "ms", "ns", "%", "A", "", "kg"]) | st.text(max_size=6)
    entry = st.fixed_dictionaries(
        {"value": number, "unit": unit},
        optional={"source": st.text(max_size=4), "assumption": st.text(max_size=4)},
    )
    anything = st.recursive(
        number,
        lambda inner: (
            st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3)
        ),
        max_leaves=6,
    )
    keys = st.sampled_from([*_VF_KEYS, "current_limt", ""]) | st.text(max_size=8)
    return st.dictionaries(keys, entry | anything, max_size=6) | anything


def test_any_vf_table_gives_a_rig_or_a_rig_file_error():
    # Property (the settings of tests/test_properties.py): whatever [roller_drive_vf] holds,
    # reading the rig file gives a rig whose V/f settings make a controller, or one
    # RigFileError; never another exception.
    from hypothesis import HealthCheck, given, settings

    from rollerrig.rig.drive_dynamics import default_dq_drive
    from rollerrig.rig.parameters import RigParameters
    from rollerrig.rig.rigfile import RigFileError

    @settings(
        max_examples=80,
        deadline=None,
        database=None,
        derandomize=True,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )
    @given(table=_vf_entries())
    def check(table):
        try:
            sections, provenance = _rig_with_vf(table)
        except RigFileError:
            return
        rig = RigParameters(**sections, provenance=provenance)
        default_dq_drive(rig)  # the settings are within what the controller accepts

    check()


def test_the_two_filters_are_two_keys():
    # The study's variants set only the slip filter: the rig file can say the same.
    sections, _ = _rig_with_vf({"slip_filter_time": {"value": 100.0, "unit": "ms", "source": "x"}})
    options = sections["roller_drive_vf"].options()
    assert options["slip_filter_time"] == pytest.approx(0.1)
    assert options["current_filter_time"] is None  # the machine's default
    assert options["rotor_resistance_estimate"] == 1.0


def test_the_old_filter_time_is_read_as_both_filters():
    from rollerrig.rig.rigfile import RigFileError

    with pytest.warns(FutureWarning, match="filter_time is deprecated"):
        sections, _ = _rig_with_vf({"filter_time": {"value": 0.1, "unit": "s", "source": "x"}})
    options = sections["roller_drive_vf"].options()
    assert options["current_filter_time"] == options["slip_filter_time"] == 0.1
    # with either new key it is ambiguous: one error naming it
    with pytest.raises(RigFileError) as info:
        _rig_with_vf(
            {
                "filter_time": {"value": 0.1, "unit": "s", "source": "x"},
                "slip_filter_time": {"value": 0.2, "unit": "s", "source": "x"},
            }
        )
    assert "roller_drive_vf.filter_time: is the deprecated key" in info.value.problems[0]


def test_the_stator_resistance_says_its_connection():
    # DESIGN.md §3: 1.5-2 % per unit for a 55 kW, 380 V delta machine; the rig's key is per
    # delta phase: base impedance U_line/(I_line/√3) = 380/(133/√3) = 4.949 ohm, so 0.085
    # ohm is 1.72 %; the equivalent star has a third, 0.0283 ohm (base 219.4 V/133 A).
    am = default_rig().induction_motor
    assert am.connection == "delta"
    assert am.stator_resistance == pytest.approx(0.085)
    assert am.equivalent_star_stator_resistance == pytest.approx(0.085 / 3.0, rel=1e-15)
    assert am.stator_resistance_per_unit == pytest.approx(0.085 / 4.949, rel=1e-3)
    assert 0.015 <= am.stator_resistance_per_unit <= 0.02
    assert "per delta phase" in (type(am).model_fields["stator_resistance"].description or "")
