"""A calibration holds for the rig it was made on: the record of that rig and the check.

``calibration.json`` records the rig its calibration was made on (``rig``,
:func:`rig_binding`): its name, every value [SI] before the calibration, and the SHA-256 of
those values without the calibrated keys. :func:`check_rig` compares the rig in use with it: a
rig that differs in any other key is another rig, one error naming both rigs (file, name, hash)
and the first keys that differ, unless the user insists (``allow_other_rig``: a warning, which
the command records in its outputs' provenance). The calibrated rig ``calibrated-rig.toml``
differs only in the calibrated keys: it is the same rig. A file from before the binding was
recorded holds only the hash of its whole rig (``provenance.rig.sha256``), checked with the
calibrated keys at their starting values; a file with neither (written by hand) cannot be
checked, which is a warning. :func:`check_values_on_rig` then applies the calibrated values to
the rig in use with the rig's own checks.

Examples
--------
>>> from rollerrig.rig.parameters import default_rig
>>> rig = default_rig()
>>> doc = {"parameters": {"inertia.roller": {"value": 46.0, "standard_error": 0.5}},
...        "rig": rig_binding(rig, ["inertia.roller"])}
>>> check_rig(doc, rig.with_overrides({"inertia.roller": 46.0}))
('same rig', None)
>>> try:  # doctest: +ELLIPSIS
...     check_rig(doc, rig.with_overrides({"stiffness.am_mount": 2e5}))
... except CalibrationError as exc:
...     print(str(exc).split(". ")[0])
calibration.json: rig: made on another rig: they differ in stiffness.am_mount (500000 there, ...
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Iterable, Mapping
from typing import Any

from rollerrig._validation import Problem, Verbatim, show_value
from rollerrig.calibrate.calibfile import _factor_problems, _fail, _is_number
from rollerrig.calibrate.problem import CalibrationError, is_law_key
from rollerrig.output.jsonfile import SIGNIFICANT_DIGITS
from rollerrig.rig.parameters import rig_values

__all__ = [
    "calibrated_rig_keys",
    "check_rig",
    "check_values_on_rig",
    "rig_binding",
    "rig_values",
]

_SHOWN_DIFFERENCES = 5  # keys named in a mismatch of the rig


def _values_sha256(values: Mapping[str, Any]) -> str:
    text = json.dumps(dict(values), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def rig_binding(rig, calibrated: Iterable[str]) -> dict[str, Any]:
    """The record of the rig a calibration was made on (``rig`` in ``calibration.json``).

    Parameters
    ----------
    rig : RigParameters
        The rig the calibration started from.
    calibrated : iterable of str
        The rig keys whose values the calibration replaces.

    Returns
    -------
    dict
        ``name``, ``sha256`` (:func:`rollerrig.output.rig_sha256` of the whole rig, as in the
        provenance), ``calibrated_keys``, ``parameters_sha256`` (SHA-256 of the canonical JSON
        of the values without the calibrated keys: the rig's identity) and ``parameters`` (every
        value outside ``[meta]`` [SI]).
    """
    from rollerrig.output.provenance import rig_sha256

    keys = sorted(set(calibrated))
    values = rig_values(rig)
    return {
        "what": (
            "the rig this calibration was made on: its values [SI] before the calibration. "
            "`rollerrig analyze --calibration` refuses a rig that differs in any key but the "
            "calibrated ones (--allow-other-rig: used with a warning). parameters_sha256: "
            "SHA-256 of the sorted, compact JSON of parameters without calibrated_keys"
        ),
        "name": rig.meta.name,
        "sha256": rig_sha256(rig),
        "calibrated_keys": keys,
        "parameters_sha256": _values_sha256({k: v for k, v in values.items() if k not in keys}),
        "parameters": values,
    }


def calibrated_rig_keys(data: Mapping[str, Any]) -> list[str]:
    """The rig keys a (checked) calibration gives a value for (not the creep law's
    ``polach.*``, ``fastsim.*``)."""
    params = data.get("parameters") or {}
    return [
        k
        for k, e in params.items()
        if not is_law_key(k) and isinstance(e, dict) and e.get("value") is not None
    ]


_SAME_RTOL = 10.0 ** (1 - SIGNIFICANT_DIGITS)
"""Relative tolerance of "the same value" between a calibration file and a rig [-]: the JSON
writer keeps 12 significant digits (up to 5e-12 relative off), so 1256.6370614359173 is read
back as 1256.63706144 and is still the same rig."""


def _same(a: Any, b: Any) -> bool:
    if _is_number(a) and _is_number(b):
        return math.isclose(float(a), float(b), rel_tol=_SAME_RTOL, abs_tol=0.0)
    return a == b


def _rig_file(data: Mapping[str, Any]) -> str:
    """Which file the calibration's rig came from, as its provenance says."""
    provenance = data.get("provenance")
    if not isinstance(provenance, dict):
        return "rig file not recorded"
    inputs = provenance.get("inputs")
    rig = inputs.get("rig") if isinstance(inputs, dict) else None
    if isinstance(rig, dict) and isinstance(rig.get("path"), str):
        return rig["path"]
    return "the bundled rig" if isinstance(inputs, dict) else "rig file not recorded"


def _legacy_match(data: Mapping[str, Any], rig, sha: str) -> bool:
    """Whether ``rig``, with the calibrated keys at their starting values and the name and
    description before calibration, has the whole-rig hash ``sha``."""
    from rollerrig.output.provenance import rig_sha256

    params = data.get("parameters") or {}
    starts = {
        k: e["initial"]
        for k in calibrated_rig_keys(data)
        if _is_number((e := params[k]).get("initial"))
    }
    try:
        start = rig.with_overrides(starts) if starts else rig
    except ValueError:
        return False
    meta = start.meta
    name = meta.name.removesuffix("-calibrated")
    description = meta.description.split(" Calibrated by rollerrig calibrate on ")[0]
    restored = start.model_copy(
        update={"meta": meta.model_copy(update={"name": name, "description": description})}
    )
    return sha in (rig_sha256(start), rig_sha256(restored))


