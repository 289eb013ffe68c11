"""Validated rig parameter sets: TOML files with units and provenance, SI objects in memory.

A rig file (see :mod:`rollerrig.rig.rigfile` for its form) gives every physical value with its
unit and its source or stated assumption. :func:`load_rig` checks it and returns a frozen
:class:`RigParameters` whose sections (:mod:`rollerrig.rig.sections`) hold plain SI floats;
units convert through the package's one unit registry, :mod:`rollerrig.units`. Every error
names the file and the ``section.key``, the unit and the allowed range.

The bundled default rig (:func:`default_rig`) is the tram wheel–roller rig of the University of
Pardubice as described in Kayaalp's dissertation ("Kayaalp", Table 1, Table 2, section 4.5.1.5);
see ``rollerrig/rig/data/default_rig.toml`` for the provenance of every value. The hash of a
parameter set, recorded with every output, is :func:`rollerrig.output.rig_sha256`.

Examples
--------
>>> rig = default_rig()
>>> rig.inertia.roller
45.0
>>> rig.stiffness.roller_shaft
43500.0
>>> rig.provenance["stiffness.roller_shaft"]["unit"]
'kN.m/rad'
>>> stiffer = rig.with_overrides({"stiffness.roller_shaft": (63.5, "kN.m/rad")})
>>> stiffer.stiffness.roller_shaft
63500.0
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from rollerrig._display import fmt, html_table, pretty_unit, text_block
from rollerrig._toml import parse_toml, read_toml
from rollerrig._validation import FieldProblem, Problem, Verbatim, show_value
from rollerrig.output import write_text
from rollerrig.rig.library import rig_set, rig_sets
from rollerrig.rig.rigfile import (
    RigFileError,
    read_sections,
    si_value,
    validate_sections,
    write_sections,
)
from rollerrig.rig.sections import (
    SECTIONS,
    ArmParameters,
    BearingParameters,
    DampingParameters,
    FrameParameters,
    GeometryParameters,
    InductionMotorParameters,
    InertiaParameters,
    MaterialParameters,
    MetaParameters,
    PmsmParameters,
    RollerDriveVfParameters,
    SensorParameters,
    ServoRollerDriveParameters,
    StiffnessParameters,
    si_unit_of,
)

__all__ = [
    "RigFileError",
    "RigParameters",
    "default_rig",
    "load_rig",
    "load_rig_set",
    "rig_values",
    "save_rig",
]
# The section models (InertiaParameters, ...) live in rollerrig.rig.sections; they are imported
# here for RigParameters and stay importable from this module.


class RigParameters(BaseModel):
    """A complete, validated rig parameter set in SI units.

    Load one with :func:`load_rig` or :func:`default_rig`; derive variants with
    :meth:`with_overrides`; write one with :func:`save_rig`.

    Attributes
    ----------
    provenance : dict
        ``"section.key" -> {"value": value as written, "unit": unit as written,
        "source" | "assumption": text}`` for every physical value.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    meta: MetaParameters
    inertia: InertiaParameters
    stiffness: StiffnessParameters
    damping: DampingParameters
    geometry: GeometryParameters
    material: MaterialParameters
    bearing: BearingParameters
    pmsm: PmsmParameters
    induction_motor: InductionMotorParameters
    servo_roller_drive: ServoRollerDriveParameters
    sensors: SensorParameters
    frame: FrameParameters = FrameParameters()
    roller_drive_vf: RollerDriveVfParameters = RollerDriveVfParameters()
    arm: ArmParameters = ArmParameters()
    provenance: dict[str, dict[str, Any]] = Field(
        default_factory=dict,
        description="'section.key' -> {'value', 'unit', 'source' | 'assumption'} as written.",
    )

    def _display_rows(self, sections=("inertia", "stiffness", "damping", "geometry")):
        """(section, key, value, unit) of the chain's sections, for the repr and HTML."""
        rows = []
        for section in sections:
            model = getattr(self, section)
            for key, field in type(model).model_fields.items():
                rows.append((section, key, getattr(model, key), pretty_unit(si_unit_of(field))))
        return rows

    def __repr__(self) -> str:
        """A few lines: the rig's name, its inertias, stiffnesses and radii."""
        lines = []
        for section in ("inertia", "stiffness", "geometry"):
            rows = self._display_rows((section,))
            units = sorted({r[3] for r in rows})
            unit = f" [{units[0]}]" if len(units) == 1 else ""
            lines.append(
                f"{section}{unit}: " + ", ".join(f"{key} {fmt(value)}" for _, key, value, _ in rows)
            )
        lines.append(
            f"{len(type(self).model_fields) - 1} sections; every value: .to_dict(), "
            "its source: .provenance"
        )
        return text_block(f"RigParameters {self.meta.name!r}", lines)

    def _repr_html_(self) -> str:
        """The rig's name and its chain (inertias, stiffnesses, damping, radii) as a table."""
        chain = self._display_rows()
        rows = [(f"{sec}.{key}", fmt(value), unit) for sec, key, value, unit in chain]
        return html_table(
            f"RigParameters {self.meta.name!r}",
            rows,
            header=("key", "value", "unit"),
            note=self.meta.description,
        )

    def to_dict(self, *, include_provenance: bool = False) -> dict[str, dict[str, Any]]:
        """Plain nested dict of SI values ``{section: {key: value}}`` (for provenance records).

        Examples
        --------
        >>> default_rig().to_dict()["geometry"]["wheel_radius_x"]
        0.348
        """
        exclude = None if include_provenance else {"provenance"}
        return self.model_dump(exclude=exclude)

    def with_overrides(self, overrides: Mapping[str, Any]) -> RigParameters:
        """New validated parameter set with some values replaced.

        Parameters
        ----------
        overrides : mapping
            ``"section.key" -> value``. A number is taken in SI; a ``(value, unit)`` pair is
            converted with :mod:`rollerrig.units` (e.g. ``(63.5, "kN.m/rad")``). The provenance
            of each replaced value becomes an ``assumption`` that records the override and the
            old value.

        Returns
        -------
        RigParameters

        Raises
        ------
        RigFileError
            Unknown path, unit not accepted, wrong type or a non-physical value; each problem
            names the ``section.key`` (origin ``"overrides"``).

        Examples
        --------
        >>> rig = default_rig().with_overrides({"stiffness.roller_shaft": 63.5e3})
        >>> rig.stiffness.roller_shaft
        63500.0
        """
        if not isinstance(overrides, Mapping):  # a list of pairs had raised an AttributeError
            raise RigFileError(
                "overrides",
                [
                    Problem(
                        "",
                        'must be a mapping {"section.key": value}',
                        got=Verbatim(type(overrides).__name__),
                    )
                ],
            )
        data = self.model_dump(exclude={"provenance"})
        provenance = {k: dict(v) for k, v in self.provenance.items()}
        problems: list[Problem] = []
        shown: dict[str, str] = {}
        for path, given in overrides.items():
            try:
                section, key, raw, unit = _override(str(path), given)
                field = SECTIONS[section].model_fields[key]
                value = raw if unit is None else si_value(field, raw, unit, str(path))
            except FieldProblem as exc:
                problems.append(exc.problem)
                continue
            data[section][key] = value
            if section == "meta":
                continue
            if unit is not None:
                shown[str(path)] = f"{show_value(raw)} {unit}"
            old = provenance.get(str(path), {})
            old_text = old.get("source") or old.get("assumption") or "no provenance"
            old_value = f"{old['value']} {old['unit']}" if "value" in old else "unset"
            provenance[str(path)] = {
                "value": raw,
                "unit": si_unit_of(field) if unit is None else unit,
                "assumption": f"override (was {old_value}: {old_text})",
            }
        if problems:
            raise RigFileError("overrides", problems)
        sections, problems = validate_sections(data, shown)
        if problems:
            raise RigFileError("overrides", problems)
        return RigParameters(**sections, provenance=provenance)


