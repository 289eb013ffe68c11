"""JSON and text files: never NaN or inf, no float noise, provenance on every JSON object file.

Numbers: every float is written with the shortest text that reads back as the value rounded to
12 significant digits (:data:`SIGNIFICANT_DIGITS`; ``0.1 * 26.39`` = 2.6390000000000002 is
written ``2.639``), in :func:`write_json` and :func:`json_text` alike, so no call site rounds.
Data precision: a value read back is off by at most half a unit in its 12th significant digit
(5e-12 relative at most), far below what any sensor of a rig resolves (a 24-bit ADC: 6e-8 of
its range) and below the models' accuracy. Integers are written exactly.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.output.atomic import atomic_write
from rollerrig.output.provenance import jsonable, provenance

__all__ = [
    "META_KEY",
    "NULL_VALUES_KEY",
    "PROVENANCE_KEY",
    "SIGNIFICANT_DIGITS",
    "VARIABLES_KEY",
    "json_number",
    "json_text",
    "write_json",
    "write_text",
]

NULL_VALUES_KEY = "null_values"
"""Key under which :func:`write_json` lists the non-finite numbers it wrote as null."""
PROVENANCE_KEY = "provenance"
"""Key under which :func:`write_json` stores the provenance record of a top-level object (and
of the provenance record in a results file's metadata object, :mod:`rollerrig.output.tables`)."""
META_KEY = "rollerrig_metadata"
"""Where the metadata object (JSON) of a results file lives in TDMS, MAT and NetCDF files."""
VARIABLES_KEY = "variables"
"""Key of ``{column: {"units", "long_name", ...}}`` in a results file's metadata object."""
SIGNIFICANT_DIGITS = 12
"""Significant digits of the floats in JSON text (and in CSV files,
:mod:`rollerrig.output.tables`)."""


def json_number(value: float) -> float:
    """``value`` rounded to :data:`SIGNIFICANT_DIGITS` significant digits (finite floats; ``json``
    then writes it as its shortest repr: no float noise).

    Examples
    --------
    >>> json_number(0.1 * 26.39), json_number(1 / 3), json_number(-0.0)
    (2.639, 0.333333333333, -0.0)
    """
    return float(f"{value:.{SIGNIFICANT_DIGITS}g}")


def _finite_json(obj, where: str, replaced: list):
    """``obj`` with every NaN/inf float replaced by None, each replacement recorded, and every
    finite float rounded (:func:`json_number`); objects ``json`` cannot write as they are go
    through :func:`~rollerrig.output.provenance.jsonable` first, so their numbers are too."""
    if isinstance(obj, dict):
        out = {}
        for k, v in obj.items():
            key = _json_key(k, where)
            if key in out:  # {1: "a", "1": "b"}: JSON had held the key twice, a reader one
                raise ParameterError(
                    f"keys {key!r} and {k!r} of the object at {where or '/'} are the same "
                    "JSON key; give them different names"
                )
            out[key] = _finite_json(v, f"{where}/{k}", replaced)
        return out
    if isinstance(obj, list | tuple):
        return [_finite_json(v, f"{where}/{i}", replaced) for i, v in enumerate(obj)]
    if isinstance(obj, np.ndarray):
        return _finite_json(obj.tolist(), where, replaced)
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float):
        if not np.isfinite(obj):
            replaced.append({"at": where or "/", "was": repr(obj)})
            return None
        return json_number(obj)
    if obj is None or isinstance(obj, str | int):
        return obj
    try:
        plain = jsonable(obj)
    except TypeError:
        return obj  # json.dumps names what it cannot write
    return _finite_json(plain, where, replaced)


def _json_key(key: Any, where: str) -> str:
    """A dict key as the text JSON writes (``json`` writes int, float, bool and None keys as
    text), refusing a key it cannot write (a tuple)."""
    if isinstance(key, np.generic):
        key = key.item()
    if isinstance(key, str):
        return key
    if isinstance(key, bool) or key is None:
        return json.dumps(key)
    if isinstance(key, int):
        return str(key)
    if isinstance(key, float):
        return json.dumps(key) if np.isfinite(key) else repr(key)
    raise ParameterError(
        f"key {key!r} ({type(key).__name__}) of the object at {where or '/'} cannot be a JSON "
        "key; keys are str (or int, float, bool, None)"
    )


def _dumps(obj: Any, indent: int | None) -> str:
    """``json.dumps`` of a cleaned object; what JSON cannot hold refused naming what it is."""
    try:
        return json.dumps(obj, indent=indent, default=jsonable, allow_nan=False)
    except (TypeError, RecursionError) as exc:
        what = "a circular reference" if isinstance(exc, RecursionError) else str(exc)
        raise ParameterError(f"cannot write as JSON: {what}") from None
    except ValueError as exc:  # an integer of more than 4300 digits, a circular reference
        raise ParameterError(f"cannot write as JSON: {exc}") from None


