"""The form of a channel map file (pydantic): each key of [file], [time] and the entries.

Every problem is one line in the package's error format, naming the map, the dotted key, the
unit, the allowed values and the value found.
"""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from rollerrig.recordings.channels import ChannelMap, load_channel_map
from rollerrig.recordings.mapfile import SEPARATORS, FileSpec, MapFile
from rollerrig.recordings.recording import RecordingError

D = "channel map <dict>: "


def test_separators_and_decimals_accepted():
    for sep in SEPARATORS:
        decimal = "," if sep != "," else "."
        assert FileSpec(separator=sep, decimal=decimal).separator == sep


def test_the_whole_map_form():
    form = MapFile.model_validate(
        {
            "file": {"separator": ";", "header_row": 2},
            "time": {"column": "t", "unit": "ms"},
            "channels": {"torque": {"column": "T", "unit": "N.m", "scale": 2}},
            "description": "bench",
        }
    )
    assert form.file == FileSpec(separator=";", header_row=2)
    assert form.time.unit == "ms" and "unit" in form.time.model_fields_set
    assert form.channels["torque"].scale == 2.0


def _file(**keys):
    return {"file": keys, "channels": {"torque": {"column": "T", "unit": "N.m"}}}


FILE_KEYS = (
    "allowed 'separator', 'decimal', 'header_row', 'units_row', 'data_row', 'encoding', "
    "'dayfirst', 'date_format', 'group'"
)
SEPARATOR_CHOICES = (
    "allowed ',' (comma), ';' (semicolon), '\\t' (tab), ' ' (whitespace: any run of spaces or "
    "tabs), '|' (pipe)"
)
LINE = "must be a 0-based line index; allowed an integer >= 0"


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (
            _file(seperator=";"),
            f"file.seperator: unknown key (did you mean 'separator'?); {FILE_KEYS}",
        ),
        (_file(sep=";"), f"file.sep: unknown key; {FILE_KEYS}"),
        (
            _file(separator=";;"),
            f"file.separator: not an accepted separator; {SEPARATOR_CHOICES}; got ';;'",
        ),
        (
            _file(separator="tab"),
            f"file.separator: not an accepted separator; {SEPARATOR_CHOICES}; got 'tab'",
        ),
        (
            _file(decimal=";"),
            "file.decimal: not one of the allowed values; allowed '.' or ','; got ';'",
        ),
        (
            _file(separator=",", decimal=","),
            "file.decimal: must differ from file.separator; got ','",
        ),
        (_file(header_row=-1), f"file.header_row: {LINE}; got -1"),
        (_file(header_row=1.5), f"file.header_row: {LINE}; got 1.5"),
        (_file(header_row=True), f"file.header_row: {LINE}; got true"),
        (
            _file(units_row=True),
            "file.units_row: must be a 0-based line index or false; allowed an integer >= 0 or "
            "false; got true",
        ),
        (
            _file(header_row=3, units_row=2),
            "file.units_row: must come after file.header_row; allowed > 3; got 2",
        ),
        (
            _file(header_row=3, data_row=3),
            "file.data_row: must come after the header / units rows; allowed > 3; got 3",
        ),
        (
            _file(encoding="klingon"),
            "file.encoding: not a known text encoding; allowed e.g. 'utf-8', 'utf-8-sig', "
            "'latin-1', 'cp1252', 'utf-16'; got 'klingon'",
        ),
        (_file(dayfirst="yes"), "file.dayfirst: must be true or false; got 'yes'"),
        (
            _file(date_format="dd.mm.yy"),
            "file.date_format: must be a strptime format; allowed e.g. '%d.%m.%y %H:%M:%S'; "
            "got 'dd.mm.yy'",
        ),
        (
            _file(group=-1),
            "file.group: must be a group name or a 0-based group index; allowed a name or an "
            "integer >= 0; got -1",
        ),
        (_file(group=""), "file.group: must be a group name or a 0-based group index"),
        ({"file": ";", "channels": {}}, "file: must be a table; got ';'"),
        (
            {"time": {"column": "t", "resample_Hz": 0}, "channels": {}},
            "time.resample_Hz: must be > 0 [Hz]; allowed (0, 100000000]; got 0",
        ),
        (
            {"time": {"column": "t", "resampl_Hz": 5}, "channels": {}},
            "time.resampl_Hz: unknown key (did you mean 'resample_Hz'?); allowed 'column', "
            "'unit', 'sample_rate_Hz', 'resample_Hz'",
        ),
        (
            {"channels": {"torque": {"column": "T", "optional": "yes"}}},
            "channels.torque.optional: must be true or false; got 'yes'",
        ),
    ],
)
def test_invalid_file_sections_are_rejected(data, message):
    with pytest.raises(RecordingError) as info:
        ChannelMap.from_dict(data)
    assert any(line.startswith(D + message) for line in info.value.problems), info.value


def test_file_spec_validates_on_construction():
    assert FileSpec(separator=";", units_row=False).to_dict() == {
        "separator": ";",
        "units_row": False,
    }
    with pytest.raises(ValidationError):
        FileSpec(header_row=3, data_row=1)


def test_file_section_errors_name_the_map_file(tmp_path):
    f = tmp_path / "bench.toml"
    f.write_text('[file]\nseparator = "::"\n\n[channels.torque]\ncolumn = "T"\n')
    with pytest.raises(RecordingError) as info:
        load_channel_map(f)
    assert str(info.value).startswith(
        f"channel map {f}: file.separator: not an accepted separator; allowed ',' (comma)"
    )
    assert str(info.value).endswith("; got '::'")
