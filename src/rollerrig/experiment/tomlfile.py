"""Protocol files: the TOML format, its validation, the bundled protocols, and writing TOML.

A protocol file is a list of steps with the units in the key names (the edge of the package).
Each ``[[step]]`` table becomes the step object of :mod:`rollerrig.experiment.steps` with the
same meaning (``ramp_torque`` -> :class:`~rollerrig.experiment.steps.RampTorque`), validated by
the same rules, and compiled by the same function as a protocol built in Python; errors name the
file and the dotted key, e.g. ``mine.toml: step[1].steps[0].to_Nm: must be a number [N.m];
allowed (-inf, inf); got 'big'``.

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

Actions, their keys (``[req]`` required, ``[opt]`` optional) and step objects:

- ``hold``: ``duration_s`` [req], >= 0 — ``Hold(duration)``.
- ``ramp_torque``: ``to_Nm`` [req], ``duration_s`` [req], > 0 — ``RampTorque(to, duration)``.
- ``step_torque``: ``to_Nm`` [req], ``duration_s`` [opt, 0.02 s], > 0 — ``StepTorque``.
- ``release_torque``: ``duration_s`` [opt, 0.02 s], > 0 — ``ReleaseTorque``.
- ``set_roller_speed``: ``to_kmh`` [req], >= 0, ``duration_s`` [req], > 0 — ``SetRollerSpeed``
  (in m/s).
- ``set_normal_load``: ``to_kN`` [req], > 0, ``duration_s`` [req], > 0 — ``SetNormalLoad`` (in N).
- ``set_friction``: ``condition`` [req] (a name, e.g. ``"wet"``), instantaneous — ``SetFriction``.
- ``repeat``: ``count`` [req], integer >= 1, ``steps`` [req] (nested steps) — ``Repeat``.

Instead of steps, a ``[replay]`` table with ``csv = "file.csv"`` (relative to the TOML file) and
optional ``time_column`` / ``torque_column`` replays a recorded torque request with the
experiment's load, speed and friction (see :mod:`rollerrig.experiment.replay`).
"""

from __future__ import annotations

import hashlib
import math
import os
import tomllib
from importlib import resources
from pathlib import Path

from rollerrig._toml import parse_toml
from rollerrig._validation import did_you_mean, toml_string
from rollerrig.experiment.protocol import _BUILDERS, Protocol, ProtocolError
from rollerrig.experiment.replay import replay_protocol
from rollerrig.experiment.steps import (
    LOAD,
    NAME,
    SETTINGS,
    SPEED,
    STEP_TYPES,
    Hold,
    Quantity,
    RampTorque,
    ReleaseTorque,
    Repeat,
    SetFriction,
    SetNormalLoad,
    SetRollerSpeed,
    Step,
    StepTorque,
    build_protocol,
    protocol_error,
    step_fields,
)
from rollerrig.units import apply_factor, si_factor

__all__ = [
    "bundled_protocols",
    "load_protocol",
    "protocol_from_toml_string",
    "protocol_to_toml",
]

_DURATION = {"duration_s": ("duration", "s")}
STEP_KEYS: dict[type[Step], dict[str, tuple[str, str | None]]] = {
    Hold: _DURATION,
    RampTorque: {"to_Nm": ("to", "N.m"), **_DURATION},
    StepTorque: {"to_Nm": ("to", "N.m"), **_DURATION},
    ReleaseTorque: _DURATION,
    SetRollerSpeed: {"to_kmh": ("to", "km/h"), **_DURATION},
    SetNormalLoad: {"to_kN": ("to", "kN"), **_DURATION},
    SetFriction: {"condition": ("condition", None)},
    Repeat: {"count": ("count", None), "steps": ("steps", None)},
}
"""TOML key -> (field of the step object, unit of the TOML value) for each step class."""

_ACTIONS: dict[str, type[Step]] = {cls.action: cls for cls in STEP_TYPES}

EXPERIMENT_KEYS: dict[str, tuple[str, str | None]] = {
    "name": ("name", None),
    "description": ("description", None),
    "source": ("source", None),
    "normal_load_kN": ("normal_load", "kN"),
    "friction": ("friction", None),
    "roller_speed_kmh": ("roller_speed", "km/h"),
}
"""``[experiment]`` key -> (argument of :meth:`Protocol.from_steps`, unit of the TOML value)."""

_EXPERIMENT_REQUIRED = ("name", "normal_load_kN", "roller_speed_kmh")
_REPLAY_KEYS = {key: (key, None) for key in ("csv", "time_column", "torque_column")}
_TOP_LEVEL = ("experiment", "step", "replay")


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------


