"""Tests of rollerrig.experiment.steps: the step objects, their validation and their compilation.

Pinned numbers: the bundled protocols written in Python (Kayaalp 4.1.4, 4.2.1, 4.5.1.6; levels
and timings are the assumptions written in the TOML files) must compile to the very same arrays
as the files; durations are sums of the step durations by hand. Error messages: the package's
one format ``<source>: <key>: <problem> [unit]; allowed ...; got ...``, the source being the step
class (or ``Protocol.from_steps``).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.experiment import (
    DEFAULT_FAST_RAMP_DURATION,
    Hold,
    Protocol,
    ProtocolError,
    RampTorque,
    ReleaseTorque,
    Repeat,
    SetFriction,
    SetNormalLoad,
    SetRollerSpeed,
    StepTorque,
    load_protocol,
    protocol_from_toml_string,
)
from rollerrig.experiment.steps import MAX_LEAF_STEPS, STEP_TYPES

ARRAYS = (
    "torque_time",
    "torque_request",
    "speed_time",
    "roller_speed",
    "load_time",
    "normal_load",
    "friction_time",
)


def assert_same_arrays(a: Protocol, b: Protocol) -> None:
    for name in ARRAYS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.friction_condition == b.friction_condition
    assert a.events == b.events
    assert a.duration == b.duration


# --------------------------------------------------------------------------------------------
# construction and validation of each step
# --------------------------------------------------------------------------------------------


def test_steps_store_si_floats_and_defaults():
    assert Hold(2) == Hold(2.0) and isinstance(Hold(2).duration, float)
    assert StepTorque(100).duration == DEFAULT_FAST_RAMP_DURATION == 0.02
    assert ReleaseTorque().duration == 0.02 and ReleaseTorque().target == 0.0
    assert RampTorque(-300, 1.5) == RampTorque(to=-300.0, duration=1.5)
    assert SetRollerSpeed(np.float64(5.0), 1).to == 5.0  # numpy numbers are numbers
    assert SetFriction("  wet ").condition == "wet" and SetFriction("wet").duration == 0.0
    r = Repeat(2, [Hold(1.0), StepTorque(10.0)])
    assert r.steps == (Hold(1.0), StepTorque(10.0)) and r.count == 2
    assert r.duration == pytest.approx(2 * 1.02)
    assert Repeat(np.int64(3), (Hold(1.0),)).count == 3
    assert len({Hold(1.0), Hold(1.0), r, Repeat(2, (Hold(1.0), StepTorque(10.0)))}) == 2
    assert (
        repr(Repeat(2, [ReleaseTorque()]))
        == "Repeat(count=2, steps=(ReleaseTorque(duration=0.02),))"
    )
    with pytest.raises(AttributeError):
        Hold(1.0).duration = 2.0  # frozen


def test_action_names_and_channels():
    assert [c.action for c in STEP_TYPES] == [
        "hold",
        "ramp_torque",
        "step_torque",
        "release_torque",
        "set_roller_speed",
        "set_normal_load",
        "set_friction",
        "repeat",
    ]
    assert [c.channel for c in STEP_TYPES] == [
        None,
        "torque",
        "torque",
        "torque",
        "speed",
        "load",
        "friction",
        None,
    ]


BAD_STEPS = [
    (lambda: Hold(-1.0), "Hold: duration: must be >= 0 [s]; allowed [0, inf); got -1"),
    (lambda: Hold(math.nan), "Hold: duration: must be finite [s]; allowed [0, inf); got nan"),
    (lambda: Hold("2"), "Hold: duration: must be a number [s]; allowed [0, inf); got '2'"),
    (lambda: Hold(True), "Hold: duration: must be a number [s]; allowed [0, inf); got true"),
    (
        lambda: RampTorque(100.0, 0.0),
        "RampTorque: duration: must be > 0 [s]; allowed (0, inf); got 0",
    ),
    (
        lambda: RampTorque(math.inf, 1.0),
        "RampTorque: to: must be finite [N.m]; allowed (-inf, inf); got inf",
    ),
    (
        lambda: RampTorque(None, 1.0),
        "RampTorque: to: must be a number [N.m]; allowed (-inf, inf); got None",
    ),
    (
        lambda: StepTorque(100.0, -0.01),
        "StepTorque: duration: must be > 0 [s]; allowed (0, inf); got -0.01",
    ),
    (
        lambda: ReleaseTorque(0.0),
        "ReleaseTorque: duration: must be > 0 [s]; allowed (0, inf); got 0",
    ),
    (
        lambda: SetRollerSpeed(-1.0, 1.0),
        "SetRollerSpeed: to: must be >= 0 [m/s]; allowed [0, inf); got -1",
    ),
    (
        lambda: SetRollerSpeed(5.0, 0.0),
        "SetRollerSpeed: duration: must be > 0 [s]; allowed (0, inf); got 0",
    ),
    (
        lambda: SetNormalLoad(0.0, 1.0),
        "SetNormalLoad: to: must be > 0 [N]; allowed (0, inf); got 0",
    ),
    (
        lambda: SetNormalLoad(4300.0, math.nan),
        "SetNormalLoad: duration: must be finite [s]; allowed (0, inf); got nan",
    ),
    (lambda: SetFriction(""), "SetFriction: condition: must be a non-empty name; got ''"),
    (lambda: SetFriction(3), "SetFriction: condition: must be a non-empty name; got 3"),
    (
        lambda: Repeat(0, [Hold(1.0)]),
        "Repeat: count: must be an integer >= 1; allowed 1, 2, 3, ...; got 0",
    ),
    (
        lambda: Repeat(2.0, [Hold(1.0)]),
        "Repeat: count: must be an integer >= 1; allowed 1, 2, 3, ...; got 2",
    ),
    (
        lambda: Repeat(True, [Hold(1.0)]),
        "Repeat: count: must be an integer >= 1; allowed 1, 2, 3, ...; got true",
    ),
    (lambda: Repeat(2, []), "Repeat: steps: must contain at least one step; got []"),
    (
        lambda: Repeat(2, Hold(1.0)),
        "Repeat: steps: must be a list of steps (Hold, RampTorque, StepTorque, ReleaseTorque, "
        "SetRollerSpeed, SetNormalLoad, SetFriction, Repeat); got Hold(duration=1.0)",
    ),
    (
        lambda: Repeat(2, [Hold(1.0), {"action": "hold"}]),
        "Repeat: steps[1]: must be a step (Hold, RampTorque, StepTorque, ReleaseTorque, "
        "SetRollerSpeed, SetNormalLoad, SetFriction, Repeat); got {'action': 'hold'}",
    ),
    (lambda: Repeat(2, 5), "Repeat: steps: must be a list of steps"),
]


@pytest.mark.parametrize(("make", "message"), BAD_STEPS)
def test_each_step_validates_itself(make, message):
    with pytest.raises(ProtocolError, match="^" + re.escape(message)) as info:
        make()
    assert isinstance(info.value, ParameterError)


# --------------------------------------------------------------------------------------------
# Protocol.from_steps
# --------------------------------------------------------------------------------------------

GOOD = {"normal_load": 4300.0, "roller_speed": 5.0}


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"normal_load": 0.0},
            "Protocol.from_steps: normal_load: must be > 0 [N]; allowed (0, inf); got 0",
        ),
        (
            {"roller_speed": -2.0},
            "Protocol.from_steps: roller_speed: must be >= 0 [m/s]; allowed [0, inf); got -2",
        ),
        ({"friction": ""}, "Protocol.from_steps: friction: must be a non-empty name; got ''"),
        ({"name": " "}, "Protocol.from_steps: name: must be a non-empty name; got ' '"),
        ({"description": None}, "Protocol.from_steps: description: must be text; got None"),
        ({"steps": []}, "Protocol.from_steps: steps: must contain at least one step; got []"),
        ({"steps": [Hold(1.0), 2.0]}, "Protocol.from_steps: steps[1]: must be a step ("),
        (
            {"steps": [Hold(0.0), SetFriction("wet")]},
            "Protocol.from_steps: steps: the steps must add up to a duration > 0 [s]; got 0",
        ),
        (
            {"steps": [Repeat(100_000, [Repeat(100_000, [Hold(1.0)])])]},
            f"Protocol.from_steps: steps: the repeats expand to more than {MAX_LEAF_STEPS} steps",
        ),
    ],
)
def test_from_steps_errors(kwargs, message):
    args = {"name": "p", "steps": [Hold(1.0)], **GOOD, **kwargs}
    with pytest.raises(ProtocolError, match="^" + re.escape(message)):
        Protocol.from_steps(args.pop("name"), args.pop("steps"), **args)


def test_compilation_by_hand():
    p = Protocol.from_steps(
        "hand",
        [
            Hold(1.0),
            RampTorque(100.0, 2.0),  # 1 -> 3 s
            SetFriction("wet"),  # at 3 s
            SetFriction("oily"),  # same instant: the last wins
            SetRollerSpeed(10.0, 1.0),  # 3 -> 4 s
            SetNormalLoad(8000.0, 0.5),  # 4 -> 4.5 s
            ReleaseTorque(),  # 4.5 -> 4.52 s
        ],
        normal_load=4000.0,
        roller_speed=5.0,
        description="d",
        source="s",
    )
    assert p.duration == pytest.approx(4.52)
    assert p.torque_time.tolist() == pytest.approx([0.0, 1.0, 3.0, 4.5, 4.52])
    assert p.torque_request.tolist() == [0.0, 0.0, 100.0, 100.0, 0.0]
    assert p.speed_time.tolist() == pytest.approx([0.0, 3.0, 4.0, 4.52])
    assert p.roller_speed.tolist() == [5.0, 5.0, 10.0, 10.0]
    assert p.load_time.tolist() == pytest.approx([0.0, 4.0, 4.5, 4.52])
    assert p.normal_load.tolist() == [4000.0, 4000.0, 8000.0, 8000.0]
    assert p.friction_time.tolist() == [0.0, 3.0] and p.friction_condition == ("dry", "oily")
    assert [e.action for e in p.events] == [
        "hold",
        "ramp_torque",
        "set_friction",
        "set_friction",
        "set_roller_speed",
        "set_normal_load",
        "release_torque",
    ]
    assert p.events[2].target == "wet" and p.events[2].start == p.events[2].end == 3.0
    assert p.events[4].target == 10.0 and p.events[0].target is None
    assert (p.description, p.source, p.origin) == ("d", "s", "")


# --------------------------------------------------------------------------------------------
# Python and TOML: one compile path
# --------------------------------------------------------------------------------------------


def seed_protocol_in_python(name: str) -> Protocol:
    """The bundled seed protocols, written with step objects from their TOML files' numbers."""
    level, speed_kmh, friction = {
        "seed-30kmh-dry": (912.0, 30.0, "dry"),
        "seed-10kmh-wet": (440.0, 10.0, "wet"),
    }[name]
    file = load_protocol(name)
    return Protocol.from_steps(
        name,
        [
            Hold(2.0),
            Repeat(3, [RampTorque(level, 3.0), Hold(0.5), ReleaseTorque(0.02), Hold(5.48)]),
            Hold(1.0),
        ],
        normal_load=4.3e3,
        roller_speed=speed_kmh / 3.6,
        friction=friction,
        description=file.description,
        source=file.source,
    )


