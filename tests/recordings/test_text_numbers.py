"""Numbers in text files: decimal and thousands marks, a last line without a line end, and
date/time cells that need ``[file] date_format``.

One place decides what ``85,928`` or ``86.021`` means (:func:`parse_number`): under the file's
decimal mark the other mark is a thousands mark only in strict groups of three digits (noted
with the column and an example cell), anything else with it is an error naming line, column and
cell, never a decimal point (a silent factor of 1000).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig.recordings.formats._text import decimal_marks, parse_number
from rollerrig.recordings.formats.timestamps import looks_like_timestamp, suggest_date_format
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import RecordingError
from rollerrig.recordings.source import open_recording

MAP = {
    "time": {"column": "t"},
    "channels": {
        "torque": {"column": "T", "unit": "N.m"},
        "air_spring_pressure": {"column": "p", "unit": "Pa"},
    },
}


def _write(path, lines, *, final_eol=True):
    path.write_bytes(("\r\n".join(lines) + ("\r\n" if final_eol else "")).encode())
    return path


def _torque_map(time: str = "t", torque: str = "T") -> dict:
    """A map of a time column in seconds and a torque column in N.m."""
    return {
        "time": {"column": time, "unit": "s"},
        "channels": {"torque": {"column": torque, "unit": "N.m"}},
    }


def _notes(rec) -> str:
    return "\n".join(rec.metadata["notes"])


# --- parse_number, the one place


@pytest.mark.parametrize(
    ("cell", "decimal", "value"),
    [
        ("85,928", ".", 85928.0),
        ("-1,002.25", ".", -1002.25),
        ("1,234,567", ".", 1234567.0),
        ("86.021", ",", 86021.0),
        ("1.002,5", ",", 1002.5),
        ("0,45", ",", 0.45),
        ("-5.563", ".", -5.563),
        ("1e3", ".", 1000.0),
        # the other mark outside strict groups of three: not a number under that mark
        ("0,45", ".", None),
        ("8,5928", ".", None),
        ("85,92", ".", None),
        ("0,928", ".", None),  # a leading-zero group is no thousands grouping
        ("86.02", ",", None),
        ("0.004", ",", None),
        ("1,002.5", ",", None),
    ],
)
def test_parse_number(cell, decimal, value):
    assert parse_number(cell, decimal) == value


@given(
    st.floats(-1e9, 1e9, allow_nan=False).map(lambda x: round(x, 3)),
    st.sampled_from([".", ","]),
)
def test_thousands_grouped_numbers_read_back_exactly(x, decimal):
    other = "," if decimal == "." else "."
    text = f"{x:,.3f}".replace(",", "_").replace(".", decimal).replace("_", other)
    assert parse_number(text, decimal) == pytest.approx(x, abs=1e-9)
    # the same cell read under the other mark is either a plain decimal or nothing: it is
    # never silently a thousands grouping of the other reading
    if abs(x) >= 1000:
        assert parse_number(text, other) is None or other not in text.split(decimal)[0]


@given(st.from_regex(r"[+-]?[0-9]{1,7}[.,][0-9]{1,7}", fullmatch=True))
def test_a_cell_is_never_read_with_the_other_mark_as_a_decimal_point(cell):
    for decimal in ".,":
        value = parse_number(cell, decimal)
        other = "," if decimal == "." else "."
        if value is not None and other in cell:
            # the other mark was read as a thousands mark: the digits are kept whole
            assert value == float(cell.replace(other, ""))
            assert re.fullmatch(r"[+-]?[1-9]\d{0,2}(?:[.,]\d{3})+", cell)
    assert decimal_marks(cell) <= {".", ","}


# --- 1a: comma-separated, decimal points, one column with US thousands marks (quoted)

US_HEAD = ['"t","T","p"', '"0.0000","-5.563","85,928"']  # header, first row


def test_us_thousands_marks_in_quoted_cells_are_read_whole_with_a_note(tmp_path):
    f = _write(
        tmp_path / "us.csv",
        [*US_HEAD, '"0.0040","-4.530","86,021"'],
    )
    rec = read_recording(f, MAP)
    np.testing.assert_array_equal(rec["air_spring_pressure"], [85928.0, 86021.0])
    np.testing.assert_allclose(rec["torque"], [-5.563, -4.530])
    notes = _notes(rec)
    assert "column 'p' writes thousands marks ','" in notes
    assert "'85,928' at line 2" in notes and "decimal mark is '.'" in notes


def test_us_thousands_marks_also_in_chunked_reading(tmp_path):
    f = _write(
        tmp_path / "us.csv",
        [*US_HEAD, '"0.0040","-4.530","86,021"'],
    )
    with open_recording(f, MAP) as src:
        chunk = src.read()
        np.testing.assert_array_equal(chunk.channels["air_spring_pressure"], [85928.0, 86021.0])


def test_a_comma_that_is_no_thousands_mark_in_a_decimal_point_file_is_an_error(tmp_path):
    f = _write(
        tmp_path / "us.csv",
        [*US_HEAD, '"0.0040","-4.530","8,6021"'],
    )
    # '8,6021' can only be a decimal comma, '0.0000' only a decimal point: which is meant?
    with pytest.raises(RecordingError, match=r"mix decimal marks \('8,6021' at line 3, column 3"):
        read_recording(f, MAP)
    with pytest.raises(RecordingError, match=r"line 3, column 'p': '8,6021' is not a number"):
        read_recording(f, dict(MAP, file={"decimal": "."}))


def test_quoted_decimal_commas_in_a_comma_separated_file_stay_decimal_commas(tmp_path):
    # no cell with a decimal point: "0,004000" proves the comma is the decimal mark
    f = _write(
        tmp_path / "eu.csv",
        ['"t","T","p"', '"0,000000","-0,45","85,928"', '"0,004000","-0,46","85,929"'],
    )
    rec = read_recording(f, MAP)
    np.testing.assert_allclose(rec["air_spring_pressure"], [85.928, 85.929])


# --- 1b: semicolons, decimal commas, one column with German thousands marks


@pytest.mark.parametrize("given_decimal", [None, ","])
def test_german_thousands_dots_are_read_whole_with_a_note(tmp_path, given_decimal):
    f = _write(tmp_path / "de.csv", ["t;T;p", "0,000000;-0,45;85.928", "0,004000;-0,56;86.021"])
    cmap = dict(MAP, file={"decimal": given_decimal}) if given_decimal else MAP
    rec = read_recording(f, cmap)
    np.testing.assert_array_equal(rec["air_spring_pressure"], [85928.0, 86021.0])
    assert "column 'p' writes thousands marks '.'" in _notes(rec)


@pytest.mark.parametrize("cell", ["86.02", "0.021", "86.0215"])
def test_a_dot_is_never_a_decimal_point_when_the_decimal_mark_is_a_comma(tmp_path, cell):
    f = _write(tmp_path / "de.csv", ["t;T;p", "0,000000;-0,45;85.928", f"0,004000;-0,56;{cell}"])
    pattern = rf"line 3, column 'p': '{re.escape(cell)}' is not a number.*decimal mark ','"
    with pytest.raises(RecordingError, match=pattern):
        read_recording(f, dict(MAP, file={"decimal": ","}))


def test_ambiguous_marks_in_both_directions_ask_for_the_decimal_mark(tmp_path):
    f = _write(tmp_path / "amb.csv", ["t;T;p", "0;1.234;85,928", "1;1.235;85,929"])
    with pytest.raises(RecordingError, match=r"mix decimal marks.*\[file\] decimal"):
        read_recording(f, MAP)


# --- 8: a last line without a line end


def test_a_last_line_without_line_end_is_dropped_with_a_note(tmp_path):
    lines = ["t,T,p", "0.0,1.5,85912.3", "0.004,1.6,85912.3", "0.008,1.7,859"]
    f = _write(tmp_path / "cut.csv", lines, final_eol=False)
    rec = read_recording(f, MAP)
    np.testing.assert_array_equal(rec["air_spring_pressure"], [85912.3, 85912.3])
    notes = _notes(rec)
    assert "last line 4 has no line end" in notes and "2 data row(s) kept" in notes


def test_a_complete_last_line_of_a_fixed_decimals_writer_is_kept(tmp_path):
    # Most DAQ software writes fixed decimals: a last cell as long as the line before's was
    # not cut inside its number, even without a line end.
    lines = ["t,T,p", "0.000,1.50,85912.3", "0.004,1.60,85911.7", "0.008,1.70,85910.9"]
    rec = read_recording(_write(tmp_path / "whole.csv", lines, final_eol=False), MAP)
    assert rec["air_spring_pressure"].tolist() == [85912.3, 85911.7, 85910.9]
    assert "no line end" not in _notes(rec)


def test_a_last_line_ending_in_a_closing_quote_is_kept(tmp_path):
    lines = ['"t","T","p"', '"0.0","1.5","85912.3"', '"0.004","1.6","85912.3"']
    f = _write(tmp_path / "whole.csv", lines, final_eol=False)
    rec = read_recording(f, MAP)
    assert rec["torque"].tolist() == [1.5, 1.6]
    assert "no line end" not in _notes(rec)


def test_a_last_line_with_a_line_end_is_kept(tmp_path):
    f = _write(tmp_path / "ok.csv", ["t,T,p", "0.0,1.5,85912.3", "0.004,1.6,859"])
    assert read_recording(f, MAP)["air_spring_pressure"].tolist() == [85912.3, 859.0]


# --- 11: date/time cells in a form that needs [file] date_format


def test_am_pm_timestamps_name_date_format_with_an_example(tmp_path):
    cells = ["08/05/2024 01:46:13.000000 PM", "08/05/2024 01:46:13.004000 PM"]
    f = _write(tmp_path / "us.csv", ["t,T,p", *(f"{c},1.5,2.5" for c in cells)])
    pattern = re.escape("date_format = '%m/%d/%Y %I:%M:%S.%f %p'")
    with pytest.raises(RecordingError, match=rf"\[file\] date_format.*{pattern}"):
        read_recording(f, MAP)
    rec = read_recording(f, dict(MAP, file={"date_format": "%m/%d/%Y %I:%M:%S.%f %p"}))
    np.testing.assert_allclose(rec.time, [0.0, 0.004])


@pytest.mark.parametrize(
    ("cell", "fmt"),
    [
        ("08/05/2024 01:46:13.000000 PM", "%m/%d/%Y %I:%M:%S.%f %p"),
        ("13/05/2024 1:46 pm", "%d/%m/%Y %I:%M %p"),
        ("Mon 05.08.2024 13:46", "%a %d.%m.%Y %H:%M"),
        ("2024-08-05 13:46:13 +0200", "%Y-%m-%d %H:%M:%S %z"),
        # the day and year are codes, not the first row's (which failed on the next day)
        ("05-Aug-2024 11:59:59.000 PM", "%d-%b-%Y %I:%M:%S.%f %p"),
        ("Aug 05 2024 13:46", "%b %d %Y %H:%M"),
        ("August 5, 2024 01:02:03 PM", "%B %d, %Y %I:%M:%S %p"),
        ("Run 1 13:46", None),  # no format copies a number of the cell
    ],
)
def test_suggest_date_format(cell, fmt):
    assert looks_like_timestamp(cell)
    assert suggest_date_format(cell) == fmt


def test_elapsed_minutes_and_seconds_get_a_format_that_reads_them(tmp_path):
    """Excel's elapsed time ``[mm]:ss,0``: the refusal suggested ``'%H:%M,0'`` (hours and
    minutes, a constant ',0'), which reads '00:00,1' as midnight; ``'%M:%S,%f'`` reads it."""
    rows = [f"{k // 600:02d}:{k // 10 % 60:02d},{k % 10};{k}" for k in range(700)]
    f = _write(tmp_path / "elapsed.csv", ["Zeit;Moment", *rows])
    cmap = _torque_map(time="Zeit", torque="Moment")
    with pytest.raises(RecordingError, match=r"date_format = '%M:%S,%f' reads '00:00,0';"):
        read_recording(f, cmap)
    rec = read_recording(f, {**cmap, "file": {"date_format": "%M:%S,%f"}})
    np.testing.assert_allclose(rec.time, 0.1 * np.arange(700), atol=1e-9)


@pytest.mark.parametrize("cell", ["12.5", "85,928", "-1e3", "ERR"])
def test_numbers_and_text_do_not_look_like_timestamps(cell):
    assert not looks_like_timestamp(cell)


# --- marks first met beyond the rows the layout is sniffed from


def _late_marks_csv(path, values, *, decimal):
    """A recording whose torque stays below 1000 N.m in the first 2000 rows (no thousands
    mark where the layout is sniffed) and is written with thousands marks once it is above."""
    sep = "," if decimal == "." else ";"
    lines = [f"t [s]{sep}T [N.m]"]
    for k, v in enumerate(values):
        cell = f"{v:,.2f}" if decimal == "." else f"{v:,.2f}".translate({44: 46, 46: 44})
        time = f"{k / 1000:.3f}".replace(".", decimal)
        lines.append(f'{time}{sep}"{cell}"')
    return _write(path, lines)


@settings(max_examples=15, deadline=None)
@given(
    late=st.lists(st.floats(1000.0, 9.9e6), min_size=1, max_size=30),
    decimal=st.sampled_from([".", ","]),
)
def test_thousands_marks_beyond_the_sniffed_rows_are_read_whole(tmp_path_factory, late, decimal):
    """'1,000.00' under a decimal point (or '1.000,00' under a decimal comma) first met after
    the rows the layout was sniffed from is 1000, in both readers: it was an error, and an
    integer '1,000' was read as 1.0, a torque of 1000 N.m as 1 N.m."""
    values = np.concatenate([np.linspace(0.0, 999.0, 2500), np.round(late, 2)])
    f = _late_marks_csv(tmp_path_factory.mktemp("late") / "run.csv", values, decimal=decimal)
    torque_map = {"time": {"column": "t"}, "channels": {"torque": {"column": "T"}}}
    rec = read_recording(f, torque_map)
    np.testing.assert_allclose(rec["torque"], np.round(values, 2), rtol=1e-15)
    with open_recording(f, torque_map) as src:
        chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 700)])
    np.testing.assert_array_equal(chunked, rec["torque"])


def test_an_integer_with_a_thousands_comma_is_never_read_as_a_decimal_comma(tmp_path):
    """A column of integers with '1,000' among them writes thousands commas ('999' beside
    '1,000': a writer of fixed decimals writes '999,000'): read as 1000, with a note, within
    the sniffed rows and beyond them (it was read as 1.0, a decimal comma guessed)."""
    torque_map = {"time": {"column": "t"}, "channels": {"torque": {"column": "T"}}}
    values = list(range(3000))
    lines = ["t [ms],T [N.m]"] + [f'{k},"{v:,d}"' for k, v in enumerate(values)]
    rec = read_recording(_write(tmp_path / "ints.csv", lines), torque_map)
    np.testing.assert_array_equal(rec["torque"], values)
    assert "holds integers such as" in _notes(rec) and "'1,000'" in _notes(rec)

    # Beyond the sniffed rows (nothing decided there) a column alone does not decide by its
    # integers: another column's '0,5' there may say decimal commas; refused, then as given.
    values = [k % 1000 for k in range(2500)] + list(range(1000, 1500))
    lines = ["t [ms],T [N.m]"] + [f'{k},"{v:,d}"' for k, v in enumerate(values)]
    f = _write(tmp_path / "late.csv", lines)
    with pytest.raises(RecordingError, match=r"'1,000' is 1000 under a decimal point or 1 under"):
        read_recording(f, torque_map)
    given = dict(torque_map, file={"decimal": "."})
    np.testing.assert_array_equal(read_recording(f, given)["torque"], values)
    with open_recording(f, given) as src:
        chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 700)])
    np.testing.assert_array_equal(chunked, values)


@pytest.mark.parametrize(
    ("rows", "values", "decimal"),
    [
        # '1' beside '1,125': 1.125 from a writer of shortest decimals, 1125 from a grouping
        # one; nothing in the file says which (a review found the first read as 1125)
        (["t;T", "0;1", "1;1,125", "2;2", "3;2,375"], [1.0, 1.125, 2.0, 2.375], ","),
        (["t,T", "0,1", "1,1.125", "2,2", "3,2.375"], [1.0, 1.125, 2.0, 2.375], "."),
        # integer time, three fixed decimals in every cell: 12.345 or 12345
        (["t;T", "0;1,000", "1;12,345", "2;2,500"], [1.0, 12.345, 2.5], ","),
        # integer counts with thousands commas, all above 999: 12000 or 12.0
        (["t;T"] + [f'{k};"{12000 + k:,d}"' for k in range(5)], 12000.0 + np.arange(5), "."),
    ],
    ids=["shortest-comma", "shortest-point", "fixed-comma-integer-time", "counts"],
)
def test_cells_that_read_both_ways_with_nothing_to_decide_are_refused(
    tmp_path, rows, values, decimal
):
    """No guess of the decimal mark where every marked cell reads both ways: both readings
    named and [file] decimal asked for (a decimal comma was guessed: counts of 12 000 read as
    12.0), then read right in both readers."""
    torque_map = _torque_map()
    f = _write(tmp_path / "run.csv", rows)
    with pytest.raises(RecordingError, match=r"under a decimal point or .* under a decimal comma"):
        read_recording(f, torque_map)
    given = dict(torque_map, file={"decimal": decimal})
    np.testing.assert_array_equal(read_recording(f, given)["torque"], values)
    with open_recording(f, given) as src:
        chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 700)])
    np.testing.assert_array_equal(chunked, values)


@pytest.mark.parametrize(
    ("rows", "values"),
    [
        (["t;T", "0,000;1,000", "0,001;12,345", "0,002;2,500"], [1.0, 12.345, 2.5]),
        (
            ["t;T"] + [f"{k};{k % 7}" for k in range(2100)] + ["2100;0,5", "2101;1,000"],
            [k % 7 for k in range(2100)] + [0.5, 1.0],
        ),
    ],
    ids=["fixed-comma", "late-comma"],
)
def test_a_mark_that_the_cells_decide_is_read(tmp_path, rows, values):
    """'0,000' in the time column decides decimal commas; '0,5' in a column decides it for its
    '1,000' (and for the file's other columns)."""
    torque_map = _torque_map()
    f = _write(tmp_path / "run.csv", rows)
    np.testing.assert_array_equal(read_recording(f, torque_map)["torque"], values)
    with open_recording(f, torque_map) as src:
        chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 700)])
    np.testing.assert_array_equal(chunked, values)


