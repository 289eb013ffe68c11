"""Adhesion-experiment protocols written as data (TOML) or replayed from a recorded trace (CSV).

An adhesion experiment on the rig follows the procedure of Kayaalp, section 4.1.4: the air spring
sets the normal force, the roller is brought to a constant speed by its drive and the wheel rolls
freely, then a torque request is sent to the wheel motor and the system is pushed until the
requested torque or a safe slip. Section 4.2.1 repeats the torque pattern three times with a
sudden release; section 4.5.1.6 simulates it at 30 km/h (dry) and 10 km/h (wet).

A protocol is written as a list of steps in TOML with the units in the key names (the edge), and
compiled to a :class:`Protocol`: piecewise-linear, SI breakpoint arrays for the torque request
[N.m], the roller peripheral-speed set point [m/s] and the normal load [N], plus the switch
instants of the named friction condition. All changes of torque, speed and load are ramps of
positive duration, so the inputs are continuous; :meth:`Protocol.breakpoints` lists the instants
where an input has a kink or a switch, between which a solver can integrate smooth segments.

TOML format::

    [experiment]
    name = "seed-30kmh-dry"
    description = "..."
    source = "..."
    normal_load_kN = 4.3        # initial normal load
    friction = "dry"            # initial friction condition (optional, default "dry")
    roller_speed_kmh = 30.0     # roller at speed at t = 0, wheel rolling freely

    [[step]]
    action = "hold"
    duration_s = 2.0

    [[step]]
    action = "repeat"
    count = 3
      [[step.steps]]
      action = "ramp_torque"
      to_Nm = 600.0
      duration_s = 3.0
      [[step.steps]]
      action = "release_torque"   # fast ramp to 0 N.m, duration_s defaults to 0.02 s

Actions and their keys (``[req]`` required, ``[opt]`` optional):

- ``hold``: ``duration_s`` [req], >= 0.
- ``ramp_torque``: ``to_Nm`` [req], ``duration_s`` [req], > 0 (linear ramp of the request).
- ``step_torque``: ``to_Nm`` [req], ``duration_s`` [opt, 0.02 s], > 0 (a fast ramp).
- ``release_torque``: ``duration_s`` [opt, 0.02 s], > 0 (fast ramp to 0 N.m).
- ``set_roller_speed``: ``to_kmh`` [req], >= 0, ``duration_s`` [req], > 0 (set-point ramp).
- ``set_normal_load``: ``to_kN`` [req], > 0, ``duration_s`` [req], > 0 (ramp).
- ``set_friction``: ``condition`` [req] (a name, e.g. ``"wet"``), instantaneous.
- ``repeat``: ``count`` [req], integer >= 1, ``steps`` [req] (nested steps; nesting allowed).

Instead of steps, a ``[replay]`` table with ``csv = "file.csv"`` (relative to the TOML file) and
optional ``time_column`` / ``torque_column`` replays a recorded torque request with the
experiment's load, speed and friction (see :func:`protocol_from_csv`).
"""

from __future__ import annotations

import csv
import hashlib
import math
import re
import tomllib
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from rollerrig._validation import ParameterError

__all__ = [
    "DEFAULT_FAST_RAMP_DURATION",
    "Protocol",
    "ProtocolError",
    "ProtocolEvent",
    "bundled_protocols",
    "load_protocol",
    "protocol_from_csv",
    "protocol_from_toml_string",
]

DEFAULT_FAST_RAMP_DURATION = 0.02
"""Default duration [s] of ``step_torque`` and ``release_torque``: fast, but not a jump."""

_KMH = 1.0 / 3.6  # [m/s per km/h]
_MAX_SEGMENTS = 1_000_000  # guard against runaway nested repeats

_ACTION_KEYS: dict[str, tuple[frozenset[str], frozenset[str]]] = {
    "hold": (frozenset({"duration_s"}), frozenset()),
    "ramp_torque": (frozenset({"to_Nm", "duration_s"}), frozenset()),
    "step_torque": (frozenset({"to_Nm"}), frozenset({"duration_s"})),
    "release_torque": (frozenset(), frozenset({"duration_s"})),
    "set_roller_speed": (frozenset({"to_kmh", "duration_s"}), frozenset()),
    "set_normal_load": (frozenset({"to_kN", "duration_s"}), frozenset()),
    "set_friction": (frozenset({"condition"}), frozenset()),
    "repeat": (frozenset({"count", "steps"}), frozenset()),
}

