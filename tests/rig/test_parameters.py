"""Rig parameter files: format, provenance, unit conversion, errors, round trip.

Reference values: Kayaalp's dissertation (model-parameter table of section 4.5.1.5, Table 1,
Table 2); DESIGN.md §2 restates them.
"""

from __future__ import annotations

import math
import tomllib
from importlib import resources

import pytest

from rollerrig._validation import ParameterError
from rollerrig.rig.parameters import (
    UNITS,
    RigFileError,
    RigParameters,
    default_rig,
    load_rig,
    save_rig,
)

DEFAULT_TEXT = resources.files("rollerrig.rig").joinpath("data/default_rig.toml").read_text("utf-8")


def _write(tmp_path, text: str):
    path = tmp_path / "rig.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _replace(old: str, new: str) -> str:
    assert DEFAULT_TEXT.count(old) == 1, old
    return DEFAULT_TEXT.replace(old, new)


# ---- the bundled default ------------------------------------------------------------------


def test_default_rig_values_match_kayaalp_4_5_1_5():
    # Kayaalp 4.5.1.5 (J1..J7, k, b, radii, ν, f_g, W_r), Tables 1-2, section 4.1.3.
    rig = default_rig()
    assert [
        rig.inertia.pmsm_stator,
        rig.inertia.pmsm_rotor,
        rig.inertia.wheel_disc,
        rig.inertia.wheel_tyre,
        rig.inertia.roller,
        rig.inertia.am_rotor,
        rig.inertia.am_stator,
    ] == [3.0, 0.95, 5.1, 11.6, 45.0, 6.6, 35.0]
    s = rig.stiffness
    assert [s.pmsm_mount, s.wheel_shaft, s.wheel_rubber, s.roller_shaft, s.am_mount] == [
        5e5,
        3.85e5,
        3.70e5,
        0.435e5,
        5e5,
    ]
    d = rig.damping
    assert [d.pmsm_mount, d.wheel_shaft, d.wheel_rubber, d.roller_shaft, d.am_mount] == [
        1e5,
        1.0,
        1e3,
        1.0,
        1e5,
    ]
    g = rig.geometry
    assert (g.wheel_radius_x, g.wheel_radius_y, g.roller_radius_x, g.roller_radius_y) == (
        0.348,
        0.291,
        0.452,
        1.890,
    )
    assert rig.material.youngs_modulus == 210e9
    assert rig.material.poisson == 0.3
    assert rig.bearing.friction_coefficient == 0.007
    assert rig.bearing.roller_subsystem_weight == 5000.0
    assert rig.pmsm.rated_power == 58e3
    assert rig.pmsm.rated_speed == pytest.approx(650 * 2 * math.pi / 60, rel=1e-15)
    assert (rig.pmsm.rated_torque, rig.pmsm.rated_current, rig.pmsm.flux_linkage) == (
        852.0,
        122.0,
        0.2,
    )
    assert rig.pmsm.pole_pairs == 22
    im = rig.induction_motor
    assert (im.rated_power, im.rated_frequency, im.rated_torque, im.rated_current) == (
        55e3,
        50.0,
        891.0,
        133.0,
    )
    assert (im.rated_line_voltage, im.connection, im.pole_pairs) == (380.0, "delta", 5)
    assert im.response_lag_clp == 2.75
    assert rig.sensors.daq_rate == 250.0


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


def test_every_value_has_unit_and_exactly_one_provenance():
    data = tomllib.loads(DEFAULT_TEXT)
    count = 0
    for section, table in data.items():
        if section == "meta":
            assert set(table) == {"name", "description"}
            continue
        for key, entry in table.items():
            assert isinstance(entry, dict), f"{section}.{key}"
            assert isinstance(entry.get("unit"), str) and entry["unit"], f"{section}.{key}"
            kinds = [k for k in ("source", "assumption") if k in entry]
            assert len(kinds) == 1, f"{section}.{key}: {kinds}"
            assert entry[kinds[0]].strip(), f"{section}.{key}"
            count += 1
    rig = default_rig()
    assert len(rig.provenance) == count
    assert rig.provenance["inertia.roller"] == {
        "value": 45.0,
        "unit": "kg.m^2",
        "source": "Kayaalp 4.5.1.5 (J5)",
    }
    assert "assumption" in rig.provenance["bearing.wheel_bearing_radius"]


