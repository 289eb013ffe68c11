"""Tests of rollerrig.experiment.protocol: the compiled Protocol (validation, evaluation,
breakpoints, provenance dict, repr) and the old import paths.

The bundled protocols' numbers (Kayaalp 4.1.4, 4.2.1, 4.5.1.6; levels and timings are the
assumptions written in their TOML files) are pinned in test_tomlfile.py; here they serve as a
known protocol. Breakpoints: the sum of the step durations, by hand.
"""

from __future__ import annotations

import itertools
import json
import re

import numpy as np
import pytest

from rollerrig import experiment
from rollerrig._validation import ParameterError
from rollerrig.experiment import (
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
)


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


def test_breakpoints_include_every_kink():
    p = Protocol.from_steps(
        "kinks",
        [
            Hold(1.0),
            RampTorque(100.0, 2.0),
            SetRollerSpeed(5.0, 0.5),
            SetFriction("wet"),
            SetNormalLoad(5000.0, 0.25),
            ReleaseTorque(),
            Hold(0.75),
        ],
        normal_load=10e3,
        roller_speed=10.0,
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
    assert p.torque_at(3.5) == pytest.approx(456.0)  # half-way up the 3 s ramp to 912 N.m
    out = p.torque_at(np.array([[2.0, 3.5], [5.0, 40.0]]))
    assert out.shape == (2, 2)
    np.testing.assert_allclose(out, [[0.0, 456.0], [912.0, 0.0]])


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


def test_protocol_error_is_a_parameter_error():
    assert issubclass(ProtocolError, ParameterError)
    assert issubclass(ProtocolError, ValueError)


def test_repr_is_short():
    p = load_protocol("seed-30kmh-dry")
    assert repr(p) == (
        "Protocol('seed-30kmh-dry', 30 s, 14 torque, 2 speed, 2 load breakpoints, friction dry)"
    )
    wet = Protocol.from_steps(
        "w", [SetFriction("wet"), Hold(1.0)], normal_load=1e3, roller_speed=1.0
    )
    assert repr(wet).endswith("friction wet)")


def test_from_steps_keeps_its_steps_and_replay_has_none(tmp_path):
    steps = (Hold(1.0), Repeat(2, [StepTorque(50.0), ReleaseTorque()]))
    p = Protocol.from_steps("s", list(steps), normal_load=1e3, roller_speed=1.0)
    assert p.to_steps() == steps
    assert p.origin == "" and p.origin_sha256 == ""
    f = tmp_path / "r.csv"
    f.write_text("time [s],torque [N.m]\n0,0\n1,1\n")
    r = Protocol.replay(f, normal_load=1e3, roller_speed=1.0, name="rr")
    assert r.name == "rr" and r.steps == ()
    with pytest.raises(ProtocolError, match="'rr' was not compiled from steps"):
        r.to_steps()
    with pytest.raises(ProtocolError, match="not compiled from steps"):
        r.to_toml()


def test_old_import_paths_still_work():
    # Other packages and older code import these from rollerrig.experiment.protocol.
    from rollerrig.experiment import protocol as module

    for name in (
        "DEFAULT_FAST_RAMP_DURATION",
        "bundled_protocols",
        "load_protocol",
        "protocol_from_csv",
        "protocol_from_toml_string",
    ):
        assert getattr(module, name) is getattr(experiment, name)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        module.nothing  # noqa: B018


# --------------------------------------------------------------------------------------------
# Bad input at the boundary
# --------------------------------------------------------------------------------------------
def _pulse():
    return Protocol.from_steps(
        "pulse",
        [Hold(1.0), RampTorque(600.0, 2.0), experiment.SetFriction("wet"), Hold(1.0)],
        normal_load=4300.0,
        roller_speed=5.0,
    )


@pytest.mark.parametrize(
    "method", ["torque_at", "roller_speed_at", "normal_load_at", "friction_at"]
)
@pytest.mark.parametrize("t", [np.nan, None, [0.0, np.nan]])
def test_evaluation_at_nan_time_is_refused(method, t):
    """NaN (or None) time gave NaN inputs, and friction_at gave the last condition, 'wet'."""
    with pytest.raises(ParameterError, match=re.escape("t must be finite [s], got")):
        getattr(_pulse(), method)(t)


def test_evaluation_at_text_time_is_a_parameter_error():
    with pytest.raises(ParameterError, match=re.escape("t must be a number [s], got 'a'")):
        _pulse().torque_at("a")


def _arrays(**changes):
    base = dict(
        name="a",
        description="",
        source="",
        duration=2.0,
        torque_time=[0.0, 1.0],
        torque_request=[0.0, 1.0],
        speed_time=[0.0, 2.0],
        roller_speed=[1.0, 1.0],
        load_time=[0.0, 2.0],
        normal_load=[1.0, 1.0],
        friction_time=[0.0],
        friction_condition=("dry",),
    )
    return Protocol(**{**base, **changes})


@pytest.mark.parametrize("duration", [None, "2", [2.0]])
def test_protocol_duration_must_be_a_number(duration):
    """None and [2.0] were bare TypeErrors; "2" was taken as 2 s."""
    with pytest.raises(
        ProtocolError, match=re.escape(f"duration must be a number [s], got {duration!r}")
    ):
        _arrays(duration=duration)


def test_protocol_friction_condition_must_be_a_sequence_of_names():
    """ "dry" was split into three conditions 'd', 'r', 'y' (an error only by luck of length)."""
    with pytest.raises(
        ProtocolError,
        match=re.escape("friction_condition must be a sequence of names, one per friction_time"),
    ):
        _arrays(friction_condition="dry", friction_time=[0.0, 0.5, 1.0])


# --------------------------------------------------------------------------------------------
# Protocol(events=...): checked at construction
# --------------------------------------------------------------------------------------------

_EV = experiment.ProtocolEvent


@pytest.mark.parametrize(
    ("events", "message"),
    [
        (5, "events: must be a sequence of ProtocolEvent (start, end, action, target); got int"),
        ("hold", "events: must be a sequence of ProtocolEvent"),
        ({"a": 1}, "events: must be a sequence of ProtocolEvent"),
        ([5], "events[0]: must be a ProtocolEvent (start, end, action, target); got 5"),
        ([(0.0, 1.0, "hold")], "events[0]: must be a ProtocolEvent"),
        ([(np.nan, 1.0, "hold", None)], "events[0].start: must be a finite number [s]; got nan"),
        ([(0.0, "1", "hold", None)], "events[0].end: must be a finite number [s]; got '1'"),
        ([(True, 1.0, "hold", None)], "events[0].start: must be a finite number [s]; got true"),
        ([(1.0, 0.5, "hold", None)], "events[0].end: must not come before its start [s]"),
        ([(-1.0, 0.5, "hold", None)], "events[0].start: must lie in the protocol's duration"),
        ([(0.0, 5.0, "hold", None)], "events[0].end: must not come after the protocol's"),
        (
            [(0.0, 1.0, "hold", None), (0.5, 0.7, "hold", None), (0.2, 0.3, "hold", None)],
            "events[2].start: must not come before the start of events[1] (events are in time "
            "order) [s]; allowed >= 0.5; got 0.2",
        ),
        ([(0.0, 1.0, "hodl", None)], "events[0].action: unknown action (did you mean 'hold'?)"),
        ([(0.0, 1.0, 5, None)], "events[0].action: unknown action; allowed 'hold'"),
        ([(0.0, 1.0, ["hold"], None)], "events[0].action: unknown action"),
        ([(0.0, 1.0, "ramp_torque", np.nan)], "events[0].target: must be None, a finite"),
        ([(0.0, 1.0, "ramp_torque", True)], "events[0].target: must be None, a finite"),
    ],
)
def test_malformed_events_are_refused_at_construction(events, message):
    """Each had been a bare TypeError (not a sequence, three fields) or had been kept silently
    (NaN or reversed times, events out of order, a misspelt action no report would find)."""
    with pytest.raises(ProtocolError, match=re.escape(message)):
        _arrays(events=events)


def test_well_formed_events_are_kept_as_protocol_events_of_floats():
    p = _arrays(events=[(0, 1, "ramp_torque", np.int64(600)), _EV(1.0, 2.0, "set_friction", "wet")])
    assert p.events == (_EV(0.0, 1.0, "ramp_torque", 600.0), _EV(1.0, 2.0, "set_friction", "wet"))
    assert all(type(e.start) is float and type(e.end) is float for e in p.events)
    json.dumps(p.to_dict())  # np.int64 had not been JSON-able
    assert _arrays(events=[(0.0, 2.0, "replay", "trace.csv")]).events[0].action == "replay"


def test_events_given_by_a_generator_are_kept_as_before():
    """tuple(ProtocolEvent(*e) for e in events) had taken a generator; the check must too."""
    p = _arrays(events=((0.0, float(k), "hold", None) for k in (1, 2)))
    assert p.events == (_EV(0.0, 1.0, "hold", None), _EV(0.0, 2.0, "hold", None))
    with pytest.raises(ProtocolError, match=re.escape("events[1].action: unknown action")):
        _arrays(events=iter([(0.0, 1.0, "hold", None), (0.0, 1.0, "hodl", None)]))


def test_every_leaf_step_action_is_a_known_event_action():
    from rollerrig.experiment.protocol import _EVENT_ACTIONS
    from rollerrig.experiment.steps import STEP_TYPES

    leaves = {cls.action for cls in STEP_TYPES if cls is not Repeat}
    assert set(_EVENT_ACTIONS) == leaves | {"replay"}
    assert _pulse().events[-1].action == "hold"
