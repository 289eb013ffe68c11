"""Variants of vendor files that the fixtures of ``tests/vendor_files.py`` do not cover.

Each case writes the file as the tool (or a user's export) writes it and checks the contract of
the readers: a correct read, or one :class:`RecordingError` naming the file, the column and
what is wrong; never a silent wrong value; the input file never modified.
"""

import codecs
import io
import re
from decimal import Decimal

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig.recordings.formats._text import EXACT_ABOVE, exact_offsets
from rollerrig.recordings.readers import file_sha256, read_recording
from rollerrig.recordings.recording import RecordingError
from rollerrig.recordings.source import open_recording

MAP = {
    "time": {"column": "Time", "unit": "s"},
    "channels": {"torque": {"column": "Torque", "unit": "N.m"}},
}


def _write(tmp_path, name, data):
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode())
    return p, file_sha256(p)


# ------------------------------------------- absolute times in seconds since an epoch (text)


@pytest.mark.parametrize(
    ("origin", "sep", "decimal"),
    [(3805984573, ",", "."), (1722865573, ";", ","), (3805984573, "\t", ",")],
    ids=["labview-1904", "unix-decimal-comma", "labview-tab-decimal-comma"],
)
def test_epoch_seconds_in_a_text_file_keep_their_clock_exactly(tmp_path, origin, sep, decimal):
    # LabVIEW's "Write Delimited Spreadsheet" of a waveform's absolute time: seconds since
    # 1904 with 7 decimals. Parsed as floats (0.48 µs steps at 3.8e9 s) the 100 kHz clock read
    # as 99 864 Hz with steps of 9.5 and 10.0 µs, without a word.
    n = 2000
    rows = "".join(
        f"{origin}.{k * 100:07d}{sep}{1.5 + k * 1e-3:.3f}\n".replace(".", decimal) for k in range(n)
    )
    p, sha = _write(tmp_path, "epoch.csv", f"Time{sep}Torque\n{rows}")
    rec = read_recording(p, MAP)
    assert rec.sample_rate == pytest.approx(100_000.0, rel=1e-9)
    np.testing.assert_allclose(np.diff(rec.time), 1e-5, rtol=1e-9)
    assert rec.time[0] == 0.0
    np.testing.assert_allclose(rec["torque"], 1.5 + np.arange(n) * 1e-3, atol=1e-12)
    assert any("read exactly" in note for note in rec.metadata["notes"])
    # the chunked reader reads the same clock
    with open_recording(p, MAP) as src:
        chunks = list(src.iter_chunks(["torque"], chunk_samples=700))
    np.testing.assert_array_equal(np.concatenate([c.time for c in chunks]), rec.time)
    assert file_sha256(p) == sha


def test_a_large_non_time_column_still_reads_as_numbers(tmp_path):
    # a column kept as text for its size (an odometer in m) is a channel as any other
    rows = "".join(f"{k / 1000:.3f},{123456789.25 + k:.2f}\n" for k in range(5))
    p, _ = _write(tmp_path, "big.csv", "Time,Odometer\n" + rows)
    rec = read_recording(
        p,
        {
            "time": {"column": "Time", "unit": "s"},
            "extra": {"odometer": {"column": "Odometer", "unit": "m"}},
        },
    )
    np.testing.assert_array_equal(rec["odometer"], 123456789.25 + np.arange(5))


@settings(max_examples=60, deadline=None)
@given(
    origin=st.integers(int(EXACT_ABOVE), 4_000_000_000),
    steps=st.lists(st.integers(0, 10**9), min_size=1, max_size=20),
    decimal=st.sampled_from([".", ","]),
)
def test_exact_offsets_are_the_decimal_differences(origin, steps, decimal):
    ns = np.cumsum(steps)
    cells = [f"{origin + int(k) // 10**9}.{int(k) % 10**9:09d}" for k in ns]
    cells = [c.replace(".", decimal) for c in cells]
    got, o = exact_offsets(cells, decimal)
    assert o == origin + int(ns[0]) // 10**9
    want = [float(Decimal(c.replace(",", ".")) - o) for c in cells]
    assert got.tolist() == want


def test_exact_offsets_refuse_the_other_mark():
    assert exact_offsets(["3805984573,5"], ".") is None
    assert exact_offsets(["3805984573.5"], ",") is None


# ------------------------------------------------ serial day numbers (Excel, MATLAB datenum)


def _serial(first, n=50, rate=1000.0):
    return first + np.arange(n) / rate / 86400.0


def test_excel_serial_days_as_time_are_an_error_naming_the_date(tmp_path):
    # Excel's serial date (45509.5 = 2024-08-05 12:00) formatted as a number: read as seconds,
    # a 1 kHz recording was one of 86.4 MHz lasting 0.6 ms.
    rows = "".join(f"{float(t)!r},1.5\n" for t in _serial(45509.5))
    p, sha = _write(tmp_path, "excel.csv", "Time,Torque\n" + rows)
    with pytest.raises(RecordingError) as err:
        read_recording(p, MAP)
    msg = str(err.value)
    assert str(p) in msg and "'Time'" in msg and "serial day" in msg
    assert "Excel" in msg and "2024-08-05 12:00:00" in msg and "*86400" in msg
    assert file_sha256(p) == sha


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_a_matlab_datenum_time_vector_is_an_error(tmp_path, version):
    t = _serial(739469.5)
    torque = np.full(t.size, 1.5)
    p = tmp_path / "datenum.mat"
    if version == "5":
        from scipy.io import savemat

        savemat(p, {"t": t[:, None], "torque": torque[:, None]})
    else:
        h5py = pytest.importorskip("h5py")
        with h5py.File(p, "w") as f:
            for key, v in (("t", t), ("torque", torque)):
                f[key] = v[None, :]
                f[key].attrs["MATLAB_class"] = np.bytes_("double")
    cmap = {"time": {"column": "t"}, "channels": {"torque": {"column": "torque", "unit": "N.m"}}}
    with pytest.raises(RecordingError, match=r"MATLAB datenum.*2024-08-05 12:00:00"):
        read_recording(p, cmap)


def test_seconds_since_midnight_are_no_serial_days(tmp_path):
    # 45509.5 s (12.6 h) at 1 kHz is a plausible time in seconds: read as it is
    rows = "".join(f"{45509.5 + k / 1000:.3f},1.5\n" for k in range(50))
    p, _ = _write(tmp_path, "midday.csv", "Time,Torque\n" + rows)
    rec = read_recording(p, MAP)
    assert rec.sample_rate == pytest.approx(1000.0, rel=1e-6)
    assert rec.time[0] == pytest.approx(45509.5)


# ------------------------------------------------------------ UTF-16 without a byte-order mark

_TEXT = "Time;Torque [N·m]\n0,000;1,5\n0,001;1,6\n0,002;1,7\n"


@pytest.mark.parametrize("codec", ["utf-16-le", "utf-16-be"])
def test_utf16_without_bom_is_read_as_utf16(tmp_path, codec):
    # a script's or logger's UTF-16 text without a BOM was refused as a binary file
    p, sha = _write(tmp_path, "nobom.csv", _TEXT.encode(codec))
    rec = read_recording(
        p, {"time": {"column": "Time", "unit": "s"}, "channels": {"torque": {"column": "Torque"}}}
    )
    np.testing.assert_allclose(rec["torque"], [1.5, 1.6, 1.7])
    np.testing.assert_allclose(rec.time, [0.0, 0.001, 0.002])
    assert any("without a byte-order mark" in n for n in rec.metadata["notes"])
    assert file_sha256(p) == sha


