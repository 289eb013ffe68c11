"""The form of a channel map file, validated with pydantic: what each table and key may hold.

:class:`MapFile` is the whole TOML file; :class:`FileSpec` (the ``[file]`` table) is also the
object the readers take. Problems are reported by :meth:`rollerrig.recordings.channels.ChannelMap.
from_dict` in the package's one error format (:mod:`rollerrig._validation`), with the dotted key
(``file.separator``, ``channels.torque.scale``), the unit, the allowed values and the value found.
What pydantic cannot know (canonical channel names, units that fit them) is checked there.

Examples
--------
>>> MapFile.model_validate({"channels": {"torque": {"column": "T", "unit": "N.m"}}}).channels
{'torque': EntrySection(column='T', unit='N.m', scale=1.0, offset=0.0, description=None, \
optional=False)}
>>> FileSpec(separator=";", decimal=",").to_dict()
{'separator': ';', 'decimal': ','}
"""

from __future__ import annotations

import codecs
from typing import Annotated, Any, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    Strict,
    model_validator,
)
from pydantic.dataclasses import dataclass as pydantic_dataclass

from rollerrig._validation import FieldProblem
from rollerrig.recordings.validate import MAX_SAMPLE_RATE_HZ
from rollerrig.units import QUANTITIES, normalize_unit

__all__ = ["DECIMALS", "SEPARATORS", "EntrySection", "FileSpec", "MapFile", "TimeSection"]

_TIME_UNITS = QUANTITIES["time"].units

SEPARATORS: dict[str, str] = {
    ",": "comma",
    ";": "semicolon",
    "\t": "tab",
    " ": "whitespace: any run of spaces or tabs",
    "|": "pipe",
}
"""Column separators of text files accepted in ``[file] separator``."""

DECIMALS: tuple[str, ...] = (".", ",")
"""Decimal marks accepted in ``[file] decimal``."""


def _line_index(value: Any) -> Any:
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
        raise FieldProblem("", "must be a 0-based line index", allowed="an integer >= 0", got=value)
    return value


def _units_row(value: Any) -> Any:
    if value is False or value is None:
        return value
    if value is True:
        raise FieldProblem(
            "",
            "must be a 0-based line index or false",
            allowed="an integer >= 0 or false",
            got=True,
        )
    return _line_index(value)


def _separator(value: Any) -> Any:
    if value is not None and value not in SEPARATORS:
        raise FieldProblem("", "not an accepted separator", allowed=SEPARATORS, got=value)
    return value


def _encoding(value: str | None) -> str | None:
    if value is not None:
        try:
            codecs.lookup(value)
        except LookupError:
            raise FieldProblem(
                "",
                "not a known text encoding",
                allowed="e.g. 'utf-8', 'utf-8-sig', 'latin-1', 'cp1252', 'utf-16'",
                got=value,
            ) from None
    return value


def _date_format(value: str | None) -> str | None:
    if value is not None and "%" not in value:
        raise FieldProblem(
            "",
            "must be a strptime format",
            allowed="e.g. '%d.%m.%y %H:%M:%S'",
            got=value,
        )
    return value


def _name_or_index(what: str):
    """The validator of a ``[file]`` key that names a table of the file (a TDMS/MDF group, a
    workbook's sheet): a non-empty name or a 0-based index."""

    def check(value: Any) -> Any:
        if value is not None and (
            isinstance(value, bool)
            or not isinstance(value, str | int)
            or (isinstance(value, str) and not value)
            or (isinstance(value, int) and value < 0)
        ):
            raise FieldProblem(
                "",
                f"must be a {what} name or a 0-based {what} index",
                allowed="a name or an integer >= 0",
                got=value,
            )
        return value

    return check


_STRICT = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)
_LineIndex = Annotated[int | None, BeforeValidator(_line_index)]


