"""The design tables of a study file read and checked: the ``[grid]`` axes, the ``[sample]``
design and its distributions, the ``[[cases]]``; and the largest design a file may ask for.

Every value comes back in SI (a number without a unit is SI, and the reader lists where it
took one so: :attr:`_Reader.assumed`) or as one of its key's names, and
every problem of the file is collected rather than raised, so that all of them are
reported at once (:class:`rollerrig.studies.studyfile.StudyFileError`). A design's size is
checked from the numbers the file gives before any point or axis value is made
(:data:`MAX_STUDY_POINTS`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rollerrig._validation import Problem
from rollerrig.studies.spec import Axis, Case, Distribution, SampleDesign
from rollerrig.studies.varied_keys import _factor, _KeyProblem, key_quantity
from rollerrig.units import QUANTITIES, apply_factor

__all__ = ["MAX_STUDY_POINTS"]

_METHODS = ("sobol", "lhs", "random")
_DISTRIBUTIONS = {
    "uniform": ("low", "high"),
    "loguniform": ("low", "high"),
    "normal": ("mean", "std"),
    "triangular": ("low", "mode", "high"),
    "choice": ("values",),
}
MAX_STUDY_POINTS = 1_000_000
"""Largest design a study file may ask for [points]: a grid's product of axis lengths, a
sample's points (Sobol: ``n (D + 2)`` or ``n (2D + 2)``), the number of cases. It is checked
from the numbers the file gives (``values``, ``num``, ``n``) before any point or axis value is
made, so that a file of three lines cannot exhaust memory. The bundled studies run at most a
few thousand points; a million points is hours of computing on a cluster."""


class _Reader:
    """Collects the problems of one file instead of stopping at the first."""

    def __init__(self, origin: str):
        self.origin = origin
        self.problems: list[Problem] = []
        self.assumed: dict[str, str] = {}
        """Where the file gave a dimensional number without a unit -> the SI unit taken."""

    def assume_si(self, where: str, quantity: str | None, values) -> None:
        """Record that the numbers ``values`` at ``where`` were taken in SI for want of a unit
        (not for a dimensionless quantity, nor for zeros: 0 is 0 in every unit)."""
        if quantity is None or QUANTITIES[quantity].si_unit == "1":
            return
        if any(isinstance(v, int | float) and v != 0 for v in values):
            self.assumed[where] = QUANTITIES[quantity].si_unit

    def problem(self, key: str, message: str, **kw) -> None:
        self.problems.append(Problem(key, message, **kw))

    def number(self, key: str, value, quantity: str | None, unit=None) -> float | None:
        """A finite number in SI (``unit``: the unit it is in)."""
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.problem(key, "must be a number", got=value)
            return None
        try:
            finite = math.isfinite(value)
        except OverflowError:  # an integer beyond the range of a float
            finite = False
        if not finite:
            self.problem(key, "must be finite", got=value)
            return None
        if quantity is None:
            return float(value)
        try:
            factor = _factor(key, quantity, unit)
        except _KeyProblem as exc:
            self.problems.append(exc.problem)
            return None
        return float(apply_factor(float(value), factor))

    def key(self, key: str, prefix: str):
        """``(quantity, choices)`` of a varied key (:func:`key_quantity`), or None after
        recording the problem under ``prefix.key``."""
        try:
            return key_quantity(key)
        except _KeyProblem as exc:
            p = exc.problem
            self.problems.append(Problem(f"{prefix}.{p.key}", p.message, allowed=p.allowed))
            return None

    def factor(self, where: str, quantity: str | None, unit) -> float | None:
        """SI factor of ``unit`` (1 without a unit or a quantity), or None after recording
        the problem under ``where.unit``."""
        if quantity is None or unit is None:
            return 1.0
        try:
            return _factor(where, quantity, unit)
        except _KeyProblem as exc:
            self.problems.append(exc.problem)
            return None

    def quantity(self, key: str, given, quantity: str) -> float | None:
        """A number (SI) or ``{ value, unit }``."""
        if isinstance(given, dict):
            extra = set(given) - {"value", "unit"}
            if extra or "value" not in given:
                self.problem(key, "give a number (SI) or { value = ..., unit = ... }", got=given)
                return None
            if given.get("unit") is None:
                self.assume_si(key, quantity, [given["value"]])
            return self.number(f"{key}.value", given["value"], quantity, given.get("unit"))
        self.assume_si(key, quantity, [given])
        return self.number(key, given, quantity)


def _check_value(reader: _Reader, key: str, where: str, value, quantity, choices) -> Any:
    """One value of a varied key: a name among ``choices`` or a number (already SI)."""
    if choices is not None:
        if value not in choices:
            reader.problem(where, f"not a known {key}", allowed=choices, got=value)
            return None
        return value
    if quantity is None or value is None:
        return value
    # Ranges that no study can mean: the rig and the protocol validate the rest per point,
    # and an out-of-range point is reported with its reason without stopping the study.
    if key in ("load", "speed") and not value > 0:
        reader.problem(where, "must be > 0", unit=QUANTITIES[quantity].si_unit, got=value)
        return None
    if key == "drive.roller_lag" and not value >= 0:
        reader.problem(where, "must be >= 0 (0: no lag)", unit="s", got=value)
        return None
    return value


def _axis_length(spec) -> tuple[str, int] | None:
    """``(key, length)`` of a grid axis from the numbers its spec gives (``values`` or
    ``num``), before any value is made; None when the spec does not say (its own problem)."""
    if isinstance(spec, list):
        return "values", len(spec)
    if not isinstance(spec, dict):
        return None
    if "values" in spec:
        values = spec["values"]
        return ("values", len(values)) if isinstance(values, list) else None
    num = spec.get("num")
    if isinstance(num, int) and not isinstance(num, bool) and num >= 1:
        return "num", num
    return None


def _grid_size_ok(reader: _Reader, grid: dict) -> bool:
    """Whether the grid stays within :data:`MAX_STUDY_POINTS` (each axis and the product of
    their lengths), from the numbers alone; records the problem otherwise."""
    ok = True
    total = 1
    for key, spec in grid.items():
        length = _axis_length(spec)
        if length is None:
            continue
        what, n = length
        if n > MAX_STUDY_POINTS:
            reader.problem(
                f"grid.{key}.{what}",
                "too many values for one axis",
                allowed=f"at most {MAX_STUDY_POINTS} points in a study",
                got=n,
            )
            ok = False
        total = min(total * n, MAX_STUDY_POINTS + 1)  # capped: never a huge integer
    if ok and total > MAX_STUDY_POINTS:
        lengths = {k: v[1] for k, v in ((k, _axis_length(g)) for k, g in grid.items()) if v}
        reader.problem(
            "grid",
            "too many points: the product of the axis lengths "
            f"({' x '.join(str(n) for n in lengths.values())})",
            allowed=f"at most {MAX_STUDY_POINTS} points in a study",
            got=math.prod(lengths.values()),
        )
        ok = False
    return ok


def _axis(reader: _Reader, key: str, spec) -> Axis | None:
    where = f"grid.{key}"
    kind = reader.key(key, "grid")
    if kind is None:
        return None
    quantity, choices = kind
    if isinstance(spec, list):
        spec = {"values": spec}
    if not isinstance(spec, dict):
        reader.problem(
            where, "give { values = [...], unit = ... } or { start, stop, num, unit }", got=spec
        )
        return None
    known = {"values", "start", "stop", "num", "scale", "unit", "label"}
    for extra in sorted(set(spec) - known):
        reader.problem(f"{where}.{extra}", "unknown key", allowed=sorted(known))
    unit = spec.get("unit")
    label = spec.get("label", "")
    if not isinstance(label, str):
        reader.problem(f"{where}.label", "must be text", got=label)
        label = ""
    factor = reader.factor(where, quantity, unit)
    if factor is None:
        return None
    if choices is not None and unit is not None:
        reader.problem(f"{where}.unit", "a name takes no unit", got=unit)
    if "values" in spec:
        for k in ("start", "stop", "num", "scale"):
            if k in spec:
                reader.problem(f"{where}.{k}", "give either values or start/stop/num, not both")
        raw = spec["values"]
        if not isinstance(raw, list) or not raw:
            reader.problem(f"{where}.values", "must be a non-empty list", got=raw)
            return None
        scale = "list"
    else:
        missing = [k for k in ("start", "stop", "num") if k not in spec]
        if missing:
            reader.problem(where, f"missing {', '.join(missing)} (or give values = [...])")
            return None
        if choices is not None:
            reader.problem(where, "a name axis takes values = [...], not start/stop/num")
            return None
        scale = spec.get("scale", "linear")
        num = spec["num"]
        if scale not in ("linear", "log"):
            reader.problem(f"{where}.scale", "not a scale", allowed=["linear", "log"], got=scale)
            return None
        if isinstance(num, bool) or not isinstance(num, int) or num < 1:
            reader.problem(f"{where}.num", "must be an integer >= 1", got=num)
            return None
        start = reader.number(f"{where}.start", spec["start"], None)
        stop = reader.number(f"{where}.stop", spec["stop"], None)
        if start is None or stop is None:
            return None
        if scale == "log":
            if not (start > 0 and stop > 0):
                reader.problem(where, "a log axis needs start and stop > 0", got=(start, stop))
                return None
            raw = np.geomspace(start, stop, num).tolist()
        else:
            raw = np.linspace(start, stop, num).tolist()
    values = []
    for i, v in enumerate(raw):
        if choices is None:
            v = reader.number(f"{where}.values[{i}]", v, quantity, unit)
        values.append(_check_value(reader, key, f"{where}.values[{i}]", v, quantity, choices))
    if any(v is None for v in values):
        return None
    if len(set(values)) != len(values):
        reader.problem(f"{where}.values", "repeats a value", got=raw)
        return None
    if unit is None and choices is None:
        reader.assume_si(where, quantity, values)
    return Axis(key, tuple(values), unit or "", factor, scale, label)


def _distribution(reader: _Reader, key: str, spec) -> Distribution | None:
    where = f"sample.parameters.{key}"
    kind = reader.key(key, "sample.parameters")
    if kind is None:
        return None
    quantity, choices = kind
    if not isinstance(spec, dict) or "distribution" not in spec:
        reader.problem(where, "give { distribution = ..., its parameters, unit = ... }", got=spec)
        return None
    kind = spec["distribution"]
    if not isinstance(kind, str) or kind not in _DISTRIBUTIONS:
        reader.problem(
            f"{where}.distribution", "unknown distribution", allowed=list(_DISTRIBUTIONS), got=kind
        )
        return None
    if (kind == "choice") != (choices is not None):
        need = "choice" if choices is not None else "a numeric distribution"
        reader.problem(f"{where}.distribution", f"{key} needs {need}", got=kind)
        return None
    names = _DISTRIBUTIONS[kind]
    known = {"distribution", "unit", "label", *names}
    for extra in sorted(set(spec) - known):
        reader.problem(f"{where}.{extra}", "unknown key", allowed=sorted(known))
    missing = [n for n in names if n not in spec]
    if missing:
        reader.problem(where, f"{kind} needs {', '.join(names)}; missing {', '.join(missing)}")
        return None
    unit = spec.get("unit")
    factor = reader.factor(where, quantity, unit)
    if factor is None:
        return None
    params: dict[str, Any] = {}
    if kind == "choice":
        vals = spec["values"]
        if not isinstance(vals, list) or not vals:
            reader.problem(f"{where}.values", "must be a non-empty list", got=vals)
            return None
        for i, v in enumerate(vals):
            if _check_value(reader, key, f"{where}.values[{i}]", v, None, choices) is None:
                return None
        params["values"] = list(vals)
    else:
        for n in names:
            v = reader.number(f"{where}.{n}", spec[n], quantity, unit)
            if v is None:
                return None
            params[n] = v
        ok = {
            "uniform": lambda p: p["low"] < p["high"],
            "loguniform": lambda p: 0 < p["low"] < p["high"],
            "normal": lambda p: p["std"] > 0,
            "triangular": lambda p: p["low"] <= p["mode"] <= p["high"] and p["low"] < p["high"],
        }[kind]
        if not ok(params):
            rule = {
                "uniform": "low < high",
                "loguniform": "0 < low < high",
                "normal": "std > 0",
                "triangular": "low <= mode <= high, low < high",
            }[kind]
            reader.problem(where, f"{kind} needs {rule}", got=spec)
            return None
        if unit is None:
            reader.assume_si(where, quantity, params.values())
    label = spec.get("label", "")
    return Distribution(
        key, kind, params, unit or "", factor, label if isinstance(label, str) else ""
    )


def _sample(reader: _Reader, spec) -> SampleDesign | None:
    if not isinstance(spec, dict):
        reader.problem("sample", "must be a table", got=spec)
        return None
    known = {"method", "n", "seed", "second_order", "parameters"}
    for extra in sorted(set(spec) - known):
        reader.problem(f"sample.{extra}", "unknown key", allowed=sorted(known))
    method = spec.get("method", "sobol")
    if method not in _METHODS:
        reader.problem("sample.method", "unknown method", allowed=list(_METHODS), got=method)
        return None
    n = spec.get("n")
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        reader.problem("sample.n", "must be an integer >= 1 (the base sample size)", got=n)
        return None
    params = spec.get("parameters")
    d = len(params) if isinstance(params, dict) else 1
    factor = {"sobol": (2 * d + 2 if spec.get("second_order") is True else d + 2)}.get(method, 1)
    if n > MAX_STUDY_POINTS or n * factor > MAX_STUDY_POINTS:
        what = f"{n} x {factor} = {n * factor} points" if factor > 1 else f"{n} points"
        rule = " (Sobol' runs n (D + 2) points, n (2D + 2) with second_order)" if factor > 1 else ""
        reader.problem(
            "sample.n",
            f"too many points ({what})",
            allowed=f"at most {MAX_STUDY_POINTS} points in a study{rule}",
            got=n,
        )
        return None
    if method == "sobol" and n & (n - 1):
        reader.problem("sample.n", "Sobol' sequences need a power of 2", got=n)
        return None
    seed = spec.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        reader.problem("sample.seed", "must be an integer >= 0", got=seed)
        return None
    second = spec.get("second_order", False)
    if not isinstance(second, bool):
        reader.problem("sample.second_order", "must be true or false", got=second)
        return None
    if not isinstance(params, dict) or not params:
        reader.problem("sample.parameters", "give at least one parameter with its distribution")
        return None
    dists = [_distribution(reader, k, v) for k, v in params.items()]
    if any(d is None for d in dists):
        return None
    if method == "sobol" and len(dists) < 2:
        reader.problem(
            "sample.parameters", "Sobol indices need at least 2 parameters", got=len(dists)
        )
        return None
    return SampleDesign(method, n, seed, second, tuple(dists))


def _cases(reader: _Reader, spec) -> tuple[Case, ...] | None:
    if not isinstance(spec, list) or not spec:
        reader.problem("cases", "give one or more [[cases]] tables")
        return None
    if len(spec) > MAX_STUDY_POINTS:
        reader.problem(
            "cases",
            "too many cases",
            allowed=f"at most {MAX_STUDY_POINTS} points in a study",
            got=len(spec),
        )
        return None
    out, labels = [], set()
    for i, case in enumerate(spec):
        where = f"cases[{i}]"
        if not isinstance(case, dict):
            reader.problem(where, "must be a table", got=case)
            continue
        label = case.get("label")
        if not isinstance(label, str) or not label.strip():
            reader.problem(f"{where}.label", "every case needs a label (text)", got=label)
            continue
        if label in labels:
            reader.problem(f"{where}.label", "repeats another case's label", got=label)
        labels.add(label)
        settings = {}
        for key, given in case.items():
            if key == "label":
                continue
            kind = reader.key(key, where)
            if kind is None:
                continue
            quantity, choices = kind
            value = (
                given if choices is not None else reader.quantity(f"{where}.{key}", given, quantity)
            )
            settings[key] = _check_value(reader, key, f"{where}.{key}", value, quantity, choices)
        out.append(Case(label, settings))
    return tuple(out)