def test_utf16_lvm_without_bom_is_read(tmp_path):
    import vendor_files as vf

    v = vf.labview_lvm(tmp_path)
    text = v.path.read_bytes().decode("ascii")
    bare = tmp_path / "bare.lvm"
    bare.write_bytes(text.encode("utf-16-le"))
    want = read_recording(v.path, v.write_map())
    got = read_recording(bare, v.write_map())
    np.testing.assert_array_equal(got.time, want.time)
    np.testing.assert_array_equal(got["torque"], want["torque"])


def test_a_binary_file_with_a_text_suffix_is_still_refused(tmp_path):
    p, _ = _write(tmp_path, "binary.csv", bytes(range(256)) * 8)
    with pytest.raises(RecordingError, match="not a text file"):
        read_recording(p, MAP)


@pytest.mark.parametrize("n", [3000, 40000], ids=["in-the-head", "beyond-the-head"])
@pytest.mark.parametrize("cut", [0, 6], ids=["after-a-line-end", "inside-a-line"])
def test_a_nul_padded_tail_is_left_out_with_the_line_it_cut(tmp_path, n, cut):
    # An SD-card logger that lost power: the file's space allocated and zero-filled after the
    # last line it wrote. It had been refused as a binary file.
    body = "Time,Torque\n" + "".join(f"{k / 1000:.3f},{100 + k % 7}\n" for k in range(n))
    data = body.encode()[: len(body) - cut] + b"\x00" * 8192
    p, sha = _write(tmp_path, "powerloss.csv", data)
    rec = read_recording(p, MAP)
    kept = n - (1 if cut else 0)
    assert rec.time.size == kept
    np.testing.assert_allclose(rec["torque"], [100 + k % 7 for k in range(kept)])
    note = next(x for x in rec.metadata["notes"] if "NUL bytes" in x)
    assert "8192 NUL bytes" in note and "lost power" in note
    assert ("line they cut" in note) == bool(cut)
    with open_recording(p, MAP) as src:  # the chunked reader reads the same samples
        chunks = list(src.iter_chunks(["torque"], chunk_samples=700))
    np.testing.assert_array_equal(np.concatenate([c.time for c in chunks]), rec.time)
    assert file_sha256(p) == sha


@pytest.mark.parametrize("n", [3000, 40000], ids=["in-the-head", "beyond-the-head"])
@pytest.mark.parametrize("cut", [0, 6, 7], ids=["after-a-line-end", "inside-a-line", "odd-byte"])
@pytest.mark.parametrize("order", ["utf-16-le", "utf-16-be", "bare-le"])
def test_a_nul_padded_utf16_tail_is_left_out_with_the_line_it_cut(tmp_path, n, cut, order):
    # A Windows logger writes UTF-16 with a BOM (LE, or BE); one that lost power leaves its
    # file zero-filled after the last line. UTF-16's own zero bytes (every ASCII character has
    # one, a line end's last byte in LE) are no padding; the NUL run after the text is.
    body = "Time,Torque\r\n" + "".join(f"{k / 1000:.3f},{100 + k % 7}\r\n" for k in range(n))
    codec = "utf-16-le" if order == "bare-le" else order
    bom = b"" if order == "bare-le" else codecs.BOM_UTF16_LE if order == "utf-16-le" else (
        codecs.BOM_UTF16_BE
    )  # fmt: skip
    text = bom + body.encode(codec)
    data = text[: len(text) - cut] + b"\x00" * 8192
    p, sha = _write(tmp_path, "powerloss16.csv", data)
    rec = read_recording(p, MAP)
    kept = n - (1 if cut else 0)
    assert rec.time.size == kept
    np.testing.assert_allclose(rec["torque"], [100 + k % 7 for k in range(kept)])
    note = next(x for x in rec.metadata["notes"] if "NUL bytes" in x)
    assert "lost power" in note and ("line they cut" in note) == bool(cut)
    with open_recording(p, MAP) as src:  # the chunked reader reads the same samples
        chunks = list(src.iter_chunks(["torque"], chunk_samples=700))
    np.testing.assert_array_equal(np.concatenate([c.time for c in chunks]), rec.time)
    assert file_sha256(p) == sha


@pytest.mark.parametrize("codec", ["utf-16-le", "utf-16-be"])
def test_utf16_without_padding_keeps_its_last_line(tmp_path, codec):
    # the zero byte of the last line end (0A 00 in LE, 00 0A's first in BE) is the text's own
    body = "Time,Torque\r\n" + "".join(f"{k / 1000:.3f},{k}\r\n" for k in range(50))
    bom = codecs.BOM_UTF16_LE if codec == "utf-16-le" else codecs.BOM_UTF16_BE
    p, _ = _write(tmp_path, "u16.csv", bom + body.encode(codec))
    rec = read_recording(p, MAP)
    assert rec.time.size == 50 and rec["torque"][-1] == 49
    assert not any("NUL bytes" in x for x in rec.metadata["notes"])


@pytest.mark.parametrize("codec", ["utf-16-le", "utf-16-be"])
def test_a_short_utf16_file_without_a_bom_and_with_padding_reads(tmp_path, codec):
    # its padding within the first 4 KiB had made the NUL lane test fail: 'not a text file'
    # (review of 2026-12-03)
    body = "Time,Torque\n" + "".join(f"{k / 1000:.3f},{k}\n" for k in range(40))
    p, _ = _write(tmp_path, "u16.csv", body.encode(codec) + b"\x00" * 8192)
    rec = read_recording(p, MAP)
    assert rec.time.size == 40 and rec["torque"][-1] == 39
    assert any("NUL bytes" in x for x in rec.metadata["notes"])


@pytest.mark.parametrize("sep", [",", ";", "\t"])
@pytest.mark.parametrize("eol", ["\n", "\r\n"])
def test_a_quoted_header_cell_with_a_line_break_is_one_name_with_its_unit(tmp_path, sep, eol):
    # Excel writes a header cell typed with Alt+Enter quoted, its line break (LF) inside: the
    # header spans two lines. It had been "no rows of numbers found".
    dec = "," if sep == ";" else "."
    rows = "".join(f"{k / 10:.1f}{sep}{1.5 + k / 10:.1f}{sep}3{eol}".replace(".", dec) for k in
                   range(5))  # fmt: skip
    header = f'"Time\n[s]"{sep}"Torque\n[N.m]"{sep}"Speed ""fast""\n(rpm)"{eol}'
    p, sha = _write(tmp_path, "excel.csv", "Messung 7" + eol + header + rows)
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque", "unit": "N.m"}}}
    rec = read_recording(p, cmap)
    np.testing.assert_allclose(rec.time, np.arange(5) / 10)
    np.testing.assert_allclose(rec["torque"], 1.5 + np.arange(5) / 10)
    assert rec.metadata["columns"]["torque"] == "Torque [N.m]"
    assert rec.metadata["source_units"] == {"time": "s", "torque": "N.m"}
    assert any("line break" in n for n in rec.metadata["notes"])
    with open_recording(p, cmap) as src:  # the chunked reader skips the same rows
        chunks = list(src.iter_chunks(["torque"], chunk_samples=2))
    np.testing.assert_array_equal(np.concatenate([c.channels["torque"] for c in chunks]),
                                  rec["torque"])  # fmt: skip
    assert file_sha256(p) == sha


_NAME = st.builds(
    lambda first, rest: first + rest,
    st.sampled_from("QXZÖé"),  # a letter: a name, not a number or a unit
    st.lists(st.sampled_from([*'abcxyz ÄΩ,;|"\t[]()', "\n", "\r\n"]), max_size=12).map(
        "".join
    ),
).filter(lambda s: s.strip() == s and not s.endswith('"'))  # fmt: skip


