"""Text recordings as acquisition software writes them: CSV dialects and LabVIEW .lvm.

Every fixture is written byte by byte here (line ends, encoding, separators and decimal marks as
the tool writes them); the comment above each builder says what it mimics and on what the layout
is based. Expected values follow from the numbers written and the unit definitions
(1 ms = 1e-3 s, 1 µs = 1e-6 s, 1 rpm = 2π/60 rad/s, 1 bar = 1e5 Pa; BIPM SI Brochure, 9th ed.).
Every test that reads a file also checks that the file is unchanged (SHA-256 before and after).
"""

from __future__ import annotations

import datetime as dt
import hashlib
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rollerrig.recordings.channels import ChannelMap
from rollerrig.recordings.formats.sniff import sniff_layout
from rollerrig.recordings.formats.timestamps import parse_timestamps
from rollerrig.recordings.readers import detect_format, read_recording
from rollerrig.recordings.recording import RecordingError

RPM = 2 * math.pi / 60


def _sha(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _read(path, cmap=None, **kw):
    """read_recording, asserting that the file is unchanged."""
    before = _sha(path)
    try:
        return read_recording(path, cmap, **kw)
    finally:
        assert _sha(path) == before


def _raises(path, cmap, pattern, **kw):
    before = _sha(path)
    with pytest.raises(RecordingError, match=pattern):
        read_recording(path, cmap, **kw)
    assert _sha(path) == before


def _write(path, lines, *, eol="\r\n", encoding="utf-8", final_eol=True):
    path.write_bytes((eol.join(lines) + (eol if final_eol else "")).encode(encoding))
    return path


# ---------------------------------------------------------------------------------------------
# Fixtures


# PicoScope 6 "Save As > CSV": header row, units row in parentheses, an empty line, then
# comma-separated numbers with a decimal point; time in ms from before the trigger; CRLF, UTF-8.
# Layout after the PicoScope 6 User's Guide, "Text formats" (Time, Channel A / (ms), (V)).
def picoscope6(tmp_path, n=200, dt_ms=0.1):
    t = -0.5 + dt_ms * np.arange(n)
    a = np.round(0.4 + 0.1 * np.sin(2 * np.pi * t / 5.0), 8)  # as written: 8 decimals
    b = np.round(0.02 * np.cos(2 * np.pi * t / 7.0), 8)
    lines = ["Time,Channel A,Channel B", "(ms),(V),(V)", ""]
    lines += [f"{ti:.8f},{ai:.8f},{bi:.8f}" for ti, ai, bi in zip(t, a, b, strict=True)]
    return _write(tmp_path / "pico6.csv", lines), t, a, b


# PicoScope 7 CSV: same layout without the empty line, time in microseconds "(µs)", UTF-8 with
# a byte-order mark, LF line ends, channel A in mV, and "∞" where the input was over range
# (PicoScope writes the infinity sign for clipped samples).
def picoscope7(tmp_path, n=100, clipped=(40,)):
    t = -50.0 + 2.0 * np.arange(n)  # 2 µs -> 500 kHz
    a = np.round(250.0 + 50.0 * np.sin(t / 30.0), 4)  # mV, as written
    cells = [f"{v:.4f}" for v in a]
    for k in clipped:
        cells[k] = "∞"
    lines = ["Time,Channel A", "(µs),(mV)"]
    lines += [f"{ti:.4f},{c}" for ti, c in zip(t, cells, strict=True)]
    f = tmp_path / "pico7.csv"
    f.write_bytes(b"\xef\xbb\xbf" + ("\n".join(lines) + "\n").encode("utf-8"))
    return f, t, a


# HBM catman ASCII export with German settings: preamble lines "key<TAB>value", an empty line,
# a tab-separated header, a units row (the date column's unit spelled as a format, N·m with a
# middle dot), decimal commas, Windows-1252 text, CRLF; absolute day-first timestamps with
# milliseconds after a comma at 50 Hz. No public description of the layout was found; it follows
# issue 7's description of catman exports (preamble, tab, units row, day-first, decimal comma).
def catman(tmp_path, n=100, start=dt.datetime(2024, 8, 5, 13, 46, 13, 250000)):
    lines = [
        "catman®Easy ASCII-Export",
        "Datei:\tD:\\Messungen\\Rollenprüfstand\\Versuch_05.BIN",
        "Kommentar:\tLaufversuch 40 km/h, Fz = 5 kN",
        "Exportdatum:\t05.08.2024 14:02:11",
        "",
        "Datum/Uhrzeit\tDrehmoment T56\tDrehzahl Rolle\tÖltemperatur",
        "dd.mm.yyyy hh:mm:ss,sss\tN·m\t1/min\t°C",
    ]
    torque = np.round(12.0 + 0.5 * np.sin(np.arange(n) / 7.0), 4)
    speed = 1200.0 + 0.1 * np.arange(n)
    for k in range(n):
        s = start + dt.timedelta(milliseconds=20 * k)
        stamp = s.strftime("%d.%m.%Y %H:%M:%S,") + f"{s.microsecond // 1000:03d}"
        cells = [stamp, f"{torque[k]:.4f}", f"{speed[k]:.1f}", f"{41.2 + 0.01 * k:.2f}"]
        lines.append("\t".join(c.replace(".", ",") if c is not stamp else c for c in cells))
    return _write(tmp_path / "catman.txt", lines, encoding="cp1252"), torque, speed


# DIAdem / German test-bench CSV: ";" separators, decimal commas, a units row whose first cell
# (the date column) is empty, a trailing ";" on every line, two-digit-year day-first timestamps
# at 1 Hz that cross midnight from day 12 to day 13 (a month-first reading would put 12.08. in
# December and make 13.08. invalid), Latin-1 "°C", CRLF. Layout after Windows' German regional
# format (dd.MM.yy HH:mm:ss, list separator ";") as DIAdem and bench software export it.
def german_bench(tmp_path, n=20, start=dt.datetime(2024, 8, 12, 23, 59, 50)):
    lines = [
        "Datum/Uhrzeit;Drehmoment;Drehzahl Rad;Luftfederdruck;Temperatur;",
        ";Nm;U/min;bar;°C;",
    ]
    torque = 20.0 + np.arange(n) * 0.25
    for k in range(n):
        stamp = (start + dt.timedelta(seconds=k)).strftime("%d.%m.%y %H:%M:%S")
        cells = [f"{torque[k]:.2f}", "352,1", f"{0.86 + 0.001 * k:.3f}", "31,50"]
        lines.append(";".join([stamp] + [c.replace(".", ",") for c in cells]) + ";")
    return _write(tmp_path / "bench.csv", lines, encoding="latin-1"), torque


# Vector CANape measurement exported to ASCII/CSV: comment lines starting with ";" before the
# header (tool, source file, start time), a header row starting with "time", a units row without
# brackets (s, Nm, 1/min, bar), "," separators with a decimal point, rasters merged onto 250 Hz.
# No public description of the export was found; modelled on measurement-tool CSV exports
# (names row, units row) and asammdf's CSV export of MDF files (a time column first).
def canape(tmp_path, n=250):
    t = np.arange(n) / 250.0
    torque = np.array([float(f"{v:.9g}") for v in 15.0 + np.sin(2 * np.pi * 3 * t)])
    lines = [
        "; CANape 21.0 ASCII export",
        "; Source: D:\\Messung\\run05.mf4",
        "; Start: 05.08.2024 13:46:13",
        "",
        "time,T56_Torque,n_Roller,p_AirSpring",
        "s,Nm,1/min,bar",
    ]
    lines += [
        f"{ti:.6f},{qi:.9g},1200.5,{2.5 + 0.001 * i:.4f}"
        for i, (ti, qi) in enumerate(zip(t, torque, strict=True))
    ]
    return _write(tmp_path / "canape.csv", lines), t, torque


CANAPE_MAP = {
    "time": {"column": "time"},
    "channels": {
        "torque": {"column": "T56_Torque", "unit": "N.m"},
        "roller_speed": {"column": "n_Roller", "unit": "rpm"},
        "air_spring_pressure": {"column": "p_AirSpring", "unit": "bar"},
        "wheel_speed": {"column": "n_Wheel", "unit": "rpm"},  # not in the file
    },
}


# LabVIEW "Write To Measurement File" (.lvm, writer version 2): file header, then two segments
# (one per call of the Express VI), each with a segment header ended by ***End_of_Header***, a
# column-name row "X_Value ... Comment" and tab-separated rows; X_Columns One (a shared time
# column); the second segment's X values continue the first's; CRLF. Layout after NI's
# "Specification for the LabVIEW Measurement File (.lvm)" and files written by LabVIEW 2013.
def lvm_two_segments(tmp_path, n=50, dx=0.002, restart_after_s=None, name="run.lvm"):
    """``restart_after_s``: the second segment's X restarts at 0 and its header Time is that much
    later (LabVIEW writes each segment's start in its header)."""
    t = np.arange(2 * n) * dx
    torque = 10.0 + np.cos(t * 20.0)
    speed = 600.0 + t
    head = [
        "LabVIEW Measurement\t",
        "Writer_Version\t2",
        "Reader_Version\t2",
        "Separator\tTab",
        "Decimal_Separator\t.",
        "Multi_Headings\tYes",
        "X_Columns\tOne",
        "Time_Pref\tRelative",
        "Operator\trig",
        "Date\t2024/08/05",
        "Time\t13:46:13.2500000000000000000",
        "***End_of_Header***\t",
        "\t",
    ]
    lines = list(head)
    for seg in range(2):
        a, b = seg * n, (seg + 1) * n
        x = t[a:b] if restart_after_s is None or seg == 0 else t[a:b] - t[a]
        clock = (
            "13:46:13.25"
            if restart_after_s is None or seg == 0
            else (
                (
                    dt.datetime(2024, 8, 5, 13, 46, 13, 250000)
                    + dt.timedelta(seconds=restart_after_s)
                ).strftime("%H:%M:%S.%f")
            )
        )
        lines += [
            "Channels\t2\t\t",
            f"Samples\t{n}\t{n}\t",
            "Date\t2024/08/05\t2024/08/05\t",
            f"Time\t{clock}\t{clock}\t",
            "Y_Unit_Label\tN.m\trpm\t",
            "X_Dimension\tTime\tTime\t",
            f"X0\t{x[0]:.16E}\t{x[0]:.16E}\t",
            f"Delta_X\t{dx:.6f}\t{dx:.6f}\t",
            "***End_of_Header***\t\t\t",
            "X_Value\tTorque\tSpeed\tComment",
        ]
        lines += [
            f"{xk:.6f}\t{torque[k]:.6f}\t{speed[k]:.6f}"
            for xk, k in zip(x, range(a, b), strict=True)
        ]
        lines.append("")  # LabVIEW ends a segment with an empty line
    return _write(tmp_path / name, lines), t, torque, speed


# LabVIEW .lvm written on a German-locale PC: Decimal_Separator ",", X_Columns No (each row starts
# with an empty cell; time is X0 + k*Delta_X from the segment header), a Comment cell on some rows,
# two segments whose X0 continue. Layout as above and as in open-source LVM readers' test files
# (e.g. a "short.lvm" with Decimal_Separator "," and X_Columns No).
def lvm_decimal_comma(tmp_path, n=40, dx=0.004):
    head = [
        "LabVIEW Measurement\t",
        "Writer_Version\t2",
        "Reader_Version\t2",
        "Separator\tTab",
        "Decimal_Separator\t,",
        "Multi_Headings\tYes",
        "X_Columns\tNo",
        "Time_Pref\tAbsolute",
        "Date\t2024/08/12",
        "Time\t23:59:59,5",
        "***End_of_Header***\t",
        "\t",
    ]
    torque = 5.0 + 0.01 * np.arange(2 * n)
    lines = list(head)
    for seg in range(2):
        x0 = seg * n * dx
        lines += [
            "Channels\t1\t",
            f"Samples\t{n}\t",
            "Date\t2024/08/12\t",
            "Time\t23:59:59,5\t",
            "Y_Unit_Label\tNm\t",
            "X_Dimension\tTime\t",
            f"X0\t{x0:.16E}\t".replace(".", ","),
            f"Delta_X\t{dx:.6f}\t".replace(".", ","),
            "***End_of_Header***\t\t",
            "X_Value\tDrehmoment\tComment",
        ]
        for k in range(seg * n, (seg + 1) * n):
            row = f"\t{torque[k]:.6f}".replace(".", ",")
            lines.append(row + ("\tStart" if k == 0 else ""))
        lines.append("")
    return _write(tmp_path / "de.lvm", lines), torque, dx


# ---------------------------------------------------------------------------------------------
# CSV dialects


@pytest.mark.parametrize("explicit", [False, True])
def test_picoscope6_units_row_blank_line_ms(tmp_path, explicit):
    f, t, a, b = picoscope6(tmp_path)
    cmap = {
        "time": {"column": "Time"},  # unit from the units row: (ms)
        "channels": {"torque": {"column": "Channel A", "unit": "N.m", "scale": 50.0}},
        "extra": {"laser": {"column": "Channel B", "unit": "V"}},
    }
    if explicit:
        cmap["file"] = {"separator": ",", "decimal": ".", "header_row": 0, "units_row": 1}
    rec = _read(f, cmap)
    np.testing.assert_allclose(rec.time, t * 1e-3, atol=1e-12)  # pre-trigger time kept
    np.testing.assert_allclose(rec["torque"], 50.0 * a, rtol=1e-12)
    np.testing.assert_allclose(rec["laser"], b, rtol=1e-12)
    assert rec.metadata["source_units"] == {"time": "ms", "torque": "N.m", "laser": "V"}
    assert rec.metadata["channel_map"].get("file") == cmap.get("file")
    assert rec.sample_rate == pytest.approx(10_000.0)


@pytest.mark.parametrize("mark", ['in"', "″", "'"])
def test_a_units_row_with_an_inch_or_arc_second_mark_is_a_units_row(tmp_path, mark):
    """A units row whose cell holds an inch's (or arc minute's) mark had been taken for the
    names: the channels' names were then 's', 'N.m' and the mark, and the map's 'Time' was
    missing."""
    lines = ["Time,Torque,Travel", f"s,N.m,{mark}"]
    lines += [f"{k * 1e-3:.3f},{100.0 + k:.1f},{0.5 * k:.2f}" for k in range(50)]
    f = _write(tmp_path / "inch.csv", lines)
    lay = sniff_layout(f)
    assert lay.names == ("Time", "Torque", "Travel") and lay.units[:2] == ("s", "N.m")
    rec = _read(f, {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}})
    np.testing.assert_allclose(rec["torque"][:3], [100.0, 101.0, 102.0])


