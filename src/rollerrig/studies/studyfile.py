"""The study file: which experiment, on which rig, varying what, measuring what.

A study is a TOML file (or a bundled name: :func:`bundled_studies`) in one of three designs:

``[grid]``
    A full-factorial grid: one axis per varied quantity, with ``values = [...]`` or
    ``start``/``stop``/``num`` (``scale = "linear"`` or ``"log"``), and a ``unit``.
``[sample]``
    A sampled design: ``method = "sobol"`` (Saltelli's scheme for Sobol indices, via SALib),
    ``"lhs"`` (Latin hypercube) or ``"random"``, ``n`` (the base sample size; Sobol runs
    ``n (D + 2)`` points, ``n (2D + 2)`` with ``second_order = true``), ``seed``, and a
    distribution per parameter in ``[sample.parameters]``.
``[[cases]]``
    Named cases, each a ``label`` and the values it sets (the drives study).

A varied quantity is named by

- its dotted rig key, e.g. ``"stiffness.roller_shaft"``, ``"induction_motor.response_lag_clp"``
  (:mod:`rollerrig.rig.sections`), in a unit that quantity accepts;
- a protocol quantity: ``"load"`` (the normal load [N]), ``"speed"`` (the roller speed [m/s]),
  ``"friction"`` (the friction condition, ``"dry"`` or ``"wet"``). A load or speed value
  scales the experiment's schedule so that its largest value is the one given (a constant
  schedule simply becomes that value); a friction value replaces every condition;
- a model choice: ``"drive.roller"`` (``"induction"``, ``"induction_linear"``, ``"servo"``,
  ``"ideal_speed"``), ``"drive.wheel"`` (``"pmsm"``, ``"ideal_torque"``),
  ``"drive.roller_lag"`` (the roller drive's response lag τ [s]; 0: none), ``"frame"``
  (``"rigid"`` or ``"flexible"``: the frame's degree of freedom at the contact, with the rig's
  ``frame.*`` keys), ``"contact.law"`` (the creep law of the contact force: ``"polach"``,
  ``"fastsim"``, ``"modified-fastsim"``, ``"fastrip"``; :class:`rollerrig.rig.model.
  DriveConfig`).

``name`` names the study and the files its run writes (``study-NAME.zarr``, ...): 1 to 64
letters, digits, ``.``, ``_``, ``+`` and ``-``, not starting with a dot; default: the file's
stem (made safe). A study has at most :data:`MAX_STUDY_POINTS` points, checked from the file's
numbers before any point is made.

A number without a unit is SI. ``[outputs] metrics`` chooses the metrics of each run by name
(:data:`rollerrig.studies.metrics.METRICS`); ``[solver]`` sets the output rate and the largest
step. The minimal study::

    experiment = "seed-30kmh-dry"
    [grid]
    "stiffness.roller_shaft" = { values = [43.5e3, 83.5e3, 143.5e3], unit = "N.m/rad" }
    "induction_motor.response_lag_clp" = { values = [2.75, 10000.0], unit = "1/s" }
    [outputs]
    metrics = ["release_overshoot"]
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._toml import parse_toml
from rollerrig._validation import ParameterError, Problem, did_you_mean
from rollerrig.output.names import safe_file_name
from rollerrig.units import QUANTITIES, UnitError, apply_factor, quantity_factor

__all__ = [
    "MAX_NAME_LENGTH",
    "MAX_STUDY_POINTS",
    "MODEL_KEYS",
    "PROTOCOL_KEYS",
    "Axis",
    "Case",
    "Distribution",
    "SampleDesign",
    "StudyFileError",
    "StudySpec",
    "bundled_studies",
    "load_study",
    "study_from_dict",
    "study_from_toml_string",
    "study_name_from_stem",
]

PROTOCOL_KEYS = {"load": "force", "speed": "speed", "friction": None}
"""Protocol quantities a study may vary -> their quantity (None: a name)."""
MODEL_KEYS = {
    "drive.roller": None,
    "drive.wheel": None,
    "drive.roller_lag": "time",
    "frame": None,
    "contact.law": None,
}
"""Model choices a study may vary (the drives, the frame, the creep law) -> their quantity
(None: a name)."""
_DESIGNS = ("grid", "sample", "cases")
_METHODS = ("sobol", "lhs", "random")
_DISTRIBUTIONS = {
    "uniform": ("low", "high"),
    "loguniform": ("low", "high"),
    "normal": ("mean", "std"),
    "triangular": ("low", "mode", "high"),
    "choice": ("values",),
}
_TOP_KEYS = {
    "name",
    "description",
    "experiment",
    "rig",
    "grid",
    "sample",
    "cases",
    "outputs",
    "solver",
}
MAX_STUDY_POINTS = 1_000_000
"""Largest design a study file may ask for [points]: a grid's product of axis lengths, a
sample's points (Sobol: ``n (D + 2)`` or ``n (2D + 2)``), the number of cases. It is checked
from the numbers the file gives (``values``, ``num``, ``n``) before any point or axis value is
made, so that a file of three lines cannot exhaust memory. The bundled studies run at most a
few thousand points; a million points is hours of computing on a cluster."""
MAX_NAME_LENGTH = 64
"""Longest study name [characters]."""
_NAME = re.compile(f"[A-Za-z0-9_+-][A-Za-z0-9._+-]{{0,{MAX_NAME_LENGTH - 1}}}")
_NAME_RULE = (
    f"1-{MAX_NAME_LENGTH} characters of letters, digits, '.', '_', '+' and '-', not starting "
    "with '.' (it names the files a run writes: study-NAME.zarr, study-NAME.json)"
)
DEFAULT_EXPERIMENT = "release-test"
"""The experiment of a study that names none: one ramp, hold and sudden release at 30 km/h."""


class StudyFileError(ParameterError):
    """A study file is malformed: one line per problem, each naming the file and the key."""

    def __init__(self, origin: str, problems: list[Problem]):
        self.origin = origin
        self.problems = tuple(p.format(origin) for p in problems)
        super().__init__("\n".join(self.problems))


# --------------------------------------------------------------------------------------------
# What a key is
# --------------------------------------------------------------------------------------------


def key_quantity(key: str) -> tuple[str | None, list[str] | None]:
    """``(quantity, choices)`` of a varied key; raises :class:`Problem` as ``ValueError``.

    Returns the quantity name (a key of :data:`rollerrig.units.QUANTITIES`) of a numeric key, or
    None and the allowed names of a categorical one.
    """
    from rollerrig.contact.creep import POLACH_PARAMETER_SETS
    from rollerrig.rig.model import FRAME_MODES, LAW_CODES, ROLLER_MODES, WHEEL_MODES
    from rollerrig.rig.sections import SECTIONS, quantity_of

    if key in PROTOCOL_KEYS:
        q = PROTOCOL_KEYS[key]
        return (q, None) if q else (None, sorted(POLACH_PARAMETER_SETS))
    if key in MODEL_KEYS:
        q = MODEL_KEYS[key]
        if q:
            return q, None
        modes = {
            "drive.roller": ROLLER_MODES,
            "drive.wheel": WHEEL_MODES,
            "frame": FRAME_MODES,
            "contact.law": LAW_CODES,
        }
        return None, sorted(modes[key])
    section, _, name = key.partition(".")
    allowed = [*PROTOCOL_KEYS, *MODEL_KEYS, "<section>.<key> of the rig file"]
    if section not in SECTIONS or section == "meta":
        raise _KeyProblem(Problem(key, "not a quantity a study can vary", allowed=allowed))
    fields = SECTIONS[section].model_fields
    if name not in fields:
        raise _KeyProblem(
            Problem(key, f"unknown key in the rig's [{section}]", allowed=list(fields))
        )
    return quantity_of(fields[name]), None


class _KeyProblem(ValueError):
    def __init__(self, problem: Problem):
        super().__init__(problem.message)
        self.problem = problem


def _factor(key: str, quantity: str, unit: Any) -> float:
    """SI factor of ``unit`` for ``quantity``; raises _KeyProblem naming ``key.unit``."""
    if unit is None:
        return 1.0
    try:
        return quantity_factor(unit, quantity)
    except UnitError as exc:
        p = exc.problem
        raise _KeyProblem(Problem(f"{key}.unit", p.message, p.unit, p.allowed, p.got)) from None


def si_unit(key: str) -> str:
    """The SI unit of a varied key's values (``""`` for a categorical key).

    Examples
    --------
    >>> si_unit("stiffness.roller_shaft"), si_unit("load"), si_unit("friction")
    ('N.m/rad', 'N', '')
    """
    quantity, _ = key_quantity(key)
    return QUANTITIES[quantity].si_unit if quantity else ""


# --------------------------------------------------------------------------------------------
# The parts of a study
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Axis:
    """One axis of a grid: a key and its values (SI, or names for a categorical key).

    ``unit`` is the unit the file gave (labels show values in it, ``factor`` converts it to SI);
    ``scale`` is ``"list"``, ``"linear"`` or ``"log"``; ``label`` names the axis in tables and
    figures (default: the key).
    """

    key: str
    values: tuple
    unit: str = ""
    factor: float = 1.0
    scale: str = "list"
    label: str = ""

    @property
    def categorical(self) -> bool:
        """True for an axis of names (friction, drive)."""
        return bool(self.values) and isinstance(self.values[0], str)

    def show(self, value) -> str:
        """``value`` (SI) as the file gave it: ``"k56 = 43.5 kN.m/rad"``."""
        name = self.label or self.key
        if isinstance(value, str):
            return f"{name} = {value}"
        shown = value / self.factor
        return f"{name} = {shown:.6g}" + (f" {self.unit}" if self.unit else "")


@dataclass(frozen=True)
class Distribution:
    """The distribution of one sampled parameter; numbers in SI (``values`` for ``choice``).

    :meth:`ppf` maps a uniform number in [0, 1) to the parameter (the inverse CDF), so one
    unit-cube design serves every distribution.
    """

    key: str
    kind: str
    params: Mapping[str, Any]
    unit: str = ""
    factor: float = 1.0
    label: str = ""

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Inverse CDF at ``u`` in [0, 1]: the parameter's values (SI, or names)."""
        from scipy import stats

        u = np.clip(np.asarray(u, dtype=float), 0.0, np.nextafter(1.0, 0.0))
        p = self.params
        if self.kind == "uniform":
            return p["low"] + u * (p["high"] - p["low"])
        if self.kind == "loguniform":
            return np.exp(np.log(p["low"]) + u * (np.log(p["high"]) - np.log(p["low"])))
        if self.kind == "normal":
            return stats.norm.ppf(u, loc=p["mean"], scale=p["std"])
        if self.kind == "triangular":
            width = p["high"] - p["low"]
            return stats.triang.ppf(u, (p["mode"] - p["low"]) / width, loc=p["low"], scale=width)
        values = np.asarray(p["values"], dtype=object)
        return values[np.minimum((u * len(values)).astype(int), len(values) - 1)]

    def to_dict(self) -> dict:
        """The distribution for the store's attributes (SI)."""
        return {"distribution": self.kind, **{k: _plain(v) for k, v in self.params.items()}}


