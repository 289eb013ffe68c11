"""Chunked reading (open_recording): the chunks, concatenated, are what read_recording gives.

Files are written with rollerrig's writers (every format) and, for foreign layouts, with the
libraries the tools' files are read with (nptdms, asammdf, pandas, h5py), with channel maps in
non-SI units, scale and offset; the reference is :func:`read_recording` on the same file.
"""

from __future__ import annotations

import hashlib
import os

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.source import Chunk, open_recording
from rollerrig.recordings.writers import write_recording

N = 2001
RATE = 500.0


def _fingerprint(path):
    s = os.stat(path)
    return hashlib.sha256(path.read_bytes()).hexdigest(), s.st_mtime_ns, s.st_size


def _labview_tdms(path):
    """LabVIEW waveforms in two segments: kN.m torque with a calibration offset, rpm speed."""
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    t = np.arange(N) / RATE
    wf = {
        "wf_start_time": np.datetime64("2024-08-05T13:46:13", "us"),
        "wf_start_offset": 0.25,
        "wf_increment": 1 / RATE,
    }
    with TdmsWriter(str(path)) as w:
        for s in (slice(0, 1000), slice(1000, N)):
            w.write_segment(
                [
                    RootObject(),
                    GroupObject("Rig"),
                    ChannelObject("Rig", "Torque", 0.4 * np.sin(t[s]), properties=wf),
                    ChannelObject("Rig", "Speed", 300 + t[s], properties=wf),
                ]
            )
    return {
        "channels": {
            "torque": {"column": "Torque", "unit": "kN.m", "scale": 1.01, "offset": -0.002},
            "roller_speed": {"column": "Rig/Speed", "unit": "rpm"},
        }
    }


def _inca_mdf(path):
    """INCA-like: two rasters with masters named time, Torque in both; the 2 ms raster is read."""
    from asammdf import MDF, Signal

    t1 = np.arange(N) / RATE
    t2 = np.arange(40) / 10.0
    mdf = MDF(version="4.10")
    mdf.append(
        [Signal(np.cos(t1), t1, name="Torque", unit="kNm"), Signal(t1, t1, name="n", unit="rpm")],
        acq_name="2ms",
    )
    mdf.append([Signal(np.cos(t2), t2, name="Torque", unit="kNm")], acq_name="100ms")
    mdf.save(path, overwrite=True)
    mdf.close()
    return {
        "file": {"group": "2ms"},
        "channels": {"torque": {"column": "Torque"}, "roller_speed": {"column": "n"}},
    }


def _csv_ms(path):
    """A bench export: semicolons, time in ms, torque in kN.m."""
    t = np.arange(N) / RATE
    pd.DataFrame({"t_ms": 1e3 * t, "T": 0.3 * np.sin(3 * t), "F": 10 + t}).to_csv(
        path, sep=";", index=False
    )
    return {
        "time": {"column": "t_ms", "unit": "ms"},
        "channels": {
            "torque": {"column": "T", "unit": "kN.m"},
            "normal_load": {"column": "F", "unit": "kN"},
        },
    }


def _mat73_h5py(path):
    """MATLAB v7.3 layout written with h5py: a struct 'meas' of 1 x n double vectors."""
    import h5py

    t = np.arange(N) / RATE
    with h5py.File(path, "w") as h:
        g = h.create_group("meas")
        g.attrs["MATLAB_class"] = np.bytes_("struct")
        for name, v in {"t": t, "T": np.sin(t), "p": 2 + t}.items():
            ds = g.create_dataset(name, data=v.reshape(1, -1))
            ds.attrs["MATLAB_class"] = np.bytes_("double")
    return {
        "time": {"column": "meas.t"},
        "channels": {
            "torque": {"column": "meas.T", "unit": "N.m"},
            "air_spring_pressure": {"column": "meas.p", "unit": "bar"},
        },
    }


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """(path, channel map, read_recording result, fingerprint) per case."""
    d = tmp_path_factory.mktemp("src")
    t = 0.5 + np.arange(N) / RATE
    rec = Recording(
        t,
        {"torque": 400.0 * np.sin(7 * t), "roller_speed": 5.0 + t, "slip": 0.01 * t},
        {"torque": "N.m", "roller_speed": "rad/s", "slip": "m/s"},
    )
    cases = {}
    for name, suffix, kw in [
        ("csv", ".csv", {}),
        ("parquet", ".parquet", {}),
        ("tdms", ".tdms", {}),
        ("mf4", ".mf4", {}),
        ("mat5", ".mat", {}),
        ("mat73", ".mat", {"mat_version": "7.3"}),
    ]:
        f = d / f"{name}{suffix}"
        write_recording(rec, f, **kw)
        cases[name] = (f, None)
    for name, build, suffix in [
        ("labview", _labview_tdms, ".tdms"),
        ("inca", _inca_mdf, ".mf4"),
        ("csv_ms", _csv_ms, ".csv"),
        ("mat73_h5py", _mat73_h5py, ".mat"),
    ]:
        f = d / f"{name}{suffix}"
        cases[name] = (f, build(f))
    return {
        name: (f, cmap, read_recording(f, cmap), _fingerprint(f))
        for name, (f, cmap) in cases.items()
    }