def test_sniff_layout_of_picoscope6(tmp_path):
    f, *_ = picoscope6(tmp_path)
    lay = sniff_layout(f)
    assert (lay.separator, lay.decimal) == (",", ".")
    assert lay.names == ("Time", "Channel A", "Channel B")
    assert lay.units == ("ms", "V", "V")
    assert (lay.header_line, lay.units_line, lay.data_line) == (0, 1, 3)


def test_a_row_of_missing_values_inside_the_data_is_a_row_not_a_second_recording(tmp_path):
    """A sample whose every cell is NaN ended the block of numbers, and the rows above it were
    reported as "rows of numbers above the header ... recordings appended to one file?"."""
    rows = [f"{k / 250:.3f},{k * 0.5:.2f}" for k in range(40)]
    rows[20] = "nan,nan"
    f = tmp_path / "nanrow.csv"
    f.write_text("time [s],torque [N.m]\n" + "\n".join(rows) + "\n")
    lay = sniff_layout(f)
    assert (lay.header_line, lay.data_line) == (0, 1)
    with pytest.raises(RecordingError, match=r"time stamp 20 \(of 40\) is nan"):
        read_recording(f)


def test_a_nan_time_stamp_names_the_file_as_given(tmp_path, monkeypatch):
    """The message named the sample but not the file, which matters when many are read."""
    rows = [f"{k / 250:.3f},{k * 0.5:.2f}" for k in range(40)]
    rows[20] = ",10.00"  # an empty time cell
    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "nantime.csv").write_text("time [s],torque [N.m]\n" + "\n".join(rows))
    monkeypatch.chdir(tmp_path)
    given_as = str(Path("runs") / "nantime.csv")
    with pytest.raises(RecordingError) as info:
        read_recording(given_as)
    assert str(info.value).startswith(f"{given_as}: time stamp 20 (of 40) is nan")