@dataclass(frozen=True)
class SampleDesign:
    """A sampled design: method, base size ``n``, seed, second-order Sobol indices or not."""

    method: str
    n: int
    seed: int
    second_order: bool
    parameters: tuple[Distribution, ...]

    @property
    def size(self) -> int:
        """Number of points the design runs."""
        d = len(self.parameters)
        if self.method == "sobol":
            return self.n * (2 * d + 2 if self.second_order else d + 2)
        return self.n


@dataclass(frozen=True)
class Case:
    """A named case: its label and the values it sets (SI, or names)."""

    label: str
    settings: Mapping[str, Any]


@dataclass(frozen=True)
class StudySpec:
    """A validated study (see the module docstring for the file).

    Attributes
    ----------
    name, description : str
    experiment : str
        Bundled experiment name or the path of its file.
    rig : str or None
        Path of the rig file (relative paths resolved against the study file); None: the
        default rig.
    design : {"grid", "sample", "cases"}
    axes : tuple of Axis
        Grid axes (design "grid").
    sample : SampleDesign or None
    cases : tuple of Case
    metrics : tuple of str
    output_rate : float
        Sampling of each run's results [Hz].
    h_max : float or None
        Largest solver step [s]; None: the studies' default
        (:data:`rollerrig.solve.fast.SWEEP_H_MAX`).
    origin : str
        The file (``bundled:<name>`` for a bundled study).
    sha256 : str
        Of the file's text: a store remembers it, so a resumed study is the same study.
    """

    name: str
    description: str
    experiment: str
    rig: str | None
    design: str
    axes: tuple[Axis, ...] = ()
    sample: SampleDesign | None = None
    cases: tuple[Case, ...] = ()
    metrics: tuple[str, ...] = ("release_overshoot",)
    output_rate: float = 1000.0
    h_max: float | None = None
    origin: str = "<string>"
    sha256: str = ""
    text: str = field(default="", repr=False)

    @property
    def keys(self) -> tuple[str, ...]:
        """The varied keys, in design order."""
        if self.design == "grid":
            return tuple(a.key for a in self.axes)
        if self.design == "sample":
            return tuple(d.key for d in self.sample.parameters)
        keys: list[str] = []
        for case in self.cases:
            keys += [k for k in case.settings if k not in keys]
        return tuple(keys)

    @property
    def size(self) -> int:
        """Number of points."""
        if self.design == "grid":
            return math.prod(len(a.values) for a in self.axes)
        if self.design == "sample":
            return self.sample.size
        return len(self.cases)