@pytest.mark.parametrize("name", ["seed-30kmh-dry", "seed-10kmh-wet"])
def test_python_and_toml_compile_to_identical_arrays(name):
    file, python = load_protocol(name), seed_protocol_in_python(name)
    assert_same_arrays(file, python)
    np.testing.assert_array_equal(file.breakpoints(), python.breakpoints())
    assert file.to_steps() == python.to_steps()
    assert (file.name, file.description, file.source) == (
        python.name,
        python.description,
        python.source,
    )


@pytest.mark.parametrize("name", ["seed-30kmh-dry", "seed-10kmh-wet"])
def test_to_toml_round_trip_of_bundled(name):
    p = load_protocol(name)
    back = protocol_from_toml_string(p.to_toml())
    assert_same_arrays(p, back)
    assert back.to_steps() == p.to_steps()
    assert (back.description, back.source) == (p.description, p.source)


# --------------------------------------------------------------------------------------------
# property: random valid step lists
# --------------------------------------------------------------------------------------------

durations = st.floats(min_value=1e-3, max_value=5.0)
torques = st.floats(min_value=-1000.0, max_value=1000.0)
leaf = st.one_of(
    st.builds(Hold, st.floats(0.0, 5.0)),
    st.builds(RampTorque, torques, durations),
    st.builds(StepTorque, torques),
    st.builds(StepTorque, torques, durations),
    st.builds(ReleaseTorque),
    st.builds(SetRollerSpeed, st.floats(0.0, 40.0), durations),
    st.builds(SetNormalLoad, st.floats(100.0, 3e4), durations),
    st.builds(SetFriction, st.sampled_from(["dry", "wet", "oily"])),
)
step_lists = st.recursive(
    st.lists(leaf, min_size=1, max_size=5),
    lambda inner: st.lists(
        st.one_of(leaf, st.builds(Repeat, st.integers(1, 3), inner)), min_size=1, max_size=4
    ),
    max_leaves=12,
)


