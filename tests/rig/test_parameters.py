"""Rig parameter sets: load, save, round trip, overrides with provenance.

Reference values: Kayaalp's dissertation (section 4.5.1.5).
"""

from __future__ import annotations

import pytest

from rollerrig.rig.parameters import RigFileError, RigParameters, default_rig, load_rig, save_rig


def test_to_dict_is_plain_si():
    d = default_rig().to_dict()
    assert d["stiffness"]["roller_shaft"] == 43500.0
    assert d["geometry"]["roller_radius_y"] == 1.89
    assert "provenance" not in d
    assert "provenance" in default_rig().to_dict(include_provenance=True)


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


def test_missing_file(tmp_path):
    with pytest.raises(RigFileError) as info:
        load_rig(tmp_path / "nope.toml")
    assert str(info.value) == f"{tmp_path / 'nope.toml'}: rig file not found"


def test_invalid_toml(tmp_path):
    path = tmp_path / "rig.toml"
    path.write_text("[inertia\n", encoding="utf-8")
    with pytest.raises(RigFileError) as info:
        load_rig(path)
    assert str(info.value).startswith(f"{path}: not valid TOML: ")


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
    ("overrides", "line"),
    [
        (
            {"stiffness.roler_shaft": 1.0},
            "stiffness.roler_shaft: unknown key in [stiffness]; allowed 'pmsm_mount', "
            "'wheel_shaft', 'wheel_rubber', 'roller_shaft', 'am_mount'; got 'roler_shaft'",
        ),
        ({"stiffnes.roller_shaft": 1.0}, "stiffnes.roller_shaft: unknown section"),
        ({"inertia.roller": -1.0}, "inertia.roller: must be > 0 [kg.m^2]; allowed (0, inf)"),
        ({"material.poisson": 0.6}, "material.poisson: must be < 0.5; allowed (0, 0.5); got 0.6"),
        (
            {"inertia.roller": (45.0, "lb.ft^2")},
            "inertia.roller.unit: unit not accepted for inertia [kg.m^2]",
        ),
        ({"inertia.roller": float("nan")}, "inertia.roller: must be finite [kg.m^2]"),
        ({"pmsm.pole_pairs": 2.5}, "pmsm.pole_pairs: must be an integer; got 2.5"),
        ({"meta.name": 3}, "meta.name: must be a string; got 3"),
        ({"inertia.roller": (1, 2, 3)}, "inertia.roller: give a number (SI) or a (value, unit)"),
        (
            {"stiffness.roller_shaft": (-63.5, "kN.m/rad")},
            "stiffness.roller_shaft: must be > 0 [N.m/rad]; allowed (0, inf); "
            "got -63500 (written -63.5 kN.m/rad)",
        ),
    ],
)
def test_with_overrides_errors(overrides, line):
    with pytest.raises(RigFileError) as info:
        default_rig().with_overrides(overrides)
    assert str(info.value).startswith(f"overrides: {line}")


def test_with_overrides_refuses_what_is_not_a_mapping():
    import re

    with pytest.raises(RigFileError, match=re.escape("overrides: must be a mapping")):
        default_rig().with_overrides([("stiffness.roller_shaft", 1.0)])
