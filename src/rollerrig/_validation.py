"""Validation at the boundary: clear errors that name the parameter, its unit and allowed range.

Physics kernels never validate (they must stay cheap and compilable); the public functions that
wrap them call these helpers first.
"""

from __future__ import annotations

import difflib
import json
import math
import types
import typing
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "FieldProblem",
    "ParameterError",
    "Problem",
    "Verbatim",
    "close_matches",
    "did_you_mean",
    "field_error",
    "from_pydantic",
    "interval",
    "numbers_apart",
    "pydantic_problems",
    "require_broadcastable",
    "require_finite",
    "require_flag",
    "require_in_range",
    "require_increasing",
    "require_instants_within",
    "require_names",
    "require_nonnegative",
    "require_number",
    "require_positive",
    "require_whole",
    "toml_string",
]


class ParameterError(ValueError):
    """A parameter is non-physical: its message names the parameter and the allowed range.

    ``problems`` holds one line per problem when the error reports several (a user file).
    """

    problems: tuple[str, ...] = ()


def close_matches(name: str, known, *, n: int = 3, cutoff: float = 0.6) -> list[str]:
    """The names in ``known`` closest to a misspelt ``name`` (at most ``n``, best first).

    The one did-you-mean look-up of the package (:func:`difflib.get_close_matches`); a match
    that differs only in case or in ``-``/``_`` comes first.

    Parameters
    ----------
    name : str
        What the user typed.
    known : iterable of str
        The names that exist.
    n : int, optional
        How many matches at most.
    cutoff : float, optional
        Similarity in [0, 1] below which a name is no match.

    Returns
    -------
    list of str
        The matches, best first; empty when none is close.

    Examples
    --------
    >>> close_matches("seed-10kmh-wte", ["seed-10kmh-wet", "seed-30kmh-dry", "release-test"])
    ['seed-10kmh-wet', 'seed-30kmh-dry']
    """
    known = [str(k) for k in known]

    def plain(s: str) -> str:
        return s.casefold().replace("-", "_")

    same = [k for k in known if plain(k) == plain(str(name))]
    rest = difflib.get_close_matches(str(name), known, n=n, cutoff=cutoff)
    return list(dict.fromkeys([*same, *rest]))[:n]


def folder_not_file(path, what: str, give: str) -> str | None:
    """The one-line error for a folder given where a file is expected, or None where ``path``
    is not a folder: ``"<path> is a folder, not <what>; give <give>"``.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     folder_not_file(d, "a recording file", "one of the files in it")[len(d):]
    ' is a folder, not a recording file; give one of the files in it'
    >>> folder_not_file("no-such-path", "a rig file", "a rig TOML file") is None
    True
    """
    import os

    if not os.path.isdir(path):
        return None
    return f"{path} is a folder, not {what}; give {give}"


def did_you_mean(name: str, known, *, n: int = 1, cutoff: float = 0.6, style: str = "()") -> str:
    """A did-you-mean hint for a misspelt ``name``: ``" (did you mean 'x'?)"`` or ``""``.

    Parameters
    ----------
    name : str
        What the user typed.
    known : iterable of str
        The names that exist.
    n : int, optional
        How many near names to offer.
    cutoff : float, optional
        Similarity in [0, 1] below which a name is no match (:func:`close_matches`).
    style : {"()", ";"}, optional
        ``" (did you mean 'x'?)"`` or ``"; did you mean 'x'?"``.

    Returns
    -------
    str
        The hint with its leading separator, or an empty string when nothing is close.

    Examples
    --------
    >>> did_you_mean("drivs", ["arm", "drives", "lag"])
    " (did you mean 'drives'?)"
    >>> did_you_mean("zzz", ["arm", "drives"])
    ''
    """
    close = close_matches(name, known, n=n, cutoff=cutoff)
    if not close:
        return ""
    shown = [repr(c) for c in close]
    text = shown[0] if len(shown) == 1 else f"{', '.join(shown[:-1])} or {shown[-1]}"
    return f"; did you mean {text}?" if style == ";" else f" (did you mean {text}?)"


