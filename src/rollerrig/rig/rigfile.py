"""The rig parameter file: TOML entries with value, unit and provenance, read and written.

A rig file is TOML. Every physical value is an inline table with its value, its unit and where
it comes from; a value the source does not give carries its reasoning as an ``assumption``::

    [inertia]
    roller = { value = 45.0, unit = "kg.m^2", source = "Kayaalp 4.5.1.5 (J5)" }

    [bearing]
    wheel_bearing_radius = { value = 60.0, unit = "mm", assumption = "120 mm axle bearing bore" }

Only the two ``[meta]`` entries (``name``, ``description``) are plain strings. Reading checks,
with pydantic, the section and key names and the form of each entry; converts each value to SI
with :mod:`rollerrig.units` (the unit must be an accepted unit of the field's quantity); then
validates the SI sections of :mod:`rollerrig.rig.sections` (type, physical range, consistency).
Every problem of a file is reported at once, one line each in the package's error format
(:mod:`rollerrig._validation`)::

    rig.toml: inertia.roller: must be > 0 [kg.m^2]; allowed (0, inf); got -45
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    create_model,
    model_validator,
)

from rollerrig._validation import (
    FieldProblem,
    ParameterError,
    Problem,
    Verbatim,
    pydantic_problems,
    show_value,
    toml_string,
)
from rollerrig.rig.sections import SECTIONS, MetaParameters, quantity_of, si_unit_of
from rollerrig.units import UnitError, apply_factor, normalize_unit, quantity_factor

__all__ = ["RigFileError", "read_sections", "si_value", "validate_sections", "write_sections"]


class RigFileError(ParameterError):
    """A rig parameter file (or an override) is malformed or non-physical.

    The message has one line per problem, each naming the file and the ``section.key``.

    Attributes
    ----------
    origin : str
        The file (or ``"overrides"``) the problems were found in.
    problems : list of str
        One line per problem, ``<file>: <section.key>: ...``.
    """

    def __init__(self, origin: str, problems: list[Problem | str]):
        self.origin = origin
        self.problems = [
            p.format(origin) if isinstance(p, Problem) else f"{origin}: {p}" for p in problems
        ]
        super().__init__("\n".join(self.problems))


# --------------------------------------------------------------------------------------------
# The form of the file (pydantic): sections of entries { value, unit, source | assumption }
# --------------------------------------------------------------------------------------------

_ENTRY_FORM = "an inline table { value = ..., unit = ..., source | assumption = ... }"


class _Entry(BaseModel):
    """One physical value as written: value, unit and exactly one of source or assumption."""

    model_config = ConfigDict(extra="forbid", strict=True)

    value: Any
    unit: str = Field(min_length=1)
    source: str | None = Field(None, min_length=1)
    assumption: str | None = Field(None, min_length=1)

    @model_validator(mode="before")
    @classmethod
    def _table(cls, data):
        if not isinstance(data, Mapping):
            raise FieldProblem("", f"must be {_ENTRY_FORM}", got=data)
        return data

    @model_validator(mode="after")
    def _one_provenance(self):
        given = [k for k in ("source", "assumption") if getattr(self, k) is not None]
        if len(given) != 1:
            raise FieldProblem(
                "", "needs exactly one of 'source' or 'assumption'", got=Verbatim(given or "none")
            )
        for kind in given:
            if not getattr(self, kind).strip():
                raise FieldProblem(kind, "must not be blank")
        return self

    @property
    def provenance(self) -> dict[str, Any]:
        kind = "source" if self.source is not None else "assumption"
        return {"value": self.value, "unit": self.unit, kind: getattr(self, kind)}


def _file_model(model: type[BaseModel]) -> type[BaseModel]:
    """The form of one section in the file: the SI model's keys, each an :class:`_Entry`."""
    if model is MetaParameters:
        return model  # plain strings
    fields = {
        key: (_Entry, ... if field.is_required() else None)
        for key, field in model.model_fields.items()
    }
    config = ConfigDict(extra="forbid", strict=True)
    return create_model(f"{model.__name__}File", __config__=config, **fields)


_FILE_SECTIONS = {section: _file_model(model) for section, model in SECTIONS.items()}


def _optional_section(model: type[BaseModel]) -> bool:
    """A section whose every key has a default may be left out of a file (rig files written
    before it existed still load)."""
    return model is not MetaParameters and not any(
        f.is_required() for f in model.model_fields.values()
    )


_FILE = create_model(
    "RigFile",
    __config__=ConfigDict(extra="forbid", strict=True),
    **{
        section: (dict[str, Any], None if _optional_section(model) else ...)
        for section, model in SECTIONS.items()
    },
)


def _section_problems(exc: ValidationError, model, prefix: str = "") -> list[Problem]:
    """Problems of a file-level validation; top-level keys are sections."""
    out = []
    for p in pydantic_problems(exc, model=model, prefix=prefix):
        if "." not in p.key and p.message.split(" (")[0] in ("missing key", "unknown key"):
            p = dataclasses.replace(p, message=p.message.replace(" key", " section", 1))
        out.append(p)
    return out


# --------------------------------------------------------------------------------------------
# Values: file unit -> SI
# --------------------------------------------------------------------------------------------


def si_value(field, raw: Any, unit: Any, key: str) -> Any:
    """SI value of ``raw`` [unit] for a section field; a :class:`Problem` is raised as
    :class:`FieldProblem`.

    A number is converted with the factor of its unit (:func:`rollerrig.units.apply_factor`),
    as a float for a float field; an integer field keeps an integer given in a unit of factor 1.
    Anything else is passed on for the SI model to reject with its type.
    """
    try:
        factor = quantity_factor(unit, quantity_of(field))
    except UnitError as exc:
        p = exc.problem
        raise FieldProblem(
            f"{key}.unit", p.message, unit=p.unit, allowed=p.allowed, got=p.got
        ) from None
    if isinstance(raw, bool) or not isinstance(raw, int | float):
        return raw
    if field.annotation is float:
        return apply_factor(float(raw), factor)
    return raw if factor == 1.0 else apply_factor(raw, factor)