def test_picoscope7_bom_microseconds_and_infinity(tmp_path):
    f, t, a = picoscope7(tmp_path)
    cmap = {
        "time": {"column": "Time"},
        "channels": {"torque": {"column": "Channel A", "unit": "N.m", "scale": 0.1}},
    }
    _raises(f, cmap, r"channel 'torque' has 1 NaN/inf samples.*samples 40\.\.40")
    rec = _read(f, cmap, validate="lenient")
    np.testing.assert_allclose(rec.time, t * 1e-6, atol=1e-15)
    assert rec.metadata["source_units"]["time"] == "us"
    expected = 0.1 * a
    expected[40] = 0.5 * (expected[39] + expected[41])
    np.testing.assert_allclose(rec["torque"], expected, rtol=1e-9)
    assert rec.metadata["interpolated"][0]["first_sample"] == 40


@pytest.mark.parametrize("explicit", [False, True])
def test_catman_preamble_tab_units_row_decimal_comma_dayfirst(tmp_path, explicit):
    f, torque, speed = catman(tmp_path)
    cmap = {
        "time": {"column": "Datum/Uhrzeit"},
        "channels": {
            "torque": {"column": "Drehmoment T56"},  # unit from the units row: N·m
            "roller_speed": {"column": "Drehzahl Rolle"},  # 1/min
        },
        "extra": {"oil_temperature": {"column": "Öltemperatur", "unit": "°C"}},
    }
    if explicit:
        cmap["file"] = {
            "separator": "\t",
            "decimal": ",",
            "header_row": 5,
            "units_row": 6,
            "data_row": 7,
            "encoding": "cp1252",
            "date_format": "%d.%m.%Y %H:%M:%S,%f",
        }
    rec = _read(f, cmap)
    np.testing.assert_allclose(rec.time, 0.02 * np.arange(100), atol=1e-9)
    np.testing.assert_allclose(rec["torque"], np.round(torque, 4), rtol=1e-12)
    np.testing.assert_allclose(rec["roller_speed"], np.round(speed, 1) * RPM, rtol=1e-12)
    np.testing.assert_allclose(rec["oil_temperature"][:2], [41.2, 41.21])
    notes = " ".join(rec.metadata["notes"])
    if not explicit:
        assert "Latin-1" in notes and "decimal commas" in notes and "units row" in notes
        assert "day-first" in notes and "2024-08-05 13:46:13.250" in notes


def test_german_bench_dates_cross_midnight_and_day_12_to_13(tmp_path):
    f, torque = german_bench(tmp_path)
    cmap = {
        "time": {"column": "Datum/Uhrzeit"},
        "channels": {
            "torque": {"column": "Drehmoment", "unit": "N.m"},
            "air_spring_pressure": {"column": "Luftfederdruck", "unit": "bar"},
        },
    }
    rec = _read(f, cmap)
    np.testing.assert_array_equal(rec.time, np.arange(20.0))  # one format for every row
    np.testing.assert_allclose(rec["torque"], torque, rtol=1e-12)
    np.testing.assert_allclose(rec["air_spring_pressure"][:2], [0.86e5, 0.861e5], rtol=1e-12)
    assert any("day-first (dotted date)" in n for n in rec.metadata["notes"])
    lay = sniff_layout(f)
    assert lay.separator == ";" and lay.decimal == "," and lay.trailing
    assert lay.units == (None, "Nm", "U/min", "bar", "°C")


def test_slash_dates_are_day_first_when_a_day_exceeds_12_else_need_dayfirst(tmp_path):
    start = dt.datetime(2024, 8, 12, 23, 59, 58)
    stamps = [(start + dt.timedelta(seconds=k)).strftime("%d/%m/%Y %H:%M:%S") for k in range(4)]
    lines = ["Date;T"] + [f"{s};{k}" for k, s in enumerate(stamps)]
    f = _write(tmp_path / "slash.csv", lines)
    cmap = {"time": {"column": "Date"}, "channels": {"torque": {"column": "T", "unit": "N.m"}}}
    rec = _read(f, cmap)  # 13/08 exists in the column: day-first for every row
    np.testing.assert_array_equal(rec.time, [0.0, 1.0, 2.0, 3.0])
    # only days <= 12: month-first unless the map says dayfirst; both read consistently
    g = _write(
        tmp_path / "ambiguous.csv", ["Date;T", "05/08/2024 13:46:13;1", "06/08/2024 13:46:13;2"]
    )
    month_first = _read(g, cmap)
    assert month_first.time[1] == pytest.approx(31 * 86400.0)  # 8 May -> 8 June
    assert any("AMBIGUOUS" in n for n in month_first.metadata["notes"])
    day_first = _read(g, {**cmap, "file": {"dayfirst": True}})
    assert day_first.time[1] == pytest.approx(86400.0)


def test_date_format_beats_sniffing_and_names_the_bad_row(tmp_path):
    f = _write(
        tmp_path / "fmt.csv", ["t;T", "2024|08|05 13-46-13;1", "2024|08|05 13-46-14;2", "oops;3"]
    )
    cmap = {
        "file": {"date_format": "%Y|%m|%d %H-%M-%S"},
        "time": {"column": "t"},
        "channels": {"torque": {"column": "T", "unit": "N.m"}},
    }
    _raises(f, cmap, r"row 2 \(file line 4\) 'oops' does not match \[file\] date_format")


def test_a_row_with_another_date_format_is_named(tmp_path):
    f = _write(
        tmp_path / "mixed.csv",
        ["t;T", "05.08.24 13:46:13;1", "05.08.24 13:46:14;2", "2024-08-05 13:46:15;3"],
    )
    cmap = {"time": {"column": "t"}, "channels": {"torque": {"column": "T", "unit": "N.m"}}}
    _raises(f, cmap, r"row 2 \(file line 4\) '2024-08-05 13:46:15' does not have the format")


def test_canape_comment_preamble_units_row_channels_and_optional(tmp_path):
    f, t, torque = canape(tmp_path)
    # every entry needed (no channels=): the missing wheel speed is an error with close matches
    _raises(f, CANAPE_MAP, r"\[channels.wheel_speed\].*'n_Wheel', which is not in the file")
    # a command that needs only the torque reads what is there and notes the rest
    rec = _read(f, CANAPE_MAP, channels=["torque"])
    np.testing.assert_allclose(rec.time, t, atol=1e-12)
    np.testing.assert_allclose(rec["torque"], torque, rtol=1e-8)
    assert "roller_speed" in rec and "wheel_speed" not in rec
    assert any(
        "[channels.wheel_speed] (not needed here) not read" in n for n in rec.metadata["notes"]
    )
    # optional = true: the same without channels=
    opt = {**CANAPE_MAP, "channels": {**CANAPE_MAP["channels"]}}
    opt["channels"]["wheel_speed"] = {"column": "n_Wheel", "unit": "rpm", "optional": True}
    rec = _read(f, opt)
    assert any("(optional) not read" in n for n in rec.metadata["notes"])
    assert rec.metadata["channel_map"]["channels"]["wheel_speed"]["optional"] is True
    # a needed channel is still an error, optional or not
    _raises(f, opt, r"\[channels.wheel_speed\].*not in the file", channels=["wheel_speed"])