def _as_float_array(name: str, value, unit: str = "") -> np.ndarray:
    # True is not 1 N, nor "1e4" 10 kN: numpy would take both as numbers without a word.
    if isinstance(value, bool | np.bool_ | str | bytes):
        raise ParameterError(f"{name} must be a number{_unit(unit)}, got {value!r}")
    if isinstance(value, list | tuple | np.ndarray):
        kind = np.asarray(value).dtype.kind
        if kind in "bUS":
            what = "booleans" if kind == "b" else "text"
            raise ParameterError(f"{name} must be numbers{_unit(unit)}, got {what}: {value!r}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be a number{_unit(unit)}, got {value!r}") from exc
    except OverflowError:  # an integer beyond the float range (10**400)
        raise ParameterError(f"{name} must be finite, got an integer beyond 1.8e308") from None
    return arr


def require_number(name: str, value, unit: str = "") -> np.ndarray:
    """Return ``value`` as a float array, raising :class:`ParameterError` where it is not a
    number: text (``"1e4"``), True/False (which numpy reads as 1 and 0) or anything numpy
    cannot convert. NaN and ±inf pass (the caller decides): the conversion every ``require_*``
    helper starts from.

    Examples
    --------
    >>> require_number("radius", [0.35, np.inf]).tolist()
    [0.35, inf]
    >>> require_number("load", True, "N")
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: load must be a number [N], got True
    """
    return _as_float_array(name, value, unit)


def require_finite(name: str, value, unit: str = "", *, single: bool = False):
    """Return ``value`` as a float array, raising :class:`ParameterError` on NaN or inf.

    ``single``: a parameter that is one number (every ``require_*`` helper takes it): return
    a ``float``, and refuse an array of several values naming its shape (``float()`` of it
    had raised a bare TypeError).
    """
    arr = _as_float_array(name, value, unit)
    if _fails(arr, np.isfinite, math.isfinite):
        raise ParameterError(
            f"{name} must be finite{_unit(unit)}, got {_show(arr, ~np.isfinite(arr))}"
        )
    return _single(name, arr, unit) if single else arr


def _single(name: str, arr: np.ndarray, unit: str) -> float:
    """``arr`` as one float, or the error of a parameter that is one number given several."""
    if arr.size != 1:
        raise ParameterError(
            f"{name} must be a single number{_unit(unit)}, got an array of shape {arr.shape}"
        )
    return float(arr.reshape(()))


def _fails(arr: np.ndarray, test, scalar_test=None) -> bool:
    """True when ``test`` (elementwise) is false for some element of ``arr``.

    A 0-d array is tested as a Python float (with ``scalar_test`` if given, else ``test``):
    numpy's ufuncs and reductions cost microseconds on a single number, and the rig's
    assembly checks hundreds of numbers for every run (a calibration assembles thousands).
    """
    if arr.ndim == 0:
        return not (scalar_test or test)(float(arr))
    return not bool(np.all(test(arr)))


def require_positive(name: str, value, unit: str = "", *, single: bool = False):
    """Return ``value`` as a float array, raising unless every element is finite and > 0
    (``single``: :func:`require_finite`)."""
    arr = require_finite(name, value, unit)
    if _fails(arr, lambda v: v > 0.0):
        raise ParameterError(f"{name} must be > 0{_unit(unit)}, got {_show(arr, ~(arr > 0.0))}")
    return _single(name, arr, unit) if single else arr


def require_nonnegative(name: str, value, unit: str = "", *, single: bool = False):
    """Return ``value`` as a float array, raising unless every element is finite and >= 0
    (``single``: :func:`require_finite`)."""
    arr = require_finite(name, value, unit)
    if _fails(arr, lambda v: v >= 0.0):
        raise ParameterError(f"{name} must be >= 0{_unit(unit)}, got {_show(arr, ~(arr >= 0.0))}")
    return _single(name, arr, unit) if single else arr