def read_sections(data: Mapping[str, Any], origin: str) -> tuple[dict, dict]:
    """``(SI sections, provenance)`` of the parsed TOML ``data`` of a rig file.

    Returns
    -------
    sections : dict
        ``section -> validated SI model`` (see :mod:`rollerrig.rig.sections`).
    provenance : dict
        ``"section.key" -> {"value", "unit", "source" | "assumption"}`` as written.

    Raises
    ------
    RigFileError
        Every problem of the file: unknown or missing section or key, an entry not of the form
        ``{ value, unit, source | assumption }``, a unit not accepted for the quantity, a value
        of the wrong type, not finite or out of its physical range.
    """
    problems: list[Problem] = []
    try:
        _FILE.model_validate(data)
    except ValidationError as exc:
        problems += _section_problems(exc, _FILE)
    si: dict[str, dict[str, Any]] = {}
    provenance: dict[str, dict[str, Any]] = {}
    shown: dict[str, Any] = {}
    for section, model in SECTIONS.items():
        table = data.get(section)
        if table is None and _optional_section(model):
            table = {}  # every key takes its default
        if not isinstance(table, Mapping):
            continue
        try:
            entries = _FILE_SECTIONS[section].model_validate(table)
        except ValidationError as exc:
            problems += _section_problems(exc, _FILE_SECTIONS[section], section)
            continue
        if model is MetaParameters:
            si[section] = entries.model_dump()
            continue
        values: dict[str, Any] = {}
        for key, field in model.model_fields.items():
            entry = getattr(entries, key)
            if entry is None:
                continue
            name = f"{section}.{key}"
            try:
                values[key] = si_value(field, entry.value, entry.unit, name)
            except FieldProblem as exc:
                problems.append(exc.problem)
                continue
            provenance[name] = entry.provenance
            if normalize_unit(entry.unit) != si_unit_of(field):
                shown[name] = f"{show_value(entry.value)} {entry.unit}"
        if len(values) == sum(getattr(entries, k) is not None for k in model.model_fields):
            si[section] = values  # range-check only the sections whose units all converted
    sections, more = validate_sections(si, shown)
    if problems or more:
        raise RigFileError(origin, problems + more)
    return sections, provenance


def validate_sections(
    si: Mapping[str, Mapping[str, Any]], shown: Mapping[str, str] | None = None
) -> tuple[dict[str, BaseModel], list[Problem]]:
    """Validate each SI section present in ``si``: the models, and the problems found.

    ``shown`` maps ``"section.key"`` to the value as written (``"-43.5 kN.m/rad"``), added to a
    problem's ``got`` when the file did not give the value in SI.
    """
    shown = shown or {}
    models: dict[str, BaseModel] = {}
    problems: list[Problem] = []
    for section, model in SECTIONS.items():
        if section not in si:
            continue
        try:
            models[section] = model.model_validate(si[section])
        except ValidationError as exc:
            units = {f"{section}.{k}": _error_unit(f) for k, f in _si_fields(model)}
            for p in pydantic_problems(exc, units, model=model, prefix=section):
                if p.key in shown and isinstance(p.got, int | float):
                    p = dataclasses.replace(
                        p, got=Verbatim(f"{show_value(p.got)} (written {shown[p.key]})")
                    )
                problems.append(p)
    return models, problems


def _error_unit(field) -> str:
    """The unit an error of ``field`` shows: what a ratio is a multiple of where the field says
    (``json_schema_extra["unit"]``, the ``[roller_drive_vf]`` keys), else its SI unit."""
    return field.json_schema_extra.get("unit") or si_unit_of(field)


def _si_fields(model: type[BaseModel]):
    return [(k, f) for k, f in model.model_fields.items() if f.json_schema_extra]


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


def _toml_value(value: Any) -> str:
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    return repr(float(value))  # '45.0', '1e-05': valid TOML floats


def write_sections(sections: Mapping[str, BaseModel], provenance: Mapping[str, Mapping]) -> str:
    """The TOML text of a parameter set, in the form :func:`read_sections` reads.

    Each value is written in the unit it was given in (its provenance) when that reproduces the
    SI value exactly, otherwise in SI.
    """
    lines = [
        "# rollerrig rig parameter set (written by rollerrig.rig.save_rig).",
        "# Each value: { value, unit, source | assumption }. SI inside the package.",
        "",
    ]
    for section, model in SECTIONS.items():
        lines.append(f"[{section}]")
        values = sections[section]
        for key, field in model.model_fields.items():
            value = getattr(values, key)
            if model is MetaParameters:
                lines.append(f"{key} = {toml_string(value)}")
                continue
            record = provenance.get(f"{section}.{key}", {})
            written, unit = value, si_unit_of(field)
            if "value" in record and isinstance(record.get("unit"), str):
                try:
                    again = si_value(field, record["value"], record["unit"], key)
                except FieldProblem:
                    again = None
                if again == value and type(again) is type(value):
                    written, unit = record["value"], record["unit"]
            kind = "source" if "source" in record else "assumption"
            text = record.get(kind, "no provenance recorded (set in Python)")
            lines.append(
                f"{key} = {{ value = {_toml_value(written)}, unit = {toml_string(unit)}, "
                f"{kind} = {toml_string(text)} }}"
            )
        lines.append("")
    return "\n".join(lines)