def test_a_decimal_point_after_the_sniffed_rows_of_a_decimal_comma_file_is_an_error(tmp_path):
    """'1.5' in a file whose decimal mark is ',' is no number (a thousands dot needs groups of
    three), beyond the sniffed rows as within them: it was read as 1.5 by pandas."""
    rows = ["t;T"] + [f"{k};{k % 7},5" for k in range(2100)] + ["2100;1.5", "2101;2,5"]
    f = _write(tmp_path / "run.csv", rows)
    torque_map = _torque_map()
    with pytest.raises(RecordingError, match=r"'1.5'.*the file's decimal mark is ','"):
        read_recording(f, torque_map)


def test_text_columns_of_other_formats_take_the_mark_their_cells_or_the_map_give(tmp_path):
    """A Parquet string column: '0,5' decides decimal commas for '1,000' beside it; a column
    mixing '0,5' and '1,000.5' is an error; the map's [file] decimal decides where the cells
    cannot."""
    pd = pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    torque_map = _torque_map()

    def parquet(name, cells):
        path = tmp_path / name
        pd.DataFrame({"t": np.arange(float(len(cells))), "T": cells}).to_parquet(path)
        return path

    f = parquet("comma.parquet", ["0,5", "1,000", "1,250"])
    np.testing.assert_array_equal(read_recording(f, torque_map)["torque"], [0.5, 1.0, 1.25])
    with pytest.raises(RecordingError, match=r"mixes decimal marks \('0,5' and '1,000.5'\)"):
        read_recording(parquet("mixed.parquet", ["0,5", "1,000.5", "2"]), torque_map)
    f = parquet("ambiguous.parquet", ["1,000", "2,000"])
    with pytest.raises(RecordingError, match=r"give \[file\] decimal"):
        read_recording(f, torque_map)
    given = dict(torque_map, file={"decimal": "."})
    np.testing.assert_array_equal(read_recording(f, given)["torque"], [1000.0, 2000.0])