def require_in_range(
    name: str,
    value,
    low: float,
    high: float,
    unit: str = "",
    *,
    low_inclusive: bool = False,
    high_inclusive: bool = False,
    single: bool = False,
):
    """Return ``value`` as a float array, raising unless every element lies in the interval
    (``single``: :func:`require_finite`).

    The message states the interval in standard notation, e.g. ``(0, 0.5)`` or ``(0, 1]``.
    """
    arr = require_finite(name, value, unit)

    def inside(v):
        above = v >= low if low_inclusive else v > low
        below = v <= high if high_inclusive else v < high
        return above & below

    if _fails(arr, inside):
        interval = (
            f"{'[' if low_inclusive else '('}{low:g}, {high:g}{']' if high_inclusive else ')'}"
        )
        got = _show(arr, ~inside(arr))
        raise ParameterError(f"{name} must lie in {interval}{_unit(unit)}, got {got}")
    return _single(name, arr, unit) if single else arr


def require_instants_within(name: str, value, start: float, end: float) -> np.ndarray:
    """Return ``value`` as a 1-D float array of instants [s], raising :class:`ParameterError`
    unless every one is finite, none comes before the one before it, and all lie in
    ``[start, end]`` [s] (an experiment's span: its inputs are not defined outside it).

    Examples
    --------
    >>> require_instants_within("t_out", [0.0, 0.5, 0.5, 2.0], 0.0, 2.0).tolist()
    [0.0, 0.5, 0.5, 2.0]
    >>> require_instants_within("t_out", [0.0, 3.0], 0.0, 2.0)
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: t_out must lie in [0, 2] [s], the experiment's span; got t_out[1] = 3, after its end
    """  # noqa: E501
    arr = require_finite(name, value, "s")
    if arr.ndim != 1:
        raise ParameterError(f"{name} must be a 1-D array of instants [s], got shape {arr.shape}")
    if arr.size == 0:
        return arr
    for k, side in (
        (np.flatnonzero(arr < start), "before its start"),
        (np.flatnonzero(arr > end), "after its end"),
    ):
        if k.size:
            k = int(k[0])
            lo, hi, got = numbers_apart(start, end, arr[k])
            raise ParameterError(
                f"{name} must lie in [{lo}, {hi}] [s], the experiment's span; got "
                f"{name}[{k}] = {got}, {side}"
            )
    back = np.flatnonzero(np.diff(arr) < 0.0)
    if back.size:
        k = int(back[0]) + 1
        later, earlier = numbers_apart(arr[k], arr[k - 1])
        raise ParameterError(
            f"{name} must not go back in time [s]; got {name}[{k}] = {later} after "
            f"{name}[{k - 1}] = {earlier}"
        )
    return arr


def require_broadcastable(**arrays) -> tuple[np.ndarray, ...]:
    """Return the keyword arguments as float arrays broadcast against each other, raising
    :class:`ParameterError` that names them and their shapes where numpy cannot broadcast them
    (its own message, "operands could not be broadcast together", names neither).

    A scalar goes with any shape; arrays of equal shape go together.

    Examples
    --------
    >>> [a.tolist() for a in require_broadcastable(creep=[0.001, 0.002], load=5e4)]
    [[0.001, 0.002], [50000.0, 50000.0]]
    >>> require_broadcastable(creep=[0.001, 0.002, 0.003], load=[5e4, 6e4])
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: creep (shape (3,)) and load (shape (2,)) must have the same shape, or one of them be a single number
    """  # noqa: E501
    values = {name: _as_float_array(name, value) for name, value in arrays.items()}
    try:
        return tuple(np.broadcast_arrays(*values.values()))
    except ValueError:
        shaped = [f"{name} (shape {arr.shape})" for name, arr in values.items() if arr.ndim]
        joined = ", ".join(shaped[:-1]) + f" and {shaped[-1]}" if len(shaped) > 1 else shaped[0]
        one = "one of them" if len(shaped) == 2 else "some of them"
        raise ParameterError(
            f"{joined} must have the same shape, or {one} be a single number"
        ) from None


