"""Tests of rollerrig.experiment.tomlfile: the TOML format, its errors, the bundled protocols.

Sources of pinned numbers: the procedure of Kayaalp, section 4.1.4 (roller at constant speed,
wheel free rolling, torque request), section 4.2.1 (torque pattern repeated three times, sudden
release) and section 4.5.1.6 (30 km/h dry and 10 km/h wet, Figs. 40-41). The torque levels and
timings of the bundled protocols are documented assumptions in their TOML files; the tests pin
the numbers written there. Unit conversions: 1 km/h = 1/3.6 m/s, 1 kN = 1000 N. Error messages:
the package's one format ``<file>: <dotted key>: <problem> [unit]; allowed ...; got ...``.
"""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig.experiment import (
    DEFAULT_FAST_RAMP_DURATION,
    Hold,
    Protocol,
    ProtocolError,
    ReleaseTorque,
    Repeat,
    SetFriction,
    SetNormalLoad,
    SetRollerSpeed,
    StepTorque,
    bundled_protocols,
    load_protocol,
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


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


# --------------------------------------------------------------------------------------------
# bundled protocols
# --------------------------------------------------------------------------------------------


def test_bundled_names():
    names = bundled_protocols()
    assert {"seed-30kmh-dry", "seed-10kmh-wet", "replay-example"} <= set(names)
    assert list(names) == sorted(names)


@pytest.mark.parametrize(
    ("name", "speed_kmh", "friction", "level_Nm"),
    [("seed-30kmh-dry", 30.0, "dry", 912.0), ("seed-10kmh-wet", 10.0, "wet", 440.0)],
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


def test_unknown_bundled_name_lists_names():
    with pytest.raises(ProtocolError, match="seed-30kmh-dry"):
        load_protocol("no-such-protocol")


def test_load_from_path(tmp_path):
    f = tmp_path / "mine.toml"
    f.write_text(HEADER + '[[step]]\naction = "hold"\nduration_s = 1.5\n')
    p = load_protocol(f)
    assert p.duration == 1.5 and p.origin == str(f)
    assert load_protocol(str(f)).duration == 1.5


def test_bundled_files_unchanged_by_loading():
    data = Path(__file__).parents[2] / "src/rollerrig/experiment/data"
    files = sorted(data.glob("*"))
    before = {f.name: sha256(f) for f in files}
    for name in bundled_protocols():
        load_protocol(name)
    assert {f.name: sha256(f) for f in files} == before


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


S = r"<string>: step\[1\]\.steps\[0\]\."  # the file and the dotted key of the inner step


@pytest.mark.parametrize(
    ("inner", "match"),
    [
        (
            'action = "ramp_torque"\n  duration_s = 1.0',
            S + r"to_Nm: missing key required for action 'ramp_torque'$",
        ),
        (
            'action = "ramp_torque"\n  to_Nm = "big"\n  duration_s = 1.0',
            S + r"to_Nm: must be a number \[N\.m\]; allowed \(-inf, inf\); got 'big'$",
        ),
        (
            'action = "ramp_torque"\n  to_Nm = 1.0\n  duration_s = 1.0\n  speed = 3',
            S + r"speed: unknown key for action 'ramp_torque'; allowed 'action', 'to_Nm', "
            r"'duration_s'$",
        ),
        (
            'action = "ramp_torque"\n  to_Nm = 1.0\n  duration = 1.0',
            S + r"duration: unknown key .*\(did you mean 'duration_s'\?\)",
        ),
        ('action = "jump"', S + r"action: unknown action; allowed 'hold', .*'repeat'; got 'jump'$"),
        ("duration_s = 1.0", S + r"action: missing key; allowed 'hold', 'ramp_torque', "),
        (
            'action = "hold"\n  duration_s = -1.0',
            S + r"duration_s: must be >= 0 \[s\]; allowed \[0, inf\); got -1$",
        ),
        (
            'action = "ramp_torque"\n  to_Nm = 1.0\n  duration_s = 0.0',
            S + r"duration_s: must be > 0 \[s\]; allowed \(0, inf\); got 0$",
        ),
        (
            'action = "release_torque"\n  duration_s = 0.0',
            S + r"duration_s: must be > 0 \[s\]; allowed \(0, inf\); got 0$",
        ),
        (
            'action = "set_normal_load"\n  to_kN = 0.0\n  duration_s = 1.0',
            S + r"to_kN: must be > 0 \[kN\]; allowed \(0, inf\); got 0$",
        ),
        (
            'action = "set_roller_speed"\n  to_kmh = -5.0\n  duration_s = 1.0',
            S + r"to_kmh: must be >= 0 \[km/h\]; allowed \[0, inf\); got -5$",
        ),
        (
            'action = "set_roller_speed"\n  to_kmh = inf\n  duration_s = 1.0',
            S + r"to_kmh: must be finite \[km/h\]; allowed \[0, inf\); got inf$",
        ),
        ('action = "set_friction"\n  condition = ""', S + r"condition: must be a non-empty name"),
        (
            'action = "repeat"\n  count = 0\n  steps = [{action = "hold", duration_s = 1.0}]',
            S + r"count: must be an integer >= 1; allowed 1, 2, 3, \.\.\.; got 0$",
        ),
        (
            'action = "repeat"\n  count = 1.5\n  steps = [{action = "hold", duration_s = 1.0}]',
            S + r"count: must be an integer >= 1; .*got 1\.5$",
        ),
        (
            'action = "repeat"\n  count = 2\n  steps = [{action = "hold", duration_s = true}]',
            S + r"steps\[0\]\.duration_s: must be a number \[s\]; allowed \[0, inf\); got true$",
        ),
        (
            'action = "repeat"\n  count = 2\n  steps = []',
            S + r"steps: must contain at least one step",
        ),
        (
            'action = "repeat"\n  count = 2\n  steps = 3',
            S + r"steps: must be a list of step tables",
        ),
    ],
)
def test_step_errors_name_the_path(inner, match):
    with pytest.raises(ProtocolError, match=match):
        compile_steps(REPEAT_WITH.format(inner=inner))


@pytest.mark.parametrize(
    ("header", "match"),
    [
        (
            HEADER.replace("10.0", "0.0"),
            r"^<string>: experiment\.normal_load_kN: must be > 0 \[kN\]; allowed \(0, inf\); "
            r"got 0$",
        ),
        (HEADER.replace("normal_load_kN = 10.0", "normal_load_kN = -4.3"), "got -4.3$"),
        (
            HEADER.replace("normal_load_kN = 10.0\n", ""),
            r"^<string>: experiment\.normal_load_kN: missing key required for \[experiment\]$",
        ),
        (
            HEADER.replace("roller_speed_kmh = 36.0", "roller_speed_kmh = -1"),
            r"experiment\.roller_speed_kmh: must be >= 0 \[km/h\]",
        ),
        (
            HEADER.replace('name = "t"', "name = 3"),
            r"^<string>: experiment\.name: must be a non-empty name; got 3$",
        ),
        (HEADER + "friction = ''\n", r"experiment\.friction: must be a non-empty name"),
        (HEADER + "description = 1\n", r"experiment\.description: must be text; got 1"),
        (
            HEADER + "colour = 'red'\n",
            r"^<string>: experiment\.colour: unknown key for \[experiment\]",
        ),
        (
            HEADER.replace("[experiment]", "[experimnt]"),
            r"^<string>: experimnt: unknown key at the top level \(did you mean 'experiment'\?\); "
            r"allowed 'experiment', 'step', 'replay'$",
        ),
        (HEADER + "normal_load_kN = 3.0\n", "^<string>: invalid TOML"),
    ],
)
def test_experiment_errors(header, match):
    with pytest.raises(ProtocolError, match=match):
        compile_steps('[[step]]\naction = "hold"\nduration_s = 1.0\n', header=header)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('[[step]]\naction = "hold"\nduration_s = 1.0\n', r"^<string>: experiment: missing "),
        ("experiment = 3\n", r"^<string>: experiment: must be a table; got 3$"),
        (HEADER + "[[step]]\nduration_s = 1.0\n", r"^<string>: step\[0\]\.action: missing key"),
        ("step = 3\n" + HEADER, r"^<string>: step: must be a list of step tables"),
        ("step = [3]\n" + HEADER, r"^<string>: step\[0\]: must be a table with an 'action' key"),
        ("step = []\n" + HEADER, r"^<string>: step: must contain at least one step; got \[\]$"),
        (HEADER + "[replay]\ncsv = ''\n", r"^<string>: replay\.csv: must be a non-empty name"),
        ("replay = 1\n" + HEADER, r"^<string>: replay: must be a table; got 1$"),
    ],
)
def test_document_structure_errors(text, match):
    with pytest.raises(ProtocolError, match=match):
        protocol_from_toml_string(text)