_EXPERIMENT_REQUIRED = frozenset({"name", "normal_load_kN", "roller_speed_kmh"})
_EXPERIMENT_OPTIONAL = frozenset({"description", "source", "friction"})
_REPLAY_KEYS = frozenset({"csv", "time_column", "torque_column"})


class ProtocolError(ParameterError):
    """A protocol is malformed: the message names the offending key path and what is wrong."""


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


# --------------------------------------------------------------------------------------------
# The compiled protocol
# --------------------------------------------------------------------------------------------


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


@dataclass(frozen=True, eq=False)
class Protocol:
    """A compiled experiment protocol: piecewise-linear inputs in SI units.

    Values between breakpoints are linear interpolations; beyond the last breakpoint the last
    value holds. Arrays are float64 and read-only.

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

    Examples
    --------
    >>> p = load_protocol("seed-30kmh-dry")
    >>> p.duration
    30.0
    >>> round(p.roller_speed_at(0.0), 4)
    8.3333
    >>> p.friction_at(10.0)
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

    def __post_init__(self) -> None:
        duration = float(self.duration)
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
        object.__setattr__(self, "events", tuple(ProtocolEvent(*e) for e in self.events))

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
        tt = np.asarray(t, dtype=float)
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
    out = np.interp(np.asarray(t, dtype=float), xp, fp)
    return float(out) if np.ndim(out) == 0 else out


# --------------------------------------------------------------------------------------------
# TOML parsing and validation
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Step:
    action: str
    path: str
    duration: float = 0.0
    target: float | str | None = None
    count: int = 1
    steps: tuple[_Step, ...] = ()


def _number(path: str, value, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ProtocolError(f"{path} must be a number [{unit}], got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise ProtocolError(f"{path} must be finite [{unit}], got {value!r}")
    return x


def _nonneg(path: str, value, unit: str) -> float:
    x = _number(path, value, unit)
    if x < 0.0:
        raise ProtocolError(f"{path} must be >= 0 [{unit}], got {x:g}")
    return x


def _positive(path: str, value, unit: str) -> float:
    x = _number(path, value, unit)
    if x <= 0.0:
        raise ProtocolError(f"{path} must be > 0 [{unit}], got {x:g}")
    return x


def _name(path: str, value) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ProtocolError(f"{path} must be a non-empty name, got {value!r}")
    return value.strip()


def _check_keys(path: str, table: dict, required: frozenset, optional: frozenset, what: str):
    unknown = sorted(set(table) - required - optional)
    if unknown:
        allowed = ", ".join(sorted(required | optional))
        raise ProtocolError(f"{path}.{unknown[0]}: unknown key for {what} (allowed: {allowed})")
    missing = sorted(required - set(table))
    if missing:
        raise ProtocolError(f"{path}.{missing[0]}: missing key required for {what}")


def _parse_steps(path: str, steps) -> tuple[_Step, ...]:
    if not isinstance(steps, list):
        raise ProtocolError(f"{path} must be a list of step tables ([[...]]), got {steps!r}")
    return tuple(_parse_step(f"{path}[{i}]", s) for i, s in enumerate(steps))


def _parse_step(path: str, table) -> _Step:
    if not isinstance(table, dict):
        raise ProtocolError(f"{path} must be a table with an 'action' key, got {table!r}")
    if "action" not in table:
        raise ProtocolError(f"{path}.action: missing key (one of {', '.join(_ACTION_KEYS)})")
    action = table["action"]
    if action not in _ACTION_KEYS:
        raise ProtocolError(
            f"{path}.action: unknown action {action!r} (one of {', '.join(_ACTION_KEYS)})"
        )
    body = {k: v for k, v in table.items() if k != "action"}
    required, optional = _ACTION_KEYS[action]
    _check_keys(path, body, required, optional, f"action {action!r}")
    p = f"{path}."
    if action == "hold":
        return _Step(action, path, duration=_nonneg(p + "duration_s", body["duration_s"], "s"))
    if action == "ramp_torque":
        return _Step(
            action,
            path,
            duration=_positive(p + "duration_s", body["duration_s"], "s"),
            target=_number(p + "to_Nm", body["to_Nm"], "N.m"),
        )
    if action in ("step_torque", "release_torque"):
        d = body.get("duration_s", DEFAULT_FAST_RAMP_DURATION)
        target = _number(p + "to_Nm", body["to_Nm"], "N.m") if action == "step_torque" else 0.0
        return _Step(action, path, duration=_positive(p + "duration_s", d, "s"), target=target)
    if action == "set_roller_speed":
        return _Step(
            action,
            path,
            duration=_positive(p + "duration_s", body["duration_s"], "s"),
            target=_nonneg(p + "to_kmh", body["to_kmh"], "km/h") * _KMH,
        )
    if action == "set_normal_load":
        return _Step(
            action,
            path,
            duration=_positive(p + "duration_s", body["duration_s"], "s"),
            target=_positive(p + "to_kN", body["to_kN"], "kN") * 1e3,
        )
    if action == "set_friction":
        return _Step(action, path, target=_name(p + "condition", body["condition"]))
    # repeat
    count = body["count"]
    if isinstance(count, bool) or not isinstance(count, int):
        raise ProtocolError(f"{p}count must be an integer >= 1, got {count!r}")
    if count < 1:
        raise ProtocolError(f"{p}count must be an integer >= 1, got {count}")
    steps = _parse_steps(p + "steps", body["steps"])
    if not steps:
        raise ProtocolError(f"{p}steps must contain at least one step")
    return _Step(action, path, count=count, steps=steps)


def _segments(steps: tuple[_Step, ...]) -> int:
    n = 0
    for s in steps:
        n += s.count * _segments(s.steps) if s.action == "repeat" else 1
        if n > _MAX_SEGMENTS:
            break
    return n


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
    def __init__(self, torque: float, speed: float, load: float, friction: str) -> None:
        self.t = 0.0
        self.torque = _Channel(torque)
        self.speed = _Channel(speed)
        self.load = _Channel(load)
        self.friction_time = [0.0]
        self.friction = [friction]
        self.events: list[ProtocolEvent] = []

    def run(self, steps: tuple[_Step, ...]) -> None:
        for s in steps:
            if s.action == "repeat":
                for _ in range(s.count):
                    self.run(s.steps)
                continue
            t0, t1 = self.t, self.t + s.duration
            if s.action in ("ramp_torque", "step_torque", "release_torque"):
                self.torque.ramp(t0, t1, float(s.target))
            elif s.action == "set_roller_speed":
                self.speed.ramp(t0, t1, float(s.target))
            elif s.action == "set_normal_load":
                self.load.ramp(t0, t1, float(s.target))
            elif s.action == "set_friction":
                if self.friction_time[-1] == t0:  # two switches at one instant: last one wins
                    self.friction[-1] = str(s.target)
                else:
                    self.friction_time.append(t0)
                    self.friction.append(str(s.target))
            self.events.append(ProtocolEvent(t0, t1, s.action, s.target))
            self.t = t1


def protocol_from_toml_string(
    text: str,
    *,
    base_dir: str | Path | None = None,
    origin: str = "<string>",
) -> Protocol:
    """Compile a protocol written in TOML.

    Parameters
    ----------
    text : str
        The TOML text (format in the module docstring).
    base_dir : str or Path, optional
        Directory against which a relative ``[replay] csv`` path is resolved (default: the
        current directory).
    origin : str, optional
        Recorded in :attr:`Protocol.origin` for provenance.

    Returns
    -------
    Protocol
        The compiled, SI protocol.

    Raises
    ------
    ProtocolError
        On invalid TOML, unknown or missing keys, or out-of-range values; the message names the
        key path, e.g. ``step[1].steps[0].to_Nm``.

    Examples
    --------
    >>> p = protocol_from_toml_string('''
    ... [experiment]
    ... name = "tiny"
    ... normal_load_kN = 10.0
    ... roller_speed_kmh = 36.0
    ... [[step]]
    ... action = "ramp_torque"
    ... to_Nm = 100.0
    ... duration_s = 1.0
    ... ''')
    >>> p.torque_at(0.5), p.roller_speed_at(0.5), p.normal_load_at(0.5)
    (50.0, 10.0, 10000.0)
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ProtocolError(f"invalid TOML in {origin}: {exc}") from exc
    sha = hashlib.sha256(text.encode("utf-8")).hexdigest()

    unknown = sorted(set(doc) - {"experiment", "step", "replay"})
    if unknown:
        raise ProtocolError(
            f"{unknown[0]}: unknown top-level key (allowed: experiment, step, replay)"
        )
    exp = doc.get("experiment")
    if not isinstance(exp, dict):
        raise ProtocolError("experiment: missing [experiment] table")
    _check_keys("experiment", exp, _EXPERIMENT_REQUIRED, _EXPERIMENT_OPTIONAL, "[experiment]")
    name = _name("experiment.name", exp["name"])
    description = exp.get("description", "")
    source = exp.get("source", "")
    for key, val in (("description", description), ("source", source)):
        if not isinstance(val, str):
            raise ProtocolError(f"experiment.{key} must be text, got {val!r}")
    load = _positive("experiment.normal_load_kN", exp["normal_load_kN"], "kN") * 1e3
    speed = _nonneg("experiment.roller_speed_kmh", exp["roller_speed_kmh"], "km/h") * _KMH
    friction = _name("experiment.friction", exp.get("friction", "dry"))

    if "replay" in doc:
        if "step" in doc:
            raise ProtocolError("step: a protocol with [replay] must not also have steps")
        rep = doc["replay"]
        if not isinstance(rep, dict):
            raise ProtocolError("replay must be a table")
        _check_keys("replay", rep, frozenset({"csv"}), _REPLAY_KEYS - {"csv"}, "[replay]")
        csv_name = _name("replay.csv", rep["csv"])
        csv_path = Path(csv_name)
        if not csv_path.is_absolute():
            csv_path = Path(base_dir or ".") / csv_path
        cols = {}
        for key in ("time_column", "torque_column"):
            if key in rep:
                cols[key] = _name(f"replay.{key}", rep[key])
        p = protocol_from_csv(
            csv_path, load, speed, friction, name=name, description=description, **cols
        )
        src = f"{source}; " if source else ""
        return replace(
            p,
            source=f"{src}torque request replayed from {csv_path.name} "
            f"(sha256 {p.origin_sha256[:12]})",
            origin=origin,
        )

    if "step" not in doc:
        raise ProtocolError("step: no steps ([[step]] tables) and no [replay] table")
    steps = _parse_steps("step", doc["step"])
    if _segments(steps) > _MAX_SEGMENTS:
        raise ProtocolError(
            f"step: the repeats expand to more than {_MAX_SEGMENTS} steps; reduce the counts"
        )
    comp = _Compiler(0.0, speed, load, friction)
    comp.run(steps)
    duration = comp.t
    if duration <= 0.0:
        raise ProtocolError("step: the steps must add up to a duration > 0 s, got 0 s")
    tt, tv = comp.torque.finish(duration)
    st, sv = comp.speed.finish(duration)
    lt, lv = comp.load.finish(duration)
    return Protocol(
        name=name,
        description=description,
        source=source,
        duration=duration,
        torque_time=tt,
        torque_request=tv,
        speed_time=st,
        roller_speed=sv,
        load_time=lt,
        normal_load=lv,
        friction_time=np.array(comp.friction_time),
        friction_condition=tuple(comp.friction),
        events=tuple(comp.events),
        origin=origin,
        origin_sha256=sha,
    )


