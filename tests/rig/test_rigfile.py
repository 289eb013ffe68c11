"""The rig file: entries with value, unit and provenance; units; every problem in one format.

Reference values: Kayaalp's dissertation (model-parameter table of section 4.5.1.5, Table 1).
"""

from __future__ import annotations

import math
import tomllib
from importlib import resources

import pytest

from rollerrig._validation import ParameterError
from rollerrig.rig.parameters import RigFileError, default_rig, load_rig, save_rig

DEFAULT_TEXT = resources.files("rollerrig.rig").joinpath("data/default_rig.toml").read_text("utf-8")


def _write(tmp_path, text: str):
    path = tmp_path / "rig.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _replace(old: str, new: str) -> str:
    assert DEFAULT_TEXT.count(old) == 1, old
    return DEFAULT_TEXT.replace(old, new)


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
    assert default_rig().pmsm.rated_speed == pytest.approx(650 * 2 * math.pi / 60, rel=1e-15)


@pytest.mark.parametrize(
    ("old", "new", "line"),
    [
        (
            "pmsm_stator = {",
            "pmsm_statr = {",
            "inertia.pmsm_statr: unknown key (did you mean 'pmsm_stator'?); allowed "
            "'pmsm_stator', 'pmsm_rotor', 'wheel_disc', 'wheel_tyre', 'roller', 'am_rotor', "
            "'am_stator'",
        ),
        (
            'roller = { value = 45.0, unit = "kg.m^2", source = "Kayaalp 4.5.1.5 (J5)" }\n',
            "",
            "inertia.roller: missing key",
        ),
        (
            'value = 348.0, unit = "mm"',
            'value = 348.0, unit = "inch"',
            "geometry.wheel_radius_x.unit: unit not accepted for length [m]; allowed 'm', 'mm', "
            "'um' (also written 'µm', 'μm'); got 'inch'",
        ),
        (
            'value = 3.0, unit = "kg.m^2"',
            'value = nan, unit = "kg.m^2"',
            "inertia.pmsm_stator: must be finite [kg.m^2]; allowed (0, inf); got nan",
        ),
        (
            'value = 45.0, unit = "kg.m^2"',
            'value = -45.0, unit = "kg.m^2"',
            "inertia.roller: must be > 0 [kg.m^2]; allowed (0, inf); got -45",
        ),
        (
            'value = 43.5, unit = "kN.m/rad"',
            'value = -43.5, unit = "kN.m/rad"',
            "stiffness.roller_shaft: must be > 0 [N.m/rad]; allowed (0, inf); "
            "got -43500 (written -43.5 kN.m/rad)",
        ),
        (
            'value = 0.3, unit = "1"',
            'value = 0.6, unit = "1"',
            "material.poisson: must be < 0.5; allowed (0, 0.5); got 0.6",
        ),
        (
            'value = 0.95, unit = "kg.m^2"',
            'value = "heavy", unit = "kg.m^2"',
            "inertia.pmsm_rotor: must be a number [kg.m^2]; got 'heavy'",
        ),
        (
            'value = 22, unit = "1"',
            'value = 22.5, unit = "1"',
            "pmsm.pole_pairs: must be an integer; got 22.5",
        ),
        (
            'value = 1.0, unit = "N.m.s/rad", source = "Kayaalp 4.5.1.5 (b23)"',
            'value = 1.0, unit = "N.m.s/rad"',
            "damping.wheel_shaft: needs exactly one of 'source' or 'assumption'; got none",
        ),
        (
            'value = 1.0, unit = "N.m.s/rad", source = "Kayaalp 4.5.1.5 (b23)"',
            'value = 1.0, unit = "N.m.s/rad", source = "a", assumption = "b"',
            "damping.wheel_shaft: needs exactly one of 'source' or 'assumption'; "
            "got ['source', 'assumption']",
        ),
        (
            'value = 1.0, unit = "N.m.s/rad", source = "Kayaalp 4.5.1.5 (b23)"',
            'value = 1.0, unit = "N.m.s/rad", sourc = "a"',
            "damping.wheel_shaft.sourc: unknown key (did you mean 'source'?); allowed 'value', "
            "'unit', 'source', 'assumption'",
        ),
        (
            'value = 1.0, unit = "N.m.s/rad", source = "Kayaalp 4.5.1.5 (b23)"',
            'value = 1.0, unit = "N.m.s/rad", source = "  "',
            "damping.wheel_shaft.source: must not be blank",
        ),
        (
            'pmsm_rotor = { value = 0.95, unit = "kg.m^2", source = "Kayaalp 4.5.1.5 (J2)" }',
            "pmsm_rotor = 0.95",
            "inertia.pmsm_rotor: must be an inline table { value = ..., unit = ..., "
            "source | assumption = ... }; got 0.95",
        ),
        (
            'value = "delta"',
            'value = "zigzag"',
            "induction_motor.connection: not one of the allowed values; allowed 'delta' or "
            "'star'; got 'zigzag'",
        ),
        ("[sensors]", "[sensor]", "sensors: missing section"),
        (
            "[sensors]",
            "[sensor]",
            "sensor: unknown section (did you mean 'sensors'?); allowed 'meta', 'inertia', "
            "'stiffness', 'damping', 'geometry', 'material', 'bearing', 'pmsm', "
            "'induction_motor', 'servo_roller_drive', 'sensors', 'frame', 'roller_drive_vf', 'arm'",
        ),
        (
            'value = 2.75, unit = "1/s"',
            'value = 2e4, unit = "1/s"',
            "induction_motor.response_lag_clp: c_lp·Δt = 2 must be <= 1 (the filter weight of "
            "Kayaalp eq. 4.29, Δt = response_lag_reference_step) [1/s]; allowed (0, 10000]; "
            "got 20000",
        ),
        (
            'value = 244.0, unit = "A"',
            'value = 24.0, unit = "A"',
            "pmsm.max_current: must be >= rated_current [A]; allowed [122, inf); got 24",
        ),
        (
            'encoder_quadrature_factor = { value = 4, unit = "1"',
            'encoder_quadrature_factor = { value = 3, unit = "1"',
            "sensors.encoder_quadrature_factor: not a quadrature factor; allowed 1, 2, 4; got 3",
        ),
        (
            'name = "pardubice-tram-roller-rig"',
            "name = 3",
            "meta.name: must be a string; got 3",
        ),
    ],
)
def test_file_errors_name_file_key_unit_and_range(tmp_path, old, new, line):
    # One format for every user file: <file>: <dotted key>: <what> [<unit>]; allowed ...; got ...
    path = _write(tmp_path, _replace(old, new))
    with pytest.raises(RigFileError) as info:
        load_rig(path)
    assert f"{path}: {line}" in info.value.problems
    assert str(info.value) == "\n".join(info.value.problems)
    assert isinstance(info.value, ParameterError)


