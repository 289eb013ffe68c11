"""The tables of a frame file read and checked into the parts of a :class:`~rollerrig.frame.
structure.Frame`: materials, sections, nodes, members, supports, load points, masses, strain
gauges, and the frame's connectivity.

Each check is near-linear in the size of the frame: hash maps, a union-find over the members,
and a k-d tree of the nodes (points at one place, nodes inside a member's span, a load point
given by coordinates), never a loop over pairs. The sizes of the tables are checked before any
entry is read (``_size_problems``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from rollerrig._validation import Problem, interval
from rollerrig.frame._entries import _Reader
from rollerrig.frame.limits import MAX_ENTRIES, MAX_MEMBERS, MAX_NODES, NODE_TOLERANCE, PLAUSIBLE
from rollerrig.frame.sections import SectionProperties, standard_section
from rollerrig.frame.structure import (
    DOF_NAMES,
    LoadPoint,
    Material,
    Member,
    PointMass,
    StrainGauge,
)

__all__: list[str] = []

_SUPPORTS = {"fixed": (True,) * 6, "pinned": (True, True, True, False, False, False)}

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


_LIMITS = {
    "nodes": MAX_NODES,
    "members": MAX_MEMBERS,
    **{
        key: MAX_ENTRIES
        for key in ("materials", "sections", "supports", "load_points", "masses", "strain_gauges")
    },
}


def _size_problems(data: Mapping) -> list[Problem]:
    """Tables with more entries than the analysis can take (``MAX_NODES``, ``MAX_MEMBERS``,
    ``MAX_ENTRIES`` of :mod:`rollerrig.frame.limits`), found before any entry is read."""
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