def test_a_time_of_two_fields_asks_minutes_or_hours(tmp_path):
    """'00:01' is a second of an elapsed mm:ss or a minute of a time of day hh:mm: refused
    with both named (it was read as hh:mm: a 1 Hz logger 60 times too slow), read as given."""
    lines = ["Elapsed;T"] + [f"{k // 60:02d}:{k % 60:02d};{k}" for k in range(120)]
    f = _write(tmp_path / "mmss.csv", lines)
    cmap = {"time": {"column": "Elapsed"}, "channels": {"torque": {"column": "T", "unit": "N.m"}}}
    with pytest.raises(RecordingError, match=r'minutes:seconds .* "%M:%S" or "%H:%M"'):
        read_recording(f, cmap)
    rec = read_recording(f, dict(cmap, file={"date_format": "%M:%S"}))
    np.testing.assert_array_equal(rec.time, np.arange(120.0))


def test_a_named_last_column_empty_at_first_is_no_trailing_separator(tmp_path):
    """A last column the header names, empty for the first 300 rows (its sensor switched on
    later): a channel, not a trailing separator (the file was refused: 'the header has 3
    cells but the data rows have 2')."""
    rows = [
        f"{k * 0.001:.3f};{k * 0.5:.1f};" + ("" if k < 300 else f"{2 + k * 1e-4:.4f}")
        for k in range(1000)
    ]
    f = _write(tmp_path / "late_sensor.csv", ["t;T;P", *rows])
    cmap = _torque_map()
    rec = read_recording(f, cmap)
    np.testing.assert_allclose(rec["torque"], np.arange(1000) * 0.5)


