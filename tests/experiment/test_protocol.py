"""Tests of rollerrig.experiment.protocol: TOML protocols, compilation to SI, CSV replay.

Sources of pinned numbers: the procedure of Kayaalp, section 4.1.4 (roller at constant speed,
wheel free rolling, torque request), section 4.2.1 (torque pattern repeated three times, sudden
release) and section 4.5.1.6 (30 km/h dry and 10 km/h wet, Figs. 40-41). The torque levels and
timings of the bundled protocols are documented assumptions in their TOML files; the tests pin
the numbers written there. Unit conversions: 1 km/h = 1/3.6 m/s, 1 kN = 1000 N.
"""

from __future__ import annotations

import hashlib
import itertools
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.experiment.protocol import (
    DEFAULT_FAST_RAMP_DURATION,
    Protocol,
    ProtocolError,
    bundled_protocols,
    load_protocol,
    protocol_from_csv,
    protocol_from_toml_string,
)

HEADER = """
[experiment]
name = "t"
normal_load_kN = 10.0
roller_speed_kmh = 36.0
"""


def compile_steps(steps_toml: str, header: str = HEADER) -> Protocol:
    return protocol_from_toml_string(header + steps_toml)


def release_starts(p: Protocol) -> list[float]:
    """Times where the torque request starts to fall to zero (read from the arrays)."""
    t, q = p.torque_time, p.torque_request
    return [float(t[i]) for i in range(len(t) - 1) if q[i] > 0.0 and q[i + 1] == 0.0]


# --------------------------------------------------------------------------------------------
# bundled protocols
# --------------------------------------------------------------------------------------------


def test_bundled_names():
    names = bundled_protocols()
    assert {"seed-30kmh-dry", "seed-10kmh-wet", "replay-example"} <= set(names)
    assert list(names) == sorted(names)


@pytest.mark.parametrize(
    ("name", "speed_kmh", "friction", "level_Nm"),
    [("seed-30kmh-dry", 30.0, "dry", 720.0), ("seed-10kmh-wet", 10.0, "wet", 380.0)],
)
def test_seed_protocols(name, speed_kmh, friction, level_Nm):
    # Kayaalp 4.5.1.6: 30 km/h dry, 10 km/h wet; 4.2.1: three repetitions with sudden release.
    # Levels and timings: the assumptions written in the TOML files.
    p = load_protocol(name)
    assert p.name == name
    assert p.duration == pytest.approx(30.0, abs=1e-9)
    assert "assumption" in p.source and "Kayaalp" in p.source
    assert p.origin == f"bundled:{name}" and len(p.origin_sha256) == 64

    # three releases, each from the level to 0 N.m in 0.02 s, at 5.5, 14.5, 23.5 s
    assert release_starts(p) == pytest.approx([5.5, 14.5, 23.5], abs=1e-9)
    releases = [e for e in p.events if e.action == "release_torque"]
    assert [e.start for e in releases] == pytest.approx([5.5, 14.5, 23.5], abs=1e-9)
    assert all(e.end - e.start == pytest.approx(0.02) for e in releases)
    assert p.torque_at([5.5, 5.51, 5.52]) == pytest.approx([level_Nm, level_Nm / 2, 0.0])
    assert p.torque_request.max() == level_Nm and p.torque_request.min() == 0.0

    # torque continuous: the steepest segment is the release, level / 0.02 s
    slopes = np.diff(p.torque_request) / np.diff(p.torque_time)
    assert np.max(np.abs(slopes)) == pytest.approx(level_Nm / 0.02)
    t = np.linspace(0.0, 30.0, 300_001)  # dt = 1e-4 s
    assert np.max(np.abs(np.diff(p.torque_at(t)))) <= level_Nm / 0.02 * 1e-4 * (1 + 1e-9)

    # free rolling at the start and end, constant speed, load and friction
    assert p.torque_at(0.0) == 0.0 and p.torque_at(30.0) == 0.0
    assert p.torque_at(1.9) == 0.0
    v = p.roller_speed_at(t)
    assert np.all(v == pytest.approx(speed_kmh / 3.6))
    if name == "seed-30kmh-dry":
        assert p.roller_speed_at(12.3) == pytest.approx(8.333333333)
    assert np.all(p.normal_load_at(t) == pytest.approx(4300.0))
    assert set(p.friction_at(t)) == {friction}
    assert p.friction_at(0.0) == friction