@settings(max_examples=80, deadline=None)
@given(st.lists(_NAME, min_size=1, max_size=4, unique_by=lambda s: " ".join(s.split())))
def test_header_names_with_line_breaks_read_as_written_by_a_csv_writer(tmp_path_factory, names):
    # whatever the names a user types (quotes, separators, line breaks in them), a CSV
    # writer's quoting (Excel's too) gives one header row, each name with its breaks as spaces
    import csv

    from rollerrig.recordings.formats.csv import read_csv

    names = ["Time", *names]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\r\n")
    writer.writerow(names)
    for k in range(6):
        writer.writerow([f"{k / 10:.1f}"] + [f"{j + k / 100:.2f}" for j in range(len(names) - 1)])
    p, _ = _write(tmp_path_factory.mktemp("names"), "names.csv", buf.getvalue())
    table = read_csv(p)
    wanted = [re.sub(r"\s*\n\s*", " ", n).strip() for n in names]  # a break and its blanks
    assert table.names == wanted
    for j, name in enumerate(wanted[1:]):
        np.testing.assert_allclose(table.load(name).values, j + np.arange(6) / 100)


@pytest.mark.parametrize(
    ("preamble", "sep"),
    [
        # a quote after a comma in a file of ';' is a character, not a cell's start (review
        # of 2026-12-03: the header had been joined into this line and read as data)
        ('Kommentar;Rad 6,"Zoll\nOperator;"Max"\n', ";"),
        ('Kommentar,Rad 6;"Zoll\nOperator,"Max"\n', ","),
        # a quote left open in a preamble line: pandas, skipping rows of CSV, had read on to
        # the next quote as one row and lost the first sample without a word
        ('Title,"Run 7\n', ","),
        ('Titel;"Lauf 7\nBediener;"Max"\n', ";"),
    ],
)
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
def test_a_stray_quote_above_the_names_leaves_the_header_alone(tmp_path, preamble, sep, encoding):
    dec = "," if sep == ";" else "."
    rows = "".join(f"{k / 10:.1f}{sep}{3.5 + k:.1f}\n".replace(".", dec) for k in range(7))
    text = f'{preamble}"Zeit"{sep}"Moment"\n{rows}'
    p, _ = _write(tmp_path, "stray.csv", text.encode(encoding))
    cmap = {"time": {"column": "Zeit", "unit": "s"},
            "channels": {"torque": {"column": "Moment", "unit": "N.m"}}}  # fmt: skip
    rec = read_recording(p, cmap)
    np.testing.assert_allclose(rec.time, np.arange(7) / 10)
    np.testing.assert_allclose(rec["torque"], 3.5 + np.arange(7))
    assert not any("line break" in n for n in rec.metadata["notes"])
    with open_recording(p, cmap) as src:  # the streamed reader skips the same lines
        chunks = [c.channels["torque"] for c in src.iter_chunks(["torque"], chunk_samples=3)]
    np.testing.assert_array_equal(np.concatenate(chunks), rec["torque"])


def test_a_stray_quote_above_whitespace_separated_numbers_loses_nothing(tmp_path):
    # 'Title "Run 7' above columns split by spaces: pandas' rows of CSV had read on to the
    # next quote ("has a header but no data rows"; review of 2026-12-03)
    rows = "".join(f"{k / 10:.1f}   {1.5 + k}\n" for k in range(20))
    p, _ = _write(tmp_path, "ws.csv", 'Title "Run 7\nTime   Torque\n' + rows)
    rec = read_recording(p, MAP)
    np.testing.assert_allclose(rec["torque"], 1.5 + np.arange(20))


@pytest.mark.parametrize("title", ["Title,Run 7", 'Title,"Run 7'])
def test_a_row_with_more_cells_is_named_by_its_line_in_the_file(tmp_path, title):
    # below a quote left open the lines above the numbers are skipped by hand, and pandas
    # counted the lines from there ("line 11" for line 13); the streamed reader had given
    # pandas' own words
    lines = [f"{k / 10:.1f},{1.5 + k}" for k in range(20)]
    lines[10] += ",7,8"
    p, _ = _write(tmp_path, "bad.csv", f"{title}\nTime,Torque\n" + "\n".join(lines) + "\n")
    with pytest.raises(RecordingError, match="line 13 has 4 cells, the rows before it 2"):
        read_recording(p, MAP)
    with pytest.raises(RecordingError, match="line 13 has 4 cells, the rows before it 2"):
        with open_recording(p, MAP) as src:
            for _ in src.iter_chunks(["torque"], chunk_samples=6):
                pass


def test_an_open_quote_in_the_header_does_not_take_the_numbers_into_it(tmp_path):
    # '"Torque ""max' never closes before the numbers: no line of numbers joins the header
    from rollerrig.recordings.formats.sniff import _join_quoted_breaks

    lines = ['"Time","Torque ""max', '0.1,"2"', "0.2,3"]
    notes: list[str] = []
    assert _join_quoted_breaks(lines, notes) == (lines, [])
    # an unclosed quote in a preamble line above the names is not joined with them: the
    # joined line would close its quote in the middle of a cell ('Title,"Run 7 "Time"')
    lines = ['Title,"Run 7', '"Time","Torque"', "0.1,2", "0.2,3"]
    assert _join_quoted_breaks(lines, notes) == (lines, [])
    assert notes == []


def test_nul_bytes_before_the_end_of_a_text_file_are_still_binary(tmp_path):
    body = "Time,Torque\n" + "".join(f"{k / 1000:.3f},1.0\n" for k in range(100))
    p, _ = _write(tmp_path, "nul.csv", body.encode()[:500] + b"\x00" * 64 + body.encode()[500:])
    with pytest.raises(RecordingError, match="not a text file"):
        read_recording(p, MAP)
    p, _ = _write(
        tmp_path, "nul2.csv", body.encode()[:500] + b"\x00" + body.encode()[500:] + b"\x00"
    )
    with pytest.raises(RecordingError, match="not a text file"):
        read_recording(p, MAP)


# -------------------------------------------------------- variants that read (regression guard)

_E = [1.5, 1.6, 1.7]


@pytest.mark.parametrize(
    ("data", "cmap", "want"),
    [
        (b"\xef\xbb\xbfTime,Torque\n0.000,1.5\n0.001,1.6\n0.002,1.7\n", MAP, _E),
        ("Time,Torque\r0.000,1.5\r0.001,1.6\r0.002,1.7\r", MAP, _E),
        ("Time;Torque;\r\n0,000;1,5;\r\n0,001;1,6;\r\n0,002;1,7;\r\n", MAP, _E),
        (
            "Time;Torque\n0,000;1.500,5\n0,001;1.600,5\n0,002;1.700,5\n",
            MAP,
            [1500.5, 1600.5, 1700.5],
        ),
        (
            '"Time [ms]","Torque [kN·m]"\n0,1.5\n1,1.6\n2,1.7\n',
            {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}},
            [1500.0, 1600.0, 1700.0],
        ),
        (
            "# rig 3\nTime;Torque\ns;kN.m\n0,000;1,5\n0,001;1,6\n0,002;1,7\n0,003;1,",
            {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}},
            [1500.0, 1600.0, 1700.0],
        ),
        (
            "Time,Torque\n2024-08-05T13:46:13.000+02:00,1.5\n2024-08-05T13:46:13.001+02:00,1.6\n"
            "2024-08-05T13:46:13.002+02:00,1.7\n",
            {
                "time": {"column": "Time"},
                "channels": {"torque": {"column": "Torque", "unit": "N.m"}},
            },
            _E,
        ),
    ],
    ids=["bom", "bare-cr", "trailing-sep", "thousands", "bracket-units", "units-row-cut", "iso"],
)
def test_text_variants_read(tmp_path, data, cmap, want):
    p, sha = _write(tmp_path, "v.csv", data)
    rec = read_recording(p, cmap)
    np.testing.assert_allclose(rec["torque"], want)
    np.testing.assert_allclose(rec.time, [0.0, 0.001, 0.002], atol=1e-12)
    assert file_sha256(p) == sha