@pytest.mark.parametrize(
    "footer",
    [
        ["Ende der Messung"],
        ["Mittelwert;24,5"],
        ["", "Statistik", "Mittelwert;24,5", "Max;49"],
        ["Ende", ";", "n/a", "Bediener;Schmidt"],  # empty and NaN rows among its lines
        ["Mittelwert;24,5;Min;0;Max;49"],  # more cells than the header
        ["Ende", "-1.#IND;-1.#IND"],  # a row pandas reads as NaN, below the text
    ],
)
def test_a_text_footer_is_left_out_and_named(tmp_path, footer):
    """A footer below the numbers ('Ende der Messung', a statistics block) is no sample: left
    out, in both readers, with a note that names it. It was refused ('no rows of numbers'),
    and with a sample-rate map 'Mittelwert;24,5' was read as one more sample, 24.5 N.m."""
    rows = [f"{k / 100:.2f};{k},5".replace(".", ",") for k in range(50)]
    f = _write(tmp_path / "footer.csv", ["Zeit;Moment", *rows, *footer])
    first = next(t for t in footer if t)
    for cmap in (
        _torque_map(time="Zeit", torque="Moment"),
        {"time": {"sample_rate_Hz": 100.0}, "channels": {
            "torque": {"column": "Moment", "unit": "N.m"}}},
    ):  # fmt: skip
        rec = read_recording(f, cmap)
        np.testing.assert_array_equal(rec["torque"], np.arange(50) + 0.5)
        assert any("footer" in n and first in n for n in rec.metadata["notes"])
        with open_recording(f, cmap) as src:
            chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 7)])
        np.testing.assert_array_equal(chunked, rec["torque"])