# --------------------------------------------------------------------------------------------
# Bundled protocols and files
# --------------------------------------------------------------------------------------------


def _data_dir():
    return resources.files("rollerrig.experiment").joinpath("data")


def bundled_protocols() -> tuple[str, ...]:
    """Names of the protocols bundled with rollerrig (TOML files in ``experiment/data``).

    Examples
    --------
    >>> "seed-30kmh-dry" in bundled_protocols()
    True
    """
    return tuple(
        sorted(f.name[: -len(".toml")] for f in _data_dir().iterdir() if f.name.endswith(".toml"))
    )


def load_protocol(path_or_name: str | Path) -> Protocol:
    """Load a protocol by bundled name (e.g. ``"seed-30kmh-dry"``) or from a TOML file.

    Parameters
    ----------
    path_or_name : str or Path
        A bundled name (see :func:`bundled_protocols`) or the path of a ``.toml`` file.

    Returns
    -------
    Protocol

    Raises
    ------
    ProtocolError
        If the name is unknown or the file is invalid.

    Examples
    --------
    >>> load_protocol("seed-10kmh-wet").friction_at(0.0)
    'wet'
    """
    if isinstance(path_or_name, str) and path_or_name in bundled_protocols():
        res = _data_dir().joinpath(f"{path_or_name}.toml")
        with resources.as_file(res) as real:
            text = Path(real).read_text(encoding="utf-8")
            return protocol_from_toml_string(
                text, base_dir=Path(real).parent, origin=f"bundled:{path_or_name}"
            )
    path = Path(path_or_name)
    if path.suffix.lower() == ".csv":
        raise ProtocolError(
            f"{path}: a CSV trace needs a normal load and a roller speed; use protocol_from_csv"
        )
    if not path.is_file():
        raise ProtocolError(
            f"{path_or_name!s}: neither a bundled protocol ({', '.join(bundled_protocols())}) "
            "nor an existing TOML file"
        )
    text = path.read_text(encoding="utf-8")
    return protocol_from_toml_string(text, base_dir=path.parent, origin=str(path))