def _tdms_bytes(segments):
    from nptdms import TdmsWriter

    buf = io.BytesIO()
    with TdmsWriter(buf) as w:
        for objs in segments:
            w.write_segment(objs)
    return buf.getvalue()


def test_tdms_groups_of_different_rates_and_a_string_channel(tmp_path):
    nptdms = pytest.importorskip("nptdms")
    ch = nptdms.ChannelObject
    tq = np.array([1.5, 1.6, 1.7, 1.8, 1.9])
    data = _tdms_bytes(
        [
            [
                ch("Fast", "Torque", tq, properties={"wf_increment": 0.001, "unit_string": "N·m"}),
                ch("Fast", "Event", np.array(["a", "b", "c", "d", "e"])),
                ch(
                    "Slow",
                    "Load",
                    np.array([10.0, 11.0, 12.0]),
                    properties={"wf_increment": 0.002, "unit_string": "kN"},
                ),
            ]
        ]
    )
    p, sha = _write(tmp_path, "groups.tdms", data)
    rec = read_recording(
        p, {"channels": {"torque": {"column": "Torque"}, "normal_load": {"column": "Load"}}}
    )
    np.testing.assert_allclose(rec.time, np.arange(5) / 1000.0, atol=1e-12)
    np.testing.assert_allclose(rec["torque"], tq)
    np.testing.assert_allclose(rec["normal_load"], [10000, 10500, 11000, 11500, 12000])
    assert file_sha256(p) == sha


# ------------------------------------------- the format from the file's first bytes


@pytest.mark.parametrize(
    ("fmt", "mat_version", "name"),
    [
        ("mf4", "5", "inca_run.dat"),
        ("tdms", "5", "daq.dat"),
        ("mat", "5", "run"),
        ("mat", "7.3", "run.bin7"),
        ("parquet", "5", "export.data"),
    ],
    ids=["mdf-as-dat", "tdms-as-dat", "mat5-no-suffix", "mat73-odd-suffix", "parquet-odd-suffix"],
)
def test_a_binary_file_whose_suffix_does_not_say_is_read_by_its_content(
    tmp_path, fmt, mat_version, name
):
    """INCA and CANape write MDF as ``.dat``; the CLI has no --format, and such a file was
    refused for its suffix (a review, 2026-12-03). A readable format's first bytes decide
    where the suffix is none the readers know."""
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.writers import write_recording

    t = np.arange(200) / 250.0
    rec = Recording(t, {"torque": np.sin(t)}, {"torque": "N.m"})
    written = write_recording(rec, tmp_path / f"w.{fmt}", mat_version=mat_version)
    p = written.rename(tmp_path / name)
    before = file_sha256(p)
    back = read_recording(p)
    assert back.metadata["format"] == fmt
    np.testing.assert_allclose(back["torque"], np.sin(t), rtol=1e-12)
    with open_recording(p) as src:
        assert src.n_samples == 200
    assert file_sha256(p) == before


def test_feather_is_refused_with_the_parquet_advice(tmp_path):
    pa = pytest.importorskip("pyarrow")
    feather = pytest.importorskip("pyarrow.feather")
    table = pa.table({"Time": np.arange(5) / 250.0, "Torque": np.ones(5)})
    for name in ("run.feather", "run.dat"):
        feather.write_feather(table, tmp_path / name)
        with pytest.raises(RecordingError, match=r"Feather.*to_parquet"):
            read_recording(tmp_path / name, MAP)


# ------------------------------------------- an oscilloscope's CSV (Rigol DS1000Z, Keysight)


def test_a_rigol_scope_csv_is_read_and_its_increment_gives_the_rate(tmp_path):
    """``X,CH1,CH2,Start,Increment,`` over ``Sequence,Volt,Volt,-1e-3,1e-3``: the header has
    two cells more than the samples, which no [file] key could get past (a review,
    2026-12-03). Its first cells name the columns, the units row gives Volt, and Increment
    gives the time base (whole or in chunks); a map's rate that contradicts it is an error."""
    rows = "".join(f"{k},{1 + k / 1000:.6e},{2 + k / 500:.6e},\n" for k in range(400))
    p, sha = _write(
        tmp_path,
        "DS1Z_QuickPrint1.csv",
        "X,CH1,CH2,Start,Increment,\nSequence,Volt,Volt,-1.000000e-03,1.000000e-03\n" + rows,
    )
    channels = {"torque": {"column": "CH1", "unit": "N.m", "scale": 100.0}}
    rec = read_recording(p, {"channels": channels})
    assert rec.time.size == 400 and rec.sample_rate == pytest.approx(1000.0)
    np.testing.assert_allclose(rec["torque"][:3], [100.0, 100.1, 100.2])
    assert any("Rigol" in n and "1000 Hz apart" in n for n in rec.metadata["notes"])
    with open_recording(p, {"channels": channels}) as src:
        streamed = np.concatenate([c.time for c in src.iter_chunks(chunk_samples=150)])
    np.testing.assert_array_equal(streamed, rec.time)
    stated = read_recording(p, {"time": {"sample_rate_Hz": 1000.0}, "channels": channels})
    np.testing.assert_array_equal(stated.time, rec.time)
    with pytest.raises(RecordingError, match=r"sample_rate_Hz = 500 Hz .* 1000 Hz"):
        read_recording(p, {"time": {"sample_rate_Hz": 500.0}, "channels": channels})
    assert file_sha256(p) == sha
    # A wider header that is not a scope's stays an error naming the mismatch.
    q, _ = _write(tmp_path, "wide.csv", "Time,Torque,Speed,Extra\n" + "0,1,2\n1,2,3\n" * 5)
    with pytest.raises(RecordingError, match=r"wide\.csv: no rows of numbers found"):
        read_recording(q, MAP)


def test_no_time_names_the_columns_that_may_hold_it(tmp_path):
    """A pandas DatetimeIndex stored in Parquet is ``__index_level_0__``; a map without [time]
    got "no time" with no pointer to it (a review, 2026-12-03)."""
    pd = pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    index = pd.date_range("2024-08-05 13:46", periods=50, freq="4ms")
    frame = pd.DataFrame({"Torque [Nm]": np.ones(50)}, index=index)
    frame.to_parquet(tmp_path / "run.parquet")
    cmap = {"channels": {"torque": {"column": "Torque", "unit": "N.m"}}}
    with pytest.raises(RecordingError, match=r"\[time\] column = '__index_level_0__'"):
        read_recording(tmp_path / "run.parquet", cmap)
    rec = read_recording(
        tmp_path / "run.parquet", {**cmap, "time": {"column": "__index_level_0__"}}
    )
    assert rec.sample_rate == pytest.approx(250.0)


# ------------------------------------------- exports found by a review of 2026-12-03

_CATMAN_MAP = {
    "time": {"sample_rate_Hz": 1000.0},
    "channels": {
        "torque": {"column": "Drehmoment"},
        "roller_speed": {"column": "Drehzahl Rolle"},
    },
}


def _catman_rows(n=200):
    t = np.arange(n) / 1000.0
    return [f"\t{100 + 10 * np.sin(2 * np.pi * 5 * k):.4f}\t{600 + k:.3f}" for k in t]


