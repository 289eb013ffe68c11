"""``calibration.json`` read back: its values checked like rig keys, and bound to its rig.

:func:`read_calibration` reads the file that :func:`rollerrig.calibrate.write_calibration`
wrote (or one edited by hand) and checks every part that is used later, each problem in the
package's one error format (:mod:`rollerrig._validation`), all of them at once:

- each key of ``parameters`` must be a key ``rollerrig calibrate`` fits
  (:func:`~rollerrig.calibrate.free_parameter_catalogue`); its ``value`` a finite number (or
  null: not identified) that passes the rig file's own check of that key (the field's type and
  range of :mod:`rollerrig.rig.sections`; the creep law's ranges for ``polach.*`` and
  ``fastsim.*``, whose keys must be those of the file's ``law``, Polach's without one) and lies
  within
  :data:`MAX_FACTOR` of its recorded starting value ``initial``; its ``standard_error`` null,
  0, or a finite number between :data:`MIN_RELATIVE_SE` and
  :data:`~rollerrig.calibrate.fit.MAX_RELATIVE_SE` times the value (what ``calibrate`` itself
  calls identified); where the file splits it, that bound holds for
  ``standard_error_statistical`` (calibrate identifies a key by it) and ``standard_error``,
  which adds the sensor classes' systematic part, must be at least that; its ``unit``, when
  given, the key's SI unit;
- ``values`` (each value again) must agree with ``parameters``; ``correlation`` must be a
  symmetric, positive semi-definite matrix of numbers in [-1, 1] (null: unknown), one row per
  entry of its ``keys``; ``warnings`` a list of strings; ``rig`` (below) of the form written.

A problem reads ``calibration.json: inertia.roller.standard_error: must be >= 0 [kg.m^2];
allowed 0, or [...]; got -1``.

The rig binding (:func:`rollerrig.calibrate.binding.check_rig`) reads what this module
checked.

Examples
--------
>>> from rollerrig.rig.parameters import default_rig
>>> doc = {"parameters": {"inertia.roller": {"value": 46.0, "standard_error": 0.5}}}
>>> check_calibration(doc)["parameters"]["inertia.roller"]["value"]
46.0
>>> doc["parameters"]["inertia.roller"]["standard_error"] = -1
>>> try:
...     check_calibration(doc)
... except CalibrationError as exc:
...     print(exc)
calibration.json: inertia.roller.standard_error: must be >= 0 [kg.m^2]; allowed 0, or [4.6e-11, 23]; got -1
"""  # noqa: E501

from __future__ import annotations

import errno
import functools
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import ConfigDict, ValidationError, create_model

from rollerrig._validation import (
    Problem,
    Verbatim,
    did_you_mean,
    interval,
    pydantic_problems,
    show_value,
)
from rollerrig.calibrate.problem import (
    _FASTSIM_RANGES,
    _POLACH_RANGES,
    _POLACH_UNITS,
    CALIBRATION_LAWS,
    FASTSIM_KEYS,
    POLACH_KEYS,
    CalibrationError,
    free_parameter_catalogue,
    is_law_key,
    law_keys,
)
from rollerrig.calibrate.settings import MAX_RELATIVE_SE
from rollerrig.rig.parameters import rig_values
from rollerrig.rig.sections import SECTIONS, si_unit_of

__all__ = [
    "MAX_CALIBRATION_BYTES",
    "MAX_FACTOR",
    "MIN_RELATIVE_SE",
    "check_calibration",
    "read_calibration",
]

MAX_CALIBRATION_BYTES = 16 * 2**20
"""Largest ``calibration.json`` read (16 MiB); ``rollerrig calibrate`` writes tens of kB."""

MAX_FACTOR = 1.0e3
"""A calibrated value [SI] may lie at most this factor above or below its starting value
(``initial``, the rig's value), counted from the key's lower bound: a calibration corrects a
rig's value, three decades away it has found something else."""

MIN_RELATIVE_SE = 1.0e-12
"""Smallest non-zero standard error, relative to the value [-]: finer than the fit's
finite differences and double precision resolve."""

_CORRELATION_TOLERANCE = 1.0e-6  # symmetry, unit diagonal, smallest eigenvalue


