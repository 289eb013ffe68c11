"""Column names as each results format can store them: the one place where names are mapped.

Names come from recordings and DAQ software (``oil temp/bearing``, ``Group/Channel``,
``Öl-Temp``, ``[bold]x[/bold]``, ``1st harmonic``). CSV, Parquet, TDMS and MDF4 store any text
as a name; NetCDF and MATLAB do not:

- NetCDF (HDF5 underneath): ``/`` separates groups, and CF-1.10 (section 2.3, "Naming
  conventions") asks for names that begin with a letter and hold letters, digits and
  underscores only;
- MATLAB: a variable name is a letter, then letters, digits and ``_``, at most 63 characters
  (``namelengthmax``); ``time``, ``units``, ``provenance`` and ``rollerrig_metadata`` are
  taken by the file's own variables.

:func:`storable_names` maps every name to one such identifier: accents dropped (``Ö`` ->
``O``), every run of other characters one ``_``, ``v_`` in front of a name that does not start
with a letter, cut to the format's length, and ``_2``, ``_3``, ... appended where two names
would become one (a name that is already an identifier keeps it). The writer stores the name
it was given as the variable's ``original_name`` attribute, and readers of rollerrig's files
give the channel its original name back.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Iterable

from rollerrig._validation import ParameterError, did_you_mean, require_names

__all__ = ["FORMATS", "MAX_NAME_LENGTH", "ORIGINAL_NAME", "storable_name", "storable_names"]

ORIGINAL_NAME = "original_name"
"""Attribute (and metadata key) that keeps a renamed column's name as it was given."""

MAX_NAME_LENGTH = {"nc": 255, "mat": 63}
"""Formats whose names must be identifiers -> their longest name (characters)."""

_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")

FORMATS = ("csv", "parquet", "tdms", "mf4", "mat", "nc")
"""The results formats (the keys of :data:`rollerrig.output.tables.TABLE_FORMATS`)."""


def _check_format(format) -> str:
    """``format`` if it is one of :data:`FORMATS` (an unknown one had kept every name as it
    is: ``"netcdf"`` gave names NetCDF cannot store)."""
    if not isinstance(format, str) or format not in FORMATS:
        hint = did_you_mean(format, FORMATS) if isinstance(format, str) else ""
        raise ParameterError(f"format must be one of {list(FORMATS)}, got {format!r}{hint}")
    return format


def _check_name(what: str, name) -> str:
    if not isinstance(name, str):
        raise ParameterError(f"{what} must be a str, got {name!r} ({type(name).__name__})")
    return name


def storable_name(name: str, format: str) -> str:
    """``name`` as an identifier the format can store (before collisions are resolved).

    Examples
    --------
    >>> storable_name("oil temp/bearing", "nc"), storable_name("Öl-Temp [°C]", "mat")
    ('oil_temp_bearing', 'Ol_Temp_C')
    >>> storable_name("1st harmonic", "nc"), storable_name("Group/Channel", "csv")
    ('v_1st_harmonic', 'Group/Channel')
    """
    _check_name("name", name)
    limit = MAX_NAME_LENGTH.get(_check_format(format))
    if limit is None:
        return name
    if _IDENTIFIER.match(name) and len(name) <= limit:
        return name
    chars = []
    for ch in unicodedata.normalize("NFKD", str(name)):
        if unicodedata.combining(ch):
            continue  # the accent of a decomposed letter
        chars.append(ch if ch.isascii() and (ch.isalnum() or ch == "_") else "_")
    text = re.sub(r"_+", "_", "".join(chars)).strip("_")
    if not text[:1].isalpha():
        text = f"v_{text}" if text else "v"
    return text[:limit].rstrip("_")


def storable_names(
    names: Iterable[str], format: str, *, reserved: Iterable[str] = ()
) -> dict[str, str]:
    """Each name -> a distinct name the format stores (the name itself where it can).

    Parameters
    ----------
    names : iterable of str
        Column names as given (distinct).
    format : str
        A results format (``"csv"``, ``"parquet"``, ``"tdms"``, ``"mf4"``, ``"mat"``, ``"nc"``).
        Only ``"nc"`` and ``"mat"`` change names.
    reserved : iterable of str
        Names the file uses for itself (a column given one of them is renamed).

    Returns
    -------
    dict
        ``{given: stored}`` in the order given; distinct values, none of them reserved.

    Raises
    ------
    ParameterError
        ``names`` or ``reserved`` is a single str (not a list of names: ``["torque"]`` for
        one), or holds something that is not a str; ``format`` is not one of :data:`FORMATS`.

    Examples
    --------
    >>> storable_names(["a/b", "a_b", "a b", "units"], "mat", reserved=["units"])
    {'a/b': 'a_b_2', 'a_b': 'a_b', 'a b': 'a_b_3', 'units': 'units_2'}
    """
    names = require_names("names", names)
    reserved = require_names("reserved", reserved)
    limit = MAX_NAME_LENGTH.get(_check_format(format))
    if limit is None:
        return {n: n for n in names}
    taken = set(reserved)
    out: dict[str, str] = {}
    for name in names:  # identifiers keep their name: they claim it first
        if name not in taken and storable_name(name, format) == name:
            out[name] = name
            taken.add(name)
    for name in names:
        if name in out:
            continue
        base = storable_name(name, format)
        stored, k = base, 1
        while stored in taken:
            k += 1
            tail = f"_{k}"
            stored = base[: limit - len(tail)] + tail
        out[name] = stored
        taken.add(stored)
    return {n: out[n] for n in names}