def test_a_time_of_day_format_without_a_date_is_unwrapped_at_midnight(tmp_path):
    """'%H:%M' (the way out of the two-field refusal) across midnight: '23:59' then '00:00' is
    a minute later (the date_format path said 'time goes backwards')."""
    rows = [f"{(1430 + k) // 60 % 24:02d}:{(1430 + k) % 60:02d};{k}" for k in range(30)]
    f = _write(tmp_path / "hhmm.csv", ["t;T", *rows])
    cmap = {
        "file": {"date_format": "%H:%M"},
        "time": {"column": "t"},
        "channels": {"torque": {"column": "T", "unit": "N.m"}},
    }
    np.testing.assert_array_equal(read_recording(f, cmap).time, 60.0 * np.arange(30))


def test_late_marks_follow_the_file_not_the_column(tmp_path):
    """A German integer writer crossing 1000 beyond the sniffed rows ('999', then '1.000'): never
    pandas' 1.0; refused naming both readings. One column's '0,5' there decides decimal commas
    for the file's other columns too (a column alone had read its '1,000' as 1000 beside it)."""
    cmap = _torque_map(torque="n")
    rows = ["t;n"] + [f"{k};{k // 3:,d}".replace(",", ".") for k in range(4000)]
    f = _write(tmp_path / "dots.csv", rows)
    with pytest.raises(RecordingError, match=r"'1\.000' is 1 under a decimal point or 1000 under"):
        read_recording(f, cmap)
    rows = ["t;A;B"] + [
        f"{k};{'0,5' if k == 2500 else '1'};{'1,000' if k == 2600 else '999'}" for k in range(3000)
    ]
    f = _write(tmp_path / "two.csv", rows)
    both = {
        "time": {"column": "t", "unit": "s"},
        "channels": {
            "torque": {"column": "A", "unit": "N.m"},
            "normal_load": {"column": "B", "unit": "N"},
        },
    }
    rec = read_recording(f, both)
    assert rec["torque"][2500] == 0.5 and rec["normal_load"][2600] == 1.0