def require_increasing(name: str, value, unit: str = "s", *, strict: bool = True) -> np.ndarray:
    """Return ``value`` as a finite 1-D float array, raising :class:`ParameterError` at the
    first element that does not increase (``strict``) or that decreases (not ``strict``),
    naming it and its neighbour.

    Examples
    --------
    >>> require_increasing("time", [0.0, 0.1, 0.2]).tolist()
    [0.0, 0.1, 0.2]
    >>> require_increasing("time", [0.0, 0.2, 0.1])
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: time must be strictly increasing [s]; got time[2] = 0.1 after time[1] = 0.2
    """  # noqa: E501
    arr = require_finite(name, value, unit)
    if arr.ndim != 1:
        raise ParameterError(f"{name} must be a 1-D array{_unit(unit)}, got shape {arr.shape}")
    step = np.diff(arr)
    bad = np.flatnonzero(step <= 0.0 if strict else step < 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        later, earlier = numbers_apart(arr[k], arr[k - 1])
        how = "strictly increasing" if strict else "non-decreasing"
        raise ParameterError(
            f"{name} must be {how}{_unit(unit)}; got {name}[{k}] = {later} after "
            f"{name}[{k - 1}] = {earlier}"
        )
    return arr


def require_whole(
    name: str, value, minimum: int = 0, maximum: int | None = None, unit: str = "-"
) -> int:
    """Return ``value`` as an ``int``, raising :class:`ParameterError` unless it is a whole
    number (3 or 3.0, not 2.5, NaN, True or "3") in ``[minimum, maximum]``.

    Examples
    --------
    >>> require_whole("am_pole_pairs", 5.0, minimum=1)
    5
    >>> require_whole("am_pole_pairs", 2.5, minimum=1)
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: am_pole_pairs must be a whole number >= 1 [-], got 2.5
    """
    allowed = f">= {minimum}" if maximum is None else f"in [{minimum}, {maximum}]"
    got = repr(value) if len(repr(value)) <= 40 else repr(value)[:36] + " ..."
    problem = ParameterError(f"{name} must be a whole number {allowed}{_unit(unit)}, got {got}")
    if isinstance(value, bool | np.bool_ | str | bytes) or np.ndim(value) != 0:
        raise problem
    try:
        whole = int(value)
        exact = whole == value
    except (TypeError, ValueError, OverflowError):  # NaN, inf, an array, None
        raise problem from None
    if not exact or whole < minimum or (maximum is not None and whole > maximum):
        raise problem
    return whole


def require_flag(name: str, value) -> bool:
    """Return ``value`` as a ``bool``, raising :class:`ParameterError` unless it is True or
    False (numpy's bools included): the text "no" is true to Python, and had been taken so
    (an ``overwrite="no"`` that replaced the file).

    Examples
    --------
    >>> require_flag("overwrite", np.False_)
    False
    >>> try:
    ...     require_flag("overwrite", "no")
    ... except ParameterError as exc:
    ...     print(exc)
    overwrite must be True or False, got 'no'
    """
    if not isinstance(value, bool | np.bool_):
        raise ParameterError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def require_names(name: str, value) -> list[str]:
    """Return ``value``, a collection of names, as a list of str, raising
    :class:`ParameterError` for a single str (it had been taken letter by letter:
    ``"torque"`` as six names), for what is not a collection, and for an entry that is not
    a str.

    Examples
    --------
    >>> require_names("names", ("torque", "speed"))
    ['torque', 'speed']
    >>> try:
    ...     require_names("names", "torque")
    ... except ParameterError as exc:
    ...     print(exc)
    names must be a list of names, got the single name 'torque'; pass ['torque'] for one name
    """
    if isinstance(value, str | bytes):
        raise ParameterError(
            f"{name} must be a list of names, got the single name {value!r}; pass "
            f"[{value!r}] for one name"
        )
    try:
        items = list(value)
    except TypeError:
        raise ParameterError(
            f"{name} must be a list of names, got a value of type {type(value).__name__}"
        ) from None
    for k, item in enumerate(items):
        if not isinstance(item, str):
            raise ParameterError(f"{name}[{k}] must be a str, got {item!r} ({type(item).__name__})")
    return items


def numbers_apart(*values) -> list[str]:
    """``values`` as text with ``%.9g``, or all in full (``repr``) where that would show
    two different numbers alike (an instant 1e-13 s past an end of 30 s), for an error
    message that compares them.

    Examples
    --------
    >>> numbers_apart(30.0, 30.0000000000001)
    ['30.0', '30.0000000000001']
    >>> numbers_apart(0.5, 2)
    ['0.5', '2']
    """
    short = [f"{float(v):.9g}" for v in values]
    if len(set(short)) < len({float(v) for v in values}):
        return [repr(float(v)) for v in values]
    return short


def _unit(unit: str) -> str:
    # The label rule of rollerrig.units (which imports this module): dimensionless as [-].
    if not unit:
        return ""
    return " [-]" if unit in ("1", "-") else f" [{unit}]"


def _show(arr: np.ndarray, bad: np.ndarray | None = None) -> str:
    """``arr`` as the message's "got": a short array whole, a long one by its first offending
    element (``bad``, a mask) with where it is and how many there are (the first six values
    of 7 500 had said "got [0. 0. 0. 0. 0. 0.] ..." of a NaN in sample 300)."""
    if arr.ndim == 0:
        return f"{float(arr):g}"
    flat = arr.ravel()
    if flat.size <= 6 or bad is None or not np.any(bad):
        return np.array2string(flat[:6], precision=4) + (" ..." if flat.size > 6 else "")
    where = np.flatnonzero(np.ravel(bad))
    k = int(where[0])
    index = k if arr.ndim == 1 else tuple(int(i) for i in np.unravel_index(k, arr.shape))
    return f"{flat[k]:g} at index {index} ({where.size} of {flat.size} values)"


# --------------------------------------------------------------------------------------------
# One error format for every user file (rig, channel map, protocol)
# --------------------------------------------------------------------------------------------

_NOTHING: Any = object()


@dataclass(frozen=True)
class Problem:
    """One problem with one value of a user file, in the package's one error format.

    ``<file>: <dotted key>: <what is wrong> [<unit>]; allowed <range or choices>; got <value>``;
    the parts that do not apply are left out.

    Parameters
    ----------
    key : str
        Dotted key of the value in the file, e.g. ``"stiffness.roller_shaft"`` (``""``: the file
        as a whole).
    message : str
        What is wrong, e.g. ``"must be > 0"``.
    unit : str or None
        Unit of ``allowed`` and ``got``.
    allowed : str, iterable or None
        The allowed range (``"(0, inf)"``) or the allowed choices (an iterable, shown with
        ``repr``).
    got : optional
        The value found (left out when not given).

    Examples
    --------
    >>> Problem("stiffness.roller_shaft", "must be > 0", unit="N.m/rad", allowed="(0, inf)",
    ...         got=-3).format("rig.toml")
    'rig.toml: stiffness.roller_shaft: must be > 0 [N.m/rad]; allowed (0, inf); got -3'
    """

    key: str
    message: str
    unit: str | None = None
    allowed: Any = None
    got: Any = _NOTHING

    def format(self, source: str | None = None) -> str:
        """The one-line message; ``source`` (the file) starts it."""
        head = "".join(f"{part}: " for part in (source, self.key) if part)
        text = f"{head}{self.message}"
        if self.unit and self.unit not in ("1", "-"):
            text += f" [{self.unit}]"
        if self.allowed is not None:
            text += f"; allowed {show_allowed(self.allowed)}"
        if self.got is not _NOTHING:
            text += f"; got {show_value(self.got)}"
        return text


class FieldProblem(ValueError):
    """Raise inside a pydantic validator to report a :class:`Problem` of a (sub)key.

    ``key`` is relative to the model that raises it (``""``: the model itself);
    :func:`from_pydantic` prefixes it with the model's location.

    Examples
    --------
    >>> from pydantic import BaseModel, ValidationError, model_validator
    >>> class Rows(BaseModel):
    ...     header_row: int = 0
    ...     data_row: int = 1
    ...     @model_validator(mode="after")
    ...     def _order(self):
    ...         if self.data_row <= self.header_row:
    ...             raise FieldProblem("data_row", "must come after header_row",
    ...                                allowed=f"> {self.header_row}", got=self.data_row)
    ...         return self
    >>> try:
    ...     Rows(header_row=3, data_row=2)
    ... except ValidationError as exc:
    ...     print(from_pydantic(exc, "map.toml", prefix="file"))
    map.toml: file.data_row: must come after header_row; allowed > 3; got 2
    """

    def __init__(
        self, key: str, message: str, *, unit: str | None = None, allowed=None, got=_NOTHING
    ):
        super().__init__(message)
        self.problem = Problem(key, message, unit, allowed, got)


def field_error(
    source: str | None,
    key: str,
    message: str,
    *,
    unit: str | None = None,
    allowed=None,
    got=_NOTHING,
    error: type[ParameterError] | None = None,
) -> ParameterError:
    """An error (to raise) in the one format: file, dotted key, what, unit, allowed, got.

    Parameters
    ----------
    source : str or None
        The file (or ``"overrides"``, ``"<dict>"``); None: left out.
    key, message, unit, allowed, got
        See :class:`Problem`.
    error : type, optional
        The :class:`ParameterError` subclass to build (default :class:`ParameterError`); it is
        called with the message.

    Examples
    --------
    >>> str(field_error("rig.toml", "stiffness.roller_shaft", "must be > 0", unit="N.m/rad",
    ...                 allowed="(0, inf)", got=-3))
    'rig.toml: stiffness.roller_shaft: must be > 0 [N.m/rad]; allowed (0, inf); got -3'
    >>> str(field_error("map.toml", "file.decimal", "not a decimal mark", allowed=[".", ","],
    ...                 got=";"))
    "map.toml: file.decimal: not a decimal mark; allowed '.', ','; got ';'"
    """
    exc = (error or ParameterError)(Problem(key, message, unit, allowed, got).format(source))
    exc.problems = (str(exc),)
    return exc


def from_pydantic(
    exc,
    source: str | None,
    units: Mapping[str, str] | None = None,
    *,
    model=None,
    prefix: str = "",
    error: type[ParameterError] | None = None,
) -> ParameterError:
    """A pydantic ``ValidationError`` as one error in the package's format, one line per problem.

    Parameters
    ----------
    exc : pydantic.ValidationError
        The error.
    source : str or None
        The file the data came from.
    units : mapping, optional
        Dotted key (with ``prefix``) -> unit, for the ``[unit]`` of a problem. A field may also
        state its unit as ``json_schema_extra={"unit": ...}``.
    model : type of pydantic.BaseModel, optional
        The model that was validated: gives the full allowed range of a bounded field (both
        bounds) and the known keys of an unknown key. Default: the bound in the error only.
    prefix : str
        Dotted location of the validated data in the file (e.g. the section name).
    error : type, optional
        The :class:`ParameterError` subclass to build (called with the message).

    Returns
    -------
    ParameterError
        Its message holds every problem, one per line; ``problems`` holds the lines.

    Examples
    --------
    >>> from pydantic import BaseModel, ConfigDict, Field, ValidationError
    >>> class Material(BaseModel):
    ...     model_config = ConfigDict(extra="forbid")
    ...     poisson: float = Field(gt=0, lt=0.5)
    >>> try:
    ...     Material.model_validate({"poisson": 0.6})
    ... except ValidationError as e:
    ...     print(from_pydantic(e, "rig.toml", {"material.poisson": "1"}, model=Material,
    ...                         prefix="material"))
    rig.toml: material.poisson: must be < 0.5; allowed (0, 0.5); got 0.6
    """
    lines = [p.format(source) for p in pydantic_problems(exc, units, model=model, prefix=prefix)]
    out = (error or ParameterError)("\n".join(lines))
    out.problems = tuple(lines)
    return out


def pydantic_problems(
    exc, units: Mapping[str, str] | None = None, *, model=None, prefix: str = ""
) -> list[Problem]:
    """The :class:`Problem` of each error of a pydantic ``ValidationError`` (see
    :func:`from_pydantic`); duplicates at one key (union members) are reported once."""
    units = units or {}
    problems: list[Problem] = []
    seen: set[str] = set()
    for err in exc.errors(include_url=False):
        loc = [str(p) for p in err["loc"]]
        parent, field = _locate(model, err["loc"])
        ctx = err.get("ctx") or {}
        cause = ctx.get("error")
        if isinstance(cause, FieldProblem):
            p = cause.problem
            key = ".".join([*filter(None, [prefix, *loc]), *([p.key] if p.key else [])])
            unit = p.unit if p.unit is not None else units.get(key)
            problems.append(Problem(key, p.message, unit, p.allowed, p.got))
            continue
        key = ".".join(filter(None, [prefix, *loc]))
        if key in seen:
            continue
        seen.add(key)
        unit = units.get(key) or _field_extra(field).get("unit")
        message, allowed = _describe(err, ctx, cause, parent, field, loc)
        got = _NOTHING if err["type"] in ("missing", *_UNKNOWN_KEY) else err.get("input")
        problems.append(Problem(key, message, unit, allowed, got))
    return problems


_TYPE_MESSAGES = {
    "float_type": "must be a number",
    "float_parsing": "must be a number",
    "int_type": "must be an integer",
    "int_parsing": "must be an integer",
    "int_from_float": "must be an integer",
    "bool_type": "must be true or false",
    "bool_parsing": "must be true or false",
    "string_type": "must be a string",
    "dict_type": "must be a table",
    "model_type": "must be a table",
    "model_attributes_type": "must be a table",
    "dataclass_type": "must be a table",
    "dataclass_args_type": "must be a table",
    "list_type": "must be a list",
    "finite_number": "must be finite",
    "missing": "missing key",
}
_UNKNOWN_KEY = ("extra_forbidden", "unexpected_keyword_argument")
_BOUND_MESSAGES = {
    "greater_than": ("gt", ">"),
    "greater_than_equal": ("ge", ">="),
    "less_than": ("lt", "<"),
    "less_than_equal": ("le", "<="),
}


def _describe(err, ctx, cause, parent, field, loc) -> tuple[str, Any]:
    kind = err["type"]
    bounds = _bounds(field)
    if kind in _BOUND_MESSAGES:
        name, sign = _BOUND_MESSAGES[kind]
        if bounds is None:
            bounds = interval(
                ctx[name] if sign.startswith(">") else -math.inf,
                ctx[name] if sign.startswith("<") else math.inf,
                low_inclusive=sign == ">=",
                high_inclusive=sign == "<=",
            )
        return f"must be {sign} {show_value(ctx[name])}", bounds
    if kind in _UNKNOWN_KEY:
        known = _known_keys(parent)
        hint = did_you_mean(loc[-1], known) if known else ""
        return f"unknown key{hint}", (known or None)
    if kind == "literal_error":
        return "not one of the allowed values", ctx.get("expected")
    if kind == "string_too_short":
        n = ctx.get("min_length", 1)
        return ("must not be empty" if n == 1 else f"must have at least {n} characters"), None
    if kind in ("value_error", "assertion_error") and cause is not None:
        return str(cause), None
    if kind == "missing" and getattr(field, "description", None):
        return f"missing key ({field.description})", None
    if kind in _TYPE_MESSAGES:
        return _TYPE_MESSAGES[kind], (bounds if kind == "finite_number" else None)
    return str(err["msg"]), None


def _locate(model, loc) -> tuple[Any, Any]:
    """(parent model class, FieldInfo) of the error location ``loc`` in ``model``."""
    parent, field, annotation = None, None, model
    for part in loc:
        annotation = _strip_optional(annotation)
        fields = _fields(annotation)
        if fields is None:  # a container (dict, list): ``part`` is a key or index
            args = typing.get_args(annotation)
            annotation = args[-1] if args else None
            continue
        parent, field = annotation, fields.get(part)
        if field is None:
            return parent, None
        annotation = field.annotation
    return parent, field


def _strip_optional(annotation):
    """``M`` of ``Annotated[M, ...]`` and of ``M | None``; any other annotation as it is."""
    if typing.get_origin(annotation) is typing.Annotated:
        annotation = typing.get_args(annotation)[0]
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(annotation) if a is not type(None)]
        if len(args) == 1:
            return _strip_optional(args[0])
    return annotation


