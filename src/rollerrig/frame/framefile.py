"""The frame file: a rig frame described in TOML, read and validated into a :class:`Frame`.

Global axes: x longitudinal (the rolling direction at the contact), y lateral (along the
roller's axle), z vertical, up. Every physical value is an inline table with its value, its unit
and where it comes from (``source``) or why it was chosen (``assumption``), as in the rig file
(:mod:`rollerrig.rig.rigfile`)::

    [meta]
    name = "my-rig-frame"
    description = "..."

    [materials.steel]
    youngs_modulus = { value = 210, unit = "GPa", source = "EN 1993-1-1 3.2.6" }
    poisson = { value = 0.3, unit = "1", source = "EN 1993-1-1 3.2.6" }
    density = { value = 7850, unit = "kg/m^3", source = "EN 1991-1-1 Table A.4" }

    [sections.column]                 # a standard section (data/sections.csv) ...
    designation = { value = "HEB 200", assumption = "why this section" }
    [sections.plate]                  # ... or one given by its properties
    area = { value = 120, unit = "cm^2", assumption = "400 x 30 mm plate" }
    second_moment_strong = { value = 90, unit = "cm^4", assumption = "..." }
    second_moment_weak = { value = 16000, unit = "cm^4", assumption = "..." }
    torsion_constant = { value = 340, unit = "cm^4", assumption = "..." }
    depth = { value = 30, unit = "mm", assumption = "..." }
    width = { value = 400, unit = "mm", assumption = "..." }
    # optional: torsion_modulus [m^3], shear_area_strong, shear_area_weak [m^2]

    [nodes]
    base = { value = [0, 0, 0], unit = "m", assumption = "why here" }
    top = { value = [0, 0, 2], unit = "m", assumption = "..." }

    [members.column]
    nodes = ["base", "top"]
    section = "column"
    material = "steel"                # optional when there is one material
    web = [1, 0, 0]                   # optional: the direction of the section's depth

    [supports]
    base = "fixed"                    # "fixed", "pinned" or a list of "x", "y", "z", "rx", ...

    [load_points.air_spring]          # a force on the frame per unit test load [N/N]
    node = "top"                      # or at = { value = [x, y, z], unit = "m" } on a node
    normal = [0, 0, 1]                # per newton of normal load (air-spring force)
    traction = [0, 0, 0]              # per newton of traction force F_x (> 0 in traction)
    assumption = "how the load reaches the frame"

    [masses.wheel_assembly]           # a lumped mass carried at a node (modal analysis)
    node = "top"
    mass = { value = 300, unit = "kg", assumption = "..." }

    [strain_gauges.SG1]
    member = "column"
    position = { value = 0.3, unit = "m", assumption = "..." }   # from the member's first node
    fibre = "+x"                      # the face of the section in this global direction
    assumption = "where it is glued"

    [output]
    top_nodes = ["top"]               # optional: the nodes of "top horizontal deflection"

Reading checks everything and reports every problem at once, one line each naming the file, the
key, and what to change (:class:`FrameFileError`): unknown keys, units, non-physical values,
unknown designations (with the closest ones), members naming unknown nodes, zero-length members,
a node lying inside a member's span, nodes on no member, parts of the frame held by no support,
load points on no node, gauges outside their member or with a fibre along its axis, and every
number outside its plausible range (:data:`PLAUSIBLE`: a node 1e200 m away or a modulus of
1e-300 GPa is named as such, and never reaches the FE solver). A file larger than the analysis
can take (:data:`MAX_NODES`, :data:`MAX_MEMBERS`, :data:`MAX_ENTRIES`) is refused before any of
it is read; every check after that is near-linear in the size of the frame (hash maps and a
k-d tree, no loops over pairs). A mechanism (too few supports) is found by the analysis
(:func:`rollerrig.frame.analysis.check_stability`), with the same error type.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._toml import parse_toml, read_toml
from rollerrig._validation import ParameterError, Problem, Verbatim, interval, show_value
from rollerrig.frame.sections import SectionProperties, standard_section
from rollerrig.units import QUANTITIES, UnitError, apply_factor, quantity_factor

__all__ = [
    "DOF_NAMES",
    "MAX_ENTRIES",
    "MAX_MEMBERS",
    "MAX_NODES",
    "PLAUSIBLE",
    "Frame",
    "FrameFileError",
    "LoadPoint",
    "Material",
    "Member",
    "Plausible",
    "PointMass",
    "StrainGauge",
    "default_frame",
    "frame_from_dict",
    "load_frame",
]

DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
"""The six degrees of freedom of a node: translations along and rotations about x, y, z."""

_SUPPORTS = {"fixed": (True,) * 6, "pinned": (True, True, True, False, False, False)}

NODE_TOLERANCE = 1e-6
"""Two nodes closer than this are one point [m]; a load point given by coordinates must lie
within it of a node."""

MAX_MEMBERS = 200
"""Most members a frame file may hold [1]. The analysis divides each member into four beam
elements and builds the model three times in PyNite's pure Python (stability check, static,
modal), whose meshing looks at every node for each element: the cost grows faster than the
size. Measured on two cores: a ladder frame of 199 members in 9 s (36 s with the cores shared
by four other processes), one of 499 members in over 10 minutes. The bundled rig frame has 28.
Checked before any entry is read."""

MAX_NODES = 2 * MAX_MEMBERS
"""Most nodes a frame file may hold [1]: every node is the end of a member, so a frame of
:data:`MAX_MEMBERS` members has at most twice as many. Checked before any entry is read."""

MAX_ENTRIES = MAX_NODES
"""Most entries in each of the other tables (materials, sections, supports, load points,
masses, strain gauges) [1]: none can usefully hold more than one per node."""

MAX_PROBLEMS_SHOWN = 100
"""Problems listed in one :class:`FrameFileError`; the rest are counted in a last line."""


@dataclass(frozen=True)
class Plausible:
    """The plausible range of a kind of number in a frame file, in SI units.

    Attributes
    ----------
    low, high : float
        The bounds [``unit``].
    unit : str
        The SI unit of the bounds.
    why : str
        What the range covers, shown with a value outside it.
    low_inclusive, high_inclusive : bool
        Whether the bounds themselves are allowed.
    """

    low: float
    high: float
    unit: str
    why: str
    low_inclusive: bool = True
    high_inclusive: bool = True

    def __contains__(self, value: float) -> bool:
        above = value >= self.low if self.low_inclusive else value > self.low
        below = value <= self.high if self.high_inclusive else value < self.high
        return above and below

    @property
    def allowed(self) -> str:
        """The range in interval notation, e.g. ``[1e+06, 1e+13]``."""
        return (
            f"{'[' if self.low_inclusive else '('}{self.low:g}, "
            f"{self.high:g}{']' if self.high_inclusive else ')'}"
        )


PLAUSIBLE: dict[str, Plausible] = {
    "coordinate": Plausible(-1e3, 1e3, "m", "a rig frame lies within 1 km of its origin"),
    "youngs_modulus": Plausible(
        1e6, 1e13, "Pa", "from soft rubber (1 MPa) to beyond diamond (1.2 TPa)"
    ),
    "poisson": Plausible(
        0.0,
        0.5,
        "1",
        "an isotropic solid that neither grows under tension nor is incompressible",
        low_inclusive=False,
        high_inclusive=False,
    ),
    "density": Plausible(10.0, 3e4, "kg/m^3", "from foams to the densest metals (osmium 22 590)"),
    "area": Plausible(1e-6, 100.0, "m^2", "from 1 mm^2 to 100 m^2, a near-rigid link"),
    "second_moment": Plausible(1e-14, 100.0, "m^4", "from a 1 mm wire to a near-rigid link"),
    "section_modulus": Plausible(1e-10, 100.0, "m^3", "from a 1 mm wire to a near-rigid link"),
    "section_size": Plausible(1e-4, 10.0, "m", "a section's depth or width, 0.1 mm to 10 m"),
    "member_length": Plausible(
        1e-3,
        math.inf,
        "m",
        "a member shorter than 1 mm is a joint, not a beam",
        high_inclusive=False,
    ),
    "mass": Plausible(0.0, 1e6, "kg", "a lumped mass of at most 1000 t"),
    "load_factor": Plausible(
        -100.0, 100.0, "N/N", "a force on the frame per newton of test load, at most 100 N/N"
    ),
}
"""Plausible ranges of every number of a frame file, in SI units, checked as it is read:
node and load point coordinates and gauge positions (``coordinate``), the material's
``youngs_modulus``, ``poisson`` and ``density``, a section's ``area`` and shear areas
(``area``), second moments and torsion constant (``second_moment``), ``torsion_modulus``
(``section_modulus``), ``depth`` and ``width`` (``section_size``), a member's length
(``member_length``), a lumped ``mass``, and each component of a load point's ``normal`` and
``traction`` (``load_factor``). A number outside is a typing or unit mistake: it is named with
its key, unit and range before the FE solver could turn it into a false mechanism or NaN."""


class FrameFileError(ParameterError):
    """A frame file is malformed, non-physical, or describes a frame that cannot carry load.

    One line per problem, each naming the file and the key (``members.column.nodes``) and what
    to change.

    Attributes
    ----------
    origin : str
        The file (or ``"<dict>"``) the problems were found in.
    problems : list of str
        One line per problem (at most :data:`MAX_PROBLEMS_SHOWN`, then one line counting the
        rest).
    """

    def __init__(self, origin: str, problems: list[Problem | str]):
        self.origin = origin
        self.problems = [
            p.format(origin) if isinstance(p, Problem) else f"{origin}: {p}"
            for p in problems[:MAX_PROBLEMS_SHOWN]
        ]
        if len(problems) > MAX_PROBLEMS_SHOWN:
            self.problems.append(
                f"{origin}: ... and {len(problems) - MAX_PROBLEMS_SHOWN} more problems "
                "(fix these first)"
            )
        super().__init__("\n".join(self.problems))


# --------------------------------------------------------------------------------------------
# The frame in memory (SI)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Material:
    """An isotropic elastic material.

    Attributes
    ----------
    name : str
    youngs_modulus : float
        E [Pa].
    poisson : float
        ν [1].
    density : float
        Mass density ρ [kg/m^3].
    """

    name: str
    youngs_modulus: float
    poisson: float
    density: float

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + ν)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson))


@dataclass(frozen=True)
class Member:
    """A straight beam between two nodes.

    Attributes
    ----------
    name, start, end : str
        The member and its end nodes (``start`` is where ``position`` is measured from).
    section, material : str
        Names of its section and material.
    web : tuple of float
        Unit vector of the section's depth direction (local y), perpendicular to the axis.
    """

    name: str
    start: str
    end: str
    section: str
    material: str
    web: tuple[float, float, float]


@dataclass(frozen=True)
class LoadPoint:
    """Where a test load enters the frame: the force on the node per unit load [N/N]."""

    name: str
    node: str
    normal: tuple[float, float, float]
    traction: tuple[float, float, float]


@dataclass(frozen=True)
class PointMass:
    """A lumped mass [kg] carried at a node (translational inertia in x, y and z)."""

    name: str
    node: str
    mass: float


@dataclass(frozen=True)
class StrainGauge:
    """A uniaxial strain gauge along a member's axis.

    Attributes
    ----------
    name, member : str
    position : float
        Distance from the member's first node [m].
    fibre : str
        The face, as written (``"+z"``).
    direction : tuple of float
        The face's outward global direction (unit vector).
    """

    name: str
    member: str
    position: float
    fibre: str
    direction: tuple[float, float, float]


@dataclass(frozen=True)
class Frame:
    """A validated frame: nodes, members, sections, supports, load points, masses, gauges.

    Build one with :func:`load_frame`, :func:`frame_from_dict` or :func:`default_frame`.
    Coordinates [m], SI values throughout; ``provenance`` maps each physical entry's dotted key
    to its value, unit and source or assumption as written.
    """

    name: str
    description: str
    nodes: Mapping[str, tuple[float, float, float]]
    members: Mapping[str, Member]
    sections: Mapping[str, SectionProperties]
    materials: Mapping[str, Material]
    supports: Mapping[str, tuple[bool, ...]]
    load_points: Mapping[str, LoadPoint]
    masses: Mapping[str, PointMass]
    gauges: Mapping[str, StrainGauge]
    top_nodes: tuple[str, ...]
    origin: str = "<dict>"
    provenance: Mapping[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def coordinates(self, node: str) -> np.ndarray:
        """The node's position [m]."""
        return np.asarray(self.nodes[node], dtype=float)

    def length(self, member: str) -> float:
        """The member's length [m]."""
        m = self.members[member]
        return float(np.linalg.norm(self.coordinates(m.end) - self.coordinates(m.start)))

    def axes(self, member: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Local axes (x along the member, y = web direction, z = x × y) as global unit vectors."""
        m = self.members[member]
        ex = self.coordinates(m.end) - self.coordinates(m.start)
        ex = ex / np.linalg.norm(ex)
        ey = np.asarray(m.web, dtype=float)
        return ex, ey, np.cross(ex, ey)

    def total_mass(self) -> float:
        """Mass of the members (ρ A L) and of the lumped masses [kg]."""
        members = sum(
            self.materials[m.material].density * self.sections[m.section].area * self.length(n)
            for n, m in self.members.items()
        )
        return float(members + sum(p.mass for p in self.masses.values()))


# --------------------------------------------------------------------------------------------
# Units of the frame's quantities
# --------------------------------------------------------------------------------------------


def _si_unit(quantity: str) -> str:
    return QUANTITIES[quantity].si_unit


def _factor(unit: Any, quantity: str) -> float:
    """Factor to SI of ``unit`` for ``quantity`` (:mod:`rollerrig.units`); raises UnitError."""
    return quantity_factor(unit, quantity)


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------

_SECTION_PROPERTIES = {
    "area": "area",
    "second_moment_strong": "second_moment",
    "second_moment_weak": "second_moment",
    "torsion_constant": "second_moment",
    "depth": "length",
    "width": "length",
    "torsion_modulus": "section_modulus",
    "shear_area_strong": "area",
    "shear_area_weak": "area",
}
_SECTION_PLAUSIBLE = {
    "area": "area",
    "second_moment": "second_moment",
    "length": "section_size",
    "section_modulus": "section_modulus",
}
_SECTION_REQUIRED = ("area", "second_moment_strong", "second_moment_weak", "torsion_constant")
_TOP_KEYS = (
    "meta",
    "materials",
    "sections",
    "nodes",
    "members",
    "supports",
    "load_points",
    "masses",
    "strain_gauges",
    "output",
)
_ENTRY_FORM = "an inline table { value = ..., unit = ..., source | assumption = ... }"
_HINTED_PROBLEMS = 20
"""Problems after which no 'did you mean' hint is looked for."""


def _is_number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _finite_or_nan(v) -> float:
    """``float(v)``; NaN for an integer too large for a float."""
    try:
        return float(v)
    except OverflowError:
        return math.nan


def _written(si: float, written, value, unit, si_unit: str):
    """A value as it was written (a whole list), with the SI value when the unit is not the
    SI one."""
    if isinstance(value, list):
        return value if unit == si_unit else Verbatim(f"{show_value(value)} {unit}")
    if unit == si_unit:
        return written
    return Verbatim(f"{si:.4g} ({show_value(written)} {unit})")


class _Reader:
    """Collects the problems of one file while reading it."""

    def __init__(self, origin: str):
        self.origin = origin
        self.problems: list[Problem] = []
        self.provenance: dict[str, Any] = {}
        self.invalid: set[tuple[str, str]] = set()
        """(kind, name) of entries given but invalid: references to them add no problem."""
        self.nodes_tree: tuple[list[str], Any] = ([], None)
        """The valid nodes' names and their k-d tree (rows in the same order)."""

    def problem(self, key: str, message: str, **kw) -> None:
        self.problems.append(Problem(key, message, **kw))

    def table(self, data: Mapping, key: str, *, required: bool = True) -> Mapping:
        value = data.get(key.rsplit(".", 1)[-1])
        if value is None:
            if required:
                self.problem(key, "missing table")
            return {}
        if not isinstance(value, Mapping):
            self.problem(key, "must be a table", got=value)
            return {}
        return value

    def unknown_keys(self, table: Mapping, prefix: str, known) -> None:
        for k in table:
            if k not in known:
                hint = self.hint(str(k), known)
                self.problem(
                    f"{prefix}.{k}" if prefix else str(k), f"unknown key{hint}", allowed=list(known)
                )

    def entry(
        self,
        table: Mapping,
        prefix: str,
        key: str,
        quantity: str,
        plausible: str,
        *,
        required: bool = True,
        size: int | None = None,
    ):
        """The SI value of a physical entry ``{ value, unit, source | assumption }`` (a number,
        or a list of ``size`` numbers) in its range ``PLAUSIBLE[plausible]``, or None with its
        problems recorded."""
        name = f"{prefix}.{key}"
        raw = table.get(key)
        if raw is None:
            if required:
                self.problem(name, f"missing key ({_ENTRY_FORM})")
            return None
        if not isinstance(raw, Mapping):
            self.problem(name, f"must be {_ENTRY_FORM}", got=raw)
            return None
        if not self._provenance(raw, name, ("value", "unit")):
            return None
        value, unit = raw.get("value"), raw.get("unit")
        if value is None or unit is None:
            self.problem(name, "needs both 'value' and 'unit'")
            return None
        try:
            factor = _factor(unit, quantity)
        except UnitError as exc:
            p = exc.problem
            self.problem(f"{name}.unit", p.message, unit=p.unit, allowed=p.allowed, got=p.got)
            return None
        numbers = value if size is not None else [value]
        if (
            not isinstance(numbers, list)
            or (size is not None and len(numbers) != size)
            or not all(_is_number(v) for v in numbers)
        ):
            what = f"a list of {size} numbers" if size is not None else "a number"
            self.problem(f"{name}.value", f"must be {what}", got=value)
            return None
        si = [_finite_or_nan(v) for v in numbers]
        si = [apply_factor(v, factor) if math.isfinite(v) else v for v in si]
        if not all(math.isfinite(v) for v in si):
            self.problem(f"{name}.value", "must be finite", got=value)
            return None
        rng = PLAUSIBLE[plausible]
        for v, written in zip(si, numbers, strict=True):
            if v not in rng:
                self.problem(
                    f"{name}.value",
                    f"outside the plausible range ({rng.why})",
                    unit=rng.unit,
                    allowed=rng.allowed,
                    got=_written(v, written, value, unit, rng.unit),
                )
                return None
        self.provenance[name] = dict(raw)
        return tuple(si) if size is not None else si[0]

    def _provenance(self, raw: Mapping, name: str, fields: tuple[str, ...]) -> bool:
        known = (*fields, "source", "assumption")
        self.unknown_keys(raw, name, known)
        given = [k for k in ("source", "assumption") if k in raw]
        if len(given) != 1:
            self.problem(name, "needs exactly one of 'source' or 'assumption'", got=given or "none")
            return False
        text = raw[given[0]]
        if not isinstance(text, str) or not text.strip():
            self.problem(f"{name}.{given[0]}", "must be a non-empty string", got=text)
            return False
        return True

    def vector(
        self,
        table: Mapping,
        prefix: str,
        key: str,
        *,
        default=None,
        unit_vector=False,
        plausible: str | None = None,
    ):
        """A plain list of three numbers (no unit: a direction, or a force per unit load in
        the range ``PLAUSIBLE[plausible]``)."""
        raw = table.get(key, default)
        if raw is None:
            return None
        if (
            not isinstance(raw, list)
            or len(raw) != 3
            or not all(_is_number(v) for v in raw)
            or not all(math.isfinite(_finite_or_nan(v)) for v in raw)
        ):
            self.problem(
                f"{prefix}.{key}", "must be a list of three finite numbers [x, y, z]", got=raw
            )
            return None
        v = tuple(float(x) for x in raw)
        if plausible is not None:
            rng = PLAUSIBLE[plausible]
            if not all(x in rng for x in v):
                self.problem(
                    f"{prefix}.{key}",
                    f"a component is outside the plausible range ({rng.why})",
                    unit=rng.unit,
                    allowed=rng.allowed,
                    got=raw,
                )
                return None
        if unit_vector:
            n = math.hypot(*v)  # no overflow or underflow in the squares
            if n == 0.0:
                self.problem(f"{prefix}.{key}", "must not be the zero vector", got=raw)
                return None
            v = tuple(x / n for x in v)
        return v

    def hint(self, raw, known) -> str:
        """`` (did you mean 'x'?)`` for a misspelt name; none once many problems are found
        (each costs a fuzzy match against every known name)."""
        if len(self.problems) >= _HINTED_PROBLEMS or not isinstance(raw, str):
            return ""
        import difflib

        close = difflib.get_close_matches(raw, list(known), n=1)
        return f" (did you mean {close[0]!r}?)" if close else ""

    def name_ref(self, table: Mapping, prefix: str, key: str, known, what: str) -> str | None:
        raw = table.get(key)
        if raw is None:
            self.problem(f"{prefix}.{key}", f"missing key (the name of a {what})")
            return None
        if isinstance(raw, str) and (what, raw) in self.invalid:
            return None  # its own problem is reported
        if not isinstance(raw, str) or raw not in known:
            hint = self.hint(raw, known)
            self.problem(
                f"{prefix}.{key}",
                f"not a {what} of the frame{hint}; define it under "
                f"[{_PLURAL[what]}] or name one that is",
                got=raw,
            )
            return None
        return raw


_PLURAL = {"node": "nodes", "section": "sections", "material": "materials", "member": "members"}


def frame_from_dict(data: Mapping[str, Any], origin: str = "<dict>") -> Frame:
    """A :class:`Frame` from the parsed TOML of a frame file.

    Raises
    ------
    FrameFileError
        Every problem of the file, one line each (see the module docstring).
    """
    r = _Reader(origin)
    if not isinstance(data, Mapping):
        raise FrameFileError(origin, [Problem("", "must be a TOML table")])
    too_big = _size_problems(data)
    if too_big:
        raise FrameFileError(origin, too_big)
    r.unknown_keys(data, "", _TOP_KEYS)

    meta = r.table(data, "meta")
    name, description = meta.get("name"), meta.get("description", "")
    if not isinstance(name, str) or not name.strip():
        r.problem("meta.name", "must be a non-empty string", got=name)
        name = ""
    if not isinstance(description, str):
        r.problem("meta.description", "must be a string", got=description)
        description = ""
    r.unknown_keys(meta, "meta", ("name", "description"))

    materials = _materials(r, r.table(data, "materials"))
    sections = _sections(r, r.table(data, "sections"))
    nodes = _nodes(r, r.table(data, "nodes"))
    members = _members(r, r.table(data, "members"), nodes, sections, materials)
    supports = _supports(r, r.table(data, "supports"), nodes)
    load_points = _load_points(r, r.table(data, "load_points"), nodes)
    masses = _masses(r, r.table(data, "masses", required=False), nodes)
    if not r.problems:
        _connectivity(r, nodes, members, supports)
    gauges = _gauges(r, r.table(data, "strain_gauges", required=False), nodes, members, sections)
    output = r.table(data, "output", required=False)
    r.unknown_keys(output, "output", ("top_nodes",))
    top = output.get("top_nodes")
    if top is None:
        zmax = max((p[2] for p in nodes.values()), default=0.0)
        top_nodes = tuple(n for n, p in nodes.items() if p[2] >= zmax - 1e-3)
    elif (
        not isinstance(top, list)
        or not top
        or any(not isinstance(t, str) or t not in nodes for t in top)
    ):
        r.problem("output.top_nodes", "must be a non-empty list of node names", got=top)
        top_nodes = ()
    else:
        top_nodes = tuple(top)
    if r.problems:
        raise FrameFileError(origin, r.problems)
    return Frame(
        name=name,
        description=description,
        nodes=nodes,
        members=members,
        sections=sections,
        materials=materials,
        supports=supports,
        load_points=load_points,
        masses=masses,
        gauges=gauges,
        top_nodes=top_nodes,
        origin=origin,
        provenance=r.provenance,
    )


_LIMITS = {
    "nodes": MAX_NODES,
    "members": MAX_MEMBERS,
    **{
        key: MAX_ENTRIES
        for key in ("materials", "sections", "supports", "load_points", "masses", "strain_gauges")
    },
}


def _size_problems(data: Mapping) -> list[Problem]:
    """Tables with more entries than the analysis can take (:data:`MAX_NODES`,
    :data:`MAX_MEMBERS`, :data:`MAX_ENTRIES`), found before any entry is read."""
    out = []
    for key, limit in _LIMITS.items():
        table = data.get(key)
        if isinstance(table, Mapping) and len(table) > limit:
            out.append(
                Problem(
                    key,
                    f"too many entries for the frame analysis (each {key} entry adds to "
                    "the FE model; split the frame or merge entries)",
                    allowed=f"at most {limit}",
                    got=len(table),
                )
            )
    return out


def _materials(r: _Reader, table: Mapping) -> dict[str, Material]:
    out = {}
    if not table:
        r.problem("materials", "needs at least one material, e.g. [materials.steel]")
    for name, spec in table.items():
        prefix = f"materials.{name}"
        if not isinstance(spec, Mapping):
            r.problem(prefix, "must be a table", got=spec)
            continue
        r.unknown_keys(spec, prefix, ("youngs_modulus", "poisson", "density"))
        e = r.entry(spec, prefix, "youngs_modulus", "pressure", "youngs_modulus")
        nu = r.entry(spec, prefix, "poisson", "dimensionless", "poisson")
        rho = r.entry(spec, prefix, "density", "density", "density")
        if None not in (e, nu, rho):
            out[name] = Material(name, e, nu, rho)
        else:
            r.invalid.add(("material", name))
    return out


def _sections(r: _Reader, table: Mapping) -> dict[str, SectionProperties]:
    out = {}
    if not table:
        r.problem("sections", "needs at least one section, e.g. [sections.column]")
    for name, spec in table.items():
        prefix = f"sections.{name}"
        r.invalid.add(("section", name))  # until it is read
        if not isinstance(spec, Mapping):
            r.problem(prefix, "must be a table", got=spec)
            continue
        if "designation" in spec:
            r.unknown_keys(spec, prefix, ("designation",))
            raw = spec["designation"]
            key = f"{prefix}.designation"
            if not isinstance(raw, Mapping):
                r.problem(
                    key,
                    'must be an inline table { value = "HEB 200", source | assumption = ... }',
                    got=raw,
                )
                continue
            if not r._provenance(raw, key, ("value",)):
                continue
            try:
                section = standard_section(str(raw.get("value")))
            except KeyError as exc:
                r.problem(
                    f"{key}.value",
                    f"unknown designation: {exc.args[0]}; use one of the "
                    "table (rollerrig.frame.sections.section_table()) or give the "
                    "section's properties instead",
                    got=raw.get("value"),
                )
                continue
            r.provenance[key] = dict(raw)
            out[name] = section
            r.invalid.discard(("section", name))
            continue
        r.unknown_keys(spec, prefix, tuple(_SECTION_PROPERTIES))
        values = {}
        for key, quantity in _SECTION_PROPERTIES.items():
            required = key in _SECTION_REQUIRED or key in ("depth", "width")
            values[key] = r.entry(
                spec, prefix, key, quantity, _SECTION_PLAUSIBLE[quantity], required=required
            )
        if any(values[k] is None for k in (*_SECTION_REQUIRED, "depth", "width")):
            continue
        area, it = values["area"], values["torsion_constant"]
        out[name] = SectionProperties(
            name=name,
            shape="general",
            area=area,
            second_moment_strong=values["second_moment_strong"],
            second_moment_weak=values["second_moment_weak"],
            torsion_constant=it,
            depth=values["depth"],
            width=values["width"],
            torsion_modulus=values["torsion_modulus"]
            or it / (0.5 * min(values["depth"], values["width"])),
            shear_area_strong=values["shear_area_strong"] or area,
            shear_area_weak=values["shear_area_weak"] or area,
            source="given by its properties in the frame file",
        )
        r.invalid.discard(("section", name))
    return out


def _nodes(r: _Reader, table: Mapping) -> dict[str, tuple[float, float, float]]:
    read: dict[str, tuple[float, float, float]] = {}
    if not table:
        r.problem(
            "nodes",
            "needs the frame's nodes, e.g. base = { value = [0, 0, 0], "
            'unit = "m", assumption = "..." }',
        )
    for name in table:
        if "~" in name or "#" in name:
            r.problem(
                f"nodes.{name}",
                "a name must not hold '~' or '#' (the analysis names "
                "the members' inner nodes and elements with them)",
            )
            r.invalid.add(("node", name))
            continue
        p = r.entry(table, "nodes", name, "length", "coordinate", size=3)
        if p is None:
            r.invalid.add(("node", name))
            continue
        read[name] = p
    # Nodes at one point: the pairs closer than the tolerance, from a k-d tree (n log n); a
    # node is refused when an earlier one, itself kept, is at its point.
    names = list(read)
    partners: dict[int, list[int]] = {}
    if len(names) > 1:
        for i, j in sorted(_tree(read.values()).query_pairs(NODE_TOLERANCE)):
            partners.setdefault(j, []).append(i)
    out: dict[str, tuple[float, float, float]] = {}
    for j, name in enumerate(names):
        other = next((names[i] for i in sorted(partners.get(j, ())) if names[i] in out), None)
        if other is None:
            out[name] = read[name]
        else:
            r.problem(
                f"nodes.{name}",
                f"is at the same point as node {other!r}; merge them or move one",
                got=list(read[name]),
            )
    r.nodes_tree = (list(out), _tree(out.values()) if out else None)
    return out


def _tree(points):
    """A k-d tree of points [m] (:class:`scipy.spatial.cKDTree`)."""
    from scipy.spatial import cKDTree

    return cKDTree(np.asarray(list(points), dtype=float).reshape(-1, 3))


def _members(r, table, nodes, sections, materials) -> dict[str, Member]:
    out: dict[str, Member] = {}
    if not table:
        r.problem("members", "needs the frame's members, e.g. [members.column]")
    ends: dict[frozenset, str] = {}
    given_materials = [*materials, *(n for kind, n in r.invalid if kind == "material")]
    for name, spec in table.items():
        prefix = f"members.{name}"
        r.invalid.add(("member", name))  # until it is read
        if "~" in name or "#" in name:
            r.problem(
                prefix,
                "a name must not hold '~' or '#' (the analysis names the "
                "members' inner nodes and elements with them)",
            )
            continue
        if not isinstance(spec, Mapping):
            r.problem(prefix, "must be a table", got=spec)
            continue
        r.unknown_keys(spec, prefix, ("nodes", "section", "material", "web", "note"))
        pair = spec.get("nodes")
        if (
            not isinstance(pair, list)
            or len(pair) != 2
            or not all(isinstance(n, str) for n in pair)
        ):
            r.problem(f"{prefix}.nodes", "must be a list of two node names [start, end]", got=pair)
            continue
        if any(("node", n) in r.invalid for n in pair):
            continue  # the node's own problem is reported
        missing = [n for n in pair if n not in nodes]
        for n in missing:
            r.problem(
                f"{prefix}.nodes",
                f"node {n!r} is not defined under [nodes]; define it or name an existing node",
                got=pair,
            )
        if missing:
            continue
        if pair[0] == pair[1]:
            r.problem(f"{prefix}.nodes", "starts and ends at the same node", got=pair)
            continue
        if frozenset(pair) in ends:
            r.problem(
                f"{prefix}.nodes",
                f"joins the same nodes as member {ends[frozenset(pair)]!r}; remove one",
                got=pair,
            )
            continue
        section = r.name_ref(spec, prefix, "section", sections, "section")
        if "material" in spec or len(given_materials) != 1:
            material = r.name_ref(spec, prefix, "material", materials, "material")
        else:  # the one material, if it is valid (its own problem is reported)
            material = materials.get(given_materials[0]) and given_materials[0]
        a, b = np.asarray(nodes[pair[0]]), np.asarray(nodes[pair[1]])
        length = float(np.linalg.norm(b - a))
        if length not in PLAUSIBLE["member_length"]:
            rng = PLAUSIBLE["member_length"]
            r.problem(
                f"{prefix}.nodes",
                f"too short: its nodes are {length:.3g} m apart ({rng.why}); merge them",
                unit=rng.unit,
                allowed=rng.allowed,
                got=pair,
            )
            continue
        ex = (b - a) / length
        web = r.vector(spec, prefix, "web", unit_vector=True)
        if web is None and "web" not in spec:
            web = (1.0, 0.0, 0.0) if abs(ex[2]) > 0.999 else (0.0, 0.0, 1.0)
        if web is None or section is None or material is None:
            continue
        w = np.asarray(web) - np.dot(web, ex) * ex
        if np.linalg.norm(w) < 0.1:
            r.problem(
                f"{prefix}.web",
                "is (nearly) along the member's axis; give the direction "
                "of the section's depth, across the member",
                got=list(spec.get("web", web)),
            )
            continue
        w = w / np.linalg.norm(w)
        ends[frozenset(pair)] = name
        r.invalid.discard(("member", name))
        out[name] = Member(name, pair[0], pair[1], section, material, tuple(float(x) for x in w))
    # A node strictly inside a member's span would be connected by the FE library without
    # being an end of it: make that explicit. The candidates are the nodes in the ball around
    # the member's midpoint that holds the member (a k-d tree query), not every node.
    names, tree = r.nodes_tree
    if tree is None:
        return out
    points = tree.data
    for name, m in out.items():
        a, b = np.asarray(nodes[m.start]), np.asarray(nodes[m.end])
        length = float(np.linalg.norm(b - a))
        near = tree.query_ball_point((a + b) / 2.0, length / 2.0 + NODE_TOLERANCE)
        near = np.asarray([i for i in near if names[i] not in (m.start, m.end)], dtype=int)
        if not near.size:
            continue
        ex = (b - a) / length
        rel = points[near] - a
        s = rel @ ex
        off = np.linalg.norm(rel - s[:, None] * ex, axis=1)
        inside = (s > NODE_TOLERANCE) & (s < length - NODE_TOLERANCE) & (off < NODE_TOLERANCE)
        for i in sorted(near[inside]):
            r.problem(
                f"members.{name}.nodes",
                f"node {names[i]!r} lies on the member between "
                "its ends; split the member there into two members",
                got=[m.start, m.end],
            )
    return out


def _supports(r, table, nodes) -> dict[str, tuple[bool, ...]]:
    out = {}
    if not table:
        r.problem("supports", 'needs at least one supported node, e.g. base = "fixed"')
    for name, kind in table.items():
        key = f"supports.{name}"
        if isinstance(kind, str) and kind in _SUPPORTS:
            fixed = _SUPPORTS[kind]
        elif (
            isinstance(kind, list)
            and kind
            and all(isinstance(d, str) and d in DOF_NAMES for d in kind)
        ):
            fixed = tuple(d in kind for d in DOF_NAMES)
        else:
            r.problem(
                key,
                "not a support",
                allowed=[*_SUPPORTS, "a list of " + ", ".join(DOF_NAMES)],
                got=kind,
            )
            continue
        if name in nodes:
            out[name] = fixed
        elif ("node", name) not in r.invalid:
            r.problem(
                key, "not a node of the frame; support a node defined under [nodes]", got=name
            )
    return out


def _at_node(r, spec, prefix, nodes) -> str | None:
    """The node of a load point or mass: ``node = "name"`` or ``at = { value = [x, y, z] }``."""
    if "at" in spec and "node" not in spec:
        p = r.entry(spec, prefix, "at", "length", "coordinate", size=3)
        if p is None:
            return None
        names, tree = r.nodes_tree
        near = names[int(tree.query(p)[1])] if tree is not None else None
        if near is None or math.dist(nodes[near], p) > 1e-3:
            where = (
                f"; the nearest is {near!r} at {math.dist(nodes[near], p) * 1e3:.1f} mm"
                if near
                else ""
            )
            r.problem(
                f"{prefix}.at",
                f"is on no node of the frame{where}: a load acts on a "
                "node; add a node there (splitting the member) or name a node with "
                'node = "..."',
                got=spec["at"].get("value"),
            )
            return None
        return near
    return r.name_ref(spec, prefix, "node", nodes, "node")


def _load_points(r, table, nodes) -> dict[str, LoadPoint]:
    out = {}
    if not table:
        r.problem(
            "load_points",
            "needs the points where the test loads enter the frame, e.g. [load_points.air_spring]",
        )
    for name, spec in table.items():
        prefix = f"load_points.{name}"
        if not isinstance(spec, Mapping):
            r.problem(prefix, "must be a table", got=spec)
            continue
        r.unknown_keys(spec, prefix, ("node", "at", "normal", "traction", "source", "assumption"))
        node = _at_node(r, spec, prefix, nodes)
        normal = r.vector(spec, prefix, "normal", default=[0, 0, 0], plausible="load_factor")
        traction = r.vector(spec, prefix, "traction", default=[0, 0, 0], plausible="load_factor")
        given = [k for k in ("source", "assumption") if k in spec]
        if len(given) != 1:
            r.problem(
                prefix,
                "needs exactly one of 'source' or 'assumption' (how the load reaches the frame)",
                got=given or "none",
            )
            continue
        text = spec[given[0]]
        if not isinstance(text, str) or not text.strip():
            r.problem(f"{prefix}.{given[0]}", "must be a non-empty string", got=text)
            continue
        if None in (node, normal, traction):
            continue
        r.provenance[prefix] = {
            "normal": list(normal),
            "traction": list(traction),
            given[0]: spec[given[0]],
        }
        out[name] = LoadPoint(name, node, normal, traction)
    return out


def _masses(r, table, nodes) -> dict[str, PointMass]:
    out = {}
    for name, spec in table.items():
        prefix = f"masses.{name}"
        if not isinstance(spec, Mapping):
            r.problem(prefix, "must be a table", got=spec)
            continue
        r.unknown_keys(spec, prefix, ("node", "at", "mass"))
        node = _at_node(r, spec, prefix, nodes)
        mass = r.entry(spec, prefix, "mass", "mass", "mass")
        if node is not None and mass is not None:
            out[name] = PointMass(name, node, mass)
    return out


def _connectivity(r, nodes, members, supports) -> None:
    """Every node on a member; every connected part of the frame held by a support."""
    used = {n for m in members.values() for n in (m.start, m.end)}
    for n in nodes:
        if n not in used:
            r.problem(
                f"nodes.{n}",
                "is on no member (a disconnected node); connect it with a member or remove it",
            )
    parent = {n: n for n in used}

    def root(n):
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for m in members.values():
        parent[root(m.start)] = root(m.end)
    parts: dict[str, list[str]] = {}
    for n in used:
        parts.setdefault(root(n), []).append(n)
    part_members: dict[str, list[str]] = {}
    for m, spec in members.items():
        part_members.setdefault(root(spec.start), []).append(m)
    for key, part in parts.items():
        if not any(n in supports for n in part):
            names = sorted(part)
            shown = ", ".join(names[:6]) + (" ..." if len(names) > 6 else "")
            held = part_members.get(key, [])
            r.problem(
                "supports",
                f"the part of the frame with nodes {shown} (members "
                f"{', '.join(sorted(held)[:4])}{' ...' if len(held) > 4 else ''}) is "
                "connected to no supported node; connect it to the rest of the frame or "
                "support one of its nodes",
            )


def _gauges(r, table, nodes, members, sections) -> dict[str, StrainGauge]:
    out = {}
    for name, spec in table.items():
        prefix = f"strain_gauges.{name}"
        if not isinstance(spec, Mapping):
            r.problem(prefix, "must be a table", got=spec)
            continue
        r.unknown_keys(spec, prefix, ("member", "position", "fibre", "source", "assumption"))
        member = r.name_ref(spec, prefix, "member", members, "member")
        position = r.entry(spec, prefix, "position", "length", "coordinate")
        fibre = spec.get("fibre")
        direction = _FIBRES.get(fibre) if isinstance(fibre, str) else None
        if direction is None:
            r.problem(
                f"{prefix}.fibre", "not a face of the section", allowed=list(_FIBRES), got=fibre
            )
        if member is None or position is None or direction is None:
            continue
        m = members[member]
        a, b = np.asarray(nodes[m.start]), np.asarray(nodes[m.end])
        length = float(np.linalg.norm(b - a))
        if not 0.0 <= position <= length + 1e-9:
            r.problem(
                f"{prefix}.position",
                f"lies outside member {member!r} ({length:g} m long, from node {m.start!r})",
                unit="m",
                allowed=interval(0, length, low_inclusive=True, high_inclusive=True),
                got=position,
            )
            continue
        ex = (b - a) / length
        if abs(float(np.dot(ex, direction))) > 0.5:
            r.problem(
                f"{prefix}.fibre",
                f"is along member {member!r}'s axis; give the face across it the gauge is glued on",
                got=fibre,
            )
            continue
        out[name] = StrainGauge(name, member, min(position, length), fibre, direction)
    return out


_FIBRES = {
    f"{sign}{axis}": tuple(float(s * (i == j)) for j in range(3))
    for axis, i in (("x", 0), ("y", 1), ("z", 2))
    for sign, s in (("+", 1.0), ("-", -1.0))
}
"""Faces a gauge may be glued on: the outward global direction of the face."""


def load_frame(path: str | Path) -> Frame:
    """Read and validate a frame file (TOML).

    Raises
    ------
    FrameFileError
        A missing file, invalid TOML, or any problem of :func:`frame_from_dict`.
    """
    path = Path(path)
    if not path.is_file():
        raise FrameFileError(str(path), ["frame file not found"])
    try:
        data = read_toml(path)
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise FrameFileError(str(path), [f"not valid TOML: {exc}"]) from exc
    return frame_from_dict(data, str(path))


DEFAULT_FRAME_FILE = "rollerrig/frame/data/default-frame.toml"


def default_frame() -> Frame:
    """The bundled default: the Pardubice rig's frame, every dimension a stated assumption.

    Examples
    --------
    >>> f = default_frame()
    >>> len(f.members) > 10, sorted(f.supports)[:1]
    (True, ['base_front_left'])
    """
    text = resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text("utf-8")
    return frame_from_dict(parse_toml(text), DEFAULT_FRAME_FILE)