def check_rig(
    data: Mapping[str, Any],
    rig,
    *,
    source: str = "calibration.json",
    rig_source: str = "the bundled rig",
    allow_other_rig: bool = False,
) -> tuple[str, str | None]:
    """Whether a calibration was made on ``rig``; an error if not (unless allowed).

    Parameters
    ----------
    data : mapping
        A checked ``calibration.json`` (:func:`check_calibration`).
    rig : RigParameters
        The rig in use.
    source : str
        How errors name the calibration file.
    rig_source : str
        How to name the rig in use (its file).
    allow_other_rig : bool
        Use a calibration of another rig anyway (a warning instead of the error).

    Returns
    -------
    status : str
        ``"same rig"``, ``"other rig"`` (allowed) or ``"not recorded"``.
    warning : str or None
        What the command must print and record in its outputs' provenance.

    Raises
    ------
    CalibrationError
        Another rig, naming both rigs (file, name, hash) and the first keys that differ.
    """
    from rollerrig.output.provenance import rig_sha256

    calibrated = set(calibrated_rig_keys(data))
    here_values = rig_values(rig)
    record = data.get("rig")
    there_file = _rig_file(data)
    provenance = data.get("provenance") if isinstance(data.get("provenance"), dict) else {}
    legacy = provenance.get("rig") if isinstance(provenance.get("rig"), dict) else None
    if isinstance(record, dict) and isinstance(record.get("parameters"), dict):
        recorded = record["parameters"]
        excluded = calibrated | set(record.get("calibrated_keys") or [])
        differ = [
            k
            for k, v in recorded.items()
            if k not in excluded and k in here_values and not _same(v, here_values[k])
        ]
        if not differ:
            return "same rig", None
        there_name = record.get("name")
        there_hash = record.get("parameters_sha256") or "not recorded"
        here_hash = _values_sha256(
            {k: v for k, v in here_values.items() if k in recorded and k not in excluded}
        )
        shown = ", ".join(
            f"{k} ({show_value(recorded[k])} there, {show_value(here_values[k])} here)"
            for k in differ[:_SHOWN_DIFFERENCES]
        )
        more = len(differ) - _SHOWN_DIFFERENCES
        what = f"they differ in {shown}" + (f" and {more} more key(s)" if more > 0 else "")
        head = "made on another rig"
    elif legacy is not None and isinstance(legacy.get("sha256"), str):
        if _legacy_match(data, rig, legacy["sha256"]):
            return "same rig", None
        there_name, there_hash, here_hash = legacy.get("name"), legacy["sha256"], rig_sha256(rig)
        what = (
            "it records only the SHA-256 of its whole rig (written by an older rollerrig), "
            "which the rig in use does not have with the calibrated keys at their starting "
            "values (another rig, or the same one read by a rollerrig whose rig files have "
            "gained keys since; which keys differ is not recorded)"
        )
        head = "not shown to be made on this rig"
    else:
        return "not recorded", (
            f"{source}: records no rig it was made on (written by hand or edited): whether it "
            f"belongs to the rig in use ({rig.meta.name!r}, {rig_source}) cannot be checked"
        )
    there = f"{there_name!r} ({there_file}; sha256 {str(there_hash)[:12]})"
    here = f"{rig.meta.name!r} ({rig_source}; sha256 {here_hash[:12]})"
    if allow_other_rig:
        return "other rig", (
            f"{source}: {head}, used as --allow-other-rig asks: made on rig {there}, used on "
            f"rig {here}: {what}; its values and standard errors belong to the rig it was "
            "made on"
        )
    raise _fail(
        source,
        [
            Problem(
                "rig",
                f"{head}: {what}. Use the rig it was made on (or the "
                "calibrated-rig.toml written beside it), calibrate again on this rig, or pass "
                "--allow-other-rig to use it anyway",
                allowed=Verbatim(f"the rig {there}"),
                got=Verbatim(f"the rig {here}"),
            )
        ],
    )


def check_values_on_rig(data: Mapping[str, Any], rig, source: str = "calibration.json") -> None:
    """The calibrated rig keys as the rig in use takes them: each within :data:`MAX_FACTOR` of
    the rig's value, and the rig with them passing its own checks (the consistency of each
    section, e.g. ``pmsm.max_current >= pmsm.rated_current``).

    Raises
    ------
    CalibrationError
        Naming ``source: key.value`` (or the key the rig's check names).
    """
    params = data.get("parameters") or {}
    values = {k: float(params[k]["value"]) for k in calibrated_rig_keys(data)}
    here = rig_values(rig)
    problems: list[Problem] = []
    for key, value in values.items():
        if _is_number(here.get(key)):
            problems += _factor_problems(key, value, float(here[key]), "the rig's value")
    if problems:
        raise _fail(source, problems)
    if not values:
        return
    try:
        rig.with_overrides(values)
    except ValueError as exc:
        lines = []
        for line in getattr(exc, "problems", None) or [str(exc)]:
            text = str(line).removeprefix("overrides: ")
            key, sep, rest = text.partition(": ")
            if sep and key in values:
                text = f"{key}.value: {rest}"
            lines.append(f"{source}: {text} (with the calibrated values on rig {rig.meta.name!r})")
        err = CalibrationError("\n".join(lines))
        err.problems = tuple(lines)
        raise err from None