def _override(path: str, given: Any) -> tuple[str, str, Any, str | None]:
    """``(section, key, value, unit or None for SI)`` of one override; raises FieldProblem."""
    section, _, key = path.partition(".")
    if section not in SECTIONS:
        raise FieldProblem(path, "unknown section", allowed=list(SECTIONS), got=section)
    fields = SECTIONS[section].model_fields
    if key not in fields:
        raise FieldProblem(path, f"unknown key in [{section}]", allowed=list(fields), got=key)
    if not isinstance(given, tuple):
        return section, key, given, None
    if section == "meta":
        raise FieldProblem(path, "must be a string", got=given)
    if len(given) != 2:
        raise FieldProblem(path, "give a number (SI) or a (value, unit) pair", got=given)
    return section, key, given[0], given[1]


def load_rig(path: str | os.PathLike) -> RigParameters:
    """Read and validate a rig parameter file.

    Parameters
    ----------
    path : str or path-like
        TOML file in the format of ``rollerrig/rig/data/default_rig.toml``, or the name of a
        registered rig set (``"pardubice"``, ``"vt-fra-quarter-scale"``, ...; a set of an
        installed package: :mod:`rollerrig.rig.library`) when no such file exists.

    Returns
    -------
    RigParameters
        SI values and their provenance.

    Raises
    ------
    RigFileError
        Missing file, invalid TOML, unknown or missing section/key, unit not accepted, a value
        of the wrong type, not finite or non-physical. One line per problem, each naming the
        file and the ``section.key``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "rig.toml"
    >>> save_rig(default_rig(), path)
    >>> load_rig(path) == default_rig()
    True
    """
    path = Path(path)
    if not path.is_file():
        if str(path) in rig_sets():  # a set's name: its file
            path = rig_set(str(path)).path
        else:
            raise RigFileError(str(path), ["rig file not found"])
    try:
        data = read_toml(path)
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise RigFileError(str(path), [f"not valid TOML: {exc}"]) from exc
    except OSError as exc:
        raise RigFileError(str(path), [f"cannot read the rig file: {exc}"]) from exc
    return _from_toml(data, str(path))