def _fields(model) -> dict | None:
    """The fields of a pydantic model or pydantic dataclass, else None."""
    fields = getattr(model, "__pydantic_fields__", None)
    return fields if isinstance(fields, dict) else None


def _known_keys(model) -> list[str]:
    fields = _fields(model) or {}
    return [info.alias or name for name, info in fields.items()]


def _field_extra(field) -> dict:
    extra = getattr(field, "json_schema_extra", None)
    return extra if isinstance(extra, dict) else {}


def _bounds(field) -> str | None:
    """The allowed interval of a field with ``gt``/``ge``/``lt``/``le`` bounds, else None."""
    low, high, low_incl, high_incl = -math.inf, math.inf, False, False
    found = False
    for meta in getattr(field, "metadata", ()):
        for name in ("gt", "ge", "lt", "le"):
            value = getattr(meta, name, None)
            if value is None:
                continue
            found = True
            if name in ("gt", "ge"):
                low, low_incl = value, name == "ge"
            else:
                high, high_incl = value, name == "le"
    if not found:
        return None
    return interval(low, high, low_inclusive=low_incl, high_inclusive=high_incl)


def interval(low, high, *, low_inclusive: bool = False, high_inclusive: bool = False) -> str:
    """An interval in standard notation, e.g. ``(0, inf)``, ``[1, 4]``.

    Examples
    --------
    >>> interval(0, math.inf), interval(0, 1, low_inclusive=True)
    ('(0, inf)', '[0, 1)')
    """
    return (
        f"{'[' if low_inclusive else '('}{show_value(low)}, "
        f"{show_value(high)}{']' if high_inclusive else ')'}"
    )