def test_bundled_replay_example():
    p = load_protocol("replay-example")
    assert p.duration == pytest.approx(10.0)
    assert p.torque_time.size == 2501  # 10 s at 250 Hz, both ends included
    assert np.allclose(np.diff(p.torque_time), 1 / 250)
    assert p.torque_request.max() == pytest.approx(600.0)
    assert p.roller_speed_at(5.0) == pytest.approx(30 / 3.6)
    assert p.normal_load_at(5.0) == pytest.approx(4300.0)
    assert p.friction_at(5.0) == "dry"
    assert "replay-example.csv" in p.source
    csv = Path(__file__).parents[2] / "src/rollerrig/experiment/data/replay-example.csv"
    assert csv.stat().st_size < 100_000


def test_to_dict_is_json_and_complete():
    p = load_protocol("seed-30kmh-dry")
    d = json.loads(json.dumps(p.to_dict()))
    assert d["name"] == "seed-30kmh-dry"
    assert d["duration [s]"] == pytest.approx(30.0)
    assert d["torque_request [N.m]"] == p.torque_request.tolist()
    assert d["friction_condition"] == ["dry"]
    assert d["roller_speed [m/s]"][0] == pytest.approx(30 / 3.6)
    assert len(d["events"]) == 1 + 3 * 4 + 1


def test_arrays_are_read_only_float64():
    p = load_protocol("seed-30kmh-dry")
    for a in (p.torque_time, p.torque_request, p.speed_time, p.roller_speed, p.normal_load):
        assert a.dtype == np.float64
        with pytest.raises(ValueError):
            a[0] = 1.0


def test_unknown_bundled_name_lists_names():
    with pytest.raises(ProtocolError, match="seed-30kmh-dry"):
        load_protocol("no-such-protocol")


def test_load_from_path(tmp_path):
    f = tmp_path / "mine.toml"
    f.write_text(HEADER + '[[step]]\naction = "hold"\nduration_s = 1.5\n')
    p = load_protocol(f)
    assert p.duration == 1.5 and p.origin == str(f)
    assert load_protocol(str(f)).duration == 1.5


# --------------------------------------------------------------------------------------------
# compilation
# --------------------------------------------------------------------------------------------


def test_unit_conversion_at_the_edge():
    p = compile_steps('[[step]]\naction = "hold"\nduration_s = 1.0\n')
    assert p.roller_speed_at(0.5) == pytest.approx(10.0)  # 36 km/h = 10 m/s
    assert p.normal_load_at(0.5) == pytest.approx(10_000.0)  # 10 kN
    assert p.friction_at(0.5) == "dry"  # default friction


def test_nested_repeat_expansion():
    p = compile_steps(
        """
[[step]]
action = "repeat"
count = 2
  [[step.steps]]
  action = "repeat"
  count = 3
    [[step.steps.steps]]
    action = "step_torque"
    to_Nm = 10.0
    [[step.steps.steps]]
    action = "release_torque"
  [[step.steps]]
  action = "hold"
  duration_s = 1.0
"""
    )
    actions = [e.action for e in p.events]
    assert actions == (["step_torque", "release_torque"] * 3 + ["hold"]) * 2
    assert p.duration == pytest.approx(2 * (3 * 2 * DEFAULT_FAST_RAMP_DURATION + 1.0))
    assert len(release_starts(p)) == 6
    # 6 pulses of two fast ramps, each 10 N.m high, no duplicated times
    assert p.torque_request.max() == 10.0
    assert np.all(np.diff(p.torque_time) > 0)