def _fail(source: str, problems: list[Problem]) -> CalibrationError:
    lines = [p.format(source) for p in problems]
    exc = CalibrationError("\n".join(lines))
    exc.problems = tuple(lines)
    return exc


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------


def read_calibration(
    path: str | os.PathLike, source: str | None = None, rig=None, *, allow_invalid: bool = False
) -> dict[str, Any]:
    """Read and check a ``calibration.json`` (see the module's docstring).

    Parameters
    ----------
    path : path
        The file.
    source : str, optional
        How errors name the file (default: the path as given).
    rig : RigParameters, optional
        The rig in use: the reference of a value's plausibility where the file gives no
        starting value (see :func:`check_calibration`).
    allow_invalid : bool
        Accept a calibration that says it is not valid (``"valid": false``: its fit did not
        converge or ended worse than it started); without it that is an error naming why.

    Returns
    -------
    dict
        The file's content, checked.

    Raises
    ------
    FileNotFoundError
        No such file.
    CalibrationError
        Not a JSON object of the form written, or values that are not plausible; one line per
        problem, each naming the file and the key; a calibration marked not valid.
    """
    path = Path(path)
    source = str(path) if source is None else source
    if not path.is_file():
        raise FileNotFoundError(errno.ENOENT, "calibration file not found", str(path))
    size = path.stat().st_size
    if size > MAX_CALIBRATION_BYTES:
        raise _fail(
            source,
            [
                Problem(
                    "",
                    "too large for a calibration.json",
                    unit="bytes",
                    allowed=f"at most {MAX_CALIBRATION_BYTES}",
                    got=size,
                )
            ],
        )
    try:
        data = json.loads(path.read_bytes().decode("utf-8"))
    except UnicodeDecodeError:
        raise _fail(source, [Problem("", "not a JSON file (not UTF-8 text)")]) from None
    except RecursionError:
        raise _fail(source, [Problem("", "not a calibration.json (nested too deep)")]) from None
    except ValueError as exc:  # json.JSONDecodeError, an integer of too many digits
        text = " ".join(str(exc).split())[:200]
        raise _fail(
            source,
            [
                Problem(
                    "",
                    f"not a JSON file ({text}); give the calibration.json that "
                    "`rollerrig calibrate` wrote",
                )
            ],
        ) from None
    data = check_calibration(data, source, rig)
    if data.get("valid") is False and not allow_invalid:
        reasons = data.get("invalid_reasons") or ["no reason recorded"]
        raise _fail(
            source,
            [
                Problem(
                    "valid",
                    "this calibration is not valid (" + "; ".join(map(str, reasons)) + "): its "
                    "values are not a calibrated rig; calibrate again (more iterations, a better "
                    "start, the other roller-drive model or creep law: rollerrig calibrate "
                    "--compare-drives or --compare-laws), or force its use (read_calibration(..., "
                    "allow_invalid=True))",
                )
            ],
        )
    return data


def check_calibration(data: Any, source: str = "calibration.json", rig=None) -> dict[str, Any]:
    """Check the content of a ``calibration.json``; return it unchanged.

    Parameters
    ----------
    data : object
        What the JSON parser gave.
    source : str
        How errors name the file.
    rig : RigParameters, optional
        The rig in use. A value must lie within :data:`MAX_FACTOR` of its starting value
        (``initial``), or, where the file gives none, of this rig's value.

    Returns
    -------
    dict

    Raises
    ------
    CalibrationError
        Every problem at once, one line each (``source: key.field: ...``).
    """
    if not isinstance(data, dict):
        raise _fail(
            source,
            [
                Problem(
                    "",
                    "must be a JSON object (the calibration.json that `rollerrig calibrate` wrote)",
                    got=Verbatim(_kind(data)),
                )
            ],
        )
    problems: list[Problem] = []
    params = data.get("parameters")
    if "parameters" not in data:
        problems.append(
            Problem("parameters", "missing key (the fitted values: {key: {value, standard_error}})")
        )
    elif not isinstance(params, dict):
        problems.append(Problem("parameters", "must be an object", got=Verbatim(_kind(params))))
    else:
        here = {} if rig is None else rig_values(rig)
        for key, entry in params.items():
            problems += _entry_problems(str(key), entry, here.get(str(key)))
        problems += _values_problems(data.get("values"), params)
    problems += _law_problems(data)
    problems += _correlation_problems(data)
    problems += _report_problems(data)
    problems += _rig_record_problems(data)
    if problems:
        raise _fail(source, problems)
    return data