def test_a_footer_beyond_the_sniffed_head_is_left_out(tmp_path):
    """The same below 30 000 rows (beyond the 256 KiB the layout is sniffed from): found from
    the file's end, not the head."""
    rows = [f"{k / 1000:.3f};{k % 997},25".replace(".", ",") for k in range(30_000)]
    f = _write(tmp_path / "long.csv", ["Zeit;Moment", *rows, "Mittelwert;498,25"])
    assert f.stat().st_size > 256 * 1024
    cmap = {"time": {"sample_rate_Hz": 1000.0}, "channels": {
        "torque": {"column": "Moment", "unit": "N.m"}}}  # fmt: skip
    rec = read_recording(f, cmap)
    np.testing.assert_array_equal(rec["torque"], np.arange(30_000) % 997 + 0.25)
    assert any("line 30002" in n for n in rec.metadata["notes"])


_FOOTER_LINE = st.one_of(
    st.sampled_from(["End of data", "Ende der Messung", "Statistics", "***", "EOF"]),
    st.builds(
        lambda word, value: f"{word};{value}",
        st.sampled_from(["Mean", "Max", "Min", "Mittelwert", "RMS"]),
        st.integers(-999, 999).map(str),
    ),
)


@settings(max_examples=40, deadline=None)
@given(
    torque=st.lists(st.integers(-99_999, 99_999), min_size=3, max_size=40),
    header=st.sampled_from(["Zeit;Moment", "Time;1", "t;T", "#;Torque [N.m]"]),
    footer=st.lists(_FOOTER_LINE, max_size=4),
    blank_before_footer=st.booleans(),
)
def test_samples_come_back_whole_with_any_header_and_footer(
    tmp_path_factory, torque, header, footer, blank_before_footer
):
    """Property: a table of samples, under a row of names (words, channel numbers, units) and
    above any footer, is read back sample for sample, every sample and nothing else, by both
    readers; a footer is named in a note."""
    rows = [f"{k / 100:.2f};{v / 100:.2f}".replace(".", ",") for k, v in enumerate(torque)]
    tail = ([""] if blank_before_footer and footer else []) + footer
    f = _write(tmp_path_factory.mktemp("prop") / "run.csv", [header, *rows, *tail])
    name = header.split(";")[1]
    cmap = {"time": {"sample_rate_Hz": 100.0}, "channels": {
        "torque": {"column": name.removesuffix(" [N.m]"), "unit": "N.m"}}}  # fmt: skip
    rec = read_recording(f, cmap)
    np.testing.assert_array_equal(rec["torque"], np.array(torque) / 100)
    assert any("footer" in n for n in rec.metadata["notes"]) == bool(footer)
    with open_recording(f, cmap) as src:
        chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 5)])
    np.testing.assert_array_equal(chunked, rec["torque"])