def test_file_errors_name_the_file(tmp_path):
    f = tmp_path / "mine.toml"
    f.write_text(HEADER + '[[step]]\naction = "ramp_torque"\nto_Nm = 1.0\nduration_s = 0\n')
    with pytest.raises(ProtocolError, match=r"^.*mine\.toml: step\[0\]\.duration_s: must be > 0"):
        load_protocol(f)
    f.write_bytes(b"\xff\xfe not text")
    with pytest.raises(ProtocolError, match=r"mine\.toml: cannot read the protocol file"):
        load_protocol(f)


def test_no_steps_and_zero_duration():
    with pytest.raises(ProtocolError, match=r"^<string>: step: no steps \(\[\[step\]\] tables\)"):
        protocol_from_toml_string(HEADER)
    with pytest.raises(ProtocolError, match=r"step: the steps must add up to a duration > 0 \[s\]"):
        compile_steps('[[step]]\naction = "hold"\nduration_s = 0.0\n')


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
    with pytest.raises(ProtocolError, match=r"replay\.columns: unknown key for \[replay\]"):
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


# --------------------------------------------------------------------------------------------
# one format for Python and TOML
# --------------------------------------------------------------------------------------------


def test_every_step_field_has_a_toml_key_and_back():
    # The TOML keys are a table over the step classes: a field without a key (or a key for a
    # field that does not exist) would let the formats drift.
    import dataclasses

    from rollerrig.experiment.steps import STEP_TYPES
    from rollerrig.experiment.tomlfile import STEP_KEYS

    assert set(STEP_KEYS) == set(STEP_TYPES)
    for cls, keys in STEP_KEYS.items():
        fields = {f.name for f in dataclasses.fields(cls)}
        assert {field for field, _ in keys.values()} == fields, cls.__name__
        for key, (field, unit) in keys.items():
            rule = cls.rules[field]
            assert (unit is None) == (rule.unit is None), (cls.__name__, key)