def _kind(value: Any) -> str:
    return {dict: "an object", list: "an array", str: "a string", bool: "true/false"}.get(
        type(value), "null" if value is None else "a number"
    )


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


# ----------------------------------------------------------------------------- one parameter


@functools.cache
def _rig_key_model(key: str):
    """A one-field pydantic model with the rig file's own field of ``key`` (its type, range and
    validators), named ``value``."""
    section, _, name = key.partition(".")
    base = SECTIONS[section]
    field = base.model_fields[name]
    config = ConfigDict(strict=True, allow_inf_nan=False, extra="forbid")
    return create_model(f"Calibrated_{section}_{name}", __config__=config, value=(float, field))


def _key_unit(key: str) -> str:
    if is_law_key(key):
        return _POLACH_UNITS.get(key.partition(".")[2], "1")
    section, _, name = key.partition(".")
    return si_unit_of(SECTIONS[section].model_fields[name])


def _lower_bound(key: str) -> float:
    if key in POLACH_KEYS:
        return _POLACH_RANGES[key.partition(".")[2]][0]
    if key in FASTSIM_KEYS:
        return _FASTSIM_RANGES[key.partition(".")[2]][0]
    from rollerrig.calibrate.problem import _bounds

    section, _, name = key.partition(".")
    return _bounds(SECTIONS[section].model_fields[name])[0]


_POLACH_INTERVALS = {  # (low, high, low inclusive, high inclusive): PolachParameters' checks
    "static_friction": (0.0, math.inf, False, False),
    "limit_ratio": (0.0, 1.0, False, True),
    "friction_decay": (0.0, math.inf, True, False),
    "k_adhesion": (0.0, 1.0, False, True),
    "k_slip": (0.0, 1.0, False, True),
}
_FASTSIM_INTERVALS = {  # FastsimParameters' checks
    "static_friction": (0.0, math.inf, False, False),
    "limit_ratio": (0.0, 1.0, False, True),
    "friction_decay": (0.0, math.inf, True, False),
    "k0": (0.0, 1.0, False, True),
    "alpha_inf": (0.0, 1.0, True, True),
    "beta": (0.0, math.inf, True, False),
}


def _value_problems(key: str, field: str, value: Any) -> list[Problem]:
    """The rig file's (or the Polach law's) check of one number of ``key``."""
    where = f"{key}.{field}"
    unit = _key_unit(key)
    if not _is_number(value):
        return [Problem(where, "must be a number", unit=unit, got=value)]
    if not math.isfinite(value):
        return [Problem(where, "must be finite", unit=unit, got=value)]
    if is_law_key(key):
        intervals = _POLACH_INTERVALS if key in POLACH_KEYS else _FASTSIM_INTERVALS
        low, high, low_in, high_in = intervals[key.partition(".")[2]]
        above = value >= low if low_in else value > low
        below = value <= high if high_in else value < high
        if above and below:
            return []
        allowed = interval(low, high, low_inclusive=low_in, high_inclusive=high_in)
        return [Problem(where, f"must lie in {allowed}", unit=unit, allowed=allowed, got=value)]
    model = _rig_key_model(key)
    try:
        model.model_validate({"value": float(value)})
    except ValidationError as exc:
        # the unit as the rig file's errors show it (a ratio: what it is a multiple of)
        shown = model.model_fields["value"].json_schema_extra.get("unit") or unit
        problems = pydantic_problems(exc, {"value": shown}, model=model)
        return [Problem(where, p.message, p.unit, p.allowed, value) for p in problems]
    return []