def test_speed_load_friction_changes():
    p = compile_steps(
        """
[[step]]
action = "set_roller_speed"
to_kmh = 72.0
duration_s = 2.0
[[step]]
action = "set_friction"
condition = "wet"
[[step]]
action = "set_normal_load"
to_kN = 20.0
duration_s = 1.0
[[step]]
action = "set_friction"
condition = "dry"
[[step]]
action = "hold"
duration_s = 1.0
"""
    )
    assert p.duration == pytest.approx(4.0)
    assert p.roller_speed_at([0.0, 1.0, 2.0, 4.0]) == pytest.approx([10.0, 15.0, 20.0, 20.0])
    assert p.normal_load_at([0.0, 2.0, 2.5, 3.0, 4.0]) == pytest.approx([1e4, 1e4, 1.5e4, 2e4, 2e4])
    assert p.friction_time.tolist() == [0.0, 2.0, 3.0]
    assert p.friction_condition == ("dry", "wet", "dry")
    assert p.friction_at(1.999) == "dry"
    assert p.friction_at(2.0) == "wet"  # a switch applies from its instant on
    assert list(p.friction_at([0.0, 2.5, 3.5])) == ["dry", "wet", "dry"]
    assert p.torque_at(2.0) == 0.0


def test_two_switches_at_one_instant_last_wins():
    p = compile_steps(
        '[[step]]\naction = "set_friction"\ncondition = "wet"\n'
        '[[step]]\naction = "set_friction"\ncondition = "oily"\n'
        '[[step]]\naction = "hold"\nduration_s = 1.0\n'
    )
    assert p.friction_time.tolist() == [0.0]
    assert p.friction_condition == ("oily",)


def test_breakpoints_include_every_kink():
    p = compile_steps(
        """
[[step]]
action = "hold"
duration_s = 1.0
[[step]]
action = "ramp_torque"
to_Nm = 100.0
duration_s = 2.0
[[step]]
action = "set_roller_speed"
to_kmh = 18.0
duration_s = 0.5
[[step]]
action = "set_friction"
condition = "wet"
[[step]]
action = "set_normal_load"
to_kN = 5.0
duration_s = 0.25
[[step]]
action = "release_torque"
[[step]]
action = "hold"
duration_s = 0.75
"""
    )
    expected = [0.0, 1.0, 3.0, 3.5, 3.75, 3.77, 4.52]
    assert p.breakpoints() == pytest.approx(expected)
    # independent check: between breakpoints every input is linear (midpoint = mean of ends)
    bp = p.breakpoints()
    for a, b in itertools.pairwise(bp):
        for f in (p.torque_at, p.roller_speed_at, p.normal_load_at):
            assert f(0.5 * (a + b)) == pytest.approx(0.5 * (f(a) + f(b)))
            assert f(0.25 * a + 0.75 * b) == pytest.approx(0.25 * f(a) + 0.75 * f(b))
        assert p.friction_at(a) == p.friction_at(0.5 * (a + b))


def test_breakpoints_of_bundled_dry():
    p = load_protocol("seed-30kmh-dry")
    expected = [0, 2, 5, 5.5, 5.52, 11, 14, 14.5, 14.52, 20, 23, 23.5, 23.52, 30]
    assert p.breakpoints() == pytest.approx(expected)


def test_interp_scalar_and_vector():
    p = load_protocol("seed-30kmh-dry")
    assert isinstance(p.torque_at(3.5), float)
    assert p.torque_at(3.5) == pytest.approx(360.0)  # half-way up the 3 s ramp from 2 s
    out = p.torque_at(np.array([[2.0, 3.5], [5.0, 40.0]]))
    assert out.shape == (2, 2)
    np.testing.assert_allclose(out, [[0.0, 360.0], [720.0, 0.0]])


def test_protocol_constructor_validates():
    good = load_protocol("seed-30kmh-dry")
    with pytest.raises(ProtocolError, match="torque_time must be strictly increasing"):
        Protocol(
            **{
                **{k: getattr(good, k) for k in good.__dataclass_fields__},
                "torque_time": [0.0, 1.0, 1.0],
                "torque_request": [0.0, 1.0, 2.0],
            }
        )
    with pytest.raises(ProtocolError, match="normal_load must be > 0"):
        Protocol(
            **{
                **{k: getattr(good, k) for k in good.__dataclass_fields__},
                "normal_load": [0.0, 0.0],
            }
        )