# Not strict as a whole, so that a map's [file] table (a dict) validates into it; its fields
# are checked by the validators above, and ``dayfirst`` is a strict bool.
@pydantic_dataclass(frozen=True, config=ConfigDict(extra="forbid"))
class FileSpec:
    """How to read a file: the ``[file]`` section of a channel map. None: sniffed.

    Validated on construction (pydantic); a :class:`pydantic.ValidationError` names the key.

    Parameters
    ----------
    separator : str or None
        Column separator of a text file, a key of :data:`SEPARATORS` (``" "``: any run of
        whitespace).
    decimal : str or None
        Decimal mark of a text file, ``"."`` or ``","``.
    header_row : int or None
        0-based line index of the column names, counting every line of the file (preamble and
        blank lines included).
    units_row : int, False or None
        0-based line index of a units row (e.g. ``s;N.m;1/min`` under the header); False: the file
        has none; None: detected (a non-numeric row between the header and the numbers whose
        cells look like units).
    data_row : int or None
        0-based line index of the first row of numbers (default: the first non-blank line after
        the header / units row).
    encoding : str or None
        Text encoding (default: UTF-8 with or without BOM, falling back to Latin-1, noted).
    dayfirst : bool or None
        Whether slash dates (``05/08/24``) are day-first. Dotted dates (``05.08.24``) are
        day-first by convention; ISO dates (``2024-08-05``) are year-month-day.
    date_format : str or None
        :func:`time.strptime` format of a timestamp time column (beats ``dayfirst``).
    group : str, int or None
        TDMS / MDF group that channel names default to (MDF: the group's name or index).
    sheet : str, int or None
        Excel workbook: the sheet to read, by name or 0-based index (default: the first sheet
        that holds numbers). Not ``group``: a sheet is the table read, a group only where
        unqualified names resolve.
    """

    separator: Annotated[str | None, BeforeValidator(_separator)] = None
    decimal: Literal[".", ","] | None = None
    header_row: _LineIndex = None
    units_row: Annotated[int | bool | None, BeforeValidator(_units_row)] = None
    data_row: _LineIndex = None
    encoding: Annotated[str | None, AfterValidator(_encoding)] = None
    dayfirst: Annotated[bool, Strict()] | None = None
    date_format: Annotated[str | None, AfterValidator(_date_format)] = None
    group: Annotated[str | int | None, BeforeValidator(_name_or_index("group"))] = None
    sheet: Annotated[str | int | None, BeforeValidator(_name_or_index("sheet"))] = None

    @model_validator(mode="after")
    def _consistent(self):
        if self.separator is not None and self.separator == self.decimal:
            raise FieldProblem("decimal", "must differ from file.separator", got=self.decimal)
        header, units, data = self.header_row, self.units_row, self.data_row
        rows = [r for r in (header, units) if r is not None and r is not False]
        if header is not None and units is not None and units is not False and units <= header:
            raise FieldProblem(
                "units_row", "must come after file.header_row", allowed=f"> {header}", got=units
            )
        if data is not None and rows and data <= max(rows):
            raise FieldProblem(
                "data_row",
                "must come after the header / units rows",
                allowed=f"> {max(rows)}",
                got=data,
            )
        return self

    def to_dict(self) -> dict[str, Any]:
        """The keys that are set (for provenance)."""
        return {
            k: getattr(self, k) for k in self.__dataclass_fields__ if getattr(self, k) is not None
        }


def _time_unit(value: str) -> str:
    if normalize_unit(value) not in _TIME_UNITS:
        raise FieldProblem("", "not a time unit", allowed=list(_TIME_UNITS), got=value)
    return value


def _non_zero(value: float) -> float:
    if value == 0.0:
        raise FieldProblem("", "must be non-zero", got=value)
    return value


def _not_blank(value: str | None) -> str | None:
    if value is not None and not value.strip():
        raise FieldProblem("", "must not be blank", got=value)
    return value


class TimeSection(BaseModel):
    """``[time]``: a time column (with its unit) or a sample rate; a common time base."""

    model_config = _STRICT

    column: str | None = Field(None, min_length=1)
    unit: Annotated[str, AfterValidator(_time_unit)] = "s"
    sample_rate_Hz: float | None = Field(
        None, gt=0, le=MAX_SAMPLE_RATE_HZ, json_schema_extra={"unit": "Hz"}
    )
    resample_Hz: float | None = Field(
        None, gt=0, le=MAX_SAMPLE_RATE_HZ, json_schema_extra={"unit": "Hz"}
    )

    @model_validator(mode="after")
    def _one_source(self):
        if self.column is not None and self.sample_rate_Hz is not None:
            raise FieldProblem("", "give either 'column' or 'sample_rate_Hz', not both")
        return self


class EntrySection(BaseModel):
    """``[channels.<name>]`` / ``[extra.<name>]``: one column, its unit and calibration."""

    model_config = _STRICT

    column: str = Field(min_length=1, description="the file's column / channel name")
    unit: Annotated[str | None, AfterValidator(_not_blank)] = None
    scale: Annotated[float, AfterValidator(_non_zero)] = 1.0
    offset: float = 0.0
    description: str | None = None
    optional: bool = False


class MapFile(BaseModel):
    """A channel map file: which column is which quantity, in which unit, in what layout."""

    # Not strict at this level, so that [file] (a table) validates into FileSpec (whose own
    # fields are strict); every other field is a strict model or a plain string.
    model_config = ConfigDict(extra="forbid")

    file: FileSpec | None = None
    time: TimeSection | None = None
    channels: dict[str, EntrySection] = {}
    extra: dict[str, EntrySection] = {}
    description: str | None = None
    name: str | None = None
