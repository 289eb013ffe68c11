"""Replay of a recorded wheel-torque request (CSV) as a protocol at constant load and speed.

The header of the CSV file names the unit of each column, in brackets or as a suffix:
``time [s],torque request [N.m]``, ``t (ms)``, ``time_ms,torque_kNm``. Units are read by the
package's one unit registry (:mod:`rollerrig.units`): time in s or ms (or us, ns), torque in
N.m or kN.m, written any usual way (``Nm``, ``N·m``, ``kNm``, ``KN.M``). Each sample becomes a
breakpoint of the piecewise-linear request, so a solver stops at every sample.
"""

from __future__ import annotations

import csv
import hashlib
import math
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._validation import did_you_mean
from rollerrig.experiment.protocol import (
    _BUILDERS,
    _EVENT_ACTIONS,
    Protocol,
    ProtocolError,
    ProtocolEvent,
)
from rollerrig.experiment.steps import DEFAULT_SETTINGS, SETTINGS, protocol_error
from rollerrig.units import UnitError, apply_factor, si_factor

__all__ = ["protocol_from_csv"]  # replay_protocol: behind Protocol.replay

_SI_UNIT = {"time": "s", "torque": "N.m"}
_EXAMPLE = {"time": "'time [s]' or 'time_ms'", "torque": "'torque request [N.m]' or 'torque_kNm'"}
_BRACKET = re.compile(r"^(?P<base>.*?)\s*[\[(]\s*(?P<unit>[^\])]*?)\s*[\])]\s*$")
_SUFFIX = re.compile(r"^(?P<base>.+?)_(?P<unit>ms|s|kN\.?m|N\.?m)$", re.IGNORECASE)


def _split_header(header: str) -> tuple[str, str | None]:
    """``"time [s]"`` -> ("time", "s"); ``"torque_kNm"`` -> ("torque", "kNm")."""
    h = header.strip()
    m = _BRACKET.match(h) or _SUFFIX.match(h)
    if m:
        return m["base"].strip(), m["unit"]
    return h, None


def _column_factor(path: Path, header: str, kind: str) -> float:
    """Factor of the column's unit to SI (s or N.m), from the registry."""
    unit = _split_header(header)[1]
    where = f"{path.name}: column {header.strip()!r}: "
    if unit is None:
        raise ProtocolError(f"{where}no unit in the header; name it like {_EXAMPLE[kind]}")
    try:
        return si_factor(unit, _SI_UNIT[kind], what=f"{where}{kind} ")
    except UnitError as exc:
        raise ProtocolError(str(exc)) from None


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
            f"{kind}_column= or name it like {_EXAMPLE[kind]}"
        )
    if len(hits) > 1:
        raise ProtocolError(
            f"{path.name}: several {kind} columns {[stripped[i] for i in hits]}; "
            f"choose one with {kind}_column="
        )
    return hits[0]