def _table(
    origin: str,
    path: str,
    table: dict,
    keys: dict[str, tuple[str, str | None]],
    rules: dict,
    required,
    what: str,
    also: tuple[str, ...] = (),
) -> dict:
    """Check the keys of one TOML table and convert its values to SI with ``rules``
    (``also``: keys the caller has read already)."""
    unknown = [k for k in table if k not in keys]
    if unknown:
        raise _unknown_key(origin, f"{path}.{unknown[0]}", f"for {what}", [*also, *keys])
    missing = [k for k in required if k not in table]
    if missing:
        raise protocol_error(origin, f"{path}.{missing[0]}", f"missing key required for {what}")
    out = {}
    for key, value in table.items():
        field, unit = keys[key]
        rule, dotted = rules[field], f"{path}.{key}"
        if field == "steps":
            value = _steps(origin, dotted, value)
        if isinstance(rule, Quantity):
            factor = si_factor(unit, rule.unit)
            value = rule.check(origin, dotted, value, unit=unit, scale=factor)
            value = apply_factor(value, factor)
        else:
            value = rule.check(origin, dotted, value)
        out[field] = value
    return out


def _unknown_key(origin: str, dotted: str, what: str, known: list[str]) -> ProtocolError:
    hint = did_you_mean(dotted.rpartition(".")[2], known)
    return protocol_error(origin, dotted, f"unknown key {what}{hint}", allowed=known)


def _steps(origin: str, path: str, steps) -> tuple[Step, ...]:
    if not isinstance(steps, list):
        raise protocol_error(origin, path, "must be a list of step tables ([[...]])", got=steps)
    return tuple(_step(origin, f"{path}[{i}]", s) for i, s in enumerate(steps))


def _step(origin: str, path: str, table) -> Step:
    actions = list(_ACTIONS)
    if not isinstance(table, dict):
        raise protocol_error(origin, path, "must be a table with an 'action' key", got=table)
    if "action" not in table:
        raise protocol_error(origin, f"{path}.action", "missing key", allowed=actions)
    action = table["action"]
    cls = _ACTIONS.get(action) if isinstance(action, str) else None
    if cls is None:
        raise protocol_error(
            origin, f"{path}.action", "unknown action", allowed=actions, got=action
        )
    keys = STEP_KEYS[cls]
    by_field = {field: key for key, (field, _) in keys.items()}
    required = [by_field[f] for f, needed in step_fields(cls) if needed]
    body = {k: v for k, v in table.items() if k != "action"}
    what = f"action {action!r}"
    return cls(**_table(origin, path, body, keys, cls.rules, required, what, also=("action",)))


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
        The file it came from: recorded in :attr:`Protocol.origin` and named by the errors.

    Returns
    -------
    Protocol
        The compiled, SI protocol, with its step objects (:meth:`Protocol.to_steps`).

    Raises
    ------
    ProtocolError
        On invalid TOML, unknown or missing keys, or out-of-range values; the message names the
        file and the key path, e.g. ``<string>: step[1].steps[0].to_Nm: ...``.

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
    >>> p.to_steps()
    (RampTorque(to=100.0, duration=1.0),)
    """
    if not isinstance(text, str):
        raise ProtocolError(
            f"{origin}: text must be the TOML text (a str), got {type(text).__name__}; "
            "load_protocol(path) reads a file"
        )
    try:
        doc = parse_toml(text)
    except tomllib.TOMLDecodeError as exc:
        raise ProtocolError(f"{origin}: invalid TOML: {exc}") from exc
    sha = hashlib.sha256(text.encode("utf-8")).hexdigest()

    unknown = [k for k in doc if k not in _TOP_LEVEL]
    if unknown:
        raise _unknown_key(origin, unknown[0], "at the top level", list(_TOP_LEVEL))
    if "experiment" not in doc:
        raise protocol_error(origin, "experiment", "missing [experiment] table")
    exp = doc["experiment"]
    if not isinstance(exp, dict):
        raise protocol_error(origin, "experiment", "must be a table", got=exp)
    settings = _table(
        origin,
        "experiment",
        exp,
        EXPERIMENT_KEYS,
        SETTINGS,
        _EXPERIMENT_REQUIRED,
        "[experiment]",
    )

    if "replay" in doc:
        if "step" in doc:
            raise protocol_error(
                origin, "step", "a protocol with [replay] must not also have steps"
            )
        rep = doc["replay"]
        if not isinstance(rep, dict):
            raise protocol_error(origin, "replay", "must be a table", got=rep)
        rules = dict.fromkeys(_REPLAY_KEYS, NAME)
        cols = _table(origin, "replay", rep, _REPLAY_KEYS, rules, ("csv",), "[replay]")
        csv_path = Path(cols.pop("csv"))
        if not csv_path.is_absolute():
            csv_path = Path(base_dir or ".") / csv_path
        return replay_protocol(csv_path, settings, cols, origin=origin, where=origin)

    if "step" not in doc:
        raise protocol_error(origin, "step", "no steps ([[step]] tables) and no [replay] table")
    steps = _steps(origin, "step", doc["step"])  # checked by build_protocol
    return build_protocol(steps, settings, origin=origin, origin_sha256=sha, where=(origin, "step"))


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
        Compiled; :attr:`Protocol.origin` is the path or ``"bundled:<name>"``.

    Raises
    ------
    ProtocolError
        If the name is unknown, the file is missing or invalid, or it is a CSV trace (which
        needs a load and a speed: :meth:`Protocol.replay`).

    Examples
    --------
    >>> load_protocol("seed-10kmh-wet").friction_at(0.0)
    'wet'
    """
    if not isinstance(path_or_name, str | os.PathLike):
        raise ProtocolError(
            "path_or_name must be a bundled protocol's name or a file path (str or Path), got "
            f"{path_or_name!r}"
        )
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
            f"{path}: a CSV trace needs a normal load and a roller speed; use "
            "Protocol.replay(path, normal_load=..., roller_speed=...) or a TOML file with a "
            "[replay] table"
        )
    if not path.is_file():
        hint = did_you_mean(str(path_or_name), bundled_protocols(), style=";")
        raise ProtocolError(
            f"{path_or_name!s}: neither a bundled protocol ({', '.join(bundled_protocols())}) "
            f"nor an existing TOML file{hint}"
        )
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProtocolError(f"{path}: cannot read the protocol file ({exc})") from exc
    return protocol_from_toml_string(text, base_dir=path.parent, origin=str(path))


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