def test_to_dict_is_plain_si():
    d = default_rig().to_dict()
    assert d["stiffness"]["roller_shaft"] == 43500.0
    assert d["geometry"]["roller_radius_y"] == 1.89
    assert "provenance" not in d
    assert "provenance" in default_rig().to_dict(include_provenance=True)


def test_models_are_frozen():
    rig = default_rig()
    with pytest.raises(Exception):  # noqa: B017 - pydantic's ValidationError on frozen assignment
        rig.inertia.roller = 1.0


# ---- round trip ---------------------------------------------------------------------------


def test_round_trip_default(tmp_path):
    path = tmp_path / "out.toml"
    save_rig(default_rig(), path)
    again = load_rig(path)
    assert again == default_rig()
    assert again.provenance == default_rig().provenance


def test_round_trip_with_overrides(tmp_path):
    rig = default_rig().with_overrides(
        {"stiffness.roller_shaft": (63.5, "kN.m/rad"), "pmsm.rated_speed": 70.0, "meta.name": "x"}
    )
    path = tmp_path / "out.toml"
    save_rig(rig, path)
    assert load_rig(path) == rig


def test_save_refuses_to_overwrite(tmp_path):
    path = tmp_path / "out.toml"
    path.write_text("keep me")
    with pytest.raises(FileExistsError):
        save_rig(default_rig(), path)
    assert path.read_text() == "keep me"
    save_rig(default_rig(), path, overwrite=True)
    assert load_rig(path) == default_rig()
    assert [p.name for p in tmp_path.iterdir()] == ["out.toml"]  # no temporary left behind


# ---- units --------------------------------------------------------------------------------


def test_unit_conversion_kn_m_per_rad(tmp_path):
    # Kayaalp 4.5.1.7: the shaft sweep starts at 43500 N.m/rad.
    path = _write(
        tmp_path,
        _replace('value = 43.5, unit = "kN.m/rad"', 'value = 43500, unit = "N.m/rad"'),
    )
    assert load_rig(path).stiffness.roller_shaft == 43500.0
    assert default_rig().stiffness.roller_shaft == 43500.0  # written as 43.5 kN.m/rad


@pytest.mark.parametrize(
    ("old", "new", "getter", "expected"),
    [
        (
            'value = 348.0, unit = "mm"',
            'value = 0.348, unit = "m"',
            "geometry.wheel_radius_x",
            0.348,
        ),
        ('value = 650.0, unit = "rpm"', 'value = 68.0, unit = "rad/s"', "pmsm.rated_speed", 68.0),
        ('value = 58.0, unit = "kW"', 'value = 58000, unit = "W"', "pmsm.rated_power", 58e3),
        (
            'value = 210.0, unit = "GPa"',
            'value = 2100, unit = "bar"',
            "material.youngs_modulus",
            2.1e8,
        ),
        (
            'inductance_d = { value = 0.5, unit = "mH"',
            'inductance_d = { value = 5e-4, unit = "H"',
            "pmsm.inductance_d",
            5e-4,
        ),
        (
            'value = 2.0, unit = "ms"',
            'value = 0.002, unit = "s"',
            "servo_roller_drive.torque_time_constant",
            2e-3,
        ),
        (
            'value = 5000.0, unit = "N"',
            'value = 5, unit = "kN"',
            "bearing.roller_subsystem_weight",
            5e3,
        ),
    ],
)
def test_unit_conversions(tmp_path, old, new, getter, expected):
    rig = load_rig(_write(tmp_path, _replace(old, new)))
    section, key = getter.split(".")
    assert getattr(getattr(rig, section), key) == pytest.approx(expected, rel=1e-15)


def test_hz_bandwidth_is_angular():
    # A bandwidth given in Hz is stored as an angular frequency: 5 Hz -> 2π·5 rad/s.
    assert default_rig().servo_roller_drive.speed_bandwidth == pytest.approx(2 * math.pi * 5)
    assert UNITS["angular_speed"]["rpm"] == pytest.approx(2 * math.pi / 60)