def json_text(obj: Any, *, indent: int | None = None) -> str:
    """``obj`` as JSON text with non-finite numbers as null (for attributes and metadata).

    Examples
    --------
    >>> json_text({"a": float("nan"), "b": np.int64(2), "c": 0.1 * 26.39})
    '{"a": null, "b": 2, "c": 2.639}'
    """
    return _dumps(_clean(obj, []), indent)


def _clean(obj: Any, replaced: list) -> Any:
    """:func:`_finite_json` of ``obj``; a circular reference refused."""
    try:
        return _finite_json(obj, "", replaced)
    except RecursionError:
        raise ParameterError(
            "cannot write as JSON: a circular reference (or nesting deeper than "
            f"{sys.getrecursionlimit()} levels)"
        ) from None


def write_json(path: str | os.PathLike, obj: Any, *, overwrite: bool = True) -> Path:
    """Write ``obj`` as indented JSON, atomically; never NaN or inf; with provenance.

    Floats are rounded to 12 significant digits (see the module docstring): a value read back
    is off by at most half a unit in its 12th significant digit (5e-12 relative at most).

    NaN policy: JSON has no NaN or inf, and the package never writes them. Producers give
    ``None`` with a reason beside it wherever a number cannot be given; a non-finite float
    that still arrives here is written as ``null`` and listed, with its location (a
    ``/``-separated path) and its value, under the top-level key ``"null_values"`` (so a
    ``null`` never goes unexplained). A top-level value other than a dict holding a
    non-finite number is refused (``ValueError``), as is anything ``json`` cannot write.

    Provenance: a top-level dict without a ``"provenance"`` key gets one
    (:func:`rollerrig.output.provenance`, from the run context in effect).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = write_json(pathlib.Path(tempfile.mkdtemp()) / "x.json", {"a": float("nan")})
    >>> data = json.loads(p.read_text())
    >>> data["null_values"][0]["at"], data["provenance"]["software"]
    ('/a', 'rollerrig')
    """
    replaced: list = []
    try:
        clean = _clean(obj, replaced)
    except ParameterError as exc:
        raise ParameterError(f"{path}: {exc}") from None
    if replaced:
        if not isinstance(clean, dict):
            raise ParameterError(
                f"{path}: non-finite numbers at {[r['at'] for r in replaced]} and no top-level "
                "object to state why they are null"
            )
        if NULL_VALUES_KEY in clean:  # it had been replaced by the list, silently
            raise ParameterError(
                f"{path}: the object has a key {NULL_VALUES_KEY!r} of its own and non-finite "
                f"numbers at {[r['at'] for r in replaced]}, which write_json lists under that "
                "key; rename the key or give the numbers as None with a reason"
            )
        clean[NULL_VALUES_KEY] = [
            {**r, "why": "not a finite number; written as null"} for r in replaced
        ]
    if isinstance(clean, dict) and PROVENANCE_KEY not in clean:
        clean[PROVENANCE_KEY] = _finite_json(provenance(), "", [])
    try:
        text = _dumps(clean, 2)
    except ParameterError as exc:
        raise ParameterError(f"{path}: {exc}") from None
    return write_text(path, text + "\n", overwrite=overwrite)


def write_text(
    path: str | os.PathLike,
    text: str,
    *,
    overwrite: bool = True,
    comment: str | None = None,
) -> Path:
    r"""Write ``text`` (UTF-8) to ``path`` atomically.

    ``comment``: the comment marker of the text's format (``"#"``); the file then starts with
    one comment line holding the provenance record as JSON, so that a plain-text output carries
    it too. Without it the text is written as given (a TOML or HTML writer embeds provenance
    in its own way).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> write_text(pathlib.Path(tempfile.mkdtemp()) / "x.txt", "hi").read_text()
    'hi'
    >>> p = write_text(pathlib.Path(tempfile.mkdtemp()) / "t.txt", "table\n", comment="#")
    >>> first, rest = p.read_text().split("\n", 1)
    >>> first.startswith("# provenance: {"), rest
    (True, 'table\n')
    """
    if not isinstance(text, str):
        raise ParameterError(f"{path}: text must be a str, got a {type(text).__name__}")
    if comment is not None:
        record = json_text(provenance())
        text = f"{comment} provenance: {record}\n{text}"
    return atomic_write(path, lambda p: p.write_text(text, encoding="utf-8"), overwrite=overwrite)