CASES = [
    "csv",
    "parquet",
    "tdms",
    "mf4",
    "mat5",
    "mat73",
    "labview",
    "inca",
    "csv_ms",
    "mat73_h5py",
]


@pytest.mark.parametrize("case", CASES)
@settings(
    max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.data())
def test_chunks_concatenate_to_read_recording(files, case, data):
    f, cmap, ref, before = files[case]
    chunk = data.draw(st.integers(40, 2 * N), label="chunk_samples")
    start = data.draw(st.integers(0, N - 2), label="start")
    stop = data.draw(st.one_of(st.none(), st.integers(start + 1, N)), label="stop")
    with open_recording(f, cmap) as src:
        assert set(src.names) == set(ref.channels)
        assert dict(src.units) == dict(ref.units)
        assert src.n_samples == ref.time.size
        assert src.sample_rate == pytest.approx(ref.sample_rate, rel=1e-9)
        assert src.duration == pytest.approx(ref.duration, rel=1e-12)
        assert src.metadata["columns"] == ref.metadata["columns"]
        names = data.draw(st.lists(st.sampled_from(src.names), min_size=1, unique=True))
        chunks = list(src.iter_chunks(names, chunk_samples=chunk, start=start, stop=stop))
    end = ref.time.size if stop is None else stop
    assert [c.start_index for c in chunks] == list(range(start, end, chunk))
    assert all(isinstance(c, Chunk) and len(c) <= chunk for c in chunks)
    np.testing.assert_array_equal(np.concatenate([c.time for c in chunks]), ref.time[start:end])
    for name in names:
        got = np.concatenate([c[name] for c in chunks])
        np.testing.assert_array_equal(got, ref[name][start:end])
    assert _fingerprint(f) == before


@pytest.mark.parametrize("case", ["tdms", "csv_ms", "mat73"])
def test_one_sample_chunks(files, case):
    f, cmap, ref, _ = files[case]
    with open_recording(f, cmap) as src:
        chunks = list(src.iter_chunks("torque", chunk_samples=1, start=N - 300))
    assert [len(c) for c in chunks] == [1] * 300
    np.testing.assert_array_equal(
        np.concatenate([c["torque"] for c in chunks]), ref["torque"][-300:]
    )
    np.testing.assert_array_equal(np.concatenate([c.time for c in chunks]), ref.time[-300:])


def test_metadata_and_notes_match_read_recording(files):
    f, cmap, ref, _ = files["labview"]
    with open_recording(f, cmap) as src:
        meta = src.metadata
        assert meta["sha256"] == ref.metadata["sha256"]
        assert meta["source_units"] == ref.metadata["source_units"]
        assert meta["notes"] == ref.metadata["notes"]
        assert meta["chunked"] == "partial reads"
        one = src.read(("torque",), 10, 20)
    assert one.start_index == 10 and one["torque"].size == 10
    np.testing.assert_array_equal(one.time, ref.time[10:20])
    assert ref.time[0] == pytest.approx(0.25)  # wf_start_offset


