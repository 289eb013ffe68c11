"""The one TOML reader of the package: size and nesting limits stated and enforced.

Every user file the package reads as TOML (rig, experiment, study, frame, channel map) goes
through :func:`parse_toml` or :func:`read_toml`. Python's :mod:`tomllib` parses nested inline
tables and arrays recursively, so a file nested a hundred thousand levels deep ends in a
``RecursionError``; dotted keys (``a.a.a.a…``) are parsed iteratively but make a structure that
every recursive walk downstream would trip on. Both are refused here, before any reader sees
the data, with the same :class:`tomllib.TOMLDecodeError` each reader already reports as
"not valid TOML", so one message names the file and the limit.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Any

__all__ = ["MAX_TOML_BYTES", "MAX_TOML_DEPTH", "parse_toml", "read_toml"]

MAX_TOML_BYTES = 16 * 2**20
"""Largest TOML file read (16 MiB): the biggest real input, a frame at its limit of 200 members,
is well below 1 MiB."""

MAX_TOML_DEPTH = 16
"""Deepest nesting of tables and arrays accepted; the package's own files nest at most 4 deep."""


# A dotted key of thousands of parts costs tomllib quadratic time before any depth check can
# run (16 000 parts: 4 s), so it is found in the text first: 64 dots, each after a non-empty
# segment, on one line with no '=', bracket, brace or comma between them (generous, so that a
# comment full of section numbers is not taken for a key; deeper keys than MAX_TOML_DEPTH that
# pass this are caught after parsing).
_DOTTED_PARTS = 64
_DOTTED = re.compile(r"(?:[^.\n=\[\]{},]+\.){" + str(_DOTTED_PARTS) + "}")


def _depth_problem(data: Any) -> str | None:
    """Where the structure is nested deeper than :data:`MAX_TOML_DEPTH` (walked iteratively)."""
    stack: list[tuple[Any, int, str]] = [(data, 0, "")]
    while stack:
        node, depth, where = stack.pop()
        if depth > MAX_TOML_DEPTH:
            return where or "the top level"
        if isinstance(node, dict):
            for key, value in node.items():
                if isinstance(value, (dict, list)):
                    stack.append((value, depth + 1, f"{where}.{key}" if where else str(key)))
        elif isinstance(node, list):
            for i, value in enumerate(node):
                if isinstance(value, (dict, list)):
                    stack.append((value, depth + 1, f"{where}[{i}]"))
    return None


def parse_toml(text: str) -> dict[str, Any]:
    """Parse TOML text with the package's limits.

    Raises
    ------
    tomllib.TOMLDecodeError
        Invalid TOML, a text larger than :data:`MAX_TOML_BYTES` or nested deeper than
        :data:`MAX_TOML_DEPTH` (the message names the limit and, for depth, where).

    Examples
    --------
    >>> parse_toml("a = { b = 1 }")
    {'a': {'b': 1}}
    >>> parse_toml("x = " + "[" * 40 + "]" * 40)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    tomllib.TOMLDecodeError: nested deeper than 16 levels at x[0][0]...
    """
    if len(text) > MAX_TOML_BYTES:
        raise tomllib.TOMLDecodeError(
            f"{len(text)} characters, more than the limit of {MAX_TOML_BYTES} for a TOML file"
        )
    dotted = _DOTTED.search(text)
    if dotted is not None:
        line = text.count("\n", 0, dotted.start()) + 1
        raise tomllib.TOMLDecodeError(
            f"a key of more than {_DOTTED_PARTS} dotted parts on line {line} (nested deeper "
            "than the limit of rollerrig's files)"
        )
    try:
        data = tomllib.loads(text)
    except RecursionError:
        raise tomllib.TOMLDecodeError(
            f"nested deeper than {MAX_TOML_DEPTH} levels (the limit of rollerrig's files)"
        ) from None
    where = _depth_problem(data)
    if where is not None:
        raise tomllib.TOMLDecodeError(
            f"nested deeper than {MAX_TOML_DEPTH} levels at {where} (the limit of rollerrig's "
            "files)"
        )
    return data


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read and parse a TOML file (UTF-8) with the limits of :func:`parse_toml`.

    Raises
    ------
    OSError
        The file cannot be read.
    UnicodeDecodeError
        It is not UTF-8 text.
    tomllib.TOMLDecodeError
        As :func:`parse_toml`; a file larger than the limit is refused before it is read.
    """
    path = Path(path)
    size = path.stat().st_size
    if size > MAX_TOML_BYTES:
        raise tomllib.TOMLDecodeError(
            f"{size} bytes, more than the limit of {MAX_TOML_BYTES} for a TOML file"
        )
    return parse_toml(path.read_bytes().decode("utf-8"))