def _toml_number(si_value: float, unit: str, si_unit: str) -> str:
    """The value in ``unit``, written with the fewest digits that read back exactly."""
    factor = si_factor(unit, si_unit)
    x = si_value / factor
    candidates = (float(f"{x:.15g}"), x, math.nextafter(x, math.inf), math.nextafter(x, -math.inf))
    for candidate in candidates:
        if apply_factor(candidate, factor) == si_value:
            return repr(candidate)
    return repr(x)  # no TOML number reads back exactly: the nearest, within one unit in 1e16


def _toml_value(step: Step, key: str, field: str, unit: str | None) -> str:
    value = getattr(step, field)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, int):
        return str(value)
    return _toml_number(value, unit, step.rules[field].unit)


def _steps_toml(steps, table: str, indent: str) -> list[str]:
    lines = []
    for step in steps:
        keys = STEP_KEYS[type(step)]
        lines += ["", f"{indent}[[{table}]]", f'{indent}action = "{step.action}"']
        lines += [
            f"{indent}{key} = {_toml_value(step, key, field, unit)}"
            for key, (field, unit) in keys.items()
            if field != "steps"
        ]
        if isinstance(step, Repeat):
            lines += _steps_toml(step.steps, f"{table}.steps", indent + "  ")
    return lines


def protocol_to_toml(protocol: Protocol) -> str:
    """The protocol as a TOML file (the format of the bundled files), from its steps.

    ``protocol_from_toml_string(protocol_to_toml(p))`` compiles to the same arrays.

    Raises
    ------
    ProtocolError
        For a protocol without steps (a replayed trace, or one built from arrays).

    Examples
    --------
    >>> p = Protocol.from_steps("ramp", [RampTorque(100.0, 1.0)], normal_load=4300.0,
    ...                         roller_speed=30 / 3.6)
    >>> print(protocol_to_toml(p))
    [experiment]
    name = "ramp"
    normal_load_kN = 4.3
    roller_speed_kmh = 30.0
    friction = "dry"
    <BLANKLINE>
    [[step]]
    action = "ramp_torque"
    to_Nm = 100.0
    duration_s = 1.0
    <BLANKLINE>
    """
    if not isinstance(protocol, Protocol):
        raise ProtocolError(f"protocol must be a Protocol, got {type(protocol).__name__}")
    steps = protocol.to_steps()
    lines = ["[experiment]", f"name = {toml_string(protocol.name)}"]
    for key in ("description", "source"):
        if getattr(protocol, key):
            lines.append(f"{key} = {toml_string(getattr(protocol, key))}")
    lines += [
        f"normal_load_kN = {_toml_number(float(protocol.normal_load[0]), 'kN', LOAD.unit)}",
        f"roller_speed_kmh = {_toml_number(float(protocol.roller_speed[0]), 'km/h', SPEED.unit)}",
        f"friction = {toml_string(protocol.friction_condition[0])}",
    ]
    return "\n".join(lines + _steps_toml(steps, "step", "")) + "\n"


_BUILDERS["toml"] = protocol_to_toml  # Protocol's constructor uses it (experiment.protocol)