# ---- errors -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("old", "new", "named", "says"),
    [
        ("pmsm_stator = {", "pmsm_statr = {", "inertia.pmsm_statr", "unknown key"),
        (
            'roller = { value = 45.0, unit = "kg.m^2", source = "Kayaalp 4.5.1.5 (J5)" }\n',
            "",
            "inertia.roller",
            "missing key",
        ),
        (
            'value = 348.0, unit = "mm"',
            'value = 348.0, unit = "inch"',
            "geometry.wheel_radius_x",
            "unknown unit",
        ),
        (
            'value = 3.0, unit = "kg.m^2"',
            'value = nan, unit = "kg.m^2"',
            "inertia.pmsm_stator",
            "finite",
        ),
        (
            'value = 45.0, unit = "kg.m^2"',
            'value = -45.0, unit = "kg.m^2"',
            "inertia.roller",
            "greater than 0",
        ),
        ('value = 0.3, unit = "1"', 'value = 0.6, unit = "1"', "material.poisson", "less than 0.5"),
        (
            'value = 0.95, unit = "kg.m^2"',
            'value = "heavy", unit = "kg.m^2"',
            "inertia.pmsm_rotor",
            "must be a number",
        ),
        ('value = 22, unit = "1"', 'value = 22.5, unit = "1"', "pmsm.pole_pairs", "integer"),
        (
            'value = 1.0, unit = "N.m.s/rad", source = "Kayaalp 4.5.1.5 (b23)"',
            'value = 1.0, unit = "N.m.s/rad"',
            "damping.wheel_shaft",
            "exactly one",
        ),
        (
            'value = 1.0, unit = "N.m.s/rad", source = "Kayaalp 4.5.1.5 (b23)"',
            'value = 1.0, unit = "N.m.s/rad", source = "a", assumption = "b"',
            "damping.wheel_shaft",
            "exactly one",
        ),
        ('value = "delta"', 'value = "zigzag"', "induction_motor.connection", "delta"),
        ("[sensors]", "[sensor]", "[sensor]", "unknown section"),
        (
            'value = 2.75, unit = "1/s"',
            'value = 2e4, unit = "1/s"',
            "induction_motor.response_lag_clp",
            "<= 1",
        ),
    ],
)
def test_file_errors_name_the_key(tmp_path, old, new, named, says):
    path = _write(tmp_path, _replace(old, new))
    with pytest.raises(RigFileError) as info:
        load_rig(path)
    message = str(info.value)
    assert named in message
    assert says in message
    assert isinstance(info.value, ParameterError)


def test_missing_file(tmp_path):
    with pytest.raises(RigFileError, match="not found"):
        load_rig(tmp_path / "nope.toml")


def test_invalid_toml(tmp_path):
    with pytest.raises(RigFileError, match="not valid TOML"):
        load_rig(_write(tmp_path, "[inertia\n"))


def test_all_problems_reported_at_once(tmp_path):
    text = _replace('value = 0.3, unit = "1"', 'value = 0.6, unit = "1"')
    text = text.replace('value = 348.0, unit = "mm"', 'value = 348.0, unit = "ft"')
    with pytest.raises(RigFileError) as info:
        load_rig(_write(tmp_path, text))
    assert "material.poisson" in str(info.value)
    assert "geometry.wheel_radius_x" in str(info.value)
    assert len(info.value.problems) == 2


# ---- overrides ----------------------------------------------------------------------------


def test_with_overrides_validates_and_records_provenance():
    rig = default_rig()
    stiffer = rig.with_overrides({"stiffness.roller_shaft": 63.5e3})
    assert stiffer.stiffness.roller_shaft == 63500.0
    assert rig.stiffness.roller_shaft == 43500.0  # original untouched
    record = stiffer.provenance["stiffness.roller_shaft"]
    assert record["unit"] == "N.m/rad"
    assert "override" in record["assumption"] and "43.5 kN.m/rad" in record["assumption"]
    assert "source" not in record
    assert isinstance(stiffer, RigParameters)


@pytest.mark.parametrize(
    ("overrides", "named"),
    [
        ({"stiffness.roler_shaft": 1.0}, "stiffness.roler_shaft"),
        ({"stiffnes.roller_shaft": 1.0}, "stiffnes.roller_shaft"),
        ({"inertia.roller": -1.0}, "inertia.roller"),
        ({"material.poisson": 0.6}, "material.poisson"),
        ({"inertia.roller": (45.0, "lb.ft^2")}, "inertia.roller"),
        ({"inertia.roller": float("nan")}, "inertia.roller"),
        ({"pmsm.pole_pairs": 2.5}, "pmsm.pole_pairs"),
    ],
)
def test_with_overrides_errors(overrides, named):
    with pytest.raises(RigFileError) as info:
        default_rig().with_overrides(overrides)
    assert named in str(info.value)
