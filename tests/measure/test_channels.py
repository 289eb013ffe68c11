"""Channel maps and unit conversion.

Conversion factors are checked against their definitions: 1 rpm = 2π/60 rad/s (one revolution
is 2π rad), 1 bar = 10^5 Pa (BIPM SI Brochure, 9th ed., Table 8), kN/kPa/MPa/mm/µm/ms by the SI
prefixes (SI Brochure, Table 7).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rollerrig.measure.channels import (
    UNIT_FACTORS,
    ChannelMap,
    default_channel_map,
    example_channel_map_path,
    load_channel_map,
    normalize_unit,
    si_factor,
    split_unit_header,
    to_si,
)
from rollerrig.measure.recording import CANONICAL_CHANNELS, RecordingError


@pytest.mark.parametrize(
    ("unit", "si", "factor"),
    [
        ("rpm", "rad/s", 2 * math.pi / 60),
        ("Hz", "rad/s", 2 * math.pi),
        ("rad/s", "rad/s", 1.0),
        ("bar", "Pa", 1e5),
        ("kPa", "Pa", 1e3),
        ("MPa", "Pa", 1e6),
        ("kN", "N", 1e3),
        ("kN.m", "N.m", 1e3),
        ("mm", "m", 1e-3),
        ("um", "m", 1e-6),
        ("µm", "m", 1e-6),
        ("Nm", "N.m", 1.0),
        ("1/min", "rad/s", 2 * math.pi / 60),
        ("ms", "s", 1e-3),
    ],
)
def test_si_factors_follow_definitions(unit, si, factor):
    assert si_factor(unit, si) == pytest.approx(factor, rel=1e-15)


def test_every_canonical_si_unit_has_a_table():
    for si, _meaning in CANONICAL_CHANNELS.values():
        assert UNIT_FACTORS[si][si] == 1.0


def test_to_si_converts_arrays():
    np.testing.assert_allclose(
        to_si([0.0, 30.0, 60.0], "rpm", "rad/s"), [0.0, math.pi, 2 * math.pi]
    )
    np.testing.assert_allclose(to_si([1.5], "bar", "Pa"), [1.5e5])


def test_unit_of_wrong_quantity_is_an_error_listing_allowed_units():
    with pytest.raises(RecordingError, match=r"'bar'.*allowed: \['N.m', 'kN.m'\]"):
        si_factor("bar", "N.m")


def test_normalize_and_split_headers():
    assert normalize_unit("N·m") == "N.m"
    assert split_unit_header("torque [N.m]") == ("torque", "N.m")
    assert split_unit_header("p_air (bar)") == ("p_air", "bar")
    assert split_unit_header("Torque_Roller") == ("Torque_Roller", None)
    assert split_unit_header("[x]") == ("[x]", None)


def test_example_map_loads_and_is_frozen():
    cmap = load_channel_map(example_channel_map_path())
    names = [c.name for c in cmap.channels]
    assert names[:2] == ["torque", "roller_speed"]
    assert cmap.time.column == "Time" and cmap.time.unit == "s"
    speed = cmap.channels[1]
    assert speed.conversion() == ("rad/s", pytest.approx(2 * math.pi / 60))
    assert [e.name for e in cmap.extra] == ["motor_current"]
    assert cmap.extra[0].conversion() == ("A", 1.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cmap.source = "x"  # type: ignore[misc]


def test_to_dict_round_trips():
    cmap = load_channel_map(example_channel_map_path())
    data = cmap.to_dict()
    data.pop("source")
    again = ChannelMap.from_dict(data, source=cmap.source)
    assert again == cmap


def test_scale_offset_and_sample_rate():
    cmap = ChannelMap.from_dict(
        {
            "time": {"sample_rate_Hz": 250},
            "channels": {"torque": {"column": "ai0", "unit": "N.m", "scale": 100.0, "offset": -5}},
        }
    )
    assert cmap.time.sample_rate_Hz == 250.0
    assert (cmap.channels[0].scale, cmap.channels[0].offset) == (100.0, -5.0)


def _map(**channels):
    return {"time": {"column": "t"}, "channels": channels}


@pytest.mark.parametrize(
    ("data", "pattern"),
    [
        (_map(torqe={"column": "T", "unit": "N.m"}), r"'torqe' is not a canonical.*'torque'"),
        (_map(torque={"column": "T", "unit": "bar"}), r"\[channels.torque\].*'bar'"),
        (_map(normal_load={"column": "F", "unit": "lbf"}), r"'lbf'.*allowed: \['N', 'kN'\]"),
        (_map(torque={"column": "T", "unit": "N.m", "scael": 2}), r"'scael'.*'scale'"),
        (_map(torque={"unit": "N.m"}), r"'column'.*required"),
        (_map(torque={"column": "T", "unit": "N.m", "scale": 0}), r"scale must be non-zero"),
        (_map(torque={"column": "T", "unit": "N.m", "scale": "2"}), r"scale must be a number"),
        (_map(torque={"column": "T", "unit": "N.m", "offset": math.nan}), r"must be finite"),
        (_map(), r"maps no channels"),
        ({"time": {"column": "t", "unit": "min"}, "channels": {}}, r"'min' is not a time unit"),
        (
            {"time": {"column": "t", "sample_rate_Hz": 250}, "channels": {}},
            r"either 'column' or 'sample_rate_Hz'",
        ),
        ({"time": {"sample_rate_Hz": -1}, "channels": {}}, r"must be > 0 Hz"),
        ({"time": {"column": "t"}, "chanels": {}}, r"unknown key.*'chanels'.*'channels'"),
        ({"extra": {"torque": {"column": "T", "unit": "N.m"}}}, r"is canonical"),
        ({"extra": {"current": {"column": "I"}}}, r"\[extra.current\].*explicit 'unit'"),
    ],
)
def test_invalid_maps_are_rejected(data, pattern):
    with pytest.raises(RecordingError, match=pattern):
        ChannelMap.from_dict(data)


def test_missing_map_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="channel map file not found"):
        load_channel_map(tmp_path / "nope.toml")


def test_invalid_toml_names_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[channels.torque\ncolumn = 1\n")
    with pytest.raises(RecordingError, match=r"bad.toml: not valid TOML"):
        load_channel_map(bad)


def test_errors_from_a_file_name_the_file(tmp_path):
    f = tmp_path / "map.toml"
    f.write_text('[channels.torque]\ncolumn = "T"\nunit = "psi"\n')
    with pytest.raises(RecordingError, match=r"map.toml.*\[channels.torque\].*'psi'"):
        load_channel_map(f)


def test_default_map_is_auto():
    cmap = default_channel_map()
    assert cmap.auto and cmap.time.column == "time" and cmap.source == "<default>"


# --------------------------------------------------------------------------- [file], optional


def test_file_section_resample_and_optional_round_trip():
    data = {
        "file": {
            "separator": "\t",
            "decimal": ",",
            "header_row": 5,
            "units_row": 6,
            "data_row": 7,
            "encoding": "latin-1",
            "dayfirst": True,
            "date_format": "%d.%m.%Y %H:%M:%S,%f",
            "group": "Fast",
        },
        "time": {"column": "t", "unit": "ms", "resample_Hz": 1000},
        "channels": {"torque": {"column": "T", "unit": "N.m", "optional": True}},
    }
    cmap = ChannelMap.from_dict(data)
    assert cmap.file.separator == "\t" and cmap.file.units_row == 6 and cmap.file.group == "Fast"
    assert cmap.time.resample_Hz == 1000.0 and cmap.channels[0].optional
    out = cmap.to_dict()
    assert out["file"] == data["file"]
    assert out["time"]["resample_Hz"] == 1000.0 and out["channels"]["torque"]["optional"]
    out.pop("source")
    assert ChannelMap.from_dict(out) == cmap


def test_units_row_false_and_group_index_are_valid():
    cmap = ChannelMap.from_dict(
        {"file": {"units_row": False, "group": 2}, "channels": {"torque": {"column": "T"}}}
    )
    assert cmap.file.units_row is False and cmap.file.group == 2
    assert cmap.to_dict()["file"] == {"units_row": False, "group": 2}


def test_time_unit_not_stated_is_remembered():
    cmap = ChannelMap.from_dict({"time": {"column": "t"}, "channels": {"torque": {"column": "T"}}})
    assert not cmap.time.unit_stated and cmap.time.unit == "s"
    data = cmap.to_dict()
    assert "unit" not in data["time"]
    data.pop("source")
    assert ChannelMap.from_dict(data).time == cmap.time


def _file(**keys):
    return {"file": keys, "channels": {"torque": {"column": "T", "unit": "N.m"}}}


@pytest.mark.parametrize(
    ("data", "pattern"),
    [
        (_file(seperator=";"), r"\[file\]: unknown key.*'seperator'.*did you mean 'separator'"),
        (_file(sep=";"), r"\[file\]: unknown key\(s\) \['sep'\]; allowed: \['data_row'"),
        (_file(separator=";;"), r"file.separator = ';;' is not allowed; allowed: ',' \(comma\)"),
        (_file(separator="tab"), r"file.separator = 'tab' is not allowed.*\(tab\)"),
        (_file(decimal=";"), r"file.decimal = ';' is not allowed; allowed: \['.', ','\]"),
        (_file(separator=",", decimal=","), r"separator and file.decimal are both ','"),
        (_file(header_row=-1), r"file.header_row must be a 0-based line index"),
        (_file(header_row=1.5), r"file.header_row must be a 0-based line index"),
        (_file(header_row=True), r"file.header_row must be a 0-based line index"),
        (_file(units_row=True), r"file.units_row must be a 0-based line index or false"),
        (_file(header_row=3, units_row=2), r"units_row = 2 must come after file.header_row = 3"),
        (_file(header_row=3, data_row=3), r"data_row = 3 must come after the header"),
        (_file(encoding="klingon"), r"file.encoding = 'klingon' is not a known text encoding"),
        (_file(dayfirst="yes"), r"file.dayfirst must be true or false"),
        (_file(date_format="dd.mm.yy"), r"file.date_format must be a strptime format"),
        (_file(group=-1), r"file.group must be a group name or a 0-based group index"),
        (_file(group=""), r"file.group must be a group name"),
        ({"file": ";", "channels": {}}, r"\[file\]: expected a table"),
        (
            {"time": {"column": "t", "resample_Hz": 0}, "channels": {}},
            r"time.resample_Hz must be > 0 Hz",
        ),
        (
            {"time": {"column": "t", "resampl_Hz": 5}, "channels": {}},
            r"unknown key.*'resampl_Hz'.*'resample_Hz'",
        ),
        (
            {"channels": {"torque": {"column": "T", "optional": "yes"}}},
            r"\[channels.torque\]: 'optional' must be true or false",
        ),
    ],
)
def test_invalid_file_sections_are_rejected(data, pattern):
    with pytest.raises(RecordingError, match=pattern):
        ChannelMap.from_dict(data)


def test_file_section_errors_name_the_map_file(tmp_path):
    f = tmp_path / "bench.toml"
    f.write_text('[file]\nseparator = "::"\n\n[channels.torque]\ncolumn = "T"\n')
    with pytest.raises(RecordingError, match=r"channel map .*bench.toml: file.separator = '::'"):
        load_channel_map(f)


def test_example_map_documents_the_new_keys():
    text = example_channel_map_path().read_text(encoding="utf-8")
    for key in (
        "[file]",
        "separator",
        "decimal",
        "header_row",
        "units_row",
        "data_row",
        "encoding",
        "dayfirst",
        "date_format",
        "group",
        "resample_Hz",
        "optional",
    ):
        assert key in text
    cmap = load_channel_map(example_channel_map_path())
    assert [c.name for c in cmap.channels if c.optional] == ["normal_load"]