def test_catman_key_value_rows_under_the_units_are_no_samples(tmp_path):
    # catman's channel header: names, units, then "Anzahl Werte" and "dt" rows, each giving
    # one value for every channel, above samples whose key column is empty. They had been read
    # as two samples (a torque of 2000 and of 0.001 N.m), without a word.
    lines = ["Kanalname\tDrehmoment\tDrehzahl Rolle", "Einheit\tN·m\t1/min",
             "Anzahl Werte\t200\t200", "dt\t0,001\t0,001"]  # fmt: skip
    lines += [r.replace(".", ",") for r in _catman_rows()]
    p, sha = _write(tmp_path, "catman.txt", "\r\n".join(lines).encode("cp1252"))
    rec = read_recording(p, _CATMAN_MAP)
    assert rec.time.size == 200
    assert rec["torque"][0] == pytest.approx(100.0)
    assert rec["roller_speed"][0] == pytest.approx(600 * 2 * np.pi / 60)
    assert file_sha256(p) == sha


def test_a_marker_column_with_samples_beside_it_keeps_them(tmp_path):
    # the contrary case: a marker column on the left whose first samples carry markers
    rows = "".join(f"{m},{k / 1000:.3f},{1 + k / 10:.1f}\n" for k, m in
                   enumerate(["Start", "Ramp"] + [""] * 10))  # fmt: skip
    p, _ = _write(tmp_path, "marks.csv", f"Marker,Time,Torque\n{rows}")
    assert read_recording(p, MAP).time.size == 12


def test_a_full_catman_header_is_found_above_its_key_value_rows(tmp_path):
    lines = ["catman AP V5.4.2 - ASCII Export", "Datei\tC:\\Messdaten\\Lauf_017.BIN",
             "Anzahl Kanäle\t3",
             "Kanalname\tZeit  1 - Standardmessrate\tDrehmoment\tDrehzahl Rolle",
             "Einheit\ts\tN·m\t1/min", "T0\t01.05.2024 13:59:59\t01.05.2024 13:59:59\t"
             "01.05.2024 13:59:59", "dt\t0,001\t0,001\t0,001", "Anzahl Werte\t200\t200\t200",
             ""]  # fmt: skip
    lines += [f"\t{k / 1000:.3f}{r}".replace(".", ",") for k, r in enumerate(_catman_rows())]
    p, _ = _write(tmp_path, "catman_hdr.txt", "\r\n".join(lines).encode("cp1252"))
    cmap = {**_CATMAN_MAP, "time": {"column": "Zeit  1 - Standardmessrate"}}
    rec = read_recording(p, cmap)
    assert rec.time.size == 200 and rec.sample_rate == pytest.approx(1000.0)
    assert rec.units["torque"] == "N.m"
    # the map's rate is checked against that time column, named otherwise than "Time"
    with pytest.raises(RecordingError, match=r"contradicts the file's own rate of 1000 Hz"):
        read_recording(p, {**_CATMAN_MAP, "time": {"sample_rate_Hz": 500.0}})


@pytest.mark.parametrize("cut_after", [6, 7, 8], ids=["after-T0", "after-dt", "after-count"])
def test_a_catman_header_cut_before_its_samples_says_so(tmp_path, cut_after):
    # Cut before the first sample, the header's T0/dt rows had been taken for samples: the
    # error asked for a date_format, or said no channels were found.
    lines = ["catman AP V5.4.2 - ASCII Export", "Anzahl Kanäle\t3",
             "Kanalname\tZeit  1 - Standardmessrate\tDrehmoment\tDrehzahl Rolle",
             "Einheit\ts\tN·m\t1/min", "T0\t01.05.2024 13:59:59\t01.05.2024 13:59:59\t"
             "01.05.2024 13:59:59", "dt\t0,001\t0,001\t0,001", "Anzahl Werte\t0\t0\t0",
             ]  # fmt: skip
    p, sha = _write(tmp_path, "cut.txt", "\r\n".join(lines[: cut_after - 1]).encode("cp1252"))
    with pytest.raises(RecordingError, match=r"has a header but no data rows.*cut before"):
        read_recording(p, {**_CATMAN_MAP, "time": {"column": "Zeit"}})
    assert file_sha256(p) == sha


@pytest.mark.parametrize(
    ("cell", "unit", "want"),
    [("1\u00a0500,00", "tr/min", 1500.0), ("1 500,00", "rpm", 1500.0),
     ("1'800.00", "rpm", 1800.0), ("1\u202f800,5", "rpm", 1800.5)],
    ids=["french-excel-nbsp", "space", "swiss-apostrophe", "narrow-nbsp"],
)  # fmt: skip
def test_thousands_marks_that_are_never_decimal_marks_are_read(tmp_path, cell, unit, want):
    sep = ";"
    rows = "".join(f"{k / 1000:.3f}{sep}{cell}\n" for k in range(10))
    if "," in cell:
        rows = rows.replace(".", ",")
    p, _ = _write(tmp_path, "fr.csv", f"Temps (s){sep}Vitesse ({unit})\n{rows}")
    rec = read_recording(p, {"time": {"column": "Temps"},
                             "channels": {"roller_speed": {"column": "Vitesse"}}})  # fmt: skip
    np.testing.assert_allclose(rec["roller_speed"], want * 2 * np.pi / 60)


def test_groups_that_are_not_strict_threes_stay_text(tmp_path):
    rows = "".join(f"{k / 1000:.3f};12 34\n" for k in range(10))
    p, _ = _write(tmp_path, "bad.csv", f"Time;Torque\n{rows}")
    with pytest.raises(RecordingError, match="non-numeric"):
        read_recording(p, MAP)


def test_msvc_infinity_is_an_infinite_sample(tmp_path):
    rows = "".join(f"{k / 1000:.3f},{'1.#INF' if k == 5 else '1.0'}\n" for k in range(10))
    p, _ = _write(tmp_path, "inf.csv", f"Time,Torque\n{rows}")
    with pytest.raises(RecordingError, match=r"1 NaN/inf samples"):
        read_recording(p, MAP)


def test_ambiguous_slash_dates_crossing_midnight_read_day_first(tmp_path):
    # 01/05/2024 23:59:59 then 02/05/2024 00:00:00: one second day-first, a month month-first
    clock = ["23:59:58", "23:59:59", "00:00:00", "00:00:01", "00:00:02"]
    stamps = [f"0{1 + (k >= 2)}/05/2024 {c}" for k, c in enumerate(clock)]
    rows = "".join(f"{s},{k}\n" for k, s in enumerate(stamps))
    p, _ = _write(tmp_path, "uk.csv", f"Time,Torque\n{rows}")
    rec = read_recording(p, {"time": {"column": "Time"}, "channels": {"torque": {
        "column": "Torque", "unit": "N.m"}}})  # fmt: skip
    np.testing.assert_allclose(rec.time, [0, 1, 2, 3, 4])
    assert any("read day-first" in n for n in rec.metadata["notes"])


def test_an_hour_back_names_daylight_saving_time(tmp_path):
    t = [0.0, 1.0, 2.0, 2.0 - 3600.0 + 1.0, 2.0 - 3600.0 + 2.0]
    rows = "".join(f"{v:.3f},1.0\n" for v in t)
    p, _ = _write(tmp_path, "dst.csv", f"Time,Torque\n{rows}")
    with pytest.raises(RecordingError, match="daylight saving"):
        read_recording(p, MAP)


def _cet_spring_rows(start_s: int, n: int) -> list[str]:
    """``n`` rows ``stamp;k`` at 4 Hz on a German wall clock from ``start_s`` seconds after
    00:00 UTC on 31 March 2024, when CET goes to CEST at 01:00 UTC (02:00 -> 03:00 local)."""
    import datetime as dt

    utc0 = dt.datetime(2024, 3, 31) + dt.timedelta(seconds=start_s)
    rows = []
    for k in range(n):
        u = utc0 + dt.timedelta(milliseconds=250 * k)
        local = u + dt.timedelta(hours=1 if u < dt.datetime(2024, 3, 31, 1) else 2)
        rows.append(f"{local.strftime('%d.%m.%Y %H:%M:%S,%f')[:-3]};{k}\n")
    return rows