def _plain(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------


class _Reader:
    """Collects the problems of one file instead of stopping at the first."""

    def __init__(self, origin: str):
        self.origin = origin
        self.problems: list[Problem] = []

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
            return self.number(f"{key}.value", given["value"], quantity, given.get("unit"))
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


def _study_name(reader: _Reader, name, *, given: bool) -> str:
    """The study's name, checked (it names files: see :data:`MAX_NAME_LENGTH`)."""
    if isinstance(name, str) and _NAME.fullmatch(name):
        return name
    where = "" if given else " (the name of the study file, or the name given)"
    reader.problem("name", f"not a study name{where}", allowed=_NAME_RULE, got=name)
    return "study"


def study_name_from_stem(stem: str) -> str:
    """A study name made from a file's stem: :func:`~rollerrig.output.names.safe_file_name`,
    cut to :data:`MAX_NAME_LENGTH` characters (a study file names its study unless it has a
    ``name`` key).

    Examples
    --------
    >>> study_name_from_stem("my study (v2)"), study_name_from_stem(".hidden")
    ('my_study__v2_', 'hidden')
    >>> study_name_from_stem("."), len(study_name_from_stem("x" * 300))
    ('_', 64)
    """
    name = safe_file_name(stem)[:MAX_NAME_LENGTH]
    return name if _NAME.fullmatch(name) else "study"


def study_from_toml_string(
    text: str, *, origin: str = "<string>", base_dir: Path | None = None, name: str = "study"
) -> StudySpec:
    """Read and validate a study from TOML text.

    Parameters
    ----------
    text : str
        The file's text.
    origin : str
        Where it came from (errors name it).
    base_dir : Path, optional
        Relative ``experiment`` and ``rig`` paths are resolved against it.
    name : str
        The study's name when the file gives none (for a file: its stem made safe,
        :func:`study_name_from_stem`). A name, given either way, is 1 to
        :data:`MAX_NAME_LENGTH` letters, digits, ``.``, ``_``, ``+`` and ``-``, not starting
        with a dot: it names the files of the study's run.

    Returns
    -------
    StudySpec

    Raises
    ------
    StudyFileError
        Every problem of the file, one line each, naming the key.

    Examples
    --------
    >>> spec = study_from_toml_string('''
    ... [grid]
    ... "stiffness.roller_shaft" = { values = [43.5, 143.5], unit = "kN.m/rad" }
    ... "drive.roller_lag" = { values = [0, 0.36], unit = "s" }
    ... ''')
    >>> spec.design, spec.size, spec.axes[0].values, spec.experiment
    ('grid', 4, (43500.0, 143500.0), 'release-test')
    """
    try:
        data = parse_toml(text)
    except tomllib.TOMLDecodeError as exc:
        raise StudyFileError(origin, [Problem("", f"not valid TOML ({exc})")]) from None
    return study_from_dict(data, origin=origin, base_dir=base_dir, name=name, text=text)


def study_from_dict(
    data: Mapping[str, Any],
    *,
    origin: str = "<dict>",
    base_dir: Path | None = None,
    name: str = "study",
    text: str | None = None,
) -> StudySpec:
    """Validate a study given as the dict its TOML file reads as.

    ``text`` is the file's text (kept in the store, and hashed so that a resumed study is the
    same one); default: the dict as JSON. Other parameters and errors as
    :func:`study_from_toml_string`.
    """
    from rollerrig.studies.metrics import METRICS

    if text is None:
        text = json.dumps(data, sort_keys=True, default=str)
    reader = _Reader(origin)
    if not isinstance(data, Mapping):
        raise StudyFileError(origin, [Problem("", "a study is a table of keys", got=data)])
    for extra in sorted(set(data) - _TOP_KEYS):
        reader.problem(extra, "unknown key", allowed=sorted(_TOP_KEYS))
    designs = [d for d in _DESIGNS if d in data]
    if len(designs) != 1:
        reader.problem(
            "",
            "give exactly one design: [grid], [sample] or [[cases]]",
            got=designs or "none",
        )
        raise StudyFileError(origin, reader.problems)
    design = designs[0]
    axes: tuple[Axis, ...] = ()
    sample = None
    cases: tuple[Case, ...] = ()
    if design == "grid":
        grid = data["grid"]
        if not isinstance(grid, dict) or not grid:
            reader.problem("grid", "give at least one axis")
        elif _grid_size_ok(reader, grid):
            parsed = [_axis(reader, k, v) for k, v in grid.items()]
            axes = tuple(a for a in parsed if a is not None)
    elif design == "sample":
        sample = _sample(reader, data["sample"])
    else:
        cases = _cases(reader, data["cases"]) or ()

    def text_of(key: str, default):
        value = data.get(key, default)
        if value is not None and not isinstance(value, str):
            reader.problem(key, "must be text", got=value)
            return default
        return value

    study_name = _study_name(reader, data.get("name", name), given="name" in data)
    description = text_of("description", "")
    experiment = text_of("experiment", DEFAULT_EXPERIMENT)
    rig = text_of("rig", None)
    if base_dir is not None:
        from rollerrig.experiment.tomlfile import bundled_protocols

        if experiment not in bundled_protocols() and not Path(experiment).is_absolute():
            experiment = str(base_dir / experiment)
        if rig is not None and not Path(rig).is_absolute():
            rig = str(base_dir / rig)

    metrics: tuple[str, ...] = ("release_overshoot",)
    outputs = data.get("outputs", {})
    if not isinstance(outputs, dict):
        reader.problem("outputs", "must be a table", got=outputs)
    else:
        for extra in sorted(set(outputs) - {"metrics"}):
            reader.problem(f"outputs.{extra}", "unknown key", allowed=["metrics"])
        chosen = outputs.get("metrics", list(metrics))
        if chosen == "all":
            chosen = list(METRICS)
        if not isinstance(chosen, list) or not chosen:
            reader.problem("outputs.metrics", 'give a list of metric names (or "all")', got=chosen)
        else:
            for m in chosen:
                if not isinstance(m, str) or m not in METRICS:
                    reader.problem(
                        "outputs.metrics", "unknown metric", allowed=list(METRICS), got=m
                    )
            metrics = tuple(dict.fromkeys(m for m in chosen if isinstance(m, str) and m in METRICS))

    output_rate, h_max = 1000.0, None
    solver = data.get("solver", {})
    if not isinstance(solver, dict):
        reader.problem("solver", "must be a table", got=solver)
    else:
        for extra in sorted(set(solver) - {"output_rate", "h_max"}):
            reader.problem(f"solver.{extra}", "unknown key", allowed=["output_rate", "h_max"])
        if "output_rate" in solver:
            rate = reader.quantity("solver.output_rate", solver["output_rate"], "frequency")
            if rate is not None and not 10.0 <= rate <= 1e5:
                reader.problem(
                    "solver.output_rate",
                    "out of range",
                    unit="Hz",
                    allowed="[10, 100000]",
                    got=rate,
                )
            output_rate = rate or output_rate
        if "h_max" in solver:
            h_max = reader.quantity("solver.h_max", solver["h_max"], "time")
            if h_max is not None and not 1e-6 <= h_max <= 0.01:
                reader.problem(
                    "solver.h_max", "out of range", unit="s", allowed="[1e-6, 0.01]", got=h_max
                )
    if reader.problems:
        raise StudyFileError(origin, reader.problems)
    return StudySpec(
        name=study_name,
        description=description,
        experiment=experiment,
        rig=rig,
        design=design,
        axes=axes,
        sample=sample,
        cases=cases,
        metrics=metrics,
        output_rate=output_rate,
        h_max=h_max,
        origin=origin,
        sha256=hashlib.sha256(text.encode("utf-8")).hexdigest(),
        text=text,
    )


def _data_dir():
    return resources.files("rollerrig.studies").joinpath("data")


def bundled_studies() -> tuple[str, ...]:
    """Names of the studies bundled with rollerrig (``studies/data/*.toml``).

    Examples
    --------
    >>> {"stiffness", "lag", "drives"} <= set(bundled_studies())
    True
    """
    return tuple(
        sorted(f.name[: -len(".toml")] for f in _data_dir().iterdir() if f.name.endswith(".toml"))
    )


def load_study(path_or_name: str | os.PathLike) -> StudySpec:
    """Load a study by bundled name (e.g. ``"stiffness"``) or from a TOML file.

    Raises
    ------
    StudyFileError
        Unknown name, unreadable file, or a file with problems (each named).

    Examples
    --------
    >>> load_study("stiffness").axes[0].key
    'stiffness.roller_shaft'
    """
    if isinstance(path_or_name, str) and path_or_name in bundled_studies():
        text = _data_dir().joinpath(f"{path_or_name}.toml").read_text(encoding="utf-8")
        return study_from_toml_string(text, origin=f"bundled:{path_or_name}", name=path_or_name)
    path = Path(path_or_name)
    if not path.is_file():
        raise StudyFileError(
            str(path_or_name),
            [
                Problem(
                    "",
                    f"neither a bundled study ({', '.join(bundled_studies())}) nor an "
                    "existing TOML file"
                    + did_you_mean(str(path_or_name), bundled_studies(), style=";"),
                )
            ],
        )
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise StudyFileError(str(path), [Problem("", f"cannot read the file ({exc})")]) from None
    return study_from_toml_string(
        text,
        origin=str(path),
        base_dir=path.parent.resolve(),
        name=study_name_from_stem(path.stem),
    )