# --------------------------------------------------------------------------------------------
# Replay of a recorded torque request (CSV)
# --------------------------------------------------------------------------------------------

_TIME_UNITS = {"s": 1.0, "ms": 1e-3}
_TORQUE_UNITS = {"n.m": 1.0, "nm": 1.0, "kn.m": 1e3, "knm": 1e3}
_BRACKET = re.compile(r"^(?P<base>.*?)\s*[\[(]\s*(?P<unit>[^\])]*?)\s*[\])]\s*$")
_SUFFIX = re.compile(r"^(?P<base>.+?)_(?P<unit>ms|s|kN\.?m|N\.?m)$", re.IGNORECASE)


def _split_header(header: str) -> tuple[str, str | None]:
    """``"time [s]"`` -> ("time", "s"); ``"torque_kNm"`` -> ("torque", "kNm")."""
    h = header.strip()
    m = _BRACKET.match(h) or _SUFFIX.match(h)
    if m:
        return m["base"].strip(), m["unit"]
    return h, None


def _norm_unit(unit: str) -> str:
    for ch in ("·", "⋅", "*", " "):
        unit = unit.replace(ch, "." if ch != " " else "")
    return unit.lower()


def _column_scale(header: str, kind: str) -> float:
    unit = _split_header(header)[1]
    table = _TIME_UNITS if kind == "time" else _TORQUE_UNITS
    example = "'time [s]' or 'time_ms'" if kind == "time" else "'torque [N.m]' or 'torque_kNm'"
    if unit is None:
        raise ProtocolError(f"column {header!r}: no unit in the header; name it like {example}")
    key = _norm_unit(unit) if kind == "torque" else unit.strip()
    if key not in table:
        allowed = "s, ms" if kind == "time" else "N.m, kN.m"
        raise ProtocolError(f"column {header!r}: unknown {kind} unit {unit!r} (allowed: {allowed})")
    return table[key]