def test_txt_suffix_and_whitespace_separator(tmp_path):
    # a fixed-width ASCII table (space-separated, as DASYLab / older loggers write it)
    lines = ["  Time      Torque", "  0.000     1.50", "  0.004     1.60", "  0.008     1.70"]
    f = _write(tmp_path / "ascii.txt", lines, eol="\n")
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque", "unit": "N.m"}}}
    rec = _read(f, cmap)
    np.testing.assert_allclose(rec["torque"], [1.5, 1.6, 1.7])
    assert detect_format(f) == "csv"


def test_explicit_rows_beat_a_misleading_preamble(tmp_path):
    # a preamble line with the same number of cells as the data and a header of numbers-only
    lines = ["Samples;3", "1;2", "0;10", "1;11", "2;12"]
    f = _write(tmp_path / "rows.csv", lines, eol="\n")
    cmap = {
        "file": {"separator": ";", "header_row": 1, "units_row": False, "data_row": 2},
        "time": {"column": "1", "unit": "ms"},
        "channels": {"torque": {"column": "2", "unit": "N.m"}},
    }
    rec = _read(f, cmap)
    np.testing.assert_allclose(rec.time, [0.0, 1e-3, 2e-3])
    np.testing.assert_allclose(rec["torque"], [10.0, 11.0, 12.0])
    # header_row alone is enough: the numbers are looked for below it
    del cmap["file"]["data_row"], cmap["file"]["units_row"]
    rec = _read(f, cmap)
    np.testing.assert_allclose(rec["torque"], [10.0, 11.0, 12.0])


# ---------------------------------------------------------------------------------------------
# Stated rates


def test_stated_rate_contradicting_the_time_column_is_an_error(tmp_path):
    f, *_ = canape(tmp_path)  # a 250 Hz time column
    cmap = {
        "time": {"sample_rate_Hz": 2000},
        "channels": {"torque": {"column": "T56_Torque", "unit": "N.m"}},
    }
    _raises(f, cmap, r"sample_rate_Hz = 2000 Hz.*contradicts the file's own rate of 250 Hz.*'time'")
    ok = {**cmap, "time": {"sample_rate_Hz": 250.1}}  # within 0.1 %
    assert _read(f, ok).sample_rate == pytest.approx(250.1)


def test_stated_rate_contradicting_lvm_x_values_is_an_error(tmp_path):
    f, *_ = lvm_two_segments(tmp_path)  # 500 Hz
    cmap = {"time": {"sample_rate_Hz": 1000}, "channels": {"torque": {"column": "Torque"}}}
    _raises(f, cmap, r"1000 Hz.*own rate of 500 Hz \(time base of column 'Torque'\)")


# ---------------------------------------------------------------------------------------------
# LabVIEW .lvm


def test_lvm_two_segments_shared_x_column(tmp_path):
    f, t, torque, speed = lvm_two_segments(tmp_path)
    rec = _read(
        f, {"channels": {"torque": {"column": "Torque"}, "roller_speed": {"column": "Speed"}}}
    )
    np.testing.assert_allclose(rec.time, t, atol=1e-9)
    np.testing.assert_allclose(rec["torque"], np.round(torque, 6), rtol=1e-12)
    np.testing.assert_allclose(rec["roller_speed"], np.round(speed, 6) * RPM, rtol=1e-12)
    assert rec.metadata["format"] == "lvm"
    assert any("2 LVM segments" in n for n in rec.metadata["notes"])
    # the default map reads it too: X_Value is the time, channels with a unit are extras
    auto = _read(f)
    np.testing.assert_allclose(auto.time, t, atol=1e-9)
    # and the shared X column can be named as the time column
    named = _read(f, {"time": {"column": "X_Value"}, "channels": {"torque": {"column": "Torque"}}})
    np.testing.assert_allclose(named.time, t, atol=1e-9)


def test_lvm_decimal_comma_no_x_columns_and_comments(tmp_path):
    f, torque, dx = lvm_decimal_comma(tmp_path)
    rec = _read(f, {"channels": {"torque": {"column": "Drehmoment"}}})
    np.testing.assert_allclose(rec.time, np.arange(80) * dx, atol=1e-12)
    np.testing.assert_allclose(rec["torque"], torque, rtol=1e-12)
    notes = " ".join(rec.metadata["notes"])
    assert "decimal comma" in notes and "1 LVM comment cell" in notes


def test_lvm_segment_restarting_its_time_is_placed_by_its_header_time(tmp_path):
    f, *_ = lvm_two_segments(tmp_path, restart_after_s=10.0)
    _raises(f, {"channels": {"torque": {"column": "Torque"}}}, r"gap .*between sample 49")
    rec = _read(f, {"channels": {"torque": {"column": "Torque"}}}, validate="lenient")
    assert rec.metadata["gaps"][0]["duration_s"] == pytest.approx(10.0 - 0.098)
    np.testing.assert_allclose(rec.time[:50], np.arange(50) * 0.002, atol=1e-9)
    np.testing.assert_allclose(rec.time[50:], 10.0 + np.arange(50) * 0.002, atol=1e-9)
    assert any("segment 2 restarts its time" in n for n in rec.metadata["notes"])
    # without the header's Date/Time the restart cannot be placed: an error naming the segment
    g = tmp_path / "nodate.lvm"
    g.write_bytes(f.read_bytes().replace(b"Date\t2024/08/05\t2024/08/05\t\r\n", b""))
    _raises(g, {"channels": {"torque": {"column": "Torque"}}}, r"segment 2 \(line \d+\) restarts")


def test_lvm_multi_x_columns_of_different_rates(tmp_path):
    # X_Columns Multi: each channel its own X column; channel B at half the rate (shorter)
    head = [
        "LabVIEW Measurement\t",
        "Writer_Version\t2",
        "Separator\tTab",
        "Decimal_Separator\t.",
        "X_Columns\tMulti",
        "***End_of_Header***\t",
        "\t",
        "Channels\t2\t\t\t",
        "Samples\t20\t\t10\t",
        "Y_Unit_Label\tN.m\t\tbar\t",
        "***End_of_Header***\t\t\t\t",
        "X_Value\tTorque\tX_Value\tPressure\tComment",
    ]
    rows = []
    for k in range(20):
        b = f"\t{k * 0.02:.6f}\t{2.0 + 0.01 * k:.6f}" if k < 10 else "\t\t"
        rows.append(f"{k * 0.01:.6f}\t{1.0 + k:.6f}" + b)
    f = _write(tmp_path / "multi.lvm", head + rows)
    rec = _read(
        f,
        {
            "channels": {
                "torque": {"column": "Torque"},
                "air_spring_pressure": {"column": "Pressure"},
            }
        },
    )
    np.testing.assert_allclose(rec["torque"][:5], [1.0, 2.0, 3.0, 4.0, 5.0])
    # the pressure, on its own 50 Hz base, is never index-aligned to the 100 Hz torque
    np.testing.assert_allclose(rec["air_spring_pressure"][:3], [2.0e5, 2.005e5, 2.01e5], rtol=1e-6)


@pytest.mark.parametrize(
    ("body", "pattern"),
    [
        ("Not LabVIEW\n1\t2\n", r"not a LabVIEW Measurement file"),
        ("LabVIEW Measurement\t\nSeparator\tTab\n", r"no \*\*\*End_of_Header\*\*\* line"),
        ("LabVIEW Measurement\t\n***End_of_Header***\t\n\t\n", r"header but no data rows"),
        (
            "LabVIEW Measurement\t\n***End_of_Header***\t\nX_Value\tA\tComment\n0.0\t1.0\n0.1\tx\n",
            r"line 5, column 'A' \(column 2\): 'x' is not a number",
        ),
        (
            "LabVIEW Measurement\t\n***End_of_Header***\t\nX_Value\tA\tComment\n0.0\t1.0\n"
            "0.1\t1.0\t2\t3\t4\n",
            r"line 5 has 5 cells",
        ),
    ],
)
def test_lvm_malformed_files_name_the_problem(tmp_path, body, pattern):
    f = tmp_path / "bad.lvm"
    f.write_text(body)
    _raises(f, {"channels": {"torque": {"column": "A", "unit": "N.m"}}}, pattern)


# ---------------------------------------------------------------------------------------------
# Malformed text files: one clear error naming the file and line, or a result with a note