def _entry_problems(key: str, entry: Any, rig_value: Any = None) -> list[Problem]:
    catalogue = (*free_parameter_catalogue("induction_dq"), *FASTSIM_KEYS)  # every drive, law
    if key not in catalogue:
        hint = did_you_mean(key, catalogue)
        return [
            Problem(
                key,
                f"not a key rollerrig calibrate fits{hint}",
                allowed=Verbatim("the keys `rollerrig calibrate --list-keys` lists"),
                got=key,
            )
        ]
    if not isinstance(entry, dict):
        return [
            Problem(
                key,
                "must be an object {value, standard_error} (SI; null where not identified)",
                got=Verbatim(_kind(entry)),
            )
        ]
    problems: list[Problem] = []
    unit = _key_unit(key)
    if "unit" in entry and entry["unit"] != unit:
        problems.append(
            Problem(
                f"{key}.unit",
                "must be the key's SI unit (calibration.json holds SI values)",
                allowed=[unit],
                got=entry["unit"],
            )
        )
    for name in ("why_null", "reason"):
        if entry.get(name) is not None and not isinstance(entry[name], str):
            problems.append(Problem(f"{key}.{name}", "must be a string", got=entry[name]))
    identified = entry.get("identified")
    if identified is not None and not isinstance(identified, bool):
        problems.append(Problem(f"{key}.identified", "must be true or false", got=identified))
    initial = entry.get("initial")
    initial_ok = False
    if initial is not None:
        found = _value_problems(key, "initial", initial)
        problems += found
        initial_ok = not found
    if "value" not in entry:
        problems.append(Problem(f"{key}.value", "missing key (null where not identified)"))
        return problems
    value, se = entry["value"], entry.get("standard_error")
    if value is None:
        if se is not None:
            problems.append(
                Problem(
                    f"{key}.standard_error",
                    "must be null when the value is null (not identified)",
                    unit=unit,
                    got=se,
                )
            )
        return problems
    if identified is False:
        problems.append(
            Problem(
                f"{key}.identified",
                "is false but a value is given (calibrate writes null for a value it does not "
                "identify)",
                got=identified,
            )
        )
    found = _value_problems(key, "value", value)
    problems += found
    if found:
        return problems
    if initial_ok:
        found = _factor_problems(key, float(value), float(initial), "its starting value")
    elif _is_number(rig_value):
        found = _factor_problems(key, float(value), float(rig_value), "the rig's value")
    else:
        found = []
    problems += found
    if found:
        return problems
    if se is None:
        return problems
    statistical = entry.get("standard_error_statistical")
    if statistical is None:
        problems += _se_problems(key, float(value), se)
        return problems
    # calibrate identifies a key by its statistical error; the total adds the sensor classes'
    # systematic part and may exceed the bound (bearing friction under the pressure class:
    # 0.0071 of 0.0091 on the tour's calibration, whose analyze had been refused)
    found = _se_problems(key, float(value), statistical, "standard_error_statistical")
    problems += found
    if not found:
        problems += _total_se_problems(key, se, float(statistical))
    return problems


def _total_se_problems(key: str, se: Any, statistical: float) -> list[Problem]:
    """The total ``standard_error``: a finite number not below its statistical part."""
    where, unit = f"{key}.standard_error", _key_unit(key)
    allowed = Verbatim(f">= standard_error_statistical ({statistical:.6g}), finite")
    if not _is_number(se) or not math.isfinite(se) or se < statistical * (1.0 - 1e-12):
        return [
            Problem(
                where,
                "must be a finite number, at least its statistical part",
                unit=unit,
                allowed=allowed,
                got=se,
            )
        ]
    return []


def _factor_problems(key: str, value: float, reference: float, what: str) -> list[Problem]:
    """``value`` within :data:`MAX_FACTOR` of ``reference``, counted from the lower bound."""
    lower = _lower_bound(key)
    span, ref_span = value - lower, reference - lower
    if not ref_span > 0 or not span > 0:
        return []
    if ref_span / MAX_FACTOR <= span <= ref_span * MAX_FACTOR:
        return []
    low, high = lower + ref_span / MAX_FACTOR, lower + ref_span * MAX_FACTOR
    return [
        Problem(
            f"{key}.value",
            f"not plausible: more than {MAX_FACTOR:g} times away from {what} "
            f"{show_value(reference)}",
            unit=_key_unit(key),
            allowed=Verbatim(f"[{low:.6g}, {high:.6g}]"),
            got=value,
        )
    ]