def test_formats_without_partial_reads_say_so(files):
    f, cmap, _, _ = files["mat5"]
    with open_recording(f, cmap) as src:
        assert src.metadata["chunked"] == "read whole"
        assert any("MATLAB v4-v7 files cannot be read in parts" in n for n in src.metadata["notes"])
    for case in ("csv", "csv_ms", "parquet", "tdms", "mf4", "mat73"):
        f, cmap, _, _ = files[case]
        with open_recording(f, cmap) as src:
            assert src.metadata["chunked"] == "partial reads"


def test_multi_rate_channels_are_refused(tmp_path):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    f = tmp_path / "daqmx.tdms"
    with TdmsWriter(str(f)) as w:
        w.write_segment(
            [
                RootObject(),
                GroupObject("Fast"),
                GroupObject("Slow"),
                ChannelObject("Fast", "T", np.zeros(1920), properties={"wf_increment": 1 / 19200}),
                ChannelObject("Slow", "p", np.ones(10), properties={"wf_increment": 0.1}),
            ]
        )
    cmap = {
        "channels": {
            "torque": {"column": "T", "unit": "N.m"},
            "air_spring_pressure": {"column": "p", "unit": "bar"},
        }
    }
    with pytest.raises(RecordingError, match=r"different time bases.*19200 Hz.*use read_recording"):
        open_recording(f, cmap)
    rec = read_recording(f, cmap)  # what the message points to
    assert rec.metadata["resampled"]["channels"]["air_spring_pressure"]["method"] == "linear"
    with open_recording(f, cmap, channels=["torque"]) as src:  # one rate needed: fine
        assert src.names == ("torque",) and src.sample_rate == pytest.approx(19200)


def test_nan_in_a_chunk_names_channel_and_sample(tmp_path):
    t = np.arange(1000) / 100.0
    v = np.sin(t)
    v[737] = np.nan
    f = tmp_path / "nan.parquet"
    pd.DataFrame({"time": t, "torque [N.m]": v}).to_parquet(f)
    with open_recording(f) as src:
        first = next(src.iter_chunks(chunk_samples=500))
        assert len(first) == 500
        with pytest.raises(RecordingError, match=r"'torque' has a NaN/inf sample at sample 737"):
            list(src.iter_chunks(chunk_samples=300))


def test_gap_and_backward_time_across_chunks(tmp_path):
    t = np.arange(1000) / 100.0
    t[600:] += 0.5  # 50 dropped samples
    f = tmp_path / "gap.parquet"
    pd.DataFrame({"time": t, "torque [N.m]": np.sin(t)}).to_parquet(f)
    with (
        open_recording(f) as src,
        pytest.raises(RecordingError, match=r"gap .*between sample 599 .* and 600"),
    ):
        list(src.iter_chunks(chunk_samples=600))  # the gap sits on the chunk boundary
    t2 = np.arange(1000) / 100.0
    t2[400] = t2[398]
    f2 = tmp_path / "back.parquet"
    pd.DataFrame({"time": t2, "torque [N.m]": np.sin(t2)}).to_parquet(f2)
    with open_recording(f2) as src, pytest.raises(RecordingError, match=r"at sample 400"):
        list(src.iter_chunks(chunk_samples=128))


def test_arguments_and_missing_channels(files, tmp_path):
    f, cmap, _, _ = files["inca"]
    with open_recording(f, cmap) as src:
        with pytest.raises(RecordingError, match=r"\['speed'\] not in the recording"):
            src.read(["speed"])
        with pytest.raises(RecordingError, match=r"chunk_samples must be >= 1"):
            next(src.iter_chunks(chunk_samples=0))
        with pytest.raises(RecordingError, match=r"empty sample range"):
            src.read(start=5, stop=5)
        assert src.read("torque")["torque"].size == N
    with pytest.raises(RecordingError, match=r"required channel\(s\) \['normal_load'\]"):
        open_recording(f, cmap, channels=["normal_load"])
    # without [file] group the plain name is ambiguous, as in read_recording
    plain = {k: v for k, v in cmap.items() if k != "file"}
    with pytest.raises(RecordingError, match=r"ambiguous.*'2ms/Torque'.*'100ms/Torque'"):
        open_recording(f, plain)
    with pytest.raises(FileNotFoundError):
        open_recording(tmp_path / "none.tdms")