@pytest.mark.parametrize("validate", ["strict", "lenient"])
def test_an_hour_forward_names_daylight_saving_time(tmp_path, validate):
    # 4 Hz on a local wall clock, CET -> CEST at 02:00 on 31 March 2024: 01:59:59,750 is
    # followed by 03:00:00,000. Read as a gap of 14400 dropped samples; lenient kept it and
    # the recording lasted 3603.75 s instead of 3.75 s.
    rows = _cet_spring_rows(59 * 60 + 58, 16)
    p, sha = _write(tmp_path, "spring.csv", "Zeit;Moment\n" + "".join(rows))
    cmap = {"time": {"column": "Zeit"}, "channels": {"torque": {"column": "Moment", "unit": "N.m"}}}
    with pytest.raises(RecordingError, match=r"row 7 .*daylight saving time.* UTC offset") as e:
        read_recording(p, cmap, validate=validate)
    assert "'31.03.2024 03:00:00,000'" in str(e.value) and "sample_rate_Hz" in str(e.value)
    # the fix it names: the rate instead of the time column
    rec = read_recording(p, {**cmap, "time": {"sample_rate_Hz": 4}})
    assert rec.time[-1] == pytest.approx(3.75)
    # the same step in a month without a change to daylight saving time is a gap, as before
    p2, _ = _write(tmp_path, "july.csv", "Zeit;Moment\n" + "".join(rows).replace(".03.", ".07."))
    with pytest.raises(RecordingError, match="gap"):
        read_recording(p2, cmap)
    assert file_sha256(p) == sha


@pytest.mark.parametrize("chunk", [4800, 1200, 700])
def test_an_hour_forward_at_a_chunk_boundary_names_daylight_saving_time(tmp_path, chunk):
    # 4 Hz on a local wall clock across CET -> CEST (02:00 on 31 March 2024), the step after
    # the first samples the source probes. Chunks of 4800 samples end at 01:59:59,750 and the
    # next begins at 03:00:00,000: each chunk alone was even, and the step between them read as
    # a gap of dropped samples, not as the clock going forward.
    rows = _cet_spring_rows(40 * 60, 6000)
    assert rows[4799].startswith("31.03.2024 01:59:59,750")
    assert rows[4800].startswith("31.03.2024 03:00:00,000")
    p, sha = _write(tmp_path, "spring.csv", "Zeit;Moment\n" + "".join(rows))
    cmap = {"time": {"column": "Zeit"}, "channels": {"torque": {"column": "Moment", "unit": "N.m"}}}
    with open_recording(p, cmap) as src:
        with pytest.raises(RecordingError, match=r"daylight saving time") as e:
            for _ in src.iter_chunks(["torque"], chunk_samples=chunk):
                pass
    assert "'31.03.2024 03:00:00,000'" in str(e.value) and "sample_rate_Hz" in str(e.value)
    assert "row 4799 '31.03.2024 01:59:59,750'" in str(e.value)
    assert file_sha256(p) == sha


def test_chunks_an_hour_into_a_recording_are_no_daylight_saving_step(tmp_path):
    # 1 Hz in March, chunks of 3600 samples: each chunk's first time lies 3600 s after the
    # file's first sample, which anchors it. That step is no neighbour of the chunk's samples.
    import datetime as dt

    t0 = dt.datetime(2024, 3, 12, 8, 0, 0)
    rows = [
        f"{(t0 + dt.timedelta(seconds=k)).strftime('%d.%m.%Y %H:%M:%S')};{k}\n"
        for k in range(3 * 3600 + 10)
    ]
    p, _ = _write(tmp_path, "march.csv", "Zeit;Moment\n" + "".join(rows))
    cmap = {"time": {"column": "Zeit"}, "channels": {"torque": {"column": "Moment", "unit": "N.m"}}}
    with open_recording(p, cmap) as src:
        t = np.concatenate([c.time for c in src.iter_chunks(["torque"], chunk_samples=3600)])
    np.testing.assert_array_equal(t, np.arange(3 * 3600 + 10, dtype=float))


_ABBREVIATIONS = {
    "German": "Jan Feb Mär Apr Mai Jun Jul Aug Sep Okt Nov Dez",
    "French": "janv. févr. mars avr. mai juin juil. août sept. oct. nov. déc.",
    "Spanish": "ene feb mar abr may jun jul ago sep oct nov dic",
    "Italian": "gen feb mar apr mag giu lug ago set ott nov dic",
    "Dutch": "jan feb mrt apr mei jun jul aug sep okt nov dec",
    "Portuguese": "jan fev mar abr mai jun jul ago set out nov dez",
}
"""Month abbreviations as Excel, LabVIEW and Windows write them in each language."""


def _month_word(language: str, month: int, style: str) -> str:
    from rollerrig.recordings.formats.timestamps import _MONTH_NAMES

    if style == "short":
        return _ABBREVIATIONS[language].split()[month - 1]
    word = _MONTH_NAMES[language].split()[month - 1].split("|")[0]
    return word.upper() if style == "upper" else word.capitalize()


@settings(max_examples=150, deadline=None)
@given(
    st.sampled_from(sorted(_ABBREVIATIONS)),
    st.sampled_from(["short", "long", "upper"]),
    st.sampled_from(["-", " ", "."]),
    st.dates(min_value=__import__("datetime").date(1990, 1, 1)),
    st.integers(0, 400),
)
def test_month_names_of_european_languages_read_the_right_month(language, style, sep, day, n):
    # "05-Dez-2024" had been "no English month name"; each language's names and
    # abbreviations, in any case, read as their month without the machine's locale
    import datetime as dt

    from rollerrig.recordings.formats.timestamps import parse_timestamps

    later = day + dt.timedelta(days=n)
    cells = [
        f"{d.day:02d}{sep}{_month_word(language, d.month, style)}{sep}{d.year} 12:00:00"
        for d in (day, later)
    ]
    cells = [c.replace("..", ".") for c in cells]  # "05.déc..2024" is no one's spelling
    secs, _ = parse_timestamps(cells, what="Zeit")
    assert secs.tolist() == [0.0, n * 86400.0], cells


@pytest.mark.parametrize(
    ("stamps", "language"),
    [
        (["05-Dez-2024 23:59:59,500", "06-Dez-2024 00:00:00,000"], "German"),
        (["31-Mär-2024 10:00:00,000", "31-Mär-2024 10:00:00,500"], "German"),
        (["05 déc. 2024 23:59:59,500", "06 déc. 2024 00:00:00,000"], "French"),
        (["28-févr.-2024 10:00:00,000", "28-févr.-2024 10:00:00,500"], "French"),
        (["05-ene-2025 10:00:00,000", "05-ene-2025 10:00:00,500"], "Spanish"),
        (["05-gen-2025 10:00:00,000", "05-gen-2025 10:00:00,500"], "Italian"),
    ],
)
def test_a_csv_with_non_english_month_names_is_read_and_says_the_language(
    tmp_path, stamps, language
):
    rows = "".join(f"{s};{k},5\n" for k, s in enumerate(stamps * 1))
    p, sha = _write(tmp_path, "monate.csv", "Zeit;Moment\n" + rows)
    cmap = {"time": {"column": "Zeit"}, "channels": {"torque": {"column": "Moment", "unit": "N.m"}}}
    rec = read_recording(p, cmap)
    np.testing.assert_allclose(rec.time, [0.0, 0.5])
    assert any(f"month names read as {language}" in n for n in rec.metadata["notes"])
    assert file_sha256(p) == sha