def _se_problems(key: str, value: float, se: Any, field: str = "standard_error") -> list[Problem]:
    where, unit = f"{key}.{field}", _key_unit(key)
    low, high = MIN_RELATIVE_SE * abs(value), MAX_RELATIVE_SE * abs(value)
    allowed = Verbatim(f"0, or [{low:.3g}, {high:.3g}]" if high > 0 else "0")
    if not _is_number(se):
        return [Problem(where, "must be a number or null", unit=unit, allowed=allowed, got=se)]
    if not math.isfinite(se):
        return [Problem(where, "must be finite", unit=unit, allowed=allowed, got=se)]
    if se < 0:
        return [Problem(where, "must be >= 0", unit=unit, allowed=allowed, got=se)]
    if se == 0 or low <= se <= high:
        return []
    if se > high:
        message = (
            f"more than {MAX_RELATIVE_SE:g} times the value: rollerrig calibrate reports such a "
            "key as not identified (value null)"
        )
    else:
        message = (
            f"less than {MIN_RELATIVE_SE:g} times the value: finer than the fit resolves "
            "(0 states an exact value)"
        )
    return [Problem(where, message, unit=unit, allowed=allowed, got=se)]


def _values_problems(values: Any, params: dict) -> list[Problem]:
    """``values`` (each identified value again) must agree with ``parameters``."""
    if values is None:
        return []
    if not isinstance(values, dict):
        return [Problem("values", "must be an object", got=Verbatim(_kind(values)))]
    problems = []
    for key, value in values.items():
        entry = params.get(key)
        stated = entry.get("value") if isinstance(entry, dict) else None
        if entry is None or stated is None:
            problems.append(
                Problem(
                    f"values.{key}",
                    "has no identified value in parameters (edit parameters, the values "
                    "analyze uses, and this copy alike)",
                    got=value,
                )
            )
        elif value != stated or not _is_number(value):
            problems.append(
                Problem(
                    f"values.{key}",
                    f"differs from parameters.{key}.value ({show_value(stated)}); the file "
                    "states each value twice: edit both",
                    got=value,
                )
            )
    return problems


# ----------------------------------------------------------------------------- correlation


def _correlation_problems(data: dict) -> list[Problem]:
    corr = data.get("correlation")
    if corr is None:
        return []
    where = "correlation"
    keys = data.get("keys", list(data.get("parameters") or {}))
    if isinstance(corr, dict):
        keys, corr, where = corr.get("keys"), corr.get("matrix"), "correlation.matrix"
        if not isinstance(keys, list) or not all(isinstance(k, str) for k in keys):
            return [Problem("correlation.keys", "must be an array of keys", got=keys)]
        if corr is None:
            return []
    elif not isinstance(keys, list) or not all(isinstance(k, str) for k in keys):
        return [Problem("keys", "must be an array of keys (the rows of correlation)", got=keys)]
    if len(set(keys)) != len(keys):
        return [Problem(f"{where.rpartition('.')[0] or 'correlation'}.keys", "repeats a key")]
    n = len(keys)
    shape_problem = Problem(
        where,
        f"must be a {n} x {n} array of numbers in [-1, 1] (null where unknown), one row per key",
    )
    if not isinstance(corr, list) or len(corr) != n:
        return [shape_problem]
    rows = []
    for row in corr:
        if not isinstance(row, list) or len(row) != n:
            return [shape_problem]
        if not all(v is None or _is_number(v) for v in row):
            return [shape_problem]
        rows.append([math.nan if v is None else float(v) for v in row])
    matrix = np.array(rows, dtype=float).reshape(n, n)
    known = np.isfinite(matrix)
    entries = matrix[known]
    if entries.size and np.max(np.abs(entries)) > 1.0 + _CORRELATION_TOLERANCE:
        worst = float(entries[np.argmax(np.abs(entries))])
        return [Problem(where, "holds a correlation outside [-1, 1]", allowed="[-1, 1]", got=worst)]
    diagonal = np.diag(matrix)
    if np.any(np.abs(diagonal[np.isfinite(diagonal)] - 1.0) > _CORRELATION_TOLERANCE):
        return [Problem(where, "must have 1 on its diagonal (a key's correlation with itself)")]
    both = known & known.T
    if np.any(np.abs(np.where(both, matrix - matrix.T, 0.0)) > _CORRELATION_TOLERANCE):
        return [Problem(where, "must be symmetric")]
    filled = np.where(known & known.T, matrix, 0.0)
    np.fill_diagonal(filled, 1.0)
    if n and np.min(np.linalg.eigvalsh(filled)) < -_CORRELATION_TOLERANCE * n:
        return [
            Problem(
                where,
                "is not a correlation matrix: not positive semi-definite (no set of variables "
                "has these correlations)",
            )
        ]
    return []