def _find_column(headers: list[str], wanted: str | None, kind: str, path: Path) -> int:
    stripped = [h.strip() for h in headers]
    if wanted is not None:
        if wanted.strip() not in stripped:
            raise ProtocolError(
                f"{path.name}: no column {wanted!r} for the {kind} (columns: {stripped})"
            )
        return stripped.index(wanted.strip())
    bases = [_split_header(h)[0].lower() for h in stripped]
    if kind == "time":
        hits = [i for i, b in enumerate(bases) if b in ("time", "t")]
    else:
        hits = [i for i, b in enumerate(bases) if "torque" in b]
        if len(hits) > 1:
            requested = [i for i in hits if "request" in bases[i]]
            hits = requested or hits
    if not hits:
        raise ProtocolError(
            f"{path.name}: missing {kind} column (columns: {stripped}); pass "
            f"{kind}_column= or name it like "
            + ("'time [s]'" if kind == "time" else "'torque request [N.m]'")
        )
    if len(hits) > 1:
        raise ProtocolError(
            f"{path.name}: several {kind} columns {[stripped[i] for i in hits]}; "
            f"choose one with {kind}_column="
        )
    return hits[0]


def protocol_from_csv(
    path: str | Path,
    normal_load: float,
    roller_speed: float,
    friction: str = "dry",
    *,
    time_column: str | None = None,
    torque_column: str | None = None,
    name: str | None = None,
    description: str = "",
) -> Protocol:
    """Replay a recorded wheel-torque request from a CSV file, at constant load and speed.

    The file is read once and never modified. Lines starting with ``#`` are comments. The
    header names the units, e.g. ``time [s],torque request [N.m]`` or ``time_ms,torque_kNm``;
    time in s or ms, torque in N.m or kN.m. Time is shifted to start at 0 s. Each sample is a
    breakpoint of the piecewise-linear request, so a solver stops at every sample.

    Parameters
    ----------
    path : str or Path
        CSV file.
    normal_load : float
        Constant normal load Q [N], > 0.
    roller_speed : float
        Constant roller peripheral-speed set point [m/s], >= 0 (the roller is at speed at 0 s).
    friction : str, optional
        Name of the friction condition (default "dry").
    time_column, torque_column : str, optional
        Exact header of the time and torque columns; by default the column named ``time``
        (or ``t``) and the one containing ``torque`` (preferring ``request``) are used.
    name : str, optional
        Protocol name (default: the file's stem).
    description : str, optional
        Free text.

    Returns
    -------
    Protocol

    Raises
    ------
    ProtocolError
        On a missing column, a header without a known unit, a non-numeric or non-finite cell,
        time that is duplicated or not increasing, or fewer than two samples; the message names
        the line.

    Examples
    --------
    >>> from importlib import resources
    >>> f = resources.files("rollerrig.experiment") / "data" / "replay-example.csv"
    >>> with resources.as_file(f) as real:
    ...     p = protocol_from_csv(real, normal_load=4300.0, roller_speed=30 / 3.6)
    >>> p.duration, float(p.torque_request.max())
    (10.0, 600.0)
    """
    path = Path(path)
    q = _positive("normal_load", normal_load, "N")
    v = _nonneg("roller_speed", roller_speed, "m/s")
    friction = _name("friction", friction)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ProtocolError(f"{path}: cannot read the CSV file ({exc})") from exc
    sha = hashlib.sha256(raw).hexdigest()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ProtocolError(f"{path.name}: not UTF-8 text ({exc})") from exc

    rows: list[tuple[int, list[str]]] = []
    for lineno, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        rows.append((lineno, next(csv.reader([line]))))
    if not rows:
        raise ProtocolError(f"{path.name}: no header and no data")
    headers = rows[0][1]
    data = rows[1:]
    it = _find_column(headers, time_column, "time", path)
    iq = _find_column(headers, torque_column, "torque", path)
    if it == iq:
        raise ProtocolError(f"{path.name}: the time and torque columns are the same column")
    t_scale = _column_scale(headers[it], "time")
    q_scale = _column_scale(headers[iq], "torque")
    if len(data) < 2:
        raise ProtocolError(f"{path.name}: too few rows: need at least 2 samples, got {len(data)}")

    t = np.empty(len(data))
    tq = np.empty(len(data))
    for k, (lineno, fields) in enumerate(data):
        for col, out in ((it, t), (iq, tq)):
            if col >= len(fields):
                raise ProtocolError(
                    f"{path.name}, line {lineno}: missing value for column {headers[col]!r}"
                )
            cell = fields[col].strip()
            try:
                x = float(cell)
            except ValueError:
                raise ProtocolError(
                    f"{path.name}, line {lineno}, column {headers[col]!r}: {cell!r} is not a number"
                ) from None
            if not math.isfinite(x):
                raise ProtocolError(
                    f"{path.name}, line {lineno}, column {headers[col]!r}: {cell!r} is not finite"
                )
            out[k] = x
    dt = np.diff(t)
    if np.any(dt <= 0.0):
        k = int(np.argmax(dt <= 0.0))
        a, b = data[k][0], data[k + 1][0]
        what = "duplicated time" if dt[k] == 0.0 else "time is not increasing"
        raise ProtocolError(
            f"{path.name}, line {b}: {what} ({headers[it].strip()} = {t[k + 1]:g} after "
            f"{t[k]:g} on line {a})"
        )
    t0 = t[0]
    time = (t - t0) * t_scale
    torque = tq * q_scale
    duration = float(time[-1])
    shift = f" Time shifted by {-t0:g} (file units) to start at 0 s." if t0 != 0.0 else ""
    return Protocol(
        name=name or path.stem,
        description=(description + shift).strip(),
        source=f"torque request replayed from {path.name} (sha256 {sha[:12]})",
        duration=duration,
        torque_time=time,
        torque_request=torque,
        speed_time=np.array([0.0, duration]),
        roller_speed=np.array([v, v]),
        load_time=np.array([0.0, duration]),
        normal_load=np.array([q, q]),
        friction_time=np.array([0.0]),
        friction_condition=(friction,),
        events=(ProtocolEvent(0.0, duration, "replay", path.name),),
        origin=str(path),
        origin_sha256=sha,
    )