def test_unit_aliases_are_accepted_and_kept_as_written(tmp_path):
    # One unit registry: the spellings a channel map accepts are accepted in a rig file too.
    path = _write(tmp_path, _replace('unit = "kN.m/rad"', 'unit = "kNm/rad"'))
    rig = load_rig(path)
    assert rig.stiffness.roller_shaft == 43500.0
    assert rig.provenance["stiffness.roller_shaft"]["unit"] == "kNm/rad"
    out = tmp_path / "again.toml"
    save_rig(rig, out)
    assert 'value = 43.5, unit = "kNm/rad"' in out.read_text(encoding="utf-8")
    assert load_rig(out) == rig


def test_all_problems_reported_at_once(tmp_path):
    text = _replace('value = 0.3, unit = "1"', 'value = 0.6, unit = "1"')
    text = text.replace('value = 348.0, unit = "mm"', 'value = 348.0, unit = "ft"')
    with pytest.raises(RigFileError) as info:
        load_rig(_write(tmp_path, text))
    assert [p.split(": ")[1] for p in info.value.problems] == [
        "geometry.wheel_radius_x.unit",
        "material.poisson",
    ]


def test_a_name_with_a_del_character_survives_save_and_load(tmp_path):
    # TOML forbids a raw DEL (U+007F) in a string; the rig writer escapes it as the protocol
    # writer does (one toml_string for both).
    from rollerrig.rig.parameters import default_rig, load_rig, save_rig

    rig = default_rig().with_overrides({"meta.name": "rig" + chr(0x7F) + "x"})
    save_rig(rig, tmp_path / "rig.toml")
    assert load_rig(tmp_path / "rig.toml").meta.name == "rig\x7fx"


@pytest.mark.parametrize("content", [b"\xff\xfe[meta]\n", bytes(range(256)), b""])
def test_a_binary_or_empty_rig_file_is_a_rig_file_error(tmp_path, content):
    path = tmp_path / "rig.toml"
    path.write_bytes(content)
    with pytest.raises(RigFileError, match=r"rig\.toml"):
        load_rig(path)
