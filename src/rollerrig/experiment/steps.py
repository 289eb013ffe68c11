"""Step objects, the building blocks of a protocol, and their compilation to SI breakpoints.

A protocol is a list of steps, written in Python (a notebook) or in TOML (the same objects are
built from the file by :mod:`rollerrig.experiment.tomlfile`, so the two cannot drift). Each step
is a frozen dataclass in SI units that validates itself when it is made:

================================  ==========================================================
``Hold(duration)``                keep every input as it is for ``duration`` [s] (>= 0)
``RampTorque(to, duration)``      ramp the wheel-torque request to ``to`` [N.m] in ``duration`` [s]
``StepTorque(to, duration)``      the same, fast: ``duration`` defaults to 0.02 s
``ReleaseTorque(duration)``       fast ramp of the request to 0 N.m (default 0.02 s)
``SetRollerSpeed(to, duration)``  ramp the roller speed set point to ``to`` [m/s]
``SetNormalLoad(to, duration)``   ramp the normal load to ``to`` [N]
``SetFriction(condition)``        switch the friction condition (a name, e.g. ``"wet"``)
``Repeat(count, steps)``          the nested ``steps``, ``count`` times
================================  ==========================================================

Changes of torque, speed and load are ramps of positive duration, never jumps, so the inputs are
continuous; a friction switch is instantaneous. :func:`build_protocol` (behind
:meth:`Protocol.from_steps <rollerrig.experiment.protocol.Protocol.from_steps>`) expands the
repeats and compiles the steps into the breakpoint arrays of a
:class:`~rollerrig.experiment.protocol.Protocol`.

Examples
--------
The bundled ``seed-30kmh-dry`` protocol, written in Python:

>>> from rollerrig.experiment import Protocol
>>> cycle = [RampTorque(720.0, 3.0), Hold(0.5), ReleaseTorque(), Hold(5.48)]
>>> p = Protocol.from_steps(
...     "seed-30kmh-dry", [Hold(2.0), Repeat(3, cycle), Hold(1.0)],
...     normal_load=4300.0, roller_speed=30 / 3.6)
>>> round(p.duration, 9), round(p.torque_at(5.51), 9), len(p.events)
(30.0, 360.0, 14)
>>> try:
...     RampTorque(720.0, 0.0)
... except ProtocolError as exc:
...     print(exc)
RampTorque: duration: must be > 0 [s]; allowed (0, inf); got 0
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from rollerrig._validation import field_error, interval, show_value
from rollerrig.experiment.protocol import (
    _BUILDERS,
    _EVENT_ACTIONS,
    Protocol,
    ProtocolError,
    ProtocolEvent,
)

__all__ = [
    "DEFAULT_FAST_RAMP_DURATION",
    "STEP_TYPES",
    "Hold",
    "RampTorque",
    "ReleaseTorque",
    "Repeat",
    "SetFriction",
    "SetNormalLoad",
    "SetRollerSpeed",
    "Step",
    "StepTorque",
]

DEFAULT_FAST_RAMP_DURATION = 0.02
"""Default duration [s] of ``StepTorque`` and ``ReleaseTorque``: fast, but not a jump."""

MAX_LEAF_STEPS = 1_000_000
"""Most leaf steps the repeats may expand to (a guard against runaway nested repeats)."""


def protocol_error(source: str, key: str, problem: str, **kwargs) -> ProtocolError:
    """A :class:`ProtocolError` in the package's one format (:func:`field_error`):
    ``<source>: <key>: <problem> [unit]; allowed ...; got ...``."""
    return field_error(source, key, problem, error=ProtocolError, **kwargs)


# --------------------------------------------------------------------------------------------
# Rules for the fields: one definition, used by the step objects and by the TOML file
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Quantity:
    """A numeric setting: its SI unit and its allowed range ``[low, inf)`` or ``(low, inf)``.

    Parameters
    ----------
    unit : str
        SI unit, e.g. ``"s"``.
    low : float or None
        Lower bound in ``unit``; None for any finite number.
    closed : bool
        Whether ``low`` itself is allowed.
    """

    unit: str
    low: float | None = None
    closed: bool = True

    def check(
        self, source: str, key: str, value, *, unit: str | None = None, scale: float = 1.0
    ) -> float:
        """``value`` as a float, or a :class:`ProtocolError` naming ``source``, ``key``, the unit
        and the range. ``unit``/``scale``: the value is in ``unit``, ``scale`` of it is one SI
        unit (the range is converted, the value is not)."""
        unit = unit or self.unit
        low = None if self.low is None else self.low / scale
        allowed = interval(
            -math.inf if low is None else low,
            math.inf,
            low_inclusive=low is not None and self.closed,
        )
        kw = {"unit": unit, "allowed": allowed, "got": value}
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise protocol_error(source, key, "must be a number", **kw)
        x = float(value)
        if not math.isfinite(x):
            raise protocol_error(source, key, "must be finite", **kw)
        if low is not None and (x < low or (x == low and not self.closed)):
            sign = ">=" if self.closed else ">"
            raise protocol_error(source, key, f"must be {sign} {show_value(low)}", **kw)
        return x


@dataclass(frozen=True)
class Count:
    """A repeat count: an integer >= 1."""

    unit: ClassVar[None] = None

    def check(self, source: str, key: str, value, **_) -> int:
        """``value`` as an int, or a :class:`ProtocolError`."""
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
            raise protocol_error(
                source, key, "must be an integer >= 1", allowed="1, 2, 3, ...", got=value
            )
        return int(value)


@dataclass(frozen=True)
class Name:
    """A non-empty name (a friction condition, a protocol name)."""

    unit: ClassVar[None] = None

    def check(self, source: str, key: str, value, **_) -> str:
        """``value`` stripped, or a :class:`ProtocolError`."""
        if not isinstance(value, str) or not value.strip():
            raise protocol_error(source, key, "must be a non-empty name", got=value)
        return value.strip()


@dataclass(frozen=True)
class Text:
    """Free text (a description, a source); may be empty."""

    unit: ClassVar[None] = None

    def check(self, source: str, key: str, value, **_) -> str:
        """``value``, or a :class:`ProtocolError` when it is not text."""
        if not isinstance(value, str):
            raise protocol_error(source, key, "must be text", got=value)
        return value


@dataclass(frozen=True)
class StepList:
    """A non-empty sequence of step objects."""

    unit: ClassVar[None] = None

    def check(self, source: str, key: str, value, **_) -> tuple[Step, ...]:
        """``value`` as a tuple of steps, or a :class:`ProtocolError` naming the bad item."""
        kinds = ", ".join(t.__name__ for t in STEP_TYPES)
        if isinstance(value, Step) or isinstance(value, str | bytes | dict):
            raise protocol_error(source, key, f"must be a list of steps ({kinds})", got=value)
        try:
            items = tuple(value)
        except TypeError:
            raise protocol_error(
                source, key, f"must be a list of steps ({kinds})", got=value
            ) from None
        if not items:
            raise protocol_error(source, key, "must contain at least one step", got=[])
        for i, item in enumerate(items):
            if not isinstance(item, Step):
                raise protocol_error(source, f"{key}[{i}]", f"must be a step ({kinds})", got=item)
        return items


TORQUE = Quantity("N.m")
"""Wheel-torque request [N.m], any finite value (positive is traction)."""
SPEED = Quantity("m/s", 0.0)
"""Roller peripheral-speed set point [m/s], >= 0."""
LOAD = Quantity("N", 0.0, closed=False)
"""Normal load [N], > 0."""
HOLD_TIME = Quantity("s", 0.0)
"""Duration of a hold [s], >= 0."""
RAMP_TIME = Quantity("s", 0.0, closed=False)
"""Duration of a ramp [s], > 0 (inputs never jump)."""
NAME = Name()
TEXT = Text()


# --------------------------------------------------------------------------------------------
# The step objects
# --------------------------------------------------------------------------------------------


class Step:
    """Base class of the step objects; each subclass is a frozen dataclass.

    A subclass states its class attributes as keywords of its ``class`` line: ``action`` (the
    step's name in TOML files and in :attr:`Protocol.events
    <rollerrig.experiment.protocol.Protocol.events>`), ``channel`` (the input it changes:
    ``"torque"``, ``"speed"``, ``"load"``, ``"friction"`` or None) and, for each field, the
    rule that validates it (collected in ``rules``).
    """

    action: ClassVar[str]
    channel: ClassVar[str | None]
    rules: ClassVar[dict[str, Quantity | Count | Name | StepList]]
    duration: float  # the time the step takes [s] (a field, or a property of Repeat)

    def __init_subclass__(cls, *, action: str = "", channel: str | None = None, **rules) -> None:
        super().__init_subclass__()
        if action:  # a step, not an intermediate base class
            cls.action, cls.channel, cls.rules = action, channel, rules

    def __post_init__(self) -> None:
        for field, rule in self.rules.items():
            object.__setattr__(
                self, field, rule.check(type(self).__name__, field, getattr(self, field))
            )

    @property
    def target(self) -> float | str | None:
        """What the step sets: SI value of its channel, the friction name, or None."""
        return getattr(self, "to", None)


@dataclass(frozen=True)
class Hold(Step, action="hold", duration=HOLD_TIME):
    """Keep every input as it is.

    Parameters
    ----------
    duration : float
        How long [s], >= 0.
    """

    duration: float


@dataclass(frozen=True)
class _Ramp(Step):
    """A linear ramp of one input from its present value to ``to`` in ``duration`` [s] (> 0).

    The subclasses are dataclasses through this one: they add no fields, only their class
    keywords (action, channel, rules) and documentation.
    """

    to: float
    duration: float


class RampTorque(_Ramp, action="ramp_torque", channel="torque", to=TORQUE, duration=RAMP_TIME):
    """Ramp the wheel-torque request linearly from its present value.

    Parameters
    ----------
    to : float
        Torque request at the end of the ramp [N.m]; positive is traction.
    duration : float
        Time the ramp takes [s], > 0.
    """


@dataclass(frozen=True)
class StepTorque(_Ramp, action="step_torque", channel="torque", to=TORQUE, duration=RAMP_TIME):
    """Change the wheel-torque request fast (a short ramp, so the input stays continuous).

    Parameters
    ----------
    to : float
        New torque request [N.m].
    duration : float, optional
        Length of the short ramp [s], > 0; default :data:`DEFAULT_FAST_RAMP_DURATION` (0.02 s).
    """

    duration: float = DEFAULT_FAST_RAMP_DURATION


@dataclass(frozen=True)
class ReleaseTorque(Step, action="release_torque", channel="torque", duration=RAMP_TIME):
    """Release the wheel-torque request: a fast ramp to 0 N.m (Kayaalp 4.2.1, "sudden release").

    Parameters
    ----------
    duration : float, optional
        Time to reach 0 N.m [s], > 0; default :data:`DEFAULT_FAST_RAMP_DURATION` (0.02 s).
    """

    duration: float = DEFAULT_FAST_RAMP_DURATION

    @property
    def target(self) -> float:
        """0.0 [N.m]."""
        return 0.0


class SetRollerSpeed(
    _Ramp, action="set_roller_speed", channel="speed", to=SPEED, duration=RAMP_TIME
):
    """Ramp the roller peripheral-speed set point.

    Parameters
    ----------
    to : float
        Speed set point at the end of the ramp [m/s], >= 0 (30 km/h = 30 / 3.6 m/s).
    duration : float
        Time the drive is given to reach it [s], > 0.
    """


class SetNormalLoad(_Ramp, action="set_normal_load", channel="load", to=LOAD, duration=RAMP_TIME):
    """Ramp the normal load set by the air spring.

    Parameters
    ----------
    to : float
        Normal load at the end of the ramp [N], > 0.
    duration : float
        Time the air spring takes to change it [s], > 0.
    """


@dataclass(frozen=True)
class SetFriction(Step, action="set_friction", channel="friction", condition=NAME):
    """Switch the friction condition, instantly (two switches at one instant: the last wins).

    Parameters
    ----------
    condition : str
        Name of a friction set of the simulation, e.g. ``"dry"`` or ``"wet"``.
    """

    condition: str
    duration: ClassVar[float] = 0.0

    @property
    def target(self) -> str:
        """The condition's name."""
        return self.condition


@dataclass(frozen=True)
class Repeat(Step, action="repeat", count=Count(), steps=StepList()):
    """Run ``steps`` ``count`` times (repeats nest).

    Parameters
    ----------
    count : int
        Number of repetitions, >= 1.
    steps : sequence of Step
        The steps of one repetition, at least one; stored as a tuple.
    """

    count: int
    steps: tuple[Step, ...]

    @property
    def duration(self) -> float:
        """Time all the repetitions take [s]."""
        return self.count * sum(s.duration for s in self.steps)

    def leaf_count(self, limit: int = MAX_LEAF_STEPS) -> int:
        """Number of leaf steps after expansion (stops counting past ``limit``)."""
        return _leaf_count(self.steps, limit) * self.count


STEP_TYPES: tuple[type[Step], ...] = (
    Hold,
    RampTorque,
    StepTorque,
    ReleaseTorque,
    SetRollerSpeed,
    SetNormalLoad,
    SetFriction,
    Repeat,
)
"""Every step class, in the order the documentation lists them."""

# The actions a compiled protocol's events may have (Protocol checks them): the leaf steps'.
_EVENT_ACTIONS.update(dict.fromkeys(cls.action for cls in STEP_TYPES if cls is not Repeat))


def step_fields(cls: type[Step]) -> tuple[tuple[str, bool], ...]:
    """``(field name, required)`` of a step class, in declaration order."""
    return tuple(
        (f.name, f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING)
        for f in dataclasses.fields(cls)
    )


def _leaf_count(steps: Sequence[Step], limit: int) -> int:
    n = 0
    for s in steps:
        n += s.leaf_count(limit) if isinstance(s, Repeat) else 1
        if n > limit:
            break
    return n


# --------------------------------------------------------------------------------------------
# Compilation
# --------------------------------------------------------------------------------------------


class _Channel:
    """Piecewise-linear breakpoints of one input, built step by step."""

    def __init__(self, value: float) -> None:
        self.t = [0.0]
        self.v = [value]

    def ramp(self, t0: float, t1: float, target: float) -> None:
        if self.t[-1] < t0:  # held since the last breakpoint: the ramp starts with a kink
            self.t.append(t0)
            self.v.append(self.v[-1])
        self.t.append(t1)
        self.v.append(target)

    def finish(self, t_end: float) -> tuple[np.ndarray, np.ndarray]:
        if self.t[-1] < t_end:
            self.t.append(t_end)
            self.v.append(self.v[-1])
        return np.array(self.t), np.array(self.v)


class _Compiler:
    def __init__(self, speed: float, load: float, friction: str) -> None:
        self.t = 0.0
        self.ramps = {"torque": _Channel(0.0), "speed": _Channel(speed), "load": _Channel(load)}
        self.friction_time = [0.0]
        self.friction = [friction]
        self.events: list[ProtocolEvent] = []

    def run(self, steps: Sequence[Step]) -> None:
        for s in steps:
            if isinstance(s, Repeat):
                for _ in range(s.count):
                    self.run(s.steps)
                continue
            t0, t1 = self.t, self.t + s.duration
            if s.channel in self.ramps:
                self.ramps[s.channel].ramp(t0, t1, float(s.target))
            elif s.channel == "friction":
                if self.friction_time[-1] == t0:  # two switches at one instant: last one wins
                    self.friction[-1] = s.target
                else:
                    self.friction_time.append(t0)
                    self.friction.append(s.target)
            self.events.append(ProtocolEvent(t0, t1, s.action, s.target))
            self.t = t1


SETTINGS: dict[str, Quantity | Name | Text] = {
    "name": NAME,
    "description": TEXT,
    "source": TEXT,
    "normal_load": LOAD,
    "friction": NAME,
    "roller_speed": SPEED,
}
"""The settings of a protocol besides its steps (arguments of :meth:`Protocol.from_steps
<rollerrig.experiment.protocol.Protocol.from_steps>`) and their rules."""

DEFAULT_SETTINGS = {"description": "", "source": "", "friction": "dry"}


def build_protocol(
    steps: Sequence[Step],
    settings: Mapping[str, Any],
    *,
    origin: str = "",
    origin_sha256: str = "",
    where: tuple[str, str] = ("Protocol.from_steps", "steps"),
) -> Protocol:
    """Compile steps into a :class:`Protocol` (the one compile path of Python and TOML).

    Parameters
    ----------
    steps : sequence of Step
        The steps.
    settings : mapping
        The other arguments of :meth:`Protocol.from_steps
        <rollerrig.experiment.protocol.Protocol.from_steps>` (keys of :data:`SETTINGS`;
        ``friction``, ``description`` and ``source`` optional).
    origin, origin_sha256 : str
        Provenance of a file.
    where : (str, str)
        ``(source, key)`` that errors name: ``("mine.toml", "step")`` for a file.
    """
    src, steps_key = where
    v = {
        key: rule.check(src, key, {**DEFAULT_SETTINGS, **settings}[key])
        for key, rule in SETTINGS.items()
    }
    steps = StepList().check(src, steps_key, steps)
    if _leaf_count(steps, MAX_LEAF_STEPS) > MAX_LEAF_STEPS:
        raise protocol_error(
            src,
            steps_key,
            f"the repeats expand to more than {MAX_LEAF_STEPS} steps; reduce the counts",
        )
    comp = _Compiler(v["roller_speed"], v["normal_load"], v["friction"])
    comp.run(steps)
    duration = comp.t
    if duration <= 0.0:
        raise protocol_error(
            src, steps_key, "the steps must add up to a duration > 0", unit="s", got=duration
        )
    arrays = {}
    for channel, (tname, vname) in {
        "torque": ("torque_time", "torque_request"),
        "speed": ("speed_time", "roller_speed"),
        "load": ("load_time", "normal_load"),
    }.items():
        arrays[tname], arrays[vname] = comp.ramps[channel].finish(duration)
    return Protocol(
        name=v["name"],
        description=v["description"],
        source=v["source"],
        duration=duration,
        **arrays,
        friction_time=np.array(comp.friction_time),
        friction_condition=tuple(comp.friction),
        events=tuple(comp.events),
        origin=origin,
        origin_sha256=origin_sha256,
        steps=steps,
    )


_BUILDERS["steps"] = build_protocol  # Protocol's constructor uses it (experiment.protocol)