# --------------------------------------------------------------------------------------------
# errors name the key path
# --------------------------------------------------------------------------------------------

REPEAT_WITH = """
[[step]]
action = "hold"
duration_s = 1.0
[[step]]
action = "repeat"
count = 2
  [[step.steps]]
  {inner}
"""


@pytest.mark.parametrize(
    ("inner", "match"),
    [
        ('action = "ramp_torque"\n  duration_s = 1.0', r"step\[1\]\.steps\[0\]\.to_Nm: missing"),
        (
            'action = "ramp_torque"\n  to_Nm = "big"\n  duration_s = 1.0',
            r"step\[1\]\.steps\[0\]\.to_Nm must be a number \[N\.m\]",
        ),
        (
            'action = "ramp_torque"\n  to_Nm = 1.0\n  duration_s = 1.0\n  speed = 3',
            r"step\[1\]\.steps\[0\]\.speed: unknown key",
        ),
        ('action = "jump"', r"step\[1\]\.steps\[0\]\.action: unknown action 'jump'"),
        ("duration_s = 1.0", r"step\[1\]\.steps\[0\]\.action: missing"),
        ('action = "hold"\n  duration_s = -1.0', r"step\[1\]\.steps\[0\]\.duration_s must be >= 0"),
        (
            'action = "ramp_torque"\n  to_Nm = 1.0\n  duration_s = 0.0',
            r"step\[1\]\.steps\[0\]\.duration_s must be > 0",
        ),
        (
            'action = "release_torque"\n  duration_s = 0.0',
            r"step\[1\]\.steps\[0\]\.duration_s must be > 0",
        ),
        (
            'action = "set_normal_load"\n  to_kN = 0.0\n  duration_s = 1.0',
            r"step\[1\]\.steps\[0\]\.to_kN must be > 0 \[kN\]",
        ),
        (
            'action = "set_roller_speed"\n  to_kmh = -5.0\n  duration_s = 1.0',
            r"step\[1\]\.steps\[0\]\.to_kmh must be >= 0 \[km/h\]",
        ),
        ('action = "set_friction"\n  condition = ""', r"step\[1\]\.steps\[0\]\.condition"),
        (
            'action = "repeat"\n  count = 0\n  steps = [{action = "hold", duration_s = 1.0}]',
            r"step\[1\]\.steps\[0\]\.count must be an integer >= 1",
        ),
        (
            'action = "repeat"\n  count = 1.5\n  steps = [{action = "hold", duration_s = 1.0}]',
            r"step\[1\]\.steps\[0\]\.count must be an integer",
        ),
        (
            'action = "repeat"\n  count = 2\n  steps = [{action = "hold", duration_s = true}]',
            r"step\[1\]\.steps\[0\]\.steps\[0\]\.duration_s must be a number",
        ),
        ('action = "repeat"\n  count = 2\n  steps = []', r"step\[1\]\.steps\[0\]\.steps must"),
    ],
)
def test_step_errors_name_the_path(inner, match):
    with pytest.raises(ProtocolError, match=match):
        compile_steps(REPEAT_WITH.format(inner=inner))


@pytest.mark.parametrize(
    ("header", "match"),
    [
        (HEADER.replace("10.0", "0.0"), r"experiment\.normal_load_kN must be > 0 \[kN\]"),
        (HEADER.replace("normal_load_kN = 10.0", "normal_load_kN = -4.3"), "normal_load_kN"),
        (HEADER.replace("normal_load_kN = 10.0\n", ""), r"experiment\.normal_load_kN: missing"),
        (HEADER.replace('name = "t"', "name = 3"), r"experiment\.name must be a non-empty"),
        (HEADER + "colour = 'red'\n", r"experiment\.colour: unknown key"),
        (HEADER.replace("[experiment]", "[experimnt]"), r"experimnt: unknown top-level key"),
        (HEADER + "normal_load_kN = 3.0\n", "invalid TOML"),
    ],
)
def test_experiment_errors(header, match):
    with pytest.raises(ProtocolError, match=match):
        compile_steps('[[step]]\naction = "hold"\nduration_s = 1.0\n', header=header)


