"""Stresses in the frame's members: at the strain gauges per unit load, the largest von Mises
stress, and the members' end forces.

They are computed from each element's end displacements with the cubic (Hermite) shape
functions of the same element, so that they follow from the displacement field and need no sign
convention of internal forces:

    ε(x, y, z) = u' − y v'' − z w'',   σ = E ε

(u axial, v along local y = the web direction, w along local z; exact for beams without span
loads, which is the case here: all test loads act on nodes). The largest von Mises stress of a
member combines the largest normal stress of its section (the extreme corner, or the outer
radius of a CHS) with the largest shear stress (V/A_v both ways plus T/W_t): an upper bound,
as is usual in a beam model.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from rollerrig.frame.femodel import CASES, _axes, _Mesh
from rollerrig.frame.structure import Frame

__all__ = ["GaugeStress", "MemberEnds", "StressPeak", "unit_load_stresses"]


@dataclass(frozen=True)
class GaugeStress:
    """Axial stress at a gauge per unit load: ``σ = normal · N + traction · F`` [Pa/N]."""

    normal: float
    traction: float


@dataclass(frozen=True)
class StressPeak:
    """The largest von Mises stress [Pa] of the frame and where it is."""

    value: float
    member: str
    position: float
    """Distance from the member's first node [m]."""


@dataclass(frozen=True)
class MemberEnds:
    """Internal forces at a member's two ends, in its local axes (SI): axial force N (> 0 in
    tension) [N], shear forces V_y (along the web), V_z [N], torque T [N.m], bending moments
    M_strong (about local z), M_weak (about local y) [N.m], from the strains (M = E I κ)."""

    start: dict[str, float]
    end: dict[str, float]


def _element_strains(mesh: _Mesh, element: str, d_global: np.ndarray, xi: float):
    """(u', v'', w'', v''', w''', θx') of an element at distance ``xi`` from its start, from the
    global displacements of its two nodes (12 values)."""
    member = mesh.model.members[element]
    length = member.L()
    t = member.T()
    d = t @ d_global
    u1, v1, w1, tx1, ty1, tz1, u2, v2, w2, tx2, ty2, tz2 = d
    big = length
    n1 = -6.0 / big**2 + 12.0 * xi / big**3
    n2 = -4.0 / big + 6.0 * xi / big**2
    n3 = 6.0 / big**2 - 12.0 * xi / big**3
    n4 = -2.0 / big + 6.0 * xi / big**2
    v2c = n1 * v1 + n2 * tz1 + n3 * v2 + n4 * tz2
    w2c = n1 * w1 - n2 * ty1 + n3 * w2 - n4 * ty2
    v3 = 12.0 / big**3 * (v1 - v2) + 6.0 / big**2 * (tz1 + tz2)
    w3 = 12.0 / big**3 * (w1 - w2) - 6.0 / big**2 * (ty1 + ty2)
    return (u2 - u1) / big, v2c, w2c, v3, w3, (tx2 - tx1) / big


def _element_dofs(mesh: _Mesh, element: str, disp: np.ndarray) -> np.ndarray:
    member = mesh.model.members[element]
    i = mesh.nodes.index(member.i_node.name)
    j = mesh.nodes.index(member.j_node.name)
    return np.concatenate([disp[i], disp[j]])


def _locate(mesh: _Mesh, member: str, position: float) -> tuple[str, float]:
    for el, s0, s1 in mesh.elements[member]:
        if position <= s1 + 1e-12:
            return el, max(0.0, position - s0)
    el, s0, _ = mesh.elements[member][-1]
    return el, position - s0  # pragma: no cover - the file checks the position


def _fibre_point(frame: Frame, member: str, direction, axes: np.ndarray) -> tuple[float, float]:
    """(y, z) of the gauge's fibre in the section, from the face's global direction."""
    s = frame.sections[frame.members[member].section]
    d = np.asarray(direction, dtype=float)
    dy, dz = float(np.dot(d, axes[1])), float(np.dot(d, axes[2]))
    if s.shape == "CHS":
        n = math.hypot(dy, dz)
        return s.depth / 2.0 * dy / n, s.depth / 2.0 * dz / n
    if abs(dy) >= abs(dz):
        return math.copysign(s.depth / 2.0, dy), 0.0
    return 0.0, math.copysign(s.width / 2.0, dz)


def unit_load_stresses(mesh: _Mesh, unit: Mapping[str, np.ndarray]) -> dict[str, GaugeStress]:
    """The axial stress at each gauge per newton of each test load [Pa/N]."""
    frame = mesh.frame
    out = {}
    for name, g in frame.gauges.items():
        el, xi = _locate(mesh, g.member, g.position)
        axes = _axes(mesh, el)
        y, z = _fibre_point(frame, g.member, g.direction, axes)
        e = frame.materials[frame.members[g.member].material].youngs_modulus
        values = []
        for case in CASES:
            du, kv, kw, *_ = _element_strains(mesh, el, _element_dofs(mesh, el, unit[case]), xi)
            values.append(e * (du - y * kv - z * kw))
        out[name] = GaugeStress(*values)
    return out


def _section_stresses(frame: Frame, member: str, strains) -> tuple[float, float, dict]:
    """(largest normal stress, largest shear stress [Pa], internal forces) of a section."""
    m = frame.members[member]
    s, mat = frame.sections[m.section], frame.materials[m.material]
    e, g = mat.youngs_modulus, mat.shear_modulus
    du, kv, kw, v3, w3, twist = strains
    forces = {
        "N": e * s.area * du,
        "V_y": -e * s.second_moment_strong * v3,
        "V_z": -e * s.second_moment_weak * w3,
        "T": g * s.torsion_constant * twist,
        "M_strong": e * s.second_moment_strong * kv,
        "M_weak": e * s.second_moment_weak * kw,
    }
    if s.shape == "CHS":
        sigma = e * (abs(du) + math.hypot(kv, kw) * s.depth / 2.0)
    else:
        sigma = e * (abs(du) + abs(kv) * s.depth / 2.0 + abs(kw) * s.width / 2.0)
    tau = (
        abs(forces["V_y"]) / s.shear_area_strong
        + abs(forces["V_z"]) / s.shear_area_weak
        + abs(forces["T"]) / s.torsion_modulus
    )
    return sigma, tau, forces


def _stress_survey(mesh: _Mesh, disp: np.ndarray) -> tuple[StressPeak, dict[str, MemberEnds]]:
    """The largest von Mises stress (at element ends: the moments are linear in an element)
    and each member's end forces."""
    frame = mesh.frame
    best = StressPeak(0.0, next(iter(frame.members)), 0.0)
    forces = {}
    for member, elements in mesh.elements.items():
        ends = []
        for k, (el, s0, s1) in enumerate(elements):
            d = _element_dofs(mesh, el, disp)
            for xi, at in ((0.0, s0), (s1 - s0, s1)):
                sigma, tau, f = _section_stresses(frame, member, _element_strains(mesh, el, d, xi))
                vm = math.sqrt(sigma * sigma + 3.0 * tau * tau)
                if vm > best.value:
                    best = StressPeak(vm, member, at)
                if (k == 0 and xi == 0.0) or (k == len(elements) - 1 and xi > 0.0):
                    ends.append(f)
        forces[member] = MemberEnds(ends[0], ends[-1])
    return best, forces
