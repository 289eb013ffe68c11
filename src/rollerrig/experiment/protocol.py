"""The compiled experiment protocol: piecewise-linear SI inputs and friction switches.

An adhesion experiment on the rig follows the procedure of Kayaalp, section 4.1.4: the air spring
sets the normal force, the roller is brought to a constant speed by its drive and the wheel rolls
freely, then a torque request is sent to the wheel motor and the system is pushed until the
requested torque or a safe slip. Section 4.2.1 repeats the torque pattern three times with a
sudden release; section 4.5.1.6 simulates it at 30 km/h (dry) and 10 km/h (wet).

A :class:`Protocol` holds SI breakpoint arrays for the torque request [N.m], the roller
peripheral-speed set point [m/s] and the normal load [N], plus the switch instants of the named
friction condition. All changes of torque, speed and load are ramps of positive duration, so the
inputs are continuous; :meth:`Protocol.breakpoints` lists the instants where an input has a kink
or a switch, between which a solver can integrate smooth segments.

Where protocols come from (one module each):

- :mod:`rollerrig.experiment.steps` — step objects (``Hold``, ``RampTorque``, ...) and their
  compilation: :meth:`Protocol.from_steps`.
- :mod:`rollerrig.experiment.tomlfile` — the TOML format, bundled protocols:
  :func:`load_protocol`, :func:`protocol_from_toml_string`, :meth:`Protocol.to_toml`.
- :mod:`rollerrig.experiment.replay` — a recorded torque request (CSV): :meth:`Protocol.replay`.

The names of those modules stay importable from here (``from rollerrig.experiment.protocol
import load_protocol``) for older code; new code imports them from :mod:`rollerrig.experiment`.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from importlib import import_module
from typing import Any, NamedTuple

import numpy as np

from rollerrig._validation import (
    ParameterError,
    Verbatim,
    did_you_mean,
    field_error,
    interval,
    require_finite,
    show_value,
)

# The convenience constructors' builders, by name, registered by the modules that define them
# (experiment.steps, .replay, .tomlfile). Those import Protocol, so Protocol cannot import them
# without an import circle; the experiment package imports all three whenever this module is
# imported, so the registry is full before anyone can call a constructor.
_BUILDERS: dict[str, Callable[..., Any]] = {}

# The actions of ProtocolEvent: a leaf step's (registered by experiment.steps) and a replayed
# trace's.
_EVENT_ACTIONS: dict[str, None] = {}

__all__ = ["Protocol", "ProtocolError", "ProtocolEvent"]


class ProtocolError(ParameterError):
    """A protocol is malformed: the message names the file or step, the key and what is wrong."""


class ProtocolEvent(NamedTuple):
    """One leaf step of a compiled protocol, for reports and checks.

    Attributes
    ----------
    start : float
        Start time [s].
    end : float
        End time [s] (equal to ``start`` for instantaneous steps).
    action : str
        The step's action, e.g. ``"release_torque"``.
    target : float or str or None
        Target in SI units (torque [N.m], speed [m/s], load [N]), the friction name, or None.
    """

    start: float
    end: float
    action: str
    target: float | str | None


def _frozen_array(name: str, value) -> np.ndarray:
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ProtocolError(f"{name} must be an array of numbers, got {value!r}") from exc
    if arr.ndim != 1 or arr.size < 1:
        raise ProtocolError(f"{name} must be a non-empty 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ProtocolError(f"{name} must be finite")
    arr.setflags(write=False)
    return arr


def _check_time(name: str, t: np.ndarray, duration: float) -> None:
    if t[0] != 0.0:
        raise ProtocolError(f"{name} must start at 0 s, got {t[0]:g} s")
    if np.any(np.diff(t) <= 0.0):
        i = int(np.argmax(np.diff(t) <= 0.0))
        raise ProtocolError(
            f"{name} must be strictly increasing [s]: {t[i + 1]:g} s follows {t[i]:g} s "
            f"(index {i + 1})"
        )
    if t[-1] > duration * (1.0 + 1e-12):
        raise ProtocolError(f"{name} ends at {t[-1]:g} s, after the duration {duration:g} s")


def _event_error(key: str, message: str, **kwargs) -> ProtocolError:
    return field_error(None, key, message, error=ProtocolError, **kwargs)


_REAL = (float, int, np.floating, np.integer)


def _finite_number(value) -> bool:
    """A real number (not True/False, not text), finite."""
    return isinstance(value, _REAL) and not isinstance(value, bool) and math.isfinite(value)


def _event_problem(k: int, event, last_start: float, duration: float):
    """Raise the error of event ``k`` whose times or action are wrong (the checks of
    :func:`_checked_events`, one by one, for the message)."""
    start, end, action, _ = event
    for key, t in (("start", start), ("end", end)):
        if not _finite_number(t):
            raise _event_error(f"events[{k}].{key}", "must be a finite number", unit="s", got=t)
    limit = duration * (1.0 + 1e-12)
    if start < 0.0 or start > limit:
        raise _event_error(
            f"events[{k}].start", "must lie in the protocol's duration", unit="s",
            allowed=interval(0, duration, low_inclusive=True, high_inclusive=True), got=start,
        )  # fmt: skip
    span = interval(start, duration, low_inclusive=True, high_inclusive=True)
    if end < start:
        raise _event_error(
            f"events[{k}].end", "must not come before its start", unit="s", allowed=span,
            got=end,
        )  # fmt: skip
    if end > limit:
        raise _event_error(
            f"events[{k}].end", "must not come after the protocol's duration", unit="s",
            allowed=span, got=end,
        )  # fmt: skip
    if start < last_start:
        raise _event_error(
            f"events[{k}].start",
            f"must not come before the start of events[{k - 1}] (events are in time order)",
            unit="s",
            allowed=f">= {show_value(last_start)}",
            got=start,
        )
    hint = did_you_mean(action, _EVENT_ACTIONS) if isinstance(action, str) else ""
    raise _event_error(
        f"events[{k}].action", f"unknown action{hint}", allowed=list(_EVENT_ACTIONS), got=action
    )


def _checked_events(events, duration: float) -> tuple[ProtocolEvent, ...]:
    """``events`` as :class:`ProtocolEvent` (times and a numeric target as float), checked: a
    sequence of (start, end, action, target); times finite [s] in [0, duration], none ending
    before it starts, starts in time order; a known action (did you mean); a target that is
    None, a finite number or a name.

    A malformed event had given a bare TypeError (not a sequence, three fields) or had been
    kept silently (NaN or reversed times, a misspelt action that no report would find).
    """
    form = "(start, end, action, target)"
    if isinstance(events, Iterator):  # a generator of events, as tuple() had taken it
        events = tuple(events)
    if isinstance(events, str | bytes) or not isinstance(events, Sequence):
        got = events if isinstance(events, str | bytes) else Verbatim(type(events).__name__)
        raise _event_error("events", f"must be a sequence of ProtocolEvent {form}", got=got)
    out = []
    last_start = 0.0
    limit = duration * (1.0 + 1e-12)
    for k, e in enumerate(events):
        if type(e) is not ProtocolEvent and (
            not isinstance(e, Sequence) or isinstance(e, str | bytes) or len(e) != 4
        ):
            raise _event_error(f"events[{k}]", f"must be a ProtocolEvent {form}", got=e)
        start, end, action, target = e
        if not (
            _finite_number(start)
            and _finite_number(end)
            and last_start <= start <= end <= limit
            and isinstance(action, str)
            and action in _EVENT_ACTIONS
        ):
            _event_problem(k, e, last_start, duration)
        if target is not None and not isinstance(target, str):
            if not _finite_number(target):
                raise _event_error(
                    f"events[{k}].target",
                    "must be None, a finite number (SI) or a name",
                    got=target,
                )
            target = float(target)
        last_start = start
        out.append(ProtocolEvent(float(start), float(end), action, target))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class Protocol:
    """A compiled experiment protocol: piecewise-linear inputs in SI units.

    Values between breakpoints are linear interpolations; beyond the last breakpoint the last
    value holds. Arrays are float64 and read-only. Build one from step objects
    (:meth:`from_steps`), from a recorded torque request (:meth:`replay`) or from a TOML file
    (:func:`~rollerrig.experiment.load_protocol`).

    Parameters
    ----------
    name : str
        Short name of the protocol.
    description : str
        What the protocol does; which numbers are assumptions.
    source : str
        Where the pattern comes from (e.g. "Kayaalp, section 4.5.1.6, Fig. 40").
    duration : float
        Duration of the experiment [s], > 0.
    torque_time : ndarray
        Breakpoint times of the wheel-torque request [s], strictly increasing from 0.
    torque_request : ndarray
        Wheel-torque request at ``torque_time`` [N.m]; positive is traction.
    speed_time : ndarray
        Breakpoint times of the roller speed set point [s], strictly increasing from 0.
    roller_speed : ndarray
        Roller peripheral-speed set point at ``speed_time`` [m/s], >= 0.
    load_time : ndarray
        Breakpoint times of the normal load [s], strictly increasing from 0.
    normal_load : ndarray
        Normal load set by the air spring at ``load_time`` [N], > 0.
    friction_time : ndarray
        Instants [s] at which the friction condition switches, starting with 0.0.
    friction_condition : tuple of str
        Name of the friction condition from each switch instant on (e.g. "dry", "wet").
    events : tuple of ProtocolEvent, optional
        The leaf steps, in order, with their start and end times.
    origin : str, optional
        Where the protocol was read from (file path, "bundled:<name>" or "<string>").
    origin_sha256 : str, optional
        SHA-256 of the text or file it was read from.
    steps : tuple of Step, optional
        The steps it was compiled from (empty for a replayed trace); see :meth:`to_steps`.

    Examples
    --------
    >>> from rollerrig.experiment import Hold, RampTorque, ReleaseTorque, Repeat, load_protocol
    >>> p = Protocol.from_steps(
    ...     "two-pulses",
    ...     [Hold(1.0), Repeat(2, [RampTorque(600.0, 2.0), ReleaseTorque(), Hold(1.0)])],
    ...     normal_load=4300.0,
    ...     roller_speed=30 / 3.6,
    ... )
    >>> p
    Protocol('two-pulses', 7.04 s, 8 torque, 2 speed, 2 load breakpoints, friction dry)
    >>> p.torque_at(2.0), p.normal_load_at(5.0)
    (300.0, 4300.0)
    >>> load_protocol("seed-30kmh-dry").friction_at(10.0)
    'dry'
    """

    name: str
    description: str
    source: str
    duration: float
    torque_time: np.ndarray
    torque_request: np.ndarray
    speed_time: np.ndarray
    roller_speed: np.ndarray
    load_time: np.ndarray
    normal_load: np.ndarray
    friction_time: np.ndarray
    friction_condition: tuple[str, ...]
    events: tuple[ProtocolEvent, ...] = ()
    origin: str = ""
    origin_sha256: str = ""
    steps: tuple[Any, ...] = ()  # the Step objects of experiment.steps

    def __post_init__(self) -> None:
        try:  # text ("2") and True are no duration; None and a list are not numbers
            if isinstance(self.duration, str | bytes | bool | np.bool_):
                raise TypeError
            duration = float(self.duration)
        except (TypeError, ValueError):
            raise ProtocolError(f"duration must be a number [s], got {self.duration!r}") from None
        if not (math.isfinite(duration) and duration > 0.0):
            raise ProtocolError(f"duration must be > 0 [s], got {self.duration!r}")
        object.__setattr__(self, "duration", duration)
        pairs = (
            ("torque_time", "torque_request"),
            ("speed_time", "roller_speed"),
            ("load_time", "normal_load"),
        )
        for tname, vname in pairs:
            t = _frozen_array(tname, getattr(self, tname))
            v = _frozen_array(vname, getattr(self, vname))
            if t.shape != v.shape:
                raise ProtocolError(
                    f"{tname} and {vname} must have the same length, got {t.size} and {v.size}"
                )
            _check_time(tname, t, duration)
            object.__setattr__(self, tname, t)
            object.__setattr__(self, vname, v)
        if np.any(self.roller_speed < 0.0):
            raise ProtocolError("roller_speed must be >= 0 [m/s]")
        if np.any(self.normal_load <= 0.0):
            raise ProtocolError("normal_load must be > 0 [N]")
        ft = _frozen_array("friction_time", self.friction_time)
        _check_time("friction_time", ft, duration)
        if isinstance(self.friction_condition, str) or not isinstance(
            self.friction_condition, Sequence
        ):  # tuple("dry") would be three conditions 'd', 'r', 'y'
            raise ProtocolError(
                "friction_condition must be a sequence of names, one per friction_time, got "
                f"{self.friction_condition!r}"
            )
        names = tuple(self.friction_condition)
        if len(names) != ft.size:
            raise ProtocolError(
                f"friction_condition must have one name per friction_time, got {len(names)} "
                f"names for {ft.size} times"
            )
        for n in names:
            if not isinstance(n, str) or not n.strip():
                raise ProtocolError(f"friction_condition names must be non-empty text, got {n!r}")
        object.__setattr__(self, "friction_time", ft)
        object.__setattr__(self, "friction_condition", names)
        object.__setattr__(self, "events", _checked_events(self.events, duration))
        object.__setattr__(self, "steps", tuple(self.steps))

    def __repr__(self) -> str:
        friction = "/".join(dict.fromkeys(self.friction_condition))
        return (
            f"Protocol({self.name!r}, {self.duration:g} s, {self.torque_time.size} torque, "
            f"{self.speed_time.size} speed, {self.load_time.size} load breakpoints, "
            f"friction {friction})"
        )

    # -- constructors -------------------------------------------------------------------------

    @classmethod
    def from_steps(
        cls,
        name: str,
        steps: Sequence[Any],
        *,
        normal_load: float,
        roller_speed: float,
        friction: str = "dry",
        description: str = "",
        source: str = "",
    ) -> Protocol:
        """Compile a list of step objects into a protocol.

        Parameters
        ----------
        name : str
            Short name (used in output file names).
        steps : sequence of Step
            :class:`~rollerrig.experiment.Hold`, :class:`~rollerrig.experiment.RampTorque`,
            ... in order; :class:`~rollerrig.experiment.Repeat` nests them.
        normal_load : float
            Normal load at 0 s [N], > 0.
        roller_speed : float
            Roller peripheral-speed set point at 0 s [m/s], >= 0 (the roller is at speed, the
            wheel rolls freely).
        friction : str, optional
            Friction condition at 0 s (default "dry").
        description, source : str, optional
            What the protocol does; where the pattern comes from.

        Returns
        -------
        Protocol

        Raises
        ------
        ProtocolError
            When a setting is out of range, ``steps`` holds something that is not a step, or
            the steps add up to no time; the message names the argument, its unit and range.

        Examples
        --------
        >>> from rollerrig.experiment import Hold, SetFriction, SetRollerSpeed
        >>> p = Protocol.from_steps(
        ...     "speed-up", [SetRollerSpeed(10.0, 2.0), SetFriction("wet"), Hold(1.0)],
        ...     normal_load=4300.0, roller_speed=5.0)
        >>> p.roller_speed_at(1.0), p.friction_at(2.5)
        (7.5, 'wet')
        """
        settings = {"name": name, "normal_load": normal_load, "roller_speed": roller_speed}
        settings |= {"friction": friction, "description": description, "source": source}
        return _BUILDERS["steps"](steps, settings)  # experiment.steps.build_protocol

    @classmethod
    def replay(
        cls,
        csv_path: str | os.PathLike,
        *,
        normal_load: float,
        roller_speed: float,
        friction: str = "dry",
        time_column: str | None = None,
        torque_column: str | None = None,
        name: str | None = None,
        description: str = "",
    ) -> Protocol:
        """Replay a recorded wheel-torque request (CSV) at constant load, speed and friction.

        The header of the file names the units: time in s or ms, torque in N.m or kN.m, e.g.
        ``time [s],torque request [N.m]`` or ``time_ms,torque_kNm``
        (:mod:`rollerrig.experiment.replay`). Each sample becomes a breakpoint.

        Parameters
        ----------
        csv_path : str or path-like
            The CSV file (read once, never modified).
        normal_load : float
            Normal load [N], > 0.
        roller_speed : float
            Roller peripheral-speed set point [m/s], >= 0.
        friction : str, optional
            Friction condition (default "dry").
        time_column, torque_column : str, optional
            Exact headers of the columns to use (default: found by name).
        name : str, optional
            Protocol name (default: the file's stem).
        description : str, optional
            Free text.

        Examples
        --------
        >>> from importlib import resources
        >>> f = resources.files("rollerrig.experiment") / "data" / "replay-example.csv"
        >>> with resources.as_file(f) as real:
        ...     p = Protocol.replay(real, normal_load=4300.0, roller_speed=30 / 3.6)
        >>> p.duration, float(p.torque_request.max())
        (10.0, 600.0)
        """
        settings = {"normal_load": normal_load, "roller_speed": roller_speed}
        settings |= {"friction": friction, "description": description}
        columns = {"time_column": time_column, "torque_column": torque_column}
        named = settings | ({"name": name} if name else {})
        return _BUILDERS["replay"](csv_path, named, columns)  # experiment.replay.replay_protocol

    def to_steps(self) -> tuple[Any, ...]:
        """The step objects this protocol was compiled from.

        ``Protocol.from_steps(p.name, p.to_steps(), normal_load=p.normal_load[0],
        roller_speed=p.roller_speed[0], friction=p.friction_condition[0])`` compiles to the same
        arrays.

        Raises
        ------
        ProtocolError
            For a replayed trace or a protocol built from arrays (it has no steps).
        """
        if not self.steps:
            raise ProtocolError(
                f"protocol {self.name!r} was not compiled from steps (a replayed trace or "
                "arrays); it has no step list"
            )
        return self.steps

    def to_toml(self) -> str:
        """The protocol as TOML text in the format of the bundled files (units in the key names).

        ``protocol_from_toml_string(p.to_toml())`` compiles to the same arrays.

        Raises
        ------
        ProtocolError
            For a protocol without steps (see :meth:`to_steps`).
        """
        return _BUILDERS["toml"](self)  # experiment.tomlfile.protocol_to_toml

    # -- evaluation ---------------------------------------------------------------------------

    def torque_at(self, t):
        """Wheel-torque request at time ``t``.

        Parameters
        ----------
        t : float or array_like
            Time [s].

        Returns
        -------
        float or ndarray
            Torque request [N.m] (linear interpolation of the breakpoints).
        """
        return _interp(t, self.torque_time, self.torque_request)

    def roller_speed_at(self, t):
        """Roller peripheral-speed set point [m/s] at time ``t`` [s] (float or array)."""
        return _interp(t, self.speed_time, self.roller_speed)

    def normal_load_at(self, t):
        """Normal load [N] at time ``t`` [s] (float or array)."""
        return _interp(t, self.load_time, self.normal_load)

    def friction_at(self, t):
        """Name of the friction condition at time ``t`` [s].

        A switch at ``t_s`` applies from ``t_s`` on (inclusive). Returns a str for a scalar
        ``t`` and an object array of names for an array.
        """
        tt = require_finite("t", t, "s")  # NaN would sort after every switch: the last name
        idx = np.searchsorted(self.friction_time, tt, side="right") - 1
        idx = np.clip(idx, 0, len(self.friction_condition) - 1)
        names = np.array(self.friction_condition, dtype=object)[idx]
        return str(names) if np.ndim(names) == 0 else names

    def breakpoints(self) -> np.ndarray:
        """Sorted unique times [s] where any input has a kink or a switch, with 0 and duration.

        Inside each interval between consecutive breakpoints all inputs are linear (torque,
        speed, load) or constant (friction), so a solver can integrate segment by segment.
        """
        bp = np.concatenate(
            (
                [0.0, self.duration],
                self.torque_time,
                self.speed_time,
                self.load_time,
                self.friction_time,
            )
        )
        return np.unique(bp[bp <= self.duration])

    def to_dict(self) -> dict[str, Any]:
        """Plain, JSON-serialisable description (SI units in the keys) for provenance."""
        return {
            "name": self.name,
            "description": self.description,
            "source": self.source,
            "origin": self.origin,
            "origin_sha256": self.origin_sha256,
            "duration [s]": self.duration,
            "torque_time [s]": self.torque_time.tolist(),
            "torque_request [N.m]": self.torque_request.tolist(),
            "speed_time [s]": self.speed_time.tolist(),
            "roller_speed [m/s]": self.roller_speed.tolist(),
            "load_time [s]": self.load_time.tolist(),
            "normal_load [N]": self.normal_load.tolist(),
            "friction_time [s]": self.friction_time.tolist(),
            "friction_condition": list(self.friction_condition),
            "events": [e._asdict() for e in self.events],
        }


def _interp(t, xp: np.ndarray, fp: np.ndarray):
    out = np.interp(require_finite("t", t, "s"), xp, fp)  # np.interp gives NaN for NaN
    return float(out) if np.ndim(out) == 0 else out


# Names that lived here before the split into steps/tomlfile/replay: still importable from this
# module (``from rollerrig.experiment.protocol import load_protocol``), resolved on first use so
# that those modules can import :class:`Protocol` from here without a cycle.
_MOVED = {
    "DEFAULT_FAST_RAMP_DURATION": "rollerrig.experiment.steps",
    "bundled_protocols": "rollerrig.experiment.tomlfile",
    "load_protocol": "rollerrig.experiment.tomlfile",
    "protocol_from_toml_string": "rollerrig.experiment.tomlfile",
    "protocol_from_csv": "rollerrig.experiment.replay",
}


def __getattr__(name: str):
    module = _MOVED.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(import_module(module), name)
