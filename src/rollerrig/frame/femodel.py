"""The frame as a PyNiteFEA model: nodes, beam elements, supports and the unit load cases.

The frame (:class:`rollerrig.frame.structure.Frame`) becomes a PyNite 3-D frame model
(Euler–Bernoulli beams, 6 DOF per node, consistent mass), each member divided into
``elements_per_member`` elements so that the distributed mass is resolved in the modes
(:func:`build_model`). Two unit load cases are defined (:func:`unit_load_patterns`): the normal
load pattern (1 N of air-spring force, spread over the load points by their ``normal`` factors)
and the traction pattern (1 N of traction force F_x, by their ``traction`` factors); the
analysis is linear, so any test load is ``N u_normal + F u_traction``.

Why PyNiteFEA: it is a maintained (2016-, v3.x in 2026), MIT-licensed, pure-Python 3-D frame
library with linear static, P-Δ and modal analysis (consistent mass, sparse shift-invert
eigensolver) and member results; numpy/scipy only. Compared: anastruct (GPL-3, 2-D only: used
as the independent cross-check in the tests), OpenSeesPy (powerful but a large binary under a
non-OSI licence, and its modal API works on a global interpreter state), FrameAT (small, no
modal). Two things are our own, on PyNite's matrices: the check for mechanisms
(:mod:`rollerrig.frame.modes`; PyNite only looks at zero diagonal terms and prints them), and
the fibre stresses (:mod:`rollerrig.frame.stresses`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from rollerrig._optional import require
from rollerrig.frame.structure import Frame

__all__ = ["CASES", "DEFAULT_ELEMENTS_PER_MEMBER", "build_model", "unit_load_patterns"]

CASES = ("normal", "traction")
"""The unit load cases: 1 N of normal load, 1 N of traction force."""

DEFAULT_ELEMENTS_PER_MEMBER = 4
"""Elements per member: the first bending mode of a cantilever member with its own mass is
0.05 % high with four (Euler–Bernoulli consistent mass), 2 % with one."""

_PURPOSE = "the frame analysis (rollerrig frame)"


@dataclass
class _Mesh:
    """A PyNite model of a frame and where each member's elements are."""

    model: Any
    frame: Frame
    nodes: list[str]
    """FE node names, the frame's nodes first."""
    elements: dict[str, list[tuple[str, float, float]]]
    """member -> [(element name, start, end distance along the member [m]), ...]."""


def _pynite():
    return require("Pynite", "frame", _PURPOSE)


def build_model(
    frame: Frame,
    *,
    elements_per_member: int = DEFAULT_ELEMENTS_PER_MEMBER,
    loads: Mapping[str, Mapping[str, np.ndarray]] | None = None,
    masses: bool = False,
) -> _Mesh:
    """A PyNite ``FEModel3D`` of ``frame``.

    Parameters
    ----------
    frame : Frame
    elements_per_member : int
        Elements each member is divided into.
    loads : mapping, optional
        Load case -> {frame node: force vector [N]}; one load combination per case, same name.
    masses : bool
        Add the mass case ``"mass"`` (members' own mass and the lumped masses as loads in z with
        gravity 1, which PyNite converts to mass) for :func:`modal analysis
        <rollerrig.frame.analysis.analyze_frame>`.
    """
    pynite = _pynite()
    model = pynite.FEModel3D()
    for name, p in frame.nodes.items():
        model.add_node(name, *p)
    for name, mat in frame.materials.items():
        model.add_material(name, mat.youngs_modulus, mat.shear_modulus, mat.poisson, mat.density)
    for name, s in frame.sections.items():
        # PyNite: Iy about local y (bending in the x-z plane), Iz about local z (x-y plane).
        # The web is along local y, so the strong axis is local z.
        model.add_section(
            name, s.area, s.second_moment_weak, s.second_moment_strong, s.torsion_constant
        )
    names = list(frame.nodes)
    elements: dict[str, list[tuple[str, float, float]]] = {}
    n_el = max(1, int(elements_per_member))
    for name, m in frame.members.items():
        a, b = frame.coordinates(m.start), frame.coordinates(m.end)
        length = frame.length(name)
        chain = [m.start]
        for k in range(1, n_el):
            node = f"{name}~{k}"
            model.add_node(node, *(a + (b - a) * k / n_el))
            names.append(node)
            chain.append(node)
        chain.append(m.end)
        elements[name] = []
        for k in range(n_el):
            el = f"{name}#{k}"
            model.add_member(el, chain[k], chain[k + 1], m.material, m.section)
            _orient(model.members[el], np.asarray(m.web))
            elements[name].append((el, length * k / n_el, length * (k + 1) / n_el))
    for node, fixed in frame.supports.items():
        model.def_support(node, *fixed)
    for case, forces in (loads or {}).items():
        for node, f in forces.items():
            for axis, value in zip(("FX", "FY", "FZ"), f, strict=True):
                if value != 0.0:
                    model.add_node_load(node, axis, float(value), case=case)
        model.add_load_combo(case, {case: 1.0})
    if masses:
        model.add_member_self_weight("FZ", 1.0, case="mass")
        for pm in frame.masses.values():
            if pm.mass > 0.0:
                model.add_node_load(pm.node, "FZ", pm.mass, case="mass")
        model.add_load_combo("mass", {"mass": 1.0})
    return _Mesh(model, frame, names, elements)


def _orient(member, web: np.ndarray) -> None:
    """Rotate a PyNite member about its axis so that its local y is the web direction."""
    member.rotation = 0.0
    t = member.T()
    y0, z0 = t[1, :3], t[2, :3]
    angle = math.degrees(math.atan2(float(np.dot(web, z0)), float(np.dot(web, y0))))
    for rotation in (angle, -angle):
        member.rotation = rotation
        if np.allclose(member.T()[1, :3], web, atol=1e-9):
            return
    raise RuntimeError(f"cannot orient member {member.name} to web {web}")  # pragma: no cover


def _axes(mesh: _Mesh, element: str) -> np.ndarray:
    """Rows: the element's local x, y, z as global unit vectors."""
    return mesh.model.members[element].T()[:3, :3]


def unit_load_patterns(frame: Frame) -> dict[str, dict[str, np.ndarray]]:
    """Case -> {node: force per newton of that test load [N/N]} (load points summed by node)."""
    out: dict[str, dict[str, np.ndarray]] = {case: {} for case in CASES}
    for lp in frame.load_points.values():
        for case in CASES:
            f = np.asarray(getattr(lp, case), dtype=float)
            out[case][lp.node] = out[case].get(lp.node, np.zeros(3)) + f
    return out


def _node_matrix(mesh: _Mesh, combo: str) -> np.ndarray:
    nodes = mesh.model.nodes
    return np.array(
        [
            [
                nodes[n].DX[combo],
                nodes[n].DY[combo],
                nodes[n].DZ[combo],
                nodes[n].RX[combo],
                nodes[n].RY[combo],
                nodes[n].RZ[combo],
            ]
            for n in mesh.nodes
        ]
    )
