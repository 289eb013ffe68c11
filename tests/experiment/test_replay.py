"""Tests of rollerrig.experiment.replay: a recorded torque request (CSV) as a protocol.

Units in the headers are read by the one unit registry (rollerrig.units): 1 ms = 1e-3 s,
1 kN.m = 1000 N.m. The input file is never modified (its SHA-256 and mtime are checked).
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rollerrig.experiment import Protocol, ProtocolError, load_protocol, protocol_from_csv


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_csv_round_trip_and_file_unchanged(tmp_path):
    t = np.arange(0, 2001) / 250.0  # 8 s at 250 Hz
    q = np.interp(t, [0, 1, 4, 5, 5.02, 8], [0, 0, 500, 500, 0, 0])
    f = tmp_path / "trace.csv"
    pd.DataFrame({"time [s]": t, "torque request [N.m]": q}).to_csv(f, index=False)
    before, mtime = sha256(f), f.stat().st_mtime_ns
    p = protocol_from_csv(f, normal_load=10e3, roller_speed=5.0, friction="wet")
    assert sha256(f) == before and f.stat().st_mtime_ns == mtime
    assert p.origin_sha256 == before
    np.testing.assert_allclose(p.torque_time, t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(p.torque_request, q, rtol=0, atol=1e-9)
    assert p.duration == pytest.approx(8.0)
    assert p.torque_at(3.0) == pytest.approx(np.interp(3.0, t, q))
    assert p.roller_speed_at(4.0) == 5.0 and p.normal_load_at(4.0) == 10e3
    assert p.friction_at(4.0) == "wet"
    assert p.name == "trace"
    assert p.breakpoints() == pytest.approx(t)


@pytest.mark.parametrize(
    ("time_header", "torque_header", "t_scale", "q_scale"),
    [
        ("time_s", "torque_Nm", 1.0, 1.0),
        ("time_ms", "torque_kNm", 1e-3, 1e3),
        ("time [ms]", "torque request [kN.m]", 1e-3, 1e3),
        ("t (s)", "Torque request [N·m]", 1.0, 1.0),
        ("time [s]", "torque_request_N.m", 1.0, 1.0),
        ("time (sec)", "torque [N m]", 1.0, 1.0),  # spellings the unit registry reads
        ("time [ms]", "torque request [KNM]", 1e-3, 1e3),
        ("Time [s]", "torque request [Nm]", 1.0, 1.0),
    ],
)
def test_csv_units(tmp_path, time_header, torque_header, t_scale, q_scale):
    f = tmp_path / "u.csv"
    f.write_text(f"{time_header},{torque_header}\n0,0\n100,0.5\n200,0.25\n")
    p = protocol_from_csv(f, 4300.0, 8.0)
    assert p.torque_time.tolist() == pytest.approx([0, 100 * t_scale, 200 * t_scale])
    assert p.torque_request.tolist() == pytest.approx([0, 0.5 * q_scale, 0.25 * q_scale])


def test_csv_column_choice_comments_and_shift(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text(
        "# recorded on the rig\n"
        "time [s],torque measured [N.m],torque request [N.m],speed [km/h]\n"
        "10.0,5,0,30\n\n10.5,6,100,30\n11.0,7,200,30\n"
    )
    p = protocol_from_csv(f, 4300.0, 8.0)  # "request" preferred among torque columns
    assert p.torque_request.tolist() == [0, 100, 200]
    assert p.torque_time.tolist() == [0.0, 0.5, 1.0]  # shifted to start at 0 s
    assert "shifted" in p.description
    q = protocol_from_csv(f, 4300.0, 8.0, torque_column="torque measured [N.m]")
    assert q.torque_request.tolist() == [5, 6, 7]


@pytest.mark.parametrize(
    ("content", "kwargs", "match"),
    [
        ("time [s],speed [km/h]\n0,1\n1,2\n", {}, "missing torque column"),
        ("clock [s],torque [N.m]\n0,1\n1,2\n", {}, "missing time column"),
        ("time [s],torque [N.m]\n0,1\n1,2\n", {"torque_column": "T [N.m]"}, "no column 'T"),
        (
            "time [s],torque [N.m]\n0,1\n0.5,nan\n1,2\n",
            {},
            r"^bad\.csv: line 3, column 'torque \[N\.m\]': must be finite; got 'nan'$",
        ),
        (
            "time [s],torque [N.m]\n0,1\n0.5,abc\n1,2\n",
            {},
            r"^bad\.csv: line 3, column 'torque \[N\.m\]': must be a number; got 'abc'$",
        ),
        ("time [s],torque [N.m]\n0,1\n0.5,\n1,2\n", {}, r"line 3, .*must be a number; got ''"),
        ("time [s],torque [N.m]\n0,1\n0.5\n1,2\n", {}, r"line 3, column .*: missing value"),
        (
            "time [s],torque [N.m]\n0,1\n1,2\n1,3\n",
            {},
            r"^bad\.csv: line 4, column 'time \[s\]': duplicated time: 1 after 1 on line 3$",
        ),
        ("time [s],torque [N.m]\n0,1\n2,2\n1,3\n", {}, r"line 4, .*: time is not increasing"),
        ("time [s],torque [N.m]\n0,1\n", {}, "too few rows"),
        ("time [s],torque [N.m]\n", {}, "too few rows"),
        ("", {}, "no header"),
        ("time,torque [N.m]\n0,1\n1,2\n", {}, "no unit in the header"),
        (
            "time [d],torque [N.m]\n0,1\n1,2\n",
            {},
            r"^bad\.csv: column 'time \[d\]': time unit not accepted .*'s', 'ms'.*got 'd'$",
        ),
        (
            "time [s],torque [lbf.ft]\n0,1\n1,2\n",
            {},
            r"column 'torque \[lbf\.ft\]': torque unit not accepted .*'N\.m', 'kN\.m'",
        ),
        (
            "time [s],torque a [N.m],torque b [N.m]\n0,1,1\n1,2,2\n",
            {},
            "several torque columns",
        ),
    ],
)
def test_csv_errors(tmp_path, content, kwargs, match):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    before = sha256(f)
    with pytest.raises(ProtocolError, match=match):
        protocol_from_csv(f, 4300.0, 8.0, **kwargs)
    assert sha256(f) == before


def test_csv_argument_errors(tmp_path):
    f = tmp_path / "ok.csv"
    f.write_text("time [s],torque [N.m]\n0,0\n1,1\n")
    with pytest.raises(ProtocolError, match=r"^Protocol\.replay: normal_load: must be > 0 \[N\]"):
        protocol_from_csv(f, 0.0, 8.0)
    with pytest.raises(ProtocolError, match=r"roller_speed: must be >= 0 \[m/s\]; allowed \[0"):
        Protocol.replay(f, normal_load=4300.0, roller_speed=-1.0)
    with pytest.raises(ProtocolError, match=r"friction: must be a non-empty name"):
        Protocol.replay(f, normal_load=4300.0, roller_speed=1.0, friction=" ")
    with pytest.raises(ProtocolError, match="cannot read"):
        protocol_from_csv(tmp_path / "missing.csv", 4300.0, 8.0)
    with pytest.raises(ProtocolError, match=r"Protocol\.replay\(path, normal_load="):
        load_protocol(f)


def _two_samples(tmp_path):
    path = tmp_path / "trace.csv"
    path.write_text("time [s],torque [N.m]\n0,1\n1,2\n")
    return path


def test_unknown_option_of_protocol_from_csv_is_refused(tmp_path):
    """A misspelt option (descripton=...) was dropped silently."""
    with pytest.raises(
        ProtocolError,
        match=re.escape(
            "protocol_from_csv: unknown option 'descripton' (did you mean 'description'?)"
        ),
    ):
        protocol_from_csv(_two_samples(tmp_path), 4300.0, 5.0, descripton="x")


def test_replay_refuses_a_path_or_column_that_is_not_text(tmp_path):
    """None as the file was a bare TypeError, time_column=3 a bare AttributeError."""
    with pytest.raises(
        ProtocolError,
        match=re.escape("Protocol.replay: the CSV file must be a path (str or Path), got None"),
    ):
        Protocol.replay(None, normal_load=4300.0, roller_speed=5.0)
    with pytest.raises(
        ProtocolError,
        match=re.escape("Protocol.replay: time_column must be a column header (str), got 3"),
    ):
        Protocol.replay(_two_samples(tmp_path), normal_load=4300.0, roller_speed=5.0, time_column=3)