def _csv_text(n: int) -> str:
    lines = ["time [s],torque [N.m]"] + [f"{k / 1000:.3f},{85900 + 0.1 * k:.1f}" for k in range(n)]
    return "\n".join(lines)


@pytest.mark.parametrize(
    ("ending", "kept"),
    [
        ("cut inside the last number", 4999),  # '...,86399.' cut from '86399.9' (5000 rows)
        ("cut to fewer cells", 4999),
        ("complete, no line end", 5000),
        ("line end", 5000),
    ],
)
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
@pytest.mark.parametrize("rows", [100, 5000])  # within and beyond the first samples probed
def test_a_cut_last_line_is_dropped_as_read_recording_drops_it(
    tmp_path, ending, kept, encoding, rows
):
    """An interrupted writer leaves a last line without a line end, possibly cut inside its
    last number: the streamed reader drops it with a note, as the whole-file reader does,
    instead of reading 86399.9 N.m as 86399 or failing on a missing cell; a complete last line
    of a fixed-decimals writer is kept. Short files too (the first 4096 samples are read to
    resolve the channel map: the cut row must not be among them)."""
    kept = kept - 5000 + rows
    text = _csv_text(rows)
    body = {
        "cut inside the last number": text[:-1],
        "cut to fewer cells": text.rsplit(",", 1)[0],
        "complete, no line end": text,
        "line end": text + "\n",
    }[ending]
    path = tmp_path / "run.csv"
    path.write_text(body, encoding=encoding)
    whole = read_recording(path)
    with open_recording(path) as src:
        torque = np.concatenate([c["torque"] for c in src.iter_chunks(("torque",), 1024)])
        notes = [n for n in src.metadata["notes"] if "last line" in n]
    assert len(whole.time) == len(torque) == kept
    np.testing.assert_array_equal(torque, whole.channels["torque"])
    assert bool(notes) == (kept < rows)


def test_the_last_line_of_a_long_file_is_judged_against_the_line_before(tmp_path):
    """A file longer than the tail that is read (1 MiB) to find its last two lines."""
    text = _csv_text(80_000)
    assert len(text) > (1 << 20)
    path = tmp_path / "long.csv"
    path.write_text(text[:-2], encoding="utf-8")  # '...,93899.' -> '...,93899'
    with open_recording(path) as src:
        assert src.n_samples == 79_999
    path.write_text(text, encoding="utf-8")
    with open_recording(path) as src:
        assert src.n_samples == 80_000


@pytest.mark.parametrize("rows", [1, 2])
def test_too_short_after_a_cut_line_says_the_line_was_dropped(tmp_path, rows):
    """A file whose last (or only) row was dropped as cut is too short: both readers say why
    it holds fewer samples than it has lines, not only that it does."""
    path = tmp_path / "short.csv"
    path.write_text(_csv_text(rows)[:-1], encoding="utf-8")  # the last number cut
    readers = [read_recording, open_recording] if rows == 2 else [open_recording]
    for reader in readers:
        with pytest.raises(RecordingError, match=r"only \d sample\(s\).*no line end.*dropped"):
            reader(path)


def test_a_streamed_text_file_with_rounded_stamps_has_the_in_memory_rate(tmp_path):
    """19.2 kHz written to whole µs: read_recording's uniform base says 19 200 Hz, and the
    chunked reader (the CLI's above a few million samples) said 19 231 Hz, its head's median
    step (a review, 2026-12-03)."""
    t = np.round(np.arange(20_000) / 19_200.0, 6)
    f = tmp_path / "fast.csv"
    f.write_text(
        "t,torque\n" + "".join(f"{a:.6f},{b:.3f}\n" for a, b in zip(t, np.sin(t), strict=True))
    )
    cmap = {
        "time": {"column": "t", "unit": "s"},
        "channels": {"torque": {"column": "torque", "unit": "N.m"}},
    }
    whole = read_recording(f, cmap).sample_rate
    with open_recording(f, cmap) as src:
        streamed = src.sample_rate
    assert whole == pytest.approx(19_200.0, rel=1e-6)
    assert streamed == pytest.approx(whole, rel=1e-12)