def test_no_steps_and_zero_duration():
    with pytest.raises(ProtocolError, match="no steps"):
        protocol_from_toml_string(HEADER)
    with pytest.raises(ProtocolError, match="duration > 0"):
        compile_steps('[[step]]\naction = "hold"\nduration_s = 0.0\n')


def test_protocol_error_is_a_parameter_error():
    assert issubclass(ProtocolError, ParameterError)
    assert issubclass(ProtocolError, ValueError)


def test_runaway_repeat_is_refused():
    with pytest.raises(ProtocolError, match="expand to more than"):
        compile_steps(
            """
[[step]]
action = "repeat"
count = 100000
  [[step.steps]]
  action = "repeat"
  count = 100000
    [[step.steps.steps]]
    action = "hold"
    duration_s = 1.0
"""
        )


# --------------------------------------------------------------------------------------------
# CSV replay
# --------------------------------------------------------------------------------------------


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


def test_bundled_files_unchanged_by_loading():
    data = Path(__file__).parents[2] / "src/rollerrig/experiment/data"
    files = sorted(data.glob("*"))
    before = {f.name: sha256(f) for f in files}
    for name in bundled_protocols():
        load_protocol(name)
    assert {f.name: sha256(f) for f in files} == before


@pytest.mark.parametrize(
    ("time_header", "torque_header", "t_scale", "q_scale"),
    [
        ("time_s", "torque_Nm", 1.0, 1.0),
        ("time_ms", "torque_kNm", 1e-3, 1e3),
        ("time [ms]", "torque request [kN.m]", 1e-3, 1e3),
        ("t (s)", "Torque request [N·m]", 1.0, 1.0),
        ("time [s]", "torque_request_N.m", 1.0, 1.0),
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
        ("time [s],torque [N.m]\n0,1\n0.5,nan\n1,2\n", {}, r"line 3.*'nan' is not finite"),
        ("time [s],torque [N.m]\n0,1\n0.5,abc\n1,2\n", {}, r"line 3.*'abc' is not a number"),
        ("time [s],torque [N.m]\n0,1\n0.5,\n1,2\n", {}, r"line 3.*'' is not a number"),
        ("time [s],torque [N.m]\n0,1\n0.5\n1,2\n", {}, r"line 3: missing value"),
        ("time [s],torque [N.m]\n0,1\n1,2\n1,3\n", {}, r"line 4: duplicated time"),
        ("time [s],torque [N.m]\n0,1\n2,2\n1,3\n", {}, r"line 4: time is not increasing"),
        ("time [s],torque [N.m]\n0,1\n", {}, "too few rows"),
        ("time [s],torque [N.m]\n", {}, "too few rows"),
        ("", {}, "no header"),
        ("time,torque [N.m]\n0,1\n1,2\n", {}, "no unit in the header"),
        ("time [h],torque [N.m]\n0,1\n1,2\n", {}, "unknown time unit 'h'"),
        ("time [s],torque [lbf.ft]\n0,1\n1,2\n", {}, "unknown torque unit"),
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
    with pytest.raises(ProtocolError, match=r"normal_load must be > 0 \[N\]"):
        protocol_from_csv(f, 0.0, 8.0)
    with pytest.raises(ProtocolError, match=r"roller_speed must be >= 0 \[m/s\]"):
        protocol_from_csv(f, 4300.0, -1.0)
    with pytest.raises(ProtocolError, match="cannot read"):
        protocol_from_csv(tmp_path / "missing.csv", 4300.0, 8.0)
    with pytest.raises(ProtocolError, match="protocol_from_csv"):
        load_protocol(f)


def test_toml_replay_relative_path(tmp_path):
    (tmp_path / "tr.csv").write_text("time_ms,torque_Nm\n0,0\n500,50\n1000,0\n")
    f = tmp_path / "replay.toml"
    f.write_text(HEADER.replace('"t"', '"r"') + 'friction = "wet"\n[replay]\ncsv = "tr.csv"\n')
    p = load_protocol(f)
    assert p.name == "r" and p.duration == pytest.approx(1.0)
    assert p.torque_at(0.25) == pytest.approx(25.0)
    assert p.roller_speed_at(0.5) == pytest.approx(10.0)
    assert p.friction_at(0.5) == "wet"
    with pytest.raises(ProtocolError, match="must not also have steps"):
        protocol_from_toml_string(
            HEADER + '[replay]\ncsv = "tr.csv"\n[[step]]\naction = "hold"\nduration_s = 1.0\n',
            base_dir=tmp_path,
        )
    with pytest.raises(ProtocolError, match=r"replay\.columns: unknown key"):
        protocol_from_toml_string(
            HEADER + '[replay]\ncsv = "tr.csv"\ncolumns = 2\n', base_dir=tmp_path
        )


# --------------------------------------------------------------------------------------------
# property: continuity and duration for random valid step lists
# --------------------------------------------------------------------------------------------

durations = st.floats(min_value=1e-3, max_value=5.0, allow_nan=False)
torques = st.floats(min_value=-1000.0, max_value=1000.0, allow_nan=False)

leaf = st.one_of(
    st.builds(lambda d: {"action": "hold", "duration_s": d}, st.floats(0.0, 5.0)),
    st.builds(
        lambda q, d: {"action": "ramp_torque", "to_Nm": q, "duration_s": d}, torques, durations
    ),
    st.builds(lambda q: {"action": "step_torque", "to_Nm": q}, torques),
    st.just({"action": "release_torque"}),
    st.builds(
        lambda v, d: {"action": "set_roller_speed", "to_kmh": v, "duration_s": d},
        st.floats(0.0, 100.0),
        durations,
    ),
    st.builds(
        lambda c: {"action": "set_friction", "condition": c}, st.sampled_from(["dry", "wet"])
    ),
)
step_lists = st.recursive(
    st.lists(leaf, min_size=1, max_size=5),
    lambda inner: st.lists(
        st.one_of(
            leaf,
            st.builds(
                lambda n, s: {"action": "repeat", "count": n, "steps": s},
                st.integers(1, 3),
                inner,
            ),
        ),
        min_size=1,
        max_size=4,
    ),
    max_leaves=12,
)


def _toml_value(v) -> str:
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_inline(s) for s in v) + "]"
    return repr(v)


def _inline(step: dict) -> str:
    return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in step.items()) + "}"