def _from_toml(data: Mapping[str, Any], origin: str) -> RigParameters:
    sections, provenance = read_sections(data, origin)
    return RigParameters(**sections, provenance=provenance)


def default_rig() -> RigParameters:
    """The bundled default rig: the Pardubice tram wheel–roller rig (Kayaalp, 4.1 and 4.5.1.5).

    Examples
    --------
    >>> rig = default_rig()
    >>> rig.pmsm.pole_pairs, round(rig.induction_motor.rated_slip, 4)
    (22, 0.0176)
    """
    text = resources.files("rollerrig.rig").joinpath("data/default_rig.toml").read_text("utf-8")
    return _from_toml(parse_toml(text), "rollerrig/rig/data/default_rig.toml")


def save_rig(rig: RigParameters, path: str | os.PathLike, *, overwrite: bool = False) -> None:
    """Write a rig parameter set as TOML in the format :func:`load_rig` reads.

    Each value is written in the unit it was given in (its provenance) when that reproduces the
    SI value exactly, otherwise in SI. The file is written atomically
    (:func:`rollerrig.output.atomic_write`).

    Parameters
    ----------
    rig : RigParameters
        The parameter set.
    path : str or path-like
        Destination file.
    overwrite : bool, optional
        Replace an existing file. Default False.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    rollerrig.output.OutputError
        The file cannot be written (the message names the path).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "rig.toml"
    >>> save_rig(default_rig(), path)
    >>> path.read_text().splitlines()[0].startswith("# rollerrig rig parameter set")
    True
    """
    sections = {section: getattr(rig, section) for section in SECTIONS}
    write_text(path, write_sections(sections, rig.provenance), overwrite=overwrite)


def rig_values(rig) -> dict[str, Any]:
    """Every value of a rig parameter set outside ``[meta]``, by dotted key [SI].

    Examples
    --------
    >>> rig_values(default_rig())["inertia.roller"]
    45.0
    """
    out: dict[str, Any] = {}
    for section in SECTIONS:
        if section == "meta":
            continue
        values = getattr(rig, section, None)
        if values is None:
            continue
        for key in type(values).model_fields:
            out[f"{section}.{key}"] = getattr(values, key)
    return out


def load_rig_set(name: str):
    """Load and validate the registered rig set ``name`` (:mod:`rollerrig.rig.library`).

    Returns
    -------
    RigParameters
        As :func:`rollerrig.rig.parameters.load_rig` reads the set's file.
    """
    return load_rig(rig_set(name).path)