# ----------------------------------------------------------------------------- report parts


def _law_problems(data: dict) -> list[Problem]:
    """``law`` one of the creep laws; the law keys of ``parameters`` that law's."""
    law = data.get("law", "polach")
    if law not in CALIBRATION_LAWS:
        return [
            Problem(
                "law",
                "not a creep law rollerrig calibrate fits"
                + did_you_mean(str(law), CALIBRATION_LAWS),
                allowed=list(CALIBRATION_LAWS),
                got=law,
            )
        ]
    params = data.get("parameters")
    if not isinstance(params, dict):
        return []
    own = law_keys(law)
    wrong = [str(k) for k in params if is_law_key(str(k)) and k not in own]
    return [
        Problem(
            key,
            f"not a parameter of the calibration's creep law {law!r} (its keys: {', '.join(own)})",
            got=key,
        )
        for key in wrong
    ]


def _report_problems(data: dict) -> list[Problem]:
    problems = []
    warnings = data.get("warnings")
    if warnings is not None and (
        not isinstance(warnings, list) or not all(isinstance(w, str) for w in warnings)
    ):
        problems.append(Problem("warnings", "must be an array of strings", got=warnings))
    for name in ("valid", "standard_errors_conditional_on_model"):
        if name in data and not isinstance(data[name], bool):
            problems.append(Problem(name, "must be true or false", got=data[name]))
    reasons = data.get("invalid_reasons")
    if reasons is not None and (
        not isinstance(reasons, list) or not all(isinstance(r, str) for r in reasons)
    ):
        problems.append(Problem("invalid_reasons", "must be an array of strings", got=reasons))
    problems += _discrepancy_problems(data.get("model_discrepancy"))
    recording = data.get("recording")
    if recording is not None and not isinstance(recording, dict):
        problems.append(Problem("recording", "must be an object", got=Verbatim(_kind(recording))))
    elif isinstance(recording, dict) and not isinstance(recording.get("source", ""), str):
        problems.append(Problem("recording.source", "must be a string", got=recording["source"]))
    return problems


def _discrepancy_problems(record: Any) -> list[Problem]:
    """``model_discrepancy``: {keys: {key: {standard_uncertainty >= 0, ...}}} or absent."""
    if record is None:
        return []
    keys = record.get("keys") if isinstance(record, dict) else None
    if not isinstance(keys, dict):
        return [Problem("model_discrepancy", "must be an object with 'keys' {key: {...}}")]
    problems = []
    for key, entry in keys.items():
        u = entry.get("standard_uncertainty") if isinstance(entry, dict) else None
        if not _is_number(u) or not (0.0 <= float(u) < math.inf):
            problems.append(
                Problem(
                    f"model_discrepancy.keys.{key}.standard_uncertainty",
                    "must be a finite number >= 0",
                    got=u,
                )
            )
    return problems


def _rig_record_problems(data: dict) -> list[Problem]:
    problems = []
    record = data.get("rig")
    if record is not None:
        if not isinstance(record, dict):
            return [Problem("rig", "must be an object", got=Verbatim(_kind(record)))]
        for name in ("name", "sha256", "parameters_sha256"):
            if not isinstance(record.get(name, ""), str | None):
                problems.append(Problem(f"rig.{name}", "must be a string", got=record[name]))
        values = record.get("parameters")
        if not isinstance(values, dict) or not all(
            v is None or isinstance(v, str) or _is_number(v) for v in values.values()
        ):
            problems.append(
                Problem("rig.parameters", "must be an object of the rig's values (numbers)")
            )
        keys = record.get("calibrated_keys", [])
        if not isinstance(keys, list) or not all(isinstance(k, str) for k in keys):
            problems.append(Problem("rig.calibrated_keys", "must be an array of keys", got=keys))
    provenance = data.get("provenance")
    if provenance is not None and not isinstance(provenance, dict):
        problems.append(Problem("provenance", "must be an object", got=Verbatim(_kind(provenance))))
    return problems