def _walk(steps, state):
    """Independent expansion: total duration and the steepest torque slope [N.m/s]."""
    for s in steps:
        if s["action"] == "repeat":
            for _ in range(s["count"]):
                _walk(s["steps"], state)
            continue
        d = s.get("duration_s", 0.0 if s["action"] == "set_friction" else 0.02)
        if s["action"] in ("ramp_torque", "step_torque", "release_torque"):
            target = s.get("to_Nm", 0.0)
            state["slope"] = max(state["slope"], abs(target - state["q"]) / d)
            state["q"] = target
        state["t"] += d


@settings(max_examples=60, deadline=None)
@given(step_lists)
def test_property_continuous_torque_and_duration(steps):
    text = "step = " + _toml_value(steps) + "\n" + HEADER
    state = {"t": 0.0, "q": 0.0, "slope": 0.0}
    _walk(steps, state)
    if state["t"] <= 0.0:
        with pytest.raises(ProtocolError, match="duration > 0"):
            protocol_from_toml_string(text)
        return
    p = protocol_from_toml_string(text)
    assert p.duration == pytest.approx(state["t"], rel=1e-12, abs=1e-12)
    assert p.torque_request[-1] == pytest.approx(state["q"])
    for arr in (p.torque_time, p.speed_time, p.load_time, p.friction_time):
        assert np.all(np.diff(arr) > 0)
    t = np.linspace(0.0, p.duration, 20_001)
    dt = t[1] - t[0]
    jumps = np.abs(np.diff(p.torque_at(t)))
    assert np.all(jumps <= state["slope"] * dt * (1 + 1e-9) + 1e-9)
    bp = p.breakpoints()
    assert bp[0] == 0.0 and bp[-1] == pytest.approx(p.duration)
    assert set(p.torque_time.tolist()) <= set(bp.tolist())