def _read_rows(path: Path) -> tuple[list[tuple[int, list[str]]], str]:
    """Non-comment, non-blank rows with their line numbers, and the file's SHA-256."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ProtocolError(f"{path}: cannot read the CSV file ({exc})") from exc
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ProtocolError(f"{path.name}: not UTF-8 text ({exc})") from exc
    rows = [
        (lineno, next(csv.reader([line])))
        for lineno, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        raise ProtocolError(f"{path.name}: no header and no data")
    return rows, hashlib.sha256(raw).hexdigest()


def _column_values(path: Path, headers, data, col: int) -> np.ndarray:
    out = np.empty(len(data))
    for k, (lineno, fields) in enumerate(data):
        where = f"line {lineno}, column {headers[col].strip()!r}"
        if col >= len(fields):
            raise protocol_error(path.name, where, "missing value")
        cell = fields[col].strip()
        try:
            x = float(cell)
        except ValueError:
            raise protocol_error(path.name, where, "must be a number", got=cell) from None
        if not math.isfinite(x):
            raise protocol_error(path.name, where, "must be finite", got=cell)
        out[k] = x
    return out


def replay_protocol(
    path: str | os.PathLike,
    settings: Mapping[str, Any],
    columns: Mapping[str, str | None] | None = None,
    *,
    origin: str | None = None,
    where: str = "Protocol.replay",
) -> Protocol:
    """Replay a recorded wheel-torque request from a CSV file, at constant load and speed.

    The one implementation behind :meth:`Protocol.replay
    <rollerrig.experiment.protocol.Protocol.replay>` (the documented way) and a TOML file's
    ``[replay]`` table. The file is read once and never modified. Lines starting with ``#`` are
    comments. The header names the units (module docstring). Time is shifted to start at 0 s.

    Parameters
    ----------
    path : str or path-like
        CSV file.
    settings : mapping
        ``normal_load`` [N] (> 0) and ``roller_speed`` [m/s] (>= 0), optional ``friction``
        (default "dry"), ``name`` (default the file's stem), ``description`` and ``source``
        (put before the file's name and hash) -- the rules of
        :data:`rollerrig.experiment.steps.SETTINGS`.
    columns : mapping, optional
        ``time_column``, ``torque_column``: exact headers; by default the column named
        ``time`` (or ``t``) and the one containing ``torque`` (preferring ``request``).
    origin : str, optional
        Recorded as :attr:`Protocol.origin` (default: the CSV path).
    where : str
        What errors about ``settings`` name (the function the user called, or the TOML file).

    Returns
    -------
    Protocol
        One ``replay`` event; :attr:`Protocol.origin_sha256` is the CSV file's SHA-256.

    Raises
    ------
    ProtocolError
        On a setting out of range, a missing column, a header without a known unit, a
        non-numeric or non-finite cell, time that is duplicated or not increasing, or fewer than
        two samples; the message names the file and the line.
    """
    if not isinstance(path, str | os.PathLike):
        raise ProtocolError(f"{where}: the CSV file must be a path (str or Path), got {path!r}")
    path = Path(path)
    columns = dict(columns or {})
    for key, header in columns.items():
        if header is not None and not isinstance(header, str):
            raise ProtocolError(f"{where}: {key} must be a column header (str), got {header!r}")
    v = {"name": path.stem, **DEFAULT_SETTINGS, **settings}
    v = {key: rule.check(where, key, v[key]) for key, rule in SETTINGS.items()}
    rows, sha = _read_rows(path)
    headers, data = rows[0][1], rows[1:]
    it = _find_column(headers, columns.get("time_column"), "time", path)
    iq = _find_column(headers, columns.get("torque_column"), "torque", path)
    if it == iq:
        raise ProtocolError(f"{path.name}: the time and torque columns are the same column")
    t_factor = _column_factor(path, headers[it], "time")
    q_factor = _column_factor(path, headers[iq], "torque")
    if len(data) < 2:
        raise ProtocolError(f"{path.name}: too few rows: need at least 2 samples, got {len(data)}")
    t = _column_values(path, headers, data, it)
    tq = _column_values(path, headers, data, iq)
    dt = np.diff(t)
    if np.any(dt <= 0.0):
        k = int(np.argmax(dt <= 0.0))
        a, b = data[k][0], data[k + 1][0]
        what = "duplicated time" if dt[k] == 0.0 else "time is not increasing"
        raise protocol_error(
            path.name,
            f"line {b}, column {headers[it].strip()!r}",
            f"{what}: {t[k + 1]:g} after {t[k]:g} on line {a}",
        )
    t0 = t[0]
    time = apply_factor(t - t0, t_factor)
    duration = float(time[-1])
    shift = f" Time shifted by {-t0:g} (file units) to start at 0 s." if t0 != 0.0 else ""
    replayed = f"torque request replayed from {path.name} (sha256 {sha[:12]})"
    q, speed = v["normal_load"], v["roller_speed"]
    return Protocol(
        name=v["name"],
        description=(v["description"] + shift).strip(),
        source="; ".join(text for text in (v["source"], replayed) if text),
        duration=duration,
        torque_time=time,
        torque_request=apply_factor(tq, q_factor),
        speed_time=np.array([0.0, duration]),
        roller_speed=np.array([speed, speed]),
        load_time=np.array([0.0, duration]),
        normal_load=np.array([q, q]),
        friction_time=np.array([0.0]),
        friction_condition=(v["friction"],),
        events=(ProtocolEvent(0.0, duration, "replay", path.name),),
        origin=str(path) if origin is None else origin,
        origin_sha256=sha,
    )


def protocol_from_csv(path, normal_load, roller_speed, friction="dry", **options) -> Protocol:
    """:meth:`Protocol.replay <rollerrig.experiment.protocol.Protocol.replay>` with the load
    [N], speed [m/s] and friction as positional arguments (the older spelling).

    ``options``: ``time_column``, ``torque_column``, ``name``, ``description``.

    Examples
    --------
    >>> from importlib import resources
    >>> f = resources.files("rollerrig.experiment") / "data" / "replay-example.csv"
    >>> with resources.as_file(f) as real:
    ...     p = protocol_from_csv(real, 4300.0, 30 / 3.6)
    >>> p.duration, float(p.torque_request.max()), p.events[0].action
    (10.0, 600.0, 'replay')
    """
    known = ("time_column", "torque_column", "name", "description", "source")
    unknown = [k for k in options if k not in known]
    if unknown:  # replay_protocol reads only the keys it knows: a typo would be dropped
        raise ProtocolError(
            f"protocol_from_csv: unknown option {unknown[0]!r}{did_you_mean(unknown[0], known)}; "
            f"allowed {', '.join(known)}"
        )
    columns = {k: options.pop(k) for k in ("time_column", "torque_column") if k in options}
    settings = {"normal_load": normal_load, "roller_speed": roller_speed, "friction": friction}
    return replay_protocol(path, settings | options, columns)


_BUILDERS["replay"] = replay_protocol  # Protocol's constructor uses it (experiment.protocol)
_EVENT_ACTIONS["replay"] = None  # the one event of a replayed trace (Protocol checks actions)