def _same_steps(a, b) -> bool:
    """Equal step lists, numbers within one unit in 1e15."""
    if isinstance(a, tuple | list):
        return len(a) == len(b) and all(_same_steps(x, y) for x, y in zip(a, b, strict=True))
    if type(a) is not type(b):
        return False
    for field in a.__dataclass_fields__:
        x, y = getattr(a, field), getattr(b, field)
        if isinstance(x, float):
            if not math.isclose(x, y, rel_tol=1e-15, abs_tol=0.0):
                return False
        elif isinstance(x, tuple):
            if not _same_steps(x, y):
                return False
        elif x != y:
            return False
    return True


def _leaves(steps) -> int:
    return sum(s.count * _leaves(s.steps) if isinstance(s, Repeat) else 1 for s in steps)


@settings(max_examples=150, deadline=None)
@given(
    step_lists,
    st.floats(100.0, 3e4),
    st.floats(0.0, 40.0),
    st.sampled_from(["dry", "wet"]),
)
def test_property_monotonic_breakpoints_and_duration(steps, load, speed, friction):
    total = sum(s.duration for s in steps)
    kwargs = {"normal_load": load, "roller_speed": speed, "friction": friction}
    if total == 0.0:
        with pytest.raises(ProtocolError, match="duration > 0"):
            Protocol.from_steps("h", steps, **kwargs)
        return
    p = Protocol.from_steps("h", steps, **kwargs)
    assert p.duration == pytest.approx(total, rel=1e-12)
    for t in (p.torque_time, p.speed_time, p.load_time):
        assert t[0] == 0.0 and t[-1] == p.duration
        assert np.all(np.diff(t) > 0.0)
    assert np.all(np.diff(p.friction_time) > 0.0) and p.friction_time[-1] <= p.duration
    bp = p.breakpoints()
    assert bp[0] == 0.0 and bp[-1] == p.duration and np.all(np.diff(bp) > 0.0)
    assert len(p.events) == _leaves(steps)
    assert [e.start for e in p.events] == sorted(e.start for e in p.events)
    assert p.roller_speed[0] == speed and p.normal_load[0] == load
    # the TOML file written from the steps compiles to the same protocol (km/h and kN may
    # round in the last digit where no decimal number converts back exactly)
    back = protocol_from_toml_string(p.to_toml())
    assert _same_steps(back.to_steps(), p.to_steps())
    for name in ARRAYS:
        np.testing.assert_allclose(getattr(back, name), getattr(p, name), rtol=1e-15, atol=0)
    assert back.friction_condition == p.friction_condition
