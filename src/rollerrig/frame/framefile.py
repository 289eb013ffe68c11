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
key, and what to change (:class:`~rollerrig.frame.errors.FrameFileError`): unknown keys, units,
non-physical values, unknown designations (with the closest ones), members naming unknown nodes,
zero-length members, a node lying inside a member's span, nodes on no member, parts of the
frame held by no support, load points on no node, gauges outside their member or with a fibre
along its axis, and every number outside its plausible range
(:data:`~rollerrig.frame.limits.PLAUSIBLE`: a node 1e200 m away or a modulus of 1e-300 GPa is
named as such, and never reaches the FE solver). A file larger than the analysis can take
(:data:`~rollerrig.frame.limits.MAX_NODES`, :data:`~rollerrig.frame.limits.MAX_MEMBERS`,
:data:`~rollerrig.frame.limits.MAX_ENTRIES`) is refused before any of it is read; every check
after that is near-linear in the size of the frame (hash maps and a k-d tree, no loops over
pairs). A mechanism (too few supports) is found by the analysis
(:func:`rollerrig.frame.modes.check_stability`), with the same error type.

Where each part lives: the frame in memory in :mod:`~rollerrig.frame.structure`, the limits of
a file in :mod:`~rollerrig.frame.limits`, its error in :mod:`~rollerrig.frame.errors`; this
module reads a file into a :class:`~rollerrig.frame.structure.Frame` (the entries and tables
are read by the private ``_entries`` and ``_tables`` modules) and re-exports the names it
exported before them.
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from rollerrig._toml import parse_toml, read_toml
from rollerrig._validation import Problem
from rollerrig.frame._entries import _Reader
from rollerrig.frame._tables import (
    _connectivity,
    _gauges,
    _load_points,
    _masses,
    _materials,
    _members,
    _nodes,
    _sections,
    _size_problems,
    _supports,
)
from rollerrig.frame.errors import MAX_PROBLEMS_SHOWN, FrameFileError
from rollerrig.frame.limits import (
    MAX_ENTRIES,
    MAX_MEMBERS,
    MAX_NODES,
    NODE_TOLERANCE,
    PLAUSIBLE,
    Plausible,
)
from rollerrig.frame.structure import (
    DOF_NAMES,
    Frame,
    LoadPoint,
    Material,
    Member,
    PointMass,
    StrainGauge,
)

__all__ = [
    "DOF_NAMES",
    "MAX_ENTRIES",
    "MAX_MEMBERS",
    "MAX_NODES",
    "MAX_PROBLEMS_SHOWN",
    "NODE_TOLERANCE",
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


def load_frame(path: str | Path) -> Frame:
    """Read and validate a frame file (TOML).

    Raises
    ------
    FrameFileError
        A missing file, invalid TOML, or any problem of :func:`frame_from_dict`.
    """
    if not isinstance(path, str | os.PathLike):
        raise FrameFileError(repr(path), ["not a file path (str or Path)"])
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
