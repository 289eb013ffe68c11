"""Excel workbooks (.xlsx): rollerrig.recordings.formats.xlsx, through read_recording."""

from __future__ import annotations

import datetime as dt
import zipfile

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rollerrig.recordings import readers
from rollerrig.recordings.channels import FileSpec
from rollerrig.recordings.formats.xlsx import read_xlsx
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import RecordingError

openpyxl = pytest.importorskip("openpyxl")

MAP = {
    "time": {"column": "Time", "unit": "s"},
    "channels": {
        "torque": {"column": "Torque", "unit": "N.m"},
        "roller_speed": {"column": "Speed", "unit": "rpm"},
    },
}


def _catman(path, n=200, sheet="Data"):
    """A catman-style sheet: metadata rows, names, units, time in s, a footer."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = sheet
    ws.append(["catman Export", None, None])
    ws.append(["Measurement", "Rolle 7", None])
    ws.append([])
    ws.append(["Time", "Torque", "Speed"])
    ws.append(["s", "N.m", "1/min"])
    for k in range(n):
        ws.append([k * 0.001, 10.0 + 0.01 * k, 60.0])
    ws.append(["End of measurement"])
    return wb, ws


def test_catman_sheet_with_metadata_names_units_and_footer(tmp_path):
    wb, _ = _catman(tmp_path)
    wb.save(tmp_path / "run.xlsx")
    rec = read_recording(tmp_path / "run.xlsx", MAP)
    assert rec.time.size == 200
    np.testing.assert_allclose(np.diff(rec.time), 1e-3, atol=1e-12)
    np.testing.assert_allclose(rec["roller_speed"], 60.0 * 2 * np.pi / 60)
    notes = " ".join(rec.metadata["notes"])
    assert "units row" in notes and "footer" in notes
    assert rec.metadata["format"] == "xlsx"


def test_dewesoft_datetime_column_at_1_kHz_keeps_the_sample_interval(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time", "Torque [N.m]", "Speed [rpm]"])
    t0 = dt.datetime(2024, 5, 1, 12, 0, 0)
    for k in range(2000):
        ws.append([t0 + dt.timedelta(milliseconds=k), 1.0, 60.0])
    for (cell,) in ws.iter_rows(min_row=2, max_col=1):
        cell.number_format = "yyyy-mm-dd hh:mm:ss.000"
    wb.save(tmp_path / "dew.xlsx")
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    rec = read_recording(tmp_path / "dew.xlsx", cmap, channels=["torque"])
    # a day number is stored to ~0.86 µs (16 digits): each time within 1 µs, the interval exact
    assert abs(np.median(np.diff(rec.time)) - 1e-3) < 1e-6
    np.testing.assert_allclose(rec.time, np.arange(2000) * 1e-3, atol=1e-6)
    table = read_xlsx(tmp_path / "dew.xlsx")
    assert table.load("Time").values.dtype == np.dtype("datetime64[us]")


def test_datetimes_rounded_to_the_millisecond_are_refused_with_a_numeric_time_hint(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time", "Torque"])
    t0 = dt.datetime(2024, 5, 1, 12, 0, 0)
    for k in range(300):  # 3 kHz, as Excel shows it: to the millisecond
        ws.append([t0 + dt.timedelta(milliseconds=round(k / 3)), 1.0])
    wb.save(tmp_path / "ms.xlsx")
    with pytest.raises(RecordingError, match=r"rounded to the millisecond.*column of numbers"):
        read_xlsx(tmp_path / "ms.xlsx").load("Time")


def test_datetimes_too_fine_for_the_day_number_are_refused(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time", "Torque"])
    t0 = dt.datetime(2024, 5, 1, 12, 0, 0)
    for k in range(300):  # 100 kHz
        ws.append([t0 + dt.timedelta(microseconds=10 * k), 1.0])
    wb.save(tmp_path / "fast.xlsx")
    with pytest.raises(RecordingError, match=r"too coarse.*column of numbers"):
        read_xlsx(tmp_path / "fast.xlsx").load("Time")


def test_time_of_day_and_duration_cells_are_seconds(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Clock", "Elapsed", "Torque"])
    for k in range(10):
        ws.append([dt.time(23, 59, 59, 600_000) if k == 0 else dt.time(0, 0, k - 1, 600_000),
                   dt.timedelta(seconds=k), 1.0])  # fmt: skip
    wb.save(tmp_path / "tod.xlsx")
    table = read_xlsx(tmp_path / "tod.xlsx")
    clock = table.load("Clock").values / np.timedelta64(1, "s")
    np.testing.assert_allclose(np.diff(clock), 1.0, atol=1e-6)
    elapsed = table.load("Elapsed").values / np.timedelta64(1, "s")
    np.testing.assert_allclose(elapsed, np.arange(10.0), atol=1e-6)
    assert any("midnight" in n for n in table.notes)


def test_units_in_brackets(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time [ms]", "Torque [kN.m]", "Speed (rpm)"])
    for k in range(20):
        ws.append([4 * k, 0.5, 60])
    wb.save(tmp_path / "br.xlsx")
    table = read_xlsx(tmp_path / "br.xlsx")
    assert [table.load(n).unit for n in table.names] == ["ms", "kN.m", "rpm"]
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    rec = read_recording(tmp_path / "br.xlsx", cmap, channels=["torque"])
    np.testing.assert_allclose(np.diff(rec.time), 4e-3)
    np.testing.assert_allclose(rec["torque"], 500.0)


def test_two_sheets_first_with_data_read_and_the_other_named_or_chosen(tmp_path):
    wb, _ = _catman(tmp_path, sheet="Fast")
    cover = wb.create_sheet("Cover", 0)
    cover.append(["Test report"])
    cover.append(["Operator", "Smith"])
    slow = wb.create_sheet("Slow")
    slow.append(["Time", "Torque", "Speed"])
    for k in range(10):
        slow.append([k * 0.1, 2.0, 30.0])
    wb.save(tmp_path / "two.xlsx")
    table = read_xlsx(tmp_path / "two.xlsx")
    assert table.load("Time").values.size == 200
    assert any("'Slow'" in n and "[file]" in n for n in table.notes)
    for sheet in ("Slow", 2):
        rec = read_recording(tmp_path / "two.xlsx", {**MAP, "file": {"sheet": sheet}})
        assert rec.time.size == 10
    with pytest.raises(RecordingError, match=r"not a sheet.*Cover"):
        read_recording(tmp_path / "two.xlsx", {**MAP, "file": {"sheet": "Nope"}})
    with pytest.raises(RecordingError, match="3 sheet"):
        read_xlsx(tmp_path / "two.xlsx", FileSpec(sheet=5))


def test_the_sheet_with_the_most_rows_of_numbers_is_read_and_named(tmp_path):
    # a 3-row summary before the data sheet was read (3 samples, only a note)
    wb = openpyxl.Workbook()
    summary = wb.active
    summary.title = "Summary"
    summary.append(["Time", "Torque"])
    for k in range(3):
        summary.append([k, 5.0 + k])
    data = wb.create_sheet("Data")
    for k in range(250):  # a parameter block deeper than the first 200 rows
        data.append([f"param{k}", f"value {k}"])
    data.append(["Time", "Torque"])
    for k in range(100):
        data.append([k * 0.01, float(k)])
    wb.save(tmp_path / "cover.xlsx")
    torque = {**MAP, "channels": {"torque": MAP["channels"]["torque"]}}
    rec = read_recording(tmp_path / "cover.xlsx", torque)
    assert rec.time.size == 100
    notes = " ".join(rec.metadata["notes"])
    assert "sheet 'Data' read: the most rows of numbers" in notes and "'Summary'" in notes
    # a column the sheet read lacks: the error names the sheets and which has it
    wb.create_sheet("Other").append(["Speed", 1.0])
    wb.save(tmp_path / "cover.xlsx")
    cmap = {**MAP, "channels": {"roller_speed": {"column": "Speed", "unit": "rpm"}}}
    told = r"sheet 'Data' was read.*'Other' \(has a column 'Speed'\).*\[file\] sheet = 'Other'"
    with pytest.raises(RecordingError, match=told):
        read_recording(tmp_path / "cover.xlsx", cmap)


def test_text_in_a_numeric_column_names_the_cell(tmp_path):
    wb, ws = _catman(tmp_path)
    ws["B17"] = "ERR"
    wb.save(tmp_path / "err.xlsx")
    with pytest.raises(RecordingError, match=r"Data!B17 holds 'ERR' in column 'Torque'"):
        read_recording(tmp_path / "err.xlsx", MAP)


def test_numbers_stored_as_text_with_a_decimal_comma_are_read(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time", "Torque"])
    for k in range(20):
        ws.append([k * 0.1, f"{1.5 + k:.1f}".replace(".", ",")])
    wb.save(tmp_path / "de.xlsx")
    torque = {**MAP, "channels": {"torque": MAP["channels"]["torque"]}}
    rec = read_recording(tmp_path / "de.xlsx", torque)
    np.testing.assert_allclose(rec["torque"], 1.5 + np.arange(20))
    assert any("decimal comma" in n and "Sheet!B2" in n for n in rec.metadata["notes"])
    for k in range(20):  # '1,500' alone is ambiguous: the map's [file] decimal decides
        ws.cell(row=k + 2, column=2, value="1,500")
    wb.save(tmp_path / "de3.xlsx")
    rec = read_recording(tmp_path / "de3.xlsx", {**torque, "file": {"decimal": ","}})
    np.testing.assert_allclose(rec["torque"], 1.5)


def test_a_number_stored_as_text_and_excel_error_cells(tmp_path):
    wb, ws = _catman(tmp_path)
    ws["B17"] = "6.5"  # Excel's green triangle: a number stored as text
    ws["C20"] = "#DIV/0!"
    wb.save(tmp_path / "mix.xlsx")
    table = read_xlsx(tmp_path / "mix.xlsx")
    assert table.load("Torque").values[11] == 6.5 and np.isnan(table.load("Speed").values[14])
    rec = read_recording(tmp_path / "mix.xlsx", MAP, validate="lenient")
    notes = " ".join(rec.metadata["notes"])
    assert "1 number(s) stored as text read as numbers (first: Data!B17" in notes
    assert "1 Excel error cell(s) read as missing samples (first: Data!C20 '#DIV/0!')" in notes


def test_a_signature_or_comment_beside_the_columns_is_no_reason_to_refuse(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time", "Torque"])
    for k in range(30):
        ws.append([k * 0.1, float(k)])
    ws.append([])
    ws.append(["Tester:", None, None, "Signed JK"])  # D has no name: footer material
    wb.save(tmp_path / "signed.xlsx")
    table = read_xlsx(tmp_path / "signed.xlsx")
    assert table.load("Torque").values.size == 30
    assert any("footer" in n for n in table.notes)
    ws["A33"] = None  # the signature alone, in a column without numbers: ignored, noted
    wb.save(tmp_path / "comment.xlsx")
    table = read_xlsx(tmp_path / "comment.xlsx")
    assert table.load("Torque").values.size == 30
    assert any("ignored (first: Sheet!D33 'Signed JK')" in n for n in table.notes)


def test_formulas_without_saved_values_are_refused_with_what_to_do(tmp_path):
    wb = openpyxl.Workbook()  # written by a script: formulas, never computed by Excel
    ws = wb.active
    ws.append(["Time", "Raw", "Torque"])
    for k in range(100):
        ws.append([k * 0.01, float(k), f"=B{k + 2}*2"])
    wb.save(tmp_path / "formula.xlsx")
    cmap = {**MAP, "channels": {"torque": MAP["channels"]["torque"]}}
    with pytest.raises(RecordingError, match=r"column 'Torque' are formulas without saved values"
                       r" \(100 cells, first Sheet!C2\).*save the workbook in Excel"):  # fmt: skip
        read_recording(tmp_path / "formula.xlsx", cmap)


def test_nan_words_and_empty_cells_are_missing_samples(tmp_path):
    wb, ws = _catman(tmp_path)
    ws["B17"] = "#N/A"
    ws["C18"] = None
    wb.save(tmp_path / "nan.xlsx")
    table = read_xlsx(tmp_path / "nan.xlsx")
    assert np.isnan(table.load("Torque").values[11]) and np.isnan(table.load("Speed").values[12])


def test_merged_header_cells_are_refused(tmp_path):
    wb, ws = _catman(tmp_path)
    ws.merge_cells("A1:C1")  # a merged title above the names is fine
    wb.save(tmp_path / "title.xlsx")
    assert read_xlsx(tmp_path / "title.xlsx").names == ["Time", "Torque", "Speed"]
    ws.merge_cells("B4:C4")
    wb.save(tmp_path / "merged.xlsx")
    with pytest.raises(RecordingError, match=r"merged cells Data!B4:C4 .*unmerge"):
        read_xlsx(tmp_path / "merged.xlsx")


def test_a_sheet_without_numbers_is_refused(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Operator", "Smith"])
    ws.append(["Comment", "no data"])
    wb.save(tmp_path / "text.xlsx")
    with pytest.raises(RecordingError, match="no sheet holds numbers"):
        read_xlsx(tmp_path / "text.xlsx")
    with pytest.raises(RecordingError, match="holds no numbers"):
        read_xlsx(tmp_path / "text.xlsx", FileSpec(sheet=0))


def test_xls_ods_encrypted_and_corrupt_files_say_what_to_do(tmp_path):
    ole = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + bytes(504)
    (tmp_path / "old.xls").write_bytes(ole)
    with pytest.raises(RecordingError, match=r"\.xls.*Save As.*\.xlsx"):
        readers.detect_format(tmp_path / "old.xls")
    (tmp_path / "renamed.xlsx").write_bytes(ole)
    with pytest.raises(RecordingError, match="Excel 97-2003"):
        read_recording(tmp_path / "renamed.xlsx", MAP)
    (tmp_path / "locked.xlsx").write_bytes(ole + "EncryptedPackage".encode("utf-16-le"))
    with pytest.raises(RecordingError, match="password-protected"):
        read_recording(tmp_path / "locked.xlsx", MAP)
    with pytest.raises(RecordingError, match=r"\.ods.*Save As"):
        readers.detect_format(tmp_path / "calc.ods")
    with zipfile.ZipFile(tmp_path / "calc.xlsx", "w") as z:
        z.writestr("mimetype", "application/vnd.oasis.opendocument.spreadsheet")
    with pytest.raises(RecordingError, match="OpenDocument"):
        read_recording(tmp_path / "calc.xlsx", MAP)
    (tmp_path / "cut.xlsx").write_bytes(b"PK\x03\x04" + bytes(100))
    with pytest.raises(RecordingError, match=r"not a readable Excel workbook.*corrupt"):
        read_recording(tmp_path / "cut.xlsx", MAP)


def test_sheet_index_in_tab_order_quoted_merged_sheet_and_a_renamed_csv(tmp_path):
    from openpyxl.chart import LineChart, Reference

    wb, ws = _catman(tmp_path, sheet="Run 7")
    chart = wb.create_chartsheet("Chart", 0)  # tab 0: a chart sheet, no cells
    plot = LineChart()
    plot.add_data(Reference(ws, min_col=2, min_row=4, max_row=20), titles_from_data=True)
    chart.add_chart(plot)
    wb.save(tmp_path / "chart.xlsx")
    assert read_recording(tmp_path / "chart.xlsx", {**MAP, "file": {"sheet": 1}}).time.size == 200
    with pytest.raises(RecordingError, match=r"sheet = 0 is the chart sheet 'Chart'"):
        read_recording(tmp_path / "chart.xlsx", {**MAP, "file": {"sheet": 0}})
    ws.merge_cells("B4:C4")
    wb.save(tmp_path / "merged.xlsx")
    with pytest.raises(RecordingError, match=r"merged cells 'Run 7'!B4:C4 "):
        read_recording(tmp_path / "merged.xlsx", MAP)
    (tmp_path / "csv.xlsx").write_text("Time,Torque\n0,1\n0.1,2\n")
    with pytest.raises(RecordingError, match=r"not an Excel workbook: the file is text.*\.csv"):
        read_recording(tmp_path / "csv.xlsx", MAP)


def test_missing_openpyxl_names_the_io_extra(tmp_path, monkeypatch):
    import builtins

    wb, _ = _catman(tmp_path)
    wb.save(tmp_path / "run.xlsx")
    real = builtins.__import__

    def no_openpyxl(name, *args, **kwargs):
        if name == "openpyxl" or name.startswith("openpyxl."):
            raise ImportError("No module named 'openpyxl'")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_openpyxl)
    monkeypatch.delitem(__import__("sys").modules, "openpyxl", raising=False)
    with pytest.raises(ImportError, match=r"rollerrig\[io\]"):
        read_xlsx(tmp_path / "run.xlsx")


def test_a_workbook_reads_as_the_equivalent_csv(tmp_path):
    wb, ws = _catman(tmp_path)
    wb.save(tmp_path / "run.xlsx")
    lines = []
    for row in ws.iter_rows(values_only=True):
        lines.append(",".join("" if v is None else repr(v) if isinstance(v, float) else str(v)
                              for v in row))  # fmt: skip
    (tmp_path / "run.csv").write_text("\n".join(lines) + "\n")
    a = read_recording(tmp_path / "run.xlsx", MAP)
    b = read_recording(tmp_path / "run.csv", MAP)
    # the workbook's floats are the stored ones; pandas' CSV parser may be off by its last bit
    np.testing.assert_allclose(a.time, b.time, rtol=1e-15, atol=1e-18)
    assert set(a.channels) == set(b.channels)
    for name in a.channels:
        np.testing.assert_allclose(a[name], b[name], rtol=1e-15)
    assert a.units == b.units


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.lists(
        st.lists(
            st.floats(
                allow_nan=False, allow_infinity=False, width=64, min_value=-1e12, max_value=1e12
            ),
            min_size=3,
            max_size=3,
        ),
        min_size=2,
        max_size=40,
    )
)
def test_random_numeric_columns_round_trip(tmp_path, rows):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["a", "b", "c"])
    for r in rows:
        ws.append(r)
    path = tmp_path / "h.xlsx"
    wb.save(path)
    table = read_xlsx(path)
    got = np.column_stack([table.load(n).values for n in ("a", "b", "c")])
    np.testing.assert_allclose(got, np.array(rows), rtol=1e-15, atol=0)


TORQUE_ONLY = {"time": {"column": "Time", "unit": "s"},
               "channels": {"torque": {"column": "Torque", "unit": "N.m"}}}  # fmt: skip


def _text_torque(tmp_path, cells, name="text.xlsx"):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["Time", "Torque"])
    for k, cell in enumerate(cells):
        ws.append([k / 100, cell])
    path = tmp_path / name
    wb.save(path)
    return path


def test_text_numbers_that_read_as_thousands_too_are_refused_not_guessed(tmp_path):
    # '1.000', '1.120' beside '850': 1 and 1.12 under a decimal point, 1000 and 1120 under a
    # German thousands mark. They had been read as decimals, 1000 times too small, with a
    # note only (review of 2026-12-03).
    path = _text_torque(tmp_path, [850.0, 920.0, 999.0, "1.000", "1.120", "1.230"])
    with pytest.raises(RecordingError, match=r"1\.000.*\[file\] decimal"):
        read_recording(path, TORQUE_ONLY)
    given = TORQUE_ONLY | {"file": {"decimal": ","}}
    with pytest.raises(RecordingError):  # '1.000' under a decimal comma: a thousands mark
        read_recording(path, given)


def test_text_numbers_with_a_leading_zero_decide_the_decimal_comma(tmp_path):
    # '0,500' cannot hold a thousands mark: the column's comma is decimal (it had been refused
    # as possibly thousands, naming a decimal mark 'given' that nobody gave)
    path = _text_torque(tmp_path, ["0,000", "0,001", "0,500", "1,250"])
    rec = read_recording(path, TORQUE_ONLY)
    np.testing.assert_allclose(rec["torque"], [0.0, 0.001, 0.5, 1.25])


@pytest.mark.parametrize("encoding", ["cp1252", "utf-16", "utf-16-le"])
def test_a_text_export_named_xlsx_in_any_encoding_is_told_to_be_renamed(tmp_path, encoding):
    # a Windows-1252 or UTF-16 export had been called a corrupt workbook (review 2026-12-03)
    path = tmp_path / "export.xlsx"
    body = "Zeit;Moment\r\n" + "".join(f"{k},0;{k},5 Nm ä\r\n" for k in range(50))
    path.write_bytes(body.encode(encoding))
    with pytest.raises(RecordingError, match=r"the file is text.*rename it to \.csv"):
        read_recording(path, TORQUE_ONLY)


def test_a_workbook_cut_short_says_so(tmp_path):
    # a copy that stopped leaves a zip without its central directory: it had been called
    # "no zip archive"
    whole = _text_torque(tmp_path, [float(k) for k in range(2000)], name="whole.xlsx")
    cut = tmp_path / "cut.xlsx"
    cut.write_bytes(whole.read_bytes()[:3000])
    with pytest.raises(RecordingError, match="cut short"):
        read_recording(cut, TORQUE_ONLY)