def show_allowed(allowed) -> str:
    """``allowed`` as text: a string as it is, an iterable of choices joined with ``repr``."""
    if isinstance(allowed, str):
        return allowed
    if isinstance(allowed, Mapping):
        return ", ".join(f"{k!r} ({v})" for k, v in allowed.items())
    try:
        return ", ".join(repr(a) for a in allowed)
    except TypeError:
        return str(allowed)


class Verbatim(str):
    """Text shown as it is (no quotes) where :func:`show_value` shows a value."""


def show_value(value) -> str:
    """A value as a user file writes it: ``true``, ``-3``, ``0.6``, ``'bar'``, ``nan``."""
    if isinstance(value, Verbatim):
        return str(value)
    if isinstance(value, bool | np.bool_):
        return "true" if value else "false"
    if isinstance(value, int | np.integer):
        return str(int(value))
    if isinstance(value, float | np.floating):
        v = float(value)
        return str(int(v)) if math.isfinite(v) and v == int(v) and abs(v) < 1e15 else repr(v)
    return repr(value)


def toml_string(text: str) -> str:
    r"""``text`` as a TOML basic string (for the package's TOML writers).

    JSON string escapes are TOML basic-string escapes; TOML also forbids a raw DEL.

    Examples
    --------
    >>> print(toml_string('say "hi"' + chr(0x7F)))
    "say \"hi\"\u007f"
    """
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")