MAP = {"time": {"column": "t"}, "channels": {"torque": {"column": "T", "unit": "N.m"}}}


@pytest.mark.parametrize(
    ("content", "pattern"),
    [
        (b"", r"empty.csv: the file is empty"),
        (b"\r\n\r\n  \r\n", r"empty.csv: the file is empty"),
        (b"t;T\r\n", r"header but no data rows"),
        (b"t;T\r\ns;Nm\r\n", r"header but no data rows"),
        (bytes(range(256)) * 8, r"not a text file \(a NUL byte at byte 0\)"),
        (b"t;T\r\n0;1\r\n1;2;3\r\n2;3\r\n", r"line 3 has 3 cells, the rows before it 2"),
        (b"t;T\r\n0;1\r\n1\r\n2;3\r\n", r"line 3 has 1 cells, the header 2"),
        (
            b"t;T\r\n0;1\r\n1;ERR\r\n2;3\r\n",
            r"non-numeric entries, first at row 1: 'ERR' \(file line 3\)",
        ),
        (b"t;T\r\n0;1,5\r\n1;2.5\r\n", r"mix decimal marks"),
    ],
)
def test_malformed_csv_is_one_clear_error(tmp_path, content, pattern):
    f = tmp_path / "empty.csv"
    f.write_bytes(content)
    _raises(f, MAP, pattern)


def test_a_header_repeated_inside_the_data_is_not_taken_as_preamble(tmp_path):
    # a logger that appends a new header on restart: the first rows must not vanish silently
    f = _write(tmp_path / "twice.csv", ["t;T", "0;1", "1;2", "2;3", "t;T", "3;4", "4;5"])
    _raises(f, MAP, r"rows of numbers \(lines 2\.\.4\) above the header at line 5")


def test_quoted_header_and_cells(tmp_path):
    f = _write(tmp_path / "quoted.csv", ['"t";"T"', '"s";"Nm"', '"0";"1,5"', '"1";"2,5"'])
    rec = _read(f, MAP)
    assert rec["torque"].tolist() == [1.5, 2.5]


def test_binary_bin_file_says_which_catman_export_to_use(tmp_path):
    f = tmp_path / "Versuch_05.bin"
    f.write_bytes(b"\x94\x13" + bytes(100))
    _raises(f, MAP, r"catman.*export .*ASCII.*MDF4")


def test_truncated_last_line_is_dropped_with_a_note(tmp_path):
    f = _write(tmp_path / "cut.csv", ["t;T;S", "0;1;5", "1;2;6", "2;3"], final_eol=False)
    rec = _read(f, {**MAP, "extra": {"s": {"column": "S", "unit": "V"}}})
    assert rec.time.tolist() == [0.0, 1.0]
    assert any("last line 4 is cut short" in n for n in rec.metadata["notes"])


def test_nan_words_strict_error_lenient_interpolated(tmp_path):
    f = _write(tmp_path / "nan.csv", ["t;T", "0;1", "1;NaN", "2;3", "3;4"])
    _raises(f, MAP, r"channel 'torque' has 1 NaN/inf samples")
    rec = _read(f, MAP, validate="lenient")
    assert rec["torque"].tolist() == [1.0, 2.0, 3.0, 4.0]


def test_blank_lines_inside_the_data_are_skipped_with_a_note(tmp_path):
    f = _write(tmp_path / "blank.csv", ["t;T", "0;1", "", "1;2", "2;3", "", ""])
    rec = _read(f, MAP)
    assert rec["torque"].tolist() == [1.0, 2.0, 3.0]
    assert any("1 blank line(s) inside the data" in n for n in rec.metadata["notes"])


def test_utf16_with_bom_is_read(tmp_path):
    f = tmp_path / "u16.csv"
    f.write_bytes("t\tT\r\n0\t1,5\r\n1\t2,5\r\n".encode("utf-16"))
    assert _read(f, MAP)["torque"].tolist() == [1.5, 2.5]


def test_one_column_with_decimal_comma_and_a_stated_rate(tmp_path):
    f = _write(tmp_path / "ai0.csv", ["ai0", "0,5", "0,6", "0,7"])
    rec = _read(
        f,
        {
            "time": {"sample_rate_Hz": 100},
            "channels": {"torque": {"column": "ai0", "unit": "N.m", "scale": 10.0}},
        },
    )
    np.testing.assert_allclose(rec["torque"], [5.0, 6.0, 7.0])


_BASE = b"time;T\r\ns;Nm\r\n" + b"".join(f"{k * 0.01:.2f};{k},5\r\n".encode() for k in range(30))


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    cut=st.integers(0, len(_BASE)),
    flips=st.lists(st.tuples(st.integers(0, len(_BASE) - 1), st.integers(0, 255)), max_size=4),
)
def test_corrupted_csv_gives_a_result_or_a_clear_error(tmp_path, cut, flips):
    data = bytearray(_BASE[:cut])
    for pos, byte in flips:
        if pos < len(data):
            data[pos] = byte
    f = tmp_path / "fuzz.csv"
    f.write_bytes(bytes(data))
    before = _sha(f)
    try:
        rec = read_recording(
            f, {"time": {"column": "time"}, "channels": {"torque": {"column": "T"}}}
        )
    except RecordingError:
        pass
    else:
        assert np.all(np.isfinite(rec["torque"])) and np.all(np.diff(rec.time) > 0)
    assert _sha(f) == before


# ---------------------------------------------------------------------------------------------
# Timestamps directly


def test_parse_timestamps_decides_one_format_for_the_column():
    # 12.08. -> 13.08. across midnight: a per-row guess would read the first rows month-first
    t, note = parse_timestamps(["12.08.24 23:59:59", "13.08.24 00:00:00"], what="t")
    assert t.tolist() == [0.0, 1.0] and "day-first" in note
    t, _ = parse_timestamps(["2024-08-05T13:46:13.250+02:00", "2024-08-05T11:46:14.250Z"], what="t")
    assert t.tolist() == [0.0, 1.0]  # offsets applied
    t, note = parse_timestamps(["23:59:59,5", "00:00:00,5"], what="t")
    assert t.tolist() == [0.0, 1.0] and "midnight" in note
    with pytest.raises(RecordingError, match=r"day-first at row 2.*month-first at row 1"):
        parse_timestamps(
            ["01/02/2024 1:00:00", "01/13/2024 1:00:00", "13/01/2024 1:00:00"], what="t"
        )
    with pytest.raises(RecordingError, match=r"not a valid date read day-first"):
        parse_timestamps(["31.02.24 10:00:00"], what="t")


def test_parse_timestamps_in_chunks_keeps_the_first_decision():
    decided: dict = {}
    head = ["05/08/2024 10:00:00", "05/08/2024 10:00:01"]  # ambiguous: month-first
    parse_timestamps(head, what="t", decided=decided)
    assert decided["first_is_day"] is False and decided["kind"] == "dmy"
    # a later chunk with a day > 12 is not silently re-read day-first: its row is named
    with pytest.raises(RecordingError, match=r"row 1 '13/08/2024 10:00:02' is not a valid date"):
        parse_timestamps([head[0], "13/08/2024 10:00:02"], what="t", decided=decided)


def test_channel_map_provenance_carries_the_file_section(tmp_path):
    f, *_ = picoscope6(tmp_path)
    cmap = ChannelMap.from_dict(
        {
            "file": {"separator": ",", "units_row": 1, "encoding": "utf-8"},
            "time": {"column": "Time", "resample_Hz": 5000},
            "channels": {"torque": {"column": "Channel A", "unit": "N.m", "optional": True}},
        }
    )
    rec = _read(f, cmap)
    md = rec.metadata["channel_map"]
    assert md["file"] == {"separator": ",", "units_row": 1, "encoding": "utf-8"}
    assert md["time"]["resample_Hz"] == 5000.0