def test_to_toml_escapes_text_and_keeps_units():
    p = Protocol.from_steps(
        'quote " and \\ and\nnewline, ümlaut',
        [
            Hold(0.5),
            SetRollerSpeed(20 / 3.6, 1.0),
            SetNormalLoad(10e3, 0.5),
            SetFriction('we"t'),
            Repeat(2, [StepTorque(-50.0), Repeat(2, [ReleaseTorque(0.1)])]),
        ],
        normal_load=4300.0,
        roller_speed=0.0,
        description="tab\there \x7f",
        source="",
    )
    text = p.to_toml()
    assert "to_kmh = 20.0\n" in text and "to_kN = 10.0\n" in text
    assert "[[step.steps.steps]]" in text and "source" not in text
    back = protocol_from_toml_string(text)
    assert back.name == p.name and back.description == p.description
    assert back.to_steps() == p.to_steps()
    for name in ("torque_time", "torque_request", "roller_speed", "normal_load", "friction_time"):
        np.testing.assert_array_equal(getattr(back, name), getattr(p, name))


@pytest.mark.parametrize("value", [None, 123, ["seed-30kmh-dry"]])
def test_load_protocol_refuses_what_is_not_a_name_or_path(value):
    """A bare TypeError from pathlib before."""
    with pytest.raises(
        ProtocolError,
        match=re.escape(
            "path_or_name must be a bundled protocol's name or a file path (str or Path), got "
            f"{value!r}"
        ),
    ):
        load_protocol(value)


def test_protocol_from_toml_string_refuses_what_is_not_text():
    with pytest.raises(
        ProtocolError,
        match=re.escape("<string>: text must be the TOML text (a str), got NoneType"),
    ):
        protocol_from_toml_string(None)


@pytest.mark.parametrize("value", [None, "seed-30kmh-dry"])
def test_protocol_to_toml_refuses_what_is_not_a_protocol(value):
    """A bare AttributeError ('NoneType' object has no attribute 'to_steps') before."""
    from rollerrig.experiment import protocol_to_toml

    with pytest.raises(
        ProtocolError,
        match=re.escape(f"protocol must be a Protocol, got {type(value).__name__}"),
    ):
        protocol_to_toml(value)
