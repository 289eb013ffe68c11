"""Channel maps: the map file, its validation in the package's one error format, round trips.

The unit conversions the maps use are tested against their definitions in tests/test_units.py.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from rollerrig.recordings.channels import (
    TIME_UNITS,
    UNIT_FACTORS,
    ChannelMap,
    default_channel_map,
    example_channel_map_path,
    load_channel_map,
    split_unit_header,
)
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import CANONICAL_CHANNELS, RecordingError
from rollerrig.units import QUANTITIES, UNITS_BY_SI


def test_unit_tables_are_views_of_the_one_registry():
    # measure.readers and measure.formats.csv read these names; they are not tables of their own.
    assert TIME_UNITS == QUANTITIES["time"].units
    assert UNIT_FACTORS is UNITS_BY_SI
    for si, _meaning in CANONICAL_CHANNELS.values():
        assert UNIT_FACTORS[si][si] == 1.0


def test_split_headers():
    assert split_unit_header("torque [N.m]") == ("torque", "N.m")
    assert split_unit_header("p_air (bar)") == ("p_air", "bar")
    assert split_unit_header("Torque_Roller") == ("Torque_Roller", None)
    assert split_unit_header("[x]") == ("[x]", None)


def test_entry_units_convert_through_the_registry():
    cmap = ChannelMap.from_dict(
        {
            "time": {"column": "t", "unit": "µs"},
            "channels": {
                "torque": {"column": "T", "unit": "kNm"},
                "roller_speed": {"column": "n", "unit": "U/min"},
            },
            "extra": {
                "power": {"column": "P", "unit": "kW"},
                "temp": {"column": "C", "unit": "degC"},
            },
        }
    )
    assert cmap.time.unit == "us"
    assert cmap.channels[0].conversion() == ("N.m", 1e3)
    assert cmap.channels[1].conversion() == ("rad/s", pytest.approx(2 * math.pi / 60, rel=1e-15))
    assert cmap.extra[0].conversion() == ("W", 1e3)  # prefixed units of known quantities to SI
    assert cmap.extra[1].conversion() == ("degC", 1.0)  # others stay as they are
    with pytest.raises(RecordingError, match=r"^channel map entry \[channels.torque\]: unit not"):
        cmap.channels[0].conversion("bar")


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


D = "channel map <dict>: "
CANONICAL = ", ".join(repr(name) for name in CANONICAL_CHANNELS)


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (
            _map(torqe={"column": "T", "unit": "N.m"}),
            "channels.torqe: 'torqe' is not a canonical channel name (did you mean 'torque'?); "
            f"put other channels under [extra.torqe] with an explicit unit; allowed {CANONICAL}",
        ),
        (
            _map(torque={"column": "T", "unit": "bar"}),
            "channels.torque.unit: unit not accepted for torque [N.m]; allowed 'N.m', 'kN.m' "
            "(also written 'Nm', 'N-m', 'kNm'); got 'bar'",
        ),
        (
            _map(normal_load={"column": "F", "unit": "lbf"}),
            "channels.normal_load.unit: unit not accepted for force [N]; allowed 'N', 'kN' "
            "(also written 'Newtons'); got 'lbf'",
        ),
        (
            _map(torque={"column": "T", "unit": "N.m", "scael": 2}),
            "channels.torque.scael: unknown key (did you mean 'scale'?); allowed 'column', "
            "'unit', 'scale', 'offset', 'description', 'optional'",
        ),
        (
            _map(torque={"unit": "N.m"}),
            "channels.torque.column: missing key (the file's column / channel name)",
        ),
        (
            _map(torque={"column": "T", "unit": "N.m", "scale": 0}),
            "channels.torque.scale: must be non-zero; got 0",
        ),
        (
            _map(torque={"column": "T", "unit": "N.m", "scale": "2"}),
            "channels.torque.scale: must be a number; got '2'",
        ),
        (
            _map(torque={"column": "T", "unit": "N.m", "offset": math.nan}),
            "channels.torque.offset: must be finite; got nan",
        ),
        (
            _map(torque={"column": "T", "unit": " "}),
            "channels.torque.unit: must not be blank; got ' '",
        ),
        (_map(torque="T"), "channels.torque: must be a table; got 'T'"),
        (
            {"channels": {}},
            "maps no channels and sets nothing; add [channels.<name>] or [extra.<name>] tables, "
            "or [file] / [time] settings for columns named as the canonical channels",
        ),
        (
            {"time": {"column": "t", "unit": "d"}, "channels": {}},
            "time.unit: not a time unit; allowed 's', 'ms', 'us', 'ns', 'min', 'h'; got 'd'",
        ),
        (
            {"time": {"column": "t", "sample_rate_Hz": 250}, "channels": {}},
            "time: give either 'column' or 'sample_rate_Hz', not both",
        ),
        (
            {"time": {"sample_rate_Hz": -1}, "channels": {}},
            "time.sample_rate_Hz: must be > 0 [Hz]; allowed (0, 100000000]; got -1",
        ),
        (
            {"time": {"column": "t"}, "chanels": {}},
            "chanels: unknown key (did you mean 'channels'?); allowed 'file', 'time', "
            "'channels', 'extra', 'description', 'name'",
        ),
        (
            {"extra": {"torque": {"column": "T", "unit": "N.m"}}},
            "extra.torque: 'torque' is canonical; put it under [channels.torque]",
        ),
        (
            {"extra": {"current": {"column": "I"}}},
            "extra.current.unit: missing key (a channel outside the canonical names needs an "
            "explicit unit)",
        ),
    ],
)
def test_invalid_maps_are_rejected(data, message):
    # One format: <file>: <dotted key>: <what> [<unit>]; allowed <range or choices>; got <value>
    with pytest.raises(RecordingError) as info:
        ChannelMap.from_dict(data)
    assert D + message in info.value.problems


def test_every_problem_is_reported_at_once():
    data = _map(torque={"column": "T", "unit": "bar", "scale": 0}, speed={"column": "n"})
    with pytest.raises(RecordingError) as info:
        ChannelMap.from_dict(data)
    assert [line.split(": ")[1] for line in info.value.problems] == ["channels.torque.scale"]
    data = _map(torque={"column": "T", "unit": "bar"}, speed={"column": "n"})
    with pytest.raises(RecordingError) as info:
        ChannelMap.from_dict(data)
    assert [line.split(": ")[1] for line in info.value.problems] == [
        "channels.torque.unit",
        "channels.speed",
    ]
    assert str(info.value) == "\n".join(info.value.problems)


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
    with pytest.raises(RecordingError) as info:
        load_channel_map(f)
    assert str(info.value) == (
        f"channel map {f}: channels.torque.unit: unit not accepted for torque [N.m]; allowed "
        "'N.m', 'kN.m' (also written 'Nm', 'N-m', 'kNm'); got 'psi'"
    )


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


def test_a_map_of_settings_only_maps_the_canonical_names_with_them(tmp_path):
    """The reader's own error for mixed decimal marks asks for ``[file] decimal = ","``; a map
    of only that (or of only [time]) was refused as "maps no channels"."""
    only_file = ChannelMap.from_dict({"file": {"decimal": ","}})
    assert only_file.auto and only_file.file.decimal == ","
    assert only_file.time == default_channel_map().time
    only_time = ChannelMap.from_dict({"time": {"unit": "ms"}})
    assert only_time.auto and only_time.time.column == "time" and only_time.time.unit == "ms"
    f = tmp_path / "semi.csv"
    f.write_text("time [s];torque [N.m]\n0,000;1,5\n0,004;1,6\n0,008;1,7\n")
    rec = read_recording(f, only_file)
    assert rec["torque"].tolist() == [1.5, 1.6, 1.7]