@pytest.mark.parametrize(
    ("encoding", "unit"),
    [("utf-8", 1), ("latin-1", 1), ("UTF16", 2), ("utf_16_le", 2), ("utf-32-be", 4), ("x?", 1)],
)
def test_the_code_unit_of_an_encoding_in_any_spelling(encoding, unit):
    """A channel map may name the encoding in any spelling Python knows: a line end is then
    looked for in the file's last code unit of that width (an unknown name: one byte)."""
    from rollerrig.recordings.formats.csv import _code_unit

    assert _code_unit(encoding) == unit


@pytest.mark.parametrize("encoding", ["utf-16-le", "utf-16-be", "utf-32-le", "utf-32-be"])
@pytest.mark.parametrize(("ending", "expected"), [("\n", True), ("\r", True), ("9", False)])
def test_a_line_end_is_found_in_either_byte_order(tmp_path, encoding, ending, expected):
    from rollerrig.recordings.formats.csv import _ends_with_newline

    path = tmp_path / "f.csv"
    path.write_bytes(("t,x\n0,1" + ending).encode(encoding))
    assert _ends_with_newline(path, encoding) is expected


# ------------------------------------------------------------ headers real exports write
# Found by a hunt with files written the way acquisition software writes them (2026-11-30);
# before, each of these was read without a word: a time in msec 1000 times too slow, the
# channel-number header and TwinCAT Scope's key-value rows as samples, the first of two
# columns of one name.


def _time_torque(path, time_header, step, n=50):
    body = "".join(f"{k * step:.9g},{k}\n" for k in range(n))
    path.write_bytes(f"{time_header},Torque [N.m]\n{body}".encode())
    return path


_TIME_TORQUE = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}


@pytest.mark.parametrize(
    ("unit", "step", "seconds"),
    [("msec", 4, 4e-3), ("mS", 4, 4e-3), ("min", 1 / 15000, 4e-3), ("h", 1 / 900000, 4e-3),
     ("usec", 4000, 4e-3), ("Sec", 0.004, 4e-3)],
)  # fmt: skip
def test_time_units_as_exports_spell_them_are_converted(tmp_path, unit, step, seconds):
    """``t [msec]``, ``[mS]``, ``[min]``, ``[h]``: 1 min = 60 s, 1 h = 3600 s (SI Brochure
    Table 8); in a time column the letter case does not change the unit."""
    path = _time_torque(tmp_path / "t.csv", f"Time [{unit}]", step)
    rec = _read(path, _TIME_TORQUE)
    np.testing.assert_allclose(np.diff(rec.time), seconds, rtol=1e-6)


def test_a_time_unit_the_reader_does_not_know_is_refused(tmp_path):
    path = _time_torque(tmp_path / "t.csv", "Time [Sek]", 0.004)
    _raises(path, _TIME_TORQUE, r"time column 'Time \[Sek\]' has unit 'Sek'.*\[time\] unit")
    stated = {**_TIME_TORQUE, "time": {"column": "Time", "unit": "s"}}
    rec = _read(path, stated)  # the map says what it is: read so, and noted
    np.testing.assert_allclose(np.diff(rec.time), 0.004)
    assert any("'Sek' is not a time unit" in n for n in rec.metadata["notes"])


def test_units_rows_with_spaces_and_gauge_marks_are_units(tmp_path):
    """``N m`` and ``bar(g)`` (a gauge pressure: the rig's air spring) in a units row."""
    path = tmp_path / "u.csv"
    rows = "".join(f"{k * 0.001:.3f};{1 + k / 10:.2f};{2 + k / 10:.2f}\n" for k in range(20))
    path.write_bytes(f"Time;Torque;Pressure\ns;N m;bar(g)\n{rows}".encode())
    rec = _read(
        path,
        {
            "time": {"column": "Time"},
            "channels": {
                "torque": {"column": "Torque"},
                "air_spring_pressure": {"column": "Pressure"},
            },
        },
    )
    np.testing.assert_allclose(rec["torque"][:2], [1.0, 1.1])
    np.testing.assert_allclose(rec["air_spring_pressure"][:2], [2.0e5, 2.1e5])


def test_a_name_two_columns_share_is_ambiguous(tmp_path):
    path = tmp_path / "dup.csv"
    rows = "".join(f"{k / 1000:.3f},{1 + k / 10:.2f},{5 + k / 10:.2f}\n" for k in range(20))
    path.write_bytes(f"Time,Torque,Torque\n{rows}".encode())
    cmap = {"time": {"column": "Time", "unit": "s"}, "channels": {"torque": {"column": "Torque"}}}
    cmap["channels"]["torque"]["unit"] = "N.m"
    _raises(path, cmap, r"2 columns of that name.*\['Torque\.0', 'Torque\.1'\]")
    for column, first in (("Torque.0", 1.0), ("Torque.1", 5.0)):
        cmap["channels"]["torque"]["column"] = column
        assert _read(path, cmap)["torque"][0] == first


def test_a_repeated_name_beside_its_renamed_spelling_is_readable(tmp_path):
    """``Torque,Torque.1,Torque``: the second ``Torque`` becomes ``Torque.2`` (pandas had
    refused the file: duplicate names)."""
    path = tmp_path / "dup.csv"
    path.write_bytes(b"Time,Torque,Torque.1,Torque\n" + b"".join(
        f"{k / 1000:.3f},1,2,3\n".encode() for k in range(5)
    ))  # fmt: skip
    cmap = {"time": {"column": "Time", "unit": "s"}, "channels": {}}
    for column, value in (("Torque.1", 2.0), ("Torque.2", 3.0)):
        cmap["channels"] = {"torque": {"column": column, "unit": "N.m"}}
        assert _read(path, cmap)["torque"][0] == value


@pytest.mark.parametrize("sep", [";", ","])
def test_numbered_channel_names_are_a_header(tmp_path, sep):
    """``Time;1;2``: channels named by their numbers; the row was read as a first sample."""
    path = tmp_path / "n.csv"
    dec = "," if sep == ";" else "."
    rows = "".join(
        sep.join(f"{v:.3f}".replace(".", dec) for v in (k / 1000, 1.5 + k / 10)) + "\n"
        for k in range(4)
    )
    path.write_bytes(f"Time{sep}1\n{rows}".encode())
    rec = _read(path, {"time": {"column": "Time", "unit": "s"}, "channels": {
        "torque": {"column": "1", "unit": "N.m"}}})  # fmt: skip
    assert rec.time.size == 4
    np.testing.assert_allclose(rec["torque"], [1.5, 1.6, 1.7, 1.8])


def test_a_stray_text_cell_in_the_first_sample_stays_a_sample(tmp_path):
    """Under a row of names, text in the first row of numbers is a bad cell, not a header."""
    path = tmp_path / "s.csv"
    rows = "".join(f"{k / 1000:.3f},{1 + k / 10:.2f},{2 + k / 10:.2f}\n" for k in range(1, 10))
    path.write_bytes(f"Time,Torque,Speed\n0.000,ERR,2.00\n{rows}".encode())
    layout = sniff_layout(path)
    assert layout.names == ("Time", "Torque", "Speed")
    assert layout.data_line == 1


def test_key_value_rows_above_the_numbers_are_not_samples(tmp_path):
    """TwinCAT Scope View's export: per channel ``Key<TAB>value`` rows (``SampleTime[ms]
    <TAB>1``) above the numbers, which fit "a number in every other column"; they were read as
    the first four samples. A map that places the header and the numbers reads it as plain
    CSV; without one it is read as the TwinCAT export it is (formats/twincat.py), each channel
    on its own time column."""
    meta = (
        "Name\tMAIN.fTorque\tName\tMAIN.fPressure\nData-Type\tLREAL\tData-Type\tLREAL\n"
        "SampleTime[ms]\t1\tSampleTime[ms]\t1\nVariableSize\t8\tVariableSize\t8\n"
        "Offset\t0\tOffset\t0\nScaleFactor\t1\tScaleFactor\t1\n\t\t\t\n"
    )
    rows = "".join(f"{k}\t{k / 100:.4f}\t{k}\t{2 + k / 1000:.4f}\n" for k in range(50))
    path = tmp_path / "scope.csv"
    path.write_bytes((meta + rows).replace("\n", "\r\n").encode())
    layout = sniff_layout(path)
    assert layout.data_line == 7  # the first row of numbers, 0-based
    rec = _read(path, {"file": {"header_row": 0, "data_row": 7}, "time": {
        "column": "Name.0", "unit": "ms"}, "channels": {"torque": {
            "column": "MAIN.fTorque", "unit": "N.m"}}})  # fmt: skip
    assert rec.time.size == 50
    np.testing.assert_allclose(rec["torque"][:3], [0.0, 0.01, 0.02])
    scope = _read(path, {"channels": {"torque": {"column": "MAIN.fTorque", "unit": "N.m"}}})
    np.testing.assert_allclose(scope.time, rec.time, atol=1e-12)
    np.testing.assert_allclose(scope["torque"], rec["torque"], atol=0)