def test_non_english_month_names_with_a_date_format_are_read(tmp_path):
    # %B / %b of a date_format read English only (pandas, the C locale)
    rows = "".join(
        f"{d} 2024 12:00:00;{k}\n" for k, d in enumerate(["28 février", "29 février", "1 mars"])
    )
    p, _ = _write(tmp_path, "fr.csv", "Temps;Couple\n" + rows)
    cmap = {"file": {"date_format": "%d %B %Y %H:%M:%S"}, "time": {"column": "Temps"},
            "channels": {"torque": {"column": "Couple", "unit": "N.m"}}}  # fmt: skip
    rec = read_recording(p, cmap, validate="lenient")
    np.testing.assert_allclose(rec.time, [0.0, 86400.0, 172800.0])
    assert any("month names read as French" in n for n in rec.metadata["notes"])


def test_a_date_format_that_spells_the_abbreviation_s_point_reads_it():
    # .NET's de-DE "dd. MMM. yyyy" writes '05. Dez. 2024'; a date_format '%d. %b. %Y' had
    # failed as not matching, the point taken away with the month's name (review 2026-12-03)
    from rollerrig.recordings.formats.timestamps import parse_timestamps

    cells = ["05. Dez. 2024 10:00:00", "06. Dez. 2024 10:00:00"]
    seconds, _ = parse_timestamps(cells, what="Zeit", date_format="%d. %b. %Y %H:%M:%S")
    np.testing.assert_allclose(np.diff(seconds), [86400.0])


def test_month_names_of_two_languages_in_one_column_are_refused():
    from rollerrig.recordings.formats.timestamps import parse_timestamps

    with pytest.raises(RecordingError, match=r"row 1 .*'déc\.' is no German month's name"):
        parse_timestamps(["05-Dez-2024 10:00:00", "06-déc.-2024 10:00:00"], what="Zeit")


@pytest.mark.parametrize(
    ("stamp", "note"),
    [
        ("%d-%b-%Y %H:%M:%S.%f", "day-month name-year"),  # MATLAB datetime, Oracle, SAS
        ("%d-%B-%Y %H:%M:%S.%f", "day-month name-year"),
        ("pandas", "pandas' Timedelta"),  # DataFrame.to_csv of a timedelta column
    ],
)
def test_month_names_and_pandas_timedeltas_across_midnight_are_read(tmp_path, stamp, note):
    # The refusal had suggested date_format '05-%b-2024 %H:%M:%S.%f' (and '0 days %H:%M:%S.%f'
    # for pandas), copying the first row's day and year: the next day's rows did not match.
    import datetime as dt

    t0 = dt.datetime(2024, 8, 5, 23, 59, 59)
    stamps = [t0 + dt.timedelta(milliseconds=250 * k) for k in range(12)]
    if stamp == "pandas":
        import pandas as pd

        td = pd.to_timedelta(np.arange(12) * 250, unit="ms") + pd.Timedelta(
            hours=23, minutes=59, seconds=59
        )
        cells = [str(v) for v in td]
    else:
        cells = [s.strftime(stamp)[:-3] for s in stamps]
    rows = "".join(f"{c},{k}\n" for k, c in enumerate(cells))
    p, sha = _write(tmp_path, "mon.csv", f"Time,Torque\n{rows}")
    rec = read_recording(p, MAP)
    np.testing.assert_allclose(rec.time, np.arange(12) * 0.25, atol=1e-9)
    assert any(note in n for n in rec.metadata["notes"])
    assert file_sha256(p) == sha
    if stamp == "pandas":  # pandas writes a negative Timedelta as '-1 days +23:59:59.750000'
        neg = ["-1 days +23:59:59.500000", "-1 days +23:59:59.750000", "0 days 00:00:00"]
        rows = "".join(f"{c},{k}\n" for k, c in enumerate(neg))
        p, _ = _write(tmp_path, "neg.csv", f"Time,Torque\n{rows}")
        np.testing.assert_allclose(read_recording(p, MAP).time, [0.0, 0.25, 0.5])


def test_time_printed_to_too_few_digits_suggests_the_sample_rate(tmp_path):
    rows = "".join(f"{k / 2000:.3f},1.0\n" for k in range(40))  # 2 kHz printed to ms
    p, _ = _write(tmp_path, "ms.csv", f"Time,Torque\n{rows}")
    with pytest.raises(RecordingError, match="sample_rate_Hz"):
        read_recording(p, MAP)


def test_a_channel_that_ends_early_is_named_as_such(tmp_path):
    # two rates side by side (catman's "Zeit 2 - Langsam" beside its channel): the slow
    # channel's cells are empty after its last sample
    rows = "".join(f"{k / 1000:.3f},1.0,{k / 100:.2f},{2.0 if k < 20 else ''}\n"
                   for k in range(100))  # fmt: skip
    p, _ = _write(tmp_path, "rates.csv", f"Time,Torque,Time 2,Speed\n{rows}")
    cmap = {**MAP, "channels": {**MAP["channels"], "roller_speed": {"column": "Speed",
            "unit": "rpm"}}}  # fmt: skip
    with pytest.raises(RecordingError, match=r"ends at sample 20 .*its own time column"):
        read_recording(p, cmap)


def test_a_unit_in_brackets_may_hold_parentheses(tmp_path):
    rows = "".join(f"{k / 1000:.3f};{k}\n" for k in range(10))
    p, _ = _write(tmp_path, "p.csv", f"Time [s];Druck [bar(g)]\n{rows}")
    cmap = {"time": {"column": "Time"}, "extra": {"p": {"column": "Druck", "unit": "bar"}}}
    rec = read_recording(p, cmap)  # the file says bar(g): the same unit as the map's bar
    np.testing.assert_allclose(rec["p"], np.arange(10) * 1e5)


def test_the_chunked_reader_names_the_row_in_the_file_not_in_the_chunk(tmp_path):
    # zeros beyond the rows the layout is sniffed from, then cells that read both ways
    rows = "".join(f"{k};{'0' if k < 20000 else '100,000'}\n" for k in range(20500))
    p, _ = _write(tmp_path, "late.csv", f"Time [ms];Torque [Nm]\n{rows}")
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    with pytest.raises(RecordingError, match=r"first at row 20000\b"):
        read_recording(p, cmap)
    with pytest.raises(RecordingError, match=r"first at row 20000\b"):
        with open_recording(p, cmap) as src:
            for _ in src.iter_chunks(["torque"], chunk_samples=7000):
                pass


# ------------------------------------------- elapsed hours:minutes:seconds; samples below a footer


def _hms(s):
    return f"{int(s // 3600):02d}:{int(s % 3600 // 60):02d}:{s % 60:06.3f}"


@pytest.mark.parametrize("start_h", [99, 999, 0])
def test_elapsed_hours_of_any_digits_are_times(tmp_path, start_h):
    """An endurance run's elapsed time passing 100 hours ('99:59:59.500' then
    '100:00:00.000'): from there the cells were no times, and the rest of the file was
    dropped as a footer (60 rows, 20 kept, only a note)."""
    start = start_h * 3600 + 59 * 60 + 50
    rows = "".join(f"{_hms(start + k * 0.5)},{k}\n" for k in range(60))
    p, sha = _write(tmp_path, "elapsed.csv", "Time,Torque [N.m]\n" + rows)
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    rec = read_recording(p, cmap)
    assert file_sha256(p) == sha
    np.testing.assert_allclose(rec.time, np.arange(60) * 0.5, atol=1e-9)
    np.testing.assert_array_equal(rec["torque"], np.arange(60.0))
    assert not any("footer" in note for note in rec.metadata["notes"])
    with open_recording(p, cmap) as src:
        chunks = list(src.iter_chunks(["torque"], chunk_samples=7))
    np.testing.assert_allclose(np.concatenate([c.time for c in chunks]), rec.time, atol=1e-9)