@pytest.mark.parametrize(
    ("tail", "last_cells"),
    [
        ([";", ";;"], None),  # Excel's empty rows: blank, not a footer
        ([], "event"),  # an event column's text in the last samples
        ([], "OPEN"),  # an unmapped sensor's text
    ],
)
def test_text_beside_the_numbers_at_the_end_is_no_footer(tmp_path, tail, last_cells):
    """Only text in the lead (time) column makes a footer: a review found the last samples of
    files with an event column, or followed by separator-only rows, dropped as one."""
    rows = [f"{k // 100},{k % 100:02d};{k},5;" for k in range(40)]
    if last_cells:
        rows[-5:] = [r + last_cells for r in rows[-5:]]
    f = _write(tmp_path / "end.csv", ["Zeit;Moment;Ereignis", *rows, *tail])
    rec = read_recording(f, _torque_map(time="Zeit", torque="Moment"))
    np.testing.assert_array_equal(rec["torque"], np.arange(40) + 0.5)
    assert not any("footer" in n for n in rec.metadata["notes"])


def test_a_stray_error_cell_in_the_last_sample_is_still_an_error(tmp_path):
    rows = [f"0,{k:02d};{k},5" for k in range(10)] + ["0,10;ERR"]
    f = _write(tmp_path / "err.csv", ["Zeit;Moment", *rows])
    with pytest.raises(RecordingError, match=r"'ERR' \(file line 12\)"):
        read_recording(f, _torque_map(time="Zeit", torque="Moment"))


def test_text_in_an_unmapped_column_of_the_first_samples_keeps_them_samples(tmp_path):
    """A thermocouple reading 'OPEN' for the first samples: the rows stay samples (a review
    found them taken as the header)."""
    rows = [f"0,{k:02d};{k},5;" + ("OPEN" if k < 5 else f"2{k % 10},5") for k in range(40)]
    f = _write(tmp_path / "open.csv", ["Zeit;Moment;Temp", *rows])
    rec = read_recording(f, _torque_map(time="Zeit", torque="Moment"))
    np.testing.assert_array_equal(rec["torque"], np.arange(40) + 0.5)


def test_times_of_day_over_more_than_a_day_read_in_parts_as_whole(tmp_path):
    """An endurance run logged with times of day only, 30 h from 08:00 (0.1 Hz): read in parts
    it is the whole read, 107 990 s long. A part more than 12 h after the first sample (past
    midnight: a step back of less than 12 h from 08:00) was refused as time going backwards."""
    rows = [f"{(8 * 3600 + 10 * k) // 3600 % 24:02d}:{(10 * k) // 60 % 60:02d}:{10 * k % 60:02d};"
            f"{k % 100},5" for k in range(10_800)]  # fmt: skip
    f = _write(tmp_path / "endurance.csv", ["Uhrzeit;Moment", *rows])
    cmap = {"time": {"column": "Uhrzeit"}, "channels": {"torque": {"column": "Moment",
            "unit": "N.m"}}}  # fmt: skip
    whole = read_recording(f, cmap).time
    np.testing.assert_array_equal(whole, 10.0 * np.arange(10_800))
    with open_recording(f, cmap) as src:
        parts = np.concatenate([c.time for c in src.iter_chunks(("torque",), 1000)])
    np.testing.assert_array_equal(parts, whole)