def test_integer_epoch_nanoseconds_keep_their_resolution(tmp_path):
    """A time column of integer epoch nanoseconds (a ``time.time_ns()`` logger) at 51.2 kS/s:
    the step is 19 531 or 19 532 ns, as written. Made a float first, 1.7e18 ns became 1.7e9 s
    to 0.24 µs: steps of 19.3-19.8 µs and a rate of 51 150 Hz."""
    from rollerrig.recordings.source import open_recording

    n = 3000
    stamps = 1_722_865_573_000_000_000 + np.round(np.arange(n) * 1e9 / 51200).astype(np.int64)
    path = tmp_path / "ns.csv"
    path.write_bytes(("Time,T\n" + "".join(f"{t},{k}\n" for k, t in enumerate(stamps))).encode())
    cmap = {"time": {"column": "Time", "unit": "ns"}, "channels": {
        "torque": {"column": "T", "unit": "N.m"}}}  # fmt: skip
    rec = _read(path, cmap)
    np.testing.assert_array_equal(rec.time, (stamps - stamps[0]) * 1e-9)
    assert any("made relative to its first value" in note for note in rec.metadata["notes"])
    with open_recording(path, cmap) as src:
        chunked = np.concatenate([c.time for c in src.iter_chunks(("torque",), 700)])
    np.testing.assert_array_equal(chunked, rec.time)


def test_a_description_row_under_the_units_is_not_the_header(tmp_path):
    """DIAdem's text export: names, units, then descriptions above the numbers. The
    descriptions were taken as the names ('Time axis'), and the map's 'Time' was refused."""
    rows = "".join(f"{k / 1000:.3f};{1 + k / 10:.2f};{2 + k / 10:.2f}\n" for k in range(20))
    path = tmp_path / "diadem.csv"
    path.write_bytes(
        f"Time;Torque;p\ns;N·m;bar\nTime axis;Roller torque;Air spring\n{rows}".encode()
    )
    rec = _read(path, {"time": {"column": "Time"}, "channels": {
        "torque": {"column": "Torque"}, "air_spring_pressure": {"column": "p"}}})  # fmt: skip
    np.testing.assert_allclose(rec["air_spring_pressure"][:2], [2.0e5, 2.1e5])
    assert any("descriptions" in n for n in rec.metadata["notes"])


@pytest.mark.parametrize("x_columns", ["No", "One"])
def test_lvm_absolute_times_keep_the_sample_rate(tmp_path, x_columns):
    """``Time_Pref Absolute``: X in seconds since 1904 (3.8e9 s, where a float64 steps by 0.48
    µs). Summed or parsed at that size, 10 kHz read as 9 986 Hz and every step jittered; the
    whole seconds are taken off first (LabVIEW writes X0 as ``%.16E``, X columns with six
    decimals)."""
    rate, n, x0 = 10_000.0, 2000, 3_805_612_345.25
    head = [
        "LabVIEW Measurement\t", "Writer_Version\t2", "Reader_Version\t2", "Separator\tTab",
        "Decimal_Separator\t.", "Multi_Headings\tNo", f"X_Columns\t{x_columns}",
        "Time_Pref\tAbsolute", "Date\t2024/08/05", "Time\t13:46:13.25", "***End_of_Header***\t",
        "\t", "Channels\t1\t", f"Samples\t{n}", "Date\t2024/08/05", "Time\t13:46:13.25",
        "Y_Unit_Label\tN.m", "X_Dimension\tTime", f"X0\t{x0:.16E}", f"Delta_X\t{1 / rate:.16E}",
        "***End_of_Header***\t\t", "X_Value\tTorque\tComment",
    ]  # fmt: skip
    k = np.arange(n)
    if x_columns == "No":
        rows = [f"\t{v:.6f}" for v in np.sin(k / 100)]
    else:  # the X cells as LabVIEW writes them: six decimals of the absolute time
        rows = [f"{3_805_612_345 + (0.25 + i / rate):.6f}\t{v:.6f}" for i, v in enumerate(
            np.sin(k / 100))]  # fmt: skip
    path = tmp_path / "abs.lvm"
    path.write_bytes(("\r\n".join(head + rows) + "\r\n").encode())
    rec = _read(path, {"channels": {"torque": {"column": "Torque"}}})
    np.testing.assert_allclose(rec.time, k / rate, rtol=0, atol=1e-9)
    assert rec.sample_rate == pytest.approx(rate, rel=1e-9)


def test_an_extra_channel_in_another_unit_than_the_map_says_is_refused(tmp_path):
    """PicoScope's units row says mV, the map V: the values were taken as volts (x1000),
    without a word, where a canonical channel's clash was refused."""
    rows = "".join(f"{k * 0.1:.1f},{250 + k}\n" for k in range(20))
    path = tmp_path / "pico.csv"
    path.write_bytes(f"Time,Channel A\n(ms),(mV)\n\n{rows}".encode())
    cmap = {"time": {"column": "Time"}, "extra": {"a": {"column": "Channel A", "unit": "V"}}}
    _raises(path, cmap, r"the map says unit 'V' but the file says 'mV'")
    cmap["extra"]["a"]["unit"] = "mV"
    rec = _read(path, cmap)
    np.testing.assert_allclose(rec["a"][:2], [0.250, 0.251])  # 1 mV = 1e-3 V
    assert rec.units["a"] == "V"


def test_keysight_units_row_in_words_is_a_units_row(tmp_path):
    """Keysight InfiniiVision: ``x-axis,1,2`` above ``second,Volt,Volt``."""
    rows = "".join(f"{(k - 100) * 1e-5:.6E},{k / 100:.4E},{-k / 100:.4E}\n" for k in range(200))
    path = tmp_path / "scope.csv"
    path.write_bytes(f"x-axis,1,2\nsecond,Volt,Volt\n{rows}".replace("\n", "\r\n").encode())
    rec = _read(path, {"time": {"column": "x-axis"}, "extra": {"ch1": {"column": "1",
                "unit": "V"}}})  # fmt: skip
    assert rec.sample_rate == pytest.approx(1e5)
    assert rec.units["ch1"] == "V"


def test_key_value_rows_under_a_given_header_are_not_samples(tmp_path):
    """A Yokogawa DL export: with ``[file] header_row`` at ``TraceName,,CH1,CH2``, the rows
    ``SampleRate,,10000,10000`` ... below it were the first three samples."""
    pre = ["Model,DL850E", "TraceName,,CH1,CH2", "SampleRate,,10000,10000",
           "HResolution,,1.0000E-04,1.0000E-04", "HOffset,,0.0000E+00,0.0000E+00"]  # fmt: skip
    values = np.round(np.sin(np.arange(200) / 10), 4)
    path = tmp_path / "dl.csv"
    path.write_bytes("\r\n".join([*pre, *(f",,{v:.4E},{v:.4E}" for v in values), ""]).encode())
    cmap = {"file": {"header_row": 1}, "time": {"sample_rate_Hz": 10000.0},
            "extra": {"ch1": {"column": "CH1", "unit": "V"}}}  # fmt: skip
    np.testing.assert_array_equal(_read(path, cmap)["ch1"], values)