def test_lines_laid_out_as_samples_below_the_samples_are_no_silent_footer(tmp_path):
    """.NET's TimeSpan writes an elapsed time past a day as '1.00:00:00.0000000' (days before
    the hours): a form this reader does not know. The lines from there on were dropped as a
    footer with only a note; now an error names the first of them. A footer of words below
    them is still a footer."""

    def timespan(s):
        days, rest = divmod(s, 86400)
        hms = f"{int(rest // 3600):02d}:{int(rest % 3600 // 60):02d}:{rest % 60:010.7f}"
        return (f"{int(days)}." if days else "") + hms

    rows = "".join(f"{timespan(86400 - 20 + k * 0.5)},{k}\n" for k in range(60))
    p, sha = _write(tmp_path, "timespan.csv", "Time,Torque [N.m]\n" + rows + "Mean,29.5\n")
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    match = r"line 42 \('1\.00:00:00\.0000000,40'\) below the samples is laid out as one.*20 line"
    with pytest.raises(RecordingError, match=match):
        read_recording(p, cmap)
    with pytest.raises(RecordingError, match=match):
        open_recording(p, cmap)
    assert file_sha256(p) == sha


# ------------------------------------------- integer epoch counts without a unit


@pytest.mark.parametrize(("unit", "per_second"), [("ms", 10**3), ("us", 10**6), ("ns", 10**9)])
def test_integer_epoch_counts_without_a_unit_are_read_in_the_unit_that_makes_them_a_date(
    tmp_path, unit, per_second
):
    """Unix time in µs from a 1 kHz logger (1722865573250000): read as seconds (0.001 Hz) with
    a warning advising unit = "ms", which gave 1 Hz without a word. Now read in the one unit
    that makes the first value a date between 1990 and 2100, with a note; a stated unit that
    makes the rate implausible is an error naming the right one."""
    import warnings

    t0 = 1722865573250 * per_second // 1000
    step = per_second // 1000  # 1 kHz
    rows = "".join(f"{t0 + k * step},{100 + k % 7}\n" for k in range(3000))
    p, sha = _write(tmp_path, "epoch.csv", "Time,Torque [N.m]\n" + rows)
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no unit warning: the unit is known now
        rec = read_recording(p, cmap)
    assert rec.sample_rate == pytest.approx(1000.0, rel=1e-9)
    np.testing.assert_allclose(rec.time, np.arange(3000) * 1e-3, atol=1e-9)
    assert any(
        f"is a date only in {unit!r} (2024-08-05T13:46:13.250 UTC" in n and f'unit = "{unit}"' in n
        for n in rec.metadata["notes"]
    )
    with open_recording(p, cmap) as src:
        assert src.sample_rate == pytest.approx(1000.0, rel=1e-9)
        chunks = list(src.iter_chunks(["torque"], chunk_samples=1000))
    np.testing.assert_allclose(np.concatenate([c.time for c in chunks]), rec.time, atol=1e-9)
    # a coarser unit stated (the old advice "ms" for µs): far below any rig's rate, an error
    for wrong in ("s", "ms", "us")[: ("ms", "us", "ns").index(unit) + 1]:
        match = rf'is no date; in {unit!r} it is 2024-08-05T13:46:13\.250 UTC.*unit = "{unit}"'
        with pytest.raises(RecordingError, match=match):
            read_recording(p, {**cmap, "time": {"column": "Time", "unit": wrong}})
    assert read_recording(p, {**cmap, "time": {"column": "Time", "unit": unit}}).sample_rate == (
        pytest.approx(1000.0, rel=1e-9)
    )
    assert file_sha256(p) == sha


def test_an_int64_ns_tdms_time_channel_without_a_unit(tmp_path):
    from nptdms import ChannelObject, TdmsWriter

    n, t0 = 2000, 1722865573250000000
    p = tmp_path / "ns.tdms"
    with TdmsWriter(str(p)) as w:
        w.write_segment([
            ChannelObject("Log", "Time", t0 + np.arange(n, dtype=np.int64) * 1_000_000),
            ChannelObject("Log", "Torque", np.ones(n), properties={"unit_string": "N.m"}),
        ])  # fmt: skip
    sha = file_sha256(p)
    cmap = {"time": {"column": "Log/Time"}, "channels": {"torque": {"column": "Log/Torque"}}}
    rec = read_recording(p, cmap)
    np.testing.assert_allclose(rec.time, np.arange(n) * 1e-3, atol=1e-9)
    assert any("is a date only in 'ns'" in note for note in rec.metadata["notes"])
    match = r'in \'ns\' it is 2024-08-05T13:46:13\.250 UTC.*unit = "ns"'
    with pytest.raises(RecordingError, match=match):
        read_recording(p, {**cmap, "time": {"column": "Log/Time", "unit": "ms"}})
    assert file_sha256(p) == sha


@pytest.mark.parametrize(
    ("cells", "unit", "rate"),
    [
        ([f"{k * 4}" for k in range(1000)], "ms", 250.0),  # elapsed ms, stated
        ([f"{k * 0.004:.3f}" for k in range(1000)], None, 250.0),  # elapsed s, no unit
        ([f"{1722865573 + k * 0.004:.3f}" for k in range(1000)], None, 250.0),  # epoch in s
        ([f"{k * 1000}" for k in range(1000)], "us", 1000.0),  # elapsed µs, stated
    ],
)
def test_elapsed_times_and_epoch_seconds_keep_their_unit(tmp_path, cells, unit, rate):
    p, _ = _write(tmp_path, "t.csv", "Time,Torque [N.m]\n" + "".join(f"{c},1\n" for c in cells))
    tspec = {"column": "Time"} | ({"unit": unit} if unit else {})
    rec = read_recording(p, {"time": tspec, "channels": {"torque": {"column": "Torque"}}})
    assert rec.sample_rate == pytest.approx(rate, rel=1e-6)
    assert not any("is a date only" in note for note in rec.metadata["notes"])


def test_an_elapsed_count_of_microseconds_read_as_seconds_advises_us(tmp_path):
    """The unit warning advised "ms" whatever the count: microseconds from 0 at 1 kHz read as
    seconds are 0.001 Hz, and "ms" made them 1 Hz."""
    p, _ = _write(
        tmp_path, "us.csv", "Time,Torque [N.m]\n" + "".join(f"{k * 1000},1\n" for k in range(5000))
    )
    cmap = {"time": {"column": "Time"}, "channels": {"torque": {"column": "Torque"}}}
    with pytest.warns(UserWarning, match=r'looks like microseconds \(1000 Hz.*unit = "us"'):
        read_recording(p, cmap)


def test_a_bad_timestamp_read_in_chunks_is_named_by_its_row_in_the_file(tmp_path):
    # The streamed reader hands each chunk's cells with the file's first sample before them;
    # an error had named the row within that block ("row 217" for row 5000, review 2026-12-03)
    import datetime as dt

    t0 = dt.datetime(2024, 8, 5, 10, 0, 0)
    stamps = [(t0 + dt.timedelta(milliseconds=k)).strftime("%d.%m.%Y %H:%M:%S.%f")[:-3]
              for k in range(3000)]  # fmt: skip
    stamps[2500] = "05.08.2024 1x:00:05"
    body = "Zeit;Moment\n" + "".join(f"{s};{k}\n" for k, s in enumerate(stamps))
    p, _ = _write(tmp_path, "stamps.csv", body)
    cmap = {"time": {"column": "Zeit"},
            "channels": {"torque": {"column": "Moment", "unit": "N.m"}}}  # fmt: skip
    with pytest.raises(RecordingError, match=r"row 2500 (\(file line 2502\) )?'05\.08\.2024 1x"):
        read_recording(p, cmap)
    with pytest.raises(RecordingError, match=r"row 2500 (\(file line 2502\) )?'05\.08\.2024 1x"):
        with open_recording(p, cmap) as src:
            for _ in src.iter_chunks(["torque"], chunk_samples=700):
                pass