def test_lone_cr_line_ends_with_a_blank_line_above_the_numbers_lose_no_sample(tmp_path):
    """Mac Excel's "CSV (Macintosh)" (lines ending in a lone CR) under a preamble with a blank
    line: pandas' C reader counted the blank line's CR CR as one line end when skipping rows,
    and the first sample was lost in both readers, without a word."""
    rows = [f"0,{k:03d};{k},5" for k in range(10)]
    f = tmp_path / "mac.csv"
    f.write_bytes("\r".join(["Recorder X", "", "t;T", *rows, ""]).encode())
    rec = read_recording(f, _torque_map())
    np.testing.assert_array_equal(rec["torque"], np.arange(10) + 0.5)
    with open_recording(f, _torque_map()) as src:
        chunked = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 3)])
    np.testing.assert_array_equal(chunked, rec["torque"])


def test_a_row_of_nan_words_is_a_sample_in_both_readers(tmp_path):
    """'NaN;NaN' (every sensor out at one instant) is a sample of missing values: the chunked
    reader dropped it as a blank line, so with a sample-rate map every later sample came one
    period early; now it refuses it (chunked reading is strict), as read_recording does."""
    rows = [f"{k},25;{k},5" for k in range(10)]
    rows[5] = "NaN;NaN"
    f = _write(tmp_path / "gap.csv", ["A;T", *rows])
    cmap = {"time": {"sample_rate_Hz": 100.0}, "channels": {
        "torque": {"column": "T", "unit": "N.m"}}}  # fmt: skip
    with pytest.raises(RecordingError, match=r"NaN/inf samples? .*5"):
        read_recording(f, cmap)
    assert read_recording(f, cmap, validate="lenient")["torque"].size == 10
    with pytest.raises(RecordingError, match="NaN/inf sample at sample 5"):
        with open_recording(f, cmap) as src:
            list(src.iter_chunks(("torque",), 3))


def test_durations_with_their_unit_in_each_cell_are_seconds(tmp_path):
    """MATLAB's ``writetimetable`` writes a timetable's row times as durations with the unit
    in the cell ('0.001 sec'); they were refused as non-numeric."""
    rows = [f"{k / 1000:g} sec,{k}" for k in range(100)]
    f = _write(tmp_path / "tt.csv", ["Time,T", *rows])
    rec = read_recording(f, _torque_map(time="Time"))
    np.testing.assert_allclose(rec.time, np.arange(100) / 1000, rtol=0, atol=1e-15)
    assert any("durations" in n for n in rec.metadata["notes"])


def test_durations_with_thousands_marks_are_read_by_the_files_mark(tmp_path):
    """'1,000 sec' under a decimal point is 1000 s (a review found a traceback)."""
    rows = [f'"{k:,} sec",{k}' for k in range(998, 1003)]
    f = _write(tmp_path / "tt.csv", ["Time,T", "0.5 sec,0", *rows])
    rec = read_recording(f, _torque_map(time="Time"), validate="lenient")
    np.testing.assert_allclose(rec.time[1:3], [998.0, 999.0])
    assert rec.time[-1] == 1002.0


def test_one_headerless_column_of_decimal_commas_is_not_two_columns_of_integers(tmp_path):
    """``0,0000`` / ``29,5520`` without names: read as two integer columns (separator ','),
    every decimal was lost (29.552 N.m read as 29). Refused as ambiguous; the map's layout
    reads it."""
    f = _write(tmp_path / "one.csv", ["0,0000", "29,5520", "56,4640"])
    cmap = {"time": {"sample_rate_Hz": 10.0}, "channels": {
        "torque": {"column": "column 1", "unit": "N.m"}}}  # fmt: skip
    with pytest.raises(RecordingError, match="one number with a decimal comma"):
        read_recording(f, cmap)
    rec = read_recording(f, {**cmap, "file": {"separator": ";", "decimal": ","}})
    np.testing.assert_allclose(rec["torque"], [0.0, 29.552, 56.464])
