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
    # Each value is SI in the unit of its quantity, and its description says that unit.
    for section, model in SECTIONS.items():
        if model is MetaParameters:
            continue
        for key, field in model.model_fields.items():
            assert quantity_of(field) in QUANTITIES, f"{section}.{key}"
            assert field.description, f"{section}.{key}"
            if typing.get_origin(field.annotation) is not typing.Literal:
                assert f"[{si_unit_of(field)}]" in field.description, f"{section}.{key}"


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
