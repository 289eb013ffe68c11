"""A file's columns through the channel map (rollerrig.recordings.translate), on tables built here:
cells to numbers (NaN/inf words, decimal commas), time columns in their units or as timestamps,
column names resolved with close matches. Whole files through the map: test_readers.py and
test_formats_*.py."""

import numpy as np
import pytest

from rollerrig.recordings.channels import ChannelMap
from rollerrig.recordings.formats import Column, Table
from rollerrig.recordings.recording import RecordingError
from rollerrig.recordings.translate import apply_map, as_float, resolve_column, time_seconds


def test_cells_to_numbers_with_words_and_decimal_commas():
    words = ["NaN", "∞", "-inf", "", " 3 "]
    expected = [np.nan, np.inf, -np.inf, np.nan, 3.0]
    for cells in (["1.5", "2.5"], ["1,5", "2,5"]):
        got = as_float(np.array(cells + words, dtype=object), "c")
        np.testing.assert_array_equal(got, [1.5, 2.5, *expected])
    # one column, two decimal marks: which is meant is not the reader's guess
    with pytest.raises(RecordingError, match=r"c mixes decimal marks \('2,5' and '1.5'\)"):
        as_float(np.array(["1.5", "2,5"], dtype=object), "c")
    with pytest.raises(RecordingError, match=r"c has 1 non-numeric entries, first at row 1: 'x'"):
        as_float(np.array(["1", "x"], dtype=object), "c", line_of=lambda k: k + 3)


def test_time_in_its_unit_or_as_timestamps():
    notes: list[str] = []
    np.testing.assert_allclose(time_seconds(np.array([0.0, 4.0]), "ms", "t", notes), [0, 0.004])
    stamps = np.array(["05.08.24 13:46:13,250", "05.08.24 13:46:13,500"], dtype=object)
    np.testing.assert_allclose(time_seconds(stamps, "s", "t", notes), [0.0, 0.25])
    assert "day-first" in notes[-1]


def _table(columns: dict[str, tuple[np.ndarray, str | None]]) -> Table:
    return Table(
        names=list(columns),
        load=lambda n: Column(columns[n][0], columns[n][1]),
        base={n: n for n in columns},
    )


def test_columns_resolve_with_close_matches_and_the_map_applies_units():
    table = _table({"t_ms": (np.arange(3) * 4.0, None), "n_roller": (np.full(3, 60.0), None)})
    cmap = ChannelMap.from_dict(
        {
            "time": {"column": "t_ms", "unit": "ms"},
            "channels": {"roller_speed": {"column": "n_roller", "unit": "rpm"}},
        }
    )
    assert resolve_column(table, "n_roller", "[channels.roller_speed]", cmap, "f") == "n_roller"
    with pytest.raises(RecordingError, match=r"close matches: \['n_roller'\]"):
        resolve_column(table, "n_rollr", "[channels.roller_speed]", cmap, "f")
    time, channels, units, info = apply_map(table, cmap, "f")
    np.testing.assert_allclose(time, [0.0, 0.004, 0.008])
    np.testing.assert_allclose(channels["roller_speed"], 2 * np.pi)
    assert units["roller_speed"] == "rad/s" and info["columns"]["roller_speed"] == "n_roller"


def test_elapsed_time_as_timedelta_is_seconds():
    # pandas' Timedelta / Parquet's duration: the elapsed seconds themselves (was "not numeric")
    elapsed = (np.arange(4) * 250).astype("timedelta64[us]")
    np.testing.assert_allclose(time_seconds(elapsed, "s", "t", []), [0.0, 2.5e-4, 5e-4, 7.5e-4])


def test_a_column_of_text_says_it_holds_text_and_shows_it():
    """An MDF value-to-text channel (a gear state) arrives as bytes: the error shows its
    values (it said only 'not numeric (dtype |S1)')."""
    with pytest.raises(RecordingError, match=r"holds text, not numbers \(\['P', 'R', 'N'\]"):
        as_float(np.array([b"P", b"R", b"N", b"D"]), "gear")