def test_an_unmapped_column_named_t_that_is_no_time_base_is_not_checked(tmp_path):
    """A temperature column 'T' (not increasing) beside a stated sample rate: the rate check
    took it for a time column and refused the file ('the file's own rate of nan Hz')."""
    rows = "".join(f"{20 + (k % 7) / 10:.1f},{k}\n" for k in range(50))
    path = tmp_path / "temp.csv"
    path.write_bytes(f"T,Fz\n{rows}".encode())
    rec = _read(path, {"time": {"sample_rate_Hz": 10.0}, "channels": {
        "normal_load": {"column": "Fz", "unit": "N"}}})  # fmt: skip
    assert rec.time.size == 50


def test_repeated_names_are_ambiguous_in_the_chunked_reader_too(tmp_path):
    from rollerrig.recordings.source import open_recording

    rows = "".join(f"{k / 1000:.3f},{k},{-k}\n" for k in range(20))
    path = tmp_path / "dup.csv"
    path.write_bytes(f"time,Volt,Volt\n{rows}".encode())
    cmap = {"time": {"column": "time", "unit": "s"}, "extra": {"v": {"column": "Volt",
            "unit": "V"}}}  # fmt: skip
    with pytest.raises(RecordingError, match=r"\['Volt\.0', 'Volt\.1'\]"):
        open_recording(path, cmap).close()
    cmap["extra"]["v"]["column"] = "Volt.1"
    with open_recording(path, cmap) as src:
        np.testing.assert_array_equal(next(src.iter_chunks(("v",), 5))["v"], -np.arange(5.0))


def test_a_transposed_export_is_refused_not_read_as_a_few_samples(tmp_path):
    """LabVIEW's "Write Delimited Spreadsheet" with transpose on: 3 channels of 50 samples, one
    per row, no names. With a sample-rate map it was read as 3 samples of 50 columns. A short
    wide file (5 s at 1 Hz of 30 channels), or one under a row of names, is read."""
    rows = ["\t".join(f"{v:.3f}" for v in k + np.arange(50) / 1000) for k in range(3)]
    path = tmp_path / "t.txt"
    path.write_bytes(("\r\n".join(rows) + "\r\n").encode())
    cmap = {"time": {"sample_rate_Hz": 1000.0}, "extra": {"a": {"column": "column 2",
            "unit": "V"}}}  # fmt: skip
    _raises(path, cmap, r"3 rows of 50 cells: one channel per row")
    wide = ["\t".join(f"{k + j / 100:.2f}" for j in range(30)) for k in range(5)]
    path.write_bytes(("\r\n".join(wide) + "\r\n").encode())
    assert _read(path, {**cmap, "time": {"sample_rate_Hz": 1.0}})["a"].size == 5
    named = ["\t".join(f"ch{j}" for j in range(128))] + [
        "\t".join(f"{k + j / 100:.2f}" for j in range(128)) for k in range(12)
    ]
    path.write_bytes(("\r\n".join(named) + "\r\n").encode())
    cmap["extra"]["a"]["column"] = "ch1"
    assert _read(path, {**cmap, "time": {"sample_rate_Hz": 1.0}})["a"].size == 12


def test_a_column_named_on_another_line_than_the_header_taken_gets_a_hint(tmp_path):
    """A recorder's preamble (a HIOKI-like row of settings under the names): the reader takes
    the line above the numbers as the header; the error says where the map's name stands and
    which header_row to give."""
    rows = "".join(f"{k / 100:.2f};{k / 10:.1f}\n" for k in range(20))
    path = tmp_path / "rec.csv"
    path.write_bytes(f"Model;MR\nTime;CH1\nScaling;OFF\n{rows}".encode())
    cmap = {"time": {"column": "Time", "unit": "s"}, "extra": {"ch1": {"column": "CH1",
            "unit": "V"}}}  # fmt: skip
    _raises(path, cmap, r"line 2 of the file names 'Time'.*header_row = 1")
    cmap["file"] = {"header_row": 1, "data_row": 3}
    np.testing.assert_allclose(_read(path, cmap)["ch1"][:2], [0.0, 0.1])


@pytest.mark.parametrize("last", ["Range,V", "Unit,s", "Gain,1"])
def test_a_key_value_preamble_is_not_a_names_units_descriptions_header(tmp_path, last):
    """``Device,DL850`` / ``Range,V`` / ``Time,Torque``: the DIAdem rule (names, units,
    descriptions) took the preamble for names and units and the real header for
    descriptions (a review of the rule)."""
    rows = "".join(f"{k / 10:.1f},{1.5 + k / 10:.1f}\n" for k in range(3))
    path = tmp_path / "kv.csv"
    path.write_bytes(f"Device,DL850\n{last}\nTime,Torque\n{rows}".encode())
    rec = _read(path, {"time": {"column": "Time", "unit": "s"}, "channels": {
        "torque": {"column": "Torque", "unit": "N.m"}}})  # fmt: skip
    np.testing.assert_allclose(rec["torque"], [1.5, 1.6, 1.7])


def test_a_marker_column_on_the_left_keeps_its_first_samples(tmp_path):
    """``Marker,Time,Torque`` with 'Start', 'Ramp' in the first samples: no key-value rows."""
    marks = ["Start", "Ramp", "", "", "", "", "", "", "", "", "", ""]
    rows = "".join(f"{m},{k / 1000:.3f},{1 + k / 10:.1f}\n" for k, m in enumerate(marks))
    path = tmp_path / "marks.csv"
    path.write_bytes(f"Marker,Time,Torque\n{rows}".encode())
    rec = _read(path, {"time": {"column": "Time", "unit": "s"}, "channels": {
        "torque": {"column": "Torque", "unit": "N.m"}}})  # fmt: skip
    assert rec.time.size == 12


def test_a_unit_spelled_otherwise_is_no_clash(tmp_path):
    """An extra in MN/m by the map and kN/mm by the file: the same unit, read."""
    rows = "".join(f"{k / 1000:.3f},{k}\n" for k in range(10))
    path = tmp_path / "k.csv"
    path.write_bytes(f"Time [s],k [kN/mm]\n{rows}".encode())
    rec = _read(path, {"time": {"column": "Time"}, "extra": {"k": {"column": "k",
            "unit": "MN/m"}}})  # fmt: skip
    np.testing.assert_allclose(rec["k"], np.arange(10) * 1e6)


@settings(max_examples=40, deadline=None)
@given(
    start=st.floats(0, 86_399),
    rate=st.sampled_from([1.0, 50.0, 1000.0, 19_200.0]),
    decimals=st.integers(0, 6),
    comma=st.booleans(),
    odd=st.booleans(),
)
def test_times_of_day_read_at_once_equal_the_per_cell_reading(start, rate, decimals, comma, odd):
    """Equal-width ``hh:mm:ss.f`` cells are read from their bytes at once (a million took 5 s
    through the regular expression, a review, 2026-12-03); the seconds are the regular
    expression's to the last bit, midnight crossings included, and a cell of another layout
    (a shorter hour, a stray letter) leaves the column to the regular expression, which
    names it."""
    from unittest import mock

    from rollerrig.recordings.formats import timestamps

    t = start + np.arange(300) / rate
    cells = []
    for v in t % 86_400.0:
        h, rest = divmod(v, 3600.0)
        mi, sec = divmod(rest, 60.0)
        whole = f"{int(h):02d}:{int(mi):02d}:{int(sec):02d}"
        frac = f"{sec - int(sec):.{decimals}f}"[2:] if decimals else ""
        cells.append(whole + ((("," if comma else ".") + frac) if frac else ""))
    if odd:
        cells[150] = cells[150].replace(":", "h", 1)
    try:
        fast = parse_timestamps(cells, what="t")
    except RecordingError as exc:
        fast = str(exc)
    with mock.patch.object(timestamps, "_fixed_width_times_of_day", lambda s, first: None):
        try:
            slow = parse_timestamps(cells, what="t")
        except RecordingError as exc:
            slow = str(exc)
    if isinstance(slow, str):
        assert fast == slow
    else:
        np.testing.assert_array_equal(fast[0], slow[0])
        assert fast[1] == slow[1]
