"""Static and modal analysis of a rig frame on PyNiteFEA, and its reduction to the contact.

The frame (:class:`rollerrig.frame.framefile.Frame`) becomes a PyNite 3-D frame model
(Euler–Bernoulli beams, 6 DOF per node, consistent mass), each member divided into
``elements_per_member`` elements so that the distributed mass is resolved in the modes. Two unit
load cases are solved: the normal load pattern (1 N of air-spring force, spread over the load
points by their ``normal`` factors) and the traction pattern (1 N of traction force F_x, by their
``traction`` factors); the analysis is linear, so any test load is ``N u_normal + F u_traction``.

Why PyNiteFEA: it is a maintained (2016-, v3.x in 2026), MIT-licensed, pure-Python 3-D frame
library with linear static, P-Δ and modal analysis (consistent mass, sparse shift-invert
eigensolver) and member results; numpy/scipy only. Compared: anastruct (GPL-3, 2-D only: used
as the independent cross-check in the tests), OpenSeesPy (powerful but a large binary under a
non-OSI licence, and its modal API works on a global interpreter state), FrameAT (small, no
modal). Two things are our own, on PyNite's matrices: the check for mechanisms (PyNite only
looks at zero diagonal terms and prints them), and the fibre stresses, computed from each
element's end displacements with the cubic (Hermite) shape functions of the same element, so
that they follow from the displacement field and need no sign convention of internal forces:

    ε(x, y, z) = u' − y v'' − z w'',   σ = E ε

(u axial, v along local y = the web direction, w along local z; exact for beams without span
loads, which is the case here: all test loads act on nodes). The largest von Mises stress of a
member combines the largest normal stress of its section (the extreme corner, or the outer
radius of a CHS) with the largest shear stress (V/A_v both ways plus T/W_t): an upper bound,
as is usual in a beam model.

The contact: the traction pattern is the statically equivalent set of forces that a unit
traction force at the wheel-roller contact puts on the frame. Its work-conjugate displacement
``q = Σ f_i · u_i`` is the relative longitudinal displacement of wheel and roller at the
contact, so the frame's longitudinal stiffness at the contact is ``k = 1 / (fᵀ K⁻¹ f)`` and a
mode's participation at the contact is ``q_r = fᵀ φ_r`` (:func:`contact_dof`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rollerrig._optional import require
from rollerrig._validation import ParameterError
from rollerrig.frame.framefile import DOF_NAMES, MAX_MEMBERS, Frame, FrameFileError

__all__ = [
    "ContactDof",
    "FrameResult",
    "GaugeStress",
    "MemberEnds",
    "StressPeak",
    "analyze_frame",
    "build_model",
    "check_contact",
    "check_stability",
    "contact_dof",
    "unit_load_patterns",
    "unit_load_stresses",
]

CASES = ("normal", "traction")
"""The unit load cases: 1 N of normal load, 1 N of traction force."""

DEFAULT_ELEMENTS_PER_MEMBER = 4
"""Elements per member: the first bending mode of a cantilever member with its own mass is
0.05 % high with four (Euler–Bernoulli consistent mass), 2 % with one."""

MAX_ELEMENTS = MAX_MEMBERS * DEFAULT_ELEMENTS_PER_MEMBER
"""Most beam elements of a model (members x elements per member) [1]: the size
:data:`rollerrig.frame.framefile.MAX_MEMBERS` is chosen for (about a minute on two cores)."""

MAX_TEST_LOAD = 1e7
"""Largest test load, normal or traction, in magnitude [N] (10 MN; the rig's air spring gives
20 kN): far beyond any rig, a linear model means nothing there."""

_PURPOSE = "the frame analysis (rollerrig frame)"


# --------------------------------------------------------------------------------------------
# The model
# --------------------------------------------------------------------------------------------


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
        gravity 1, which PyNite converts to mass) for :func:`modal analysis <analyze_frame>`.
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


# --------------------------------------------------------------------------------------------
# Mechanisms
# --------------------------------------------------------------------------------------------

_DOF_WORDS = {
    "x": "move in x",
    "y": "move in y",
    "z": "move in z",
    "rx": "rotate about x",
    "ry": "rotate about y",
    "rz": "rotate about z",
}


def check_stability(mesh: _Mesh, *, tolerance: float = 1e-9) -> None:
    """Raise :class:`FrameFileError` when the supported frame is a mechanism.

    The stiffness matrix of the free DOFs is scaled to a unit diagonal; an eigenvalue below
    ``tolerance`` is a zero-energy mode (a mechanism: too few supports, or a part that can move
    without straining any member). The error names the node and the DOF that move most in it.
    The smallest eigenvalue is found sparse (shift-invert Lanczos about a small negative shift,
    where the scaled matrix minus the shift is positive definite), so that the check costs about
    what a static solution does; a tiny matrix is solved dense.
    """
    from Pynite import Analysis

    model, frame = mesh.model, mesh.frame
    if not model.load_combos:
        model.add_load_combo("stiffness", {"stiffness": 1.0})
    Analysis._prepare_model(model)
    combo = next(iter(model.load_combos))
    k = model.Ke(combo, check_stability=False, sparse=True).tocsr()
    free = np.asarray(_free_dofs(model), dtype=int)
    if not free.size:
        return
    kff = k[free][:, free]
    diag = kff.diagonal().copy()
    zero = np.flatnonzero(diag <= 1e-12 * max(float(diag.max()), 1.0))
    if zero.size:
        _mechanism(frame, model, int(free[zero[0]]), "with no stiffness at all")
    scale = scipy_sparse().diags(1.0 / np.sqrt(diag))
    s = (scale @ kff @ scale).tocsc()
    value, vector = _lowest_mode(s, tolerance)
    if value < tolerance:
        _mechanism(
            frame,
            model,
            int(free[int(np.argmax(np.abs(vector)))]),
            "without straining any member (a zero-energy mode)",
        )


def scipy_sparse():
    """:mod:`scipy.sparse` (imported when first needed)."""
    import scipy.sparse

    return scipy.sparse


_DENSE_BELOW = 200
"""Matrices with fewer rows than this are solved dense (ARPACK needs k < n and gains nothing)."""


def _lowest_mode(s, tolerance: float) -> tuple[float, np.ndarray]:
    """The smallest eigenvalue of a symmetric positive semi-definite sparse matrix with a unit
    diagonal, and its eigenvector; the shift ``-tolerance`` makes a zero-energy mode stand out
    (inverted, it is a billion times any mode above 1)."""
    if s.shape[0] < _DENSE_BELOW:
        values, vectors = np.linalg.eigh(s.toarray())
        return float(values[0]), vectors[:, 0]
    from scipy.sparse.linalg import eigsh

    # The eigenvalues lie in [0, n]; about a small negative shift the nearest is the smallest.
    values, vectors = eigsh(s, k=1, sigma=-tolerance, which="LM")
    return float(values[0]), vectors[:, 0]


def _free_dofs(model) -> list[int]:
    """Global indices of the DOFs no support holds (PyNite's numbering: node ID * 6 + DOF)."""
    free = []
    for node in model.nodes.values():
        held = (
            node.support_DX,
            node.support_DY,
            node.support_DZ,
            node.support_RX,
            node.support_RY,
            node.support_RZ,
        )
        free += [node.ID * 6 + d for d in range(6) if not held[d]]
    return free


def _frame_node(name: str) -> str:
    """The frame's name of a FE node: an element's inner node is named after its member."""
    return name.split("~")[0]


def _mechanism(frame: Frame, model, index: int, why: str) -> None:
    node = next(n for n in model.nodes.values() if n.ID == index // 6)
    dof = DOF_NAMES[index % 6]
    where = (
        f"node {node.name!r}"
        if "~" not in node.name
        else f"member {_frame_node(node.name)!r} (between its ends)"
    )
    raise FrameFileError(
        frame.origin,
        [
            f"supports: the frame is a mechanism: {where} can {_DOF_WORDS[dof]} ({dof}) {why}; "
            "add supports (e.g. fix the column feet) or members that hold it"
        ],
    )


# --------------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------------


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


@dataclass
class FrameResult:
    """Static and modal results of :func:`analyze_frame` (SI units).

    Attributes
    ----------
    frame : Frame
    normal_load, traction_force : float
        The test loads [N].
    nodes : list of str
        FE nodes (the frame's first, then the members' inner nodes ``member~k``).
    unit_displacements : dict
        Case (``"normal"``, ``"traction"``) -> (n_nodes, 6) displacements per newton
        [m/N, rad/N].
    displacements : ndarray
        (n_nodes, 6) under the test loads [m, rad].
    gauges : dict
        Gauge -> :class:`GaugeStress` (per newton).
    gauge_stresses : dict
        Gauge -> axial stress under the test loads [Pa] (> 0 tension).
    max_von_mises : StressPeak
    member_forces : dict
        Member -> :class:`MemberEnds` under the test loads.
    top_horizontal_deflection : float
        Largest horizontal displacement sqrt(u_x² + u_y²) of the top nodes [m].
    top_longitudinal_deflection : float
        u_x at that node [m].
    top_node : str
    contact_flexibility : float
        Relative longitudinal displacement of wheel and roller at the contact per newton of
        traction [m/N].
    frequencies : ndarray
        Natural frequencies [Hz], ascending.
    mode_shapes : ndarray
        (n_modes, n_nodes, 6), mass-normalised (φᵀ M φ = 1 kg).
    contact_participation : ndarray
        Per mode, the contact coordinate q_r = fᵀ φ_r [m/sqrt(kg)].
    frame_mass : float
        Mass of the modal model: members and lumped masses [kg].
    """

    frame: Frame
    normal_load: float
    traction_force: float
    nodes: list[str]
    unit_displacements: dict[str, np.ndarray]
    displacements: np.ndarray
    gauges: dict[str, GaugeStress]
    gauge_stresses: dict[str, float]
    max_von_mises: StressPeak
    member_forces: dict[str, MemberEnds]
    top_horizontal_deflection: float
    top_longitudinal_deflection: float
    top_node: str
    contact_flexibility: float
    frequencies: np.ndarray
    mode_shapes: np.ndarray
    contact_participation: np.ndarray
    frame_mass: float
    elements_per_member: int = DEFAULT_ELEMENTS_PER_MEMBER
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def longitudinal_stiffness_at_contact(self) -> float:
        """Frame stiffness seen by the traction force at the contact, 1/flexibility [N/m]."""
        return 1.0 / self.contact_flexibility

    def displacement(self, node: str) -> np.ndarray:
        """The six displacements of a node under the test loads [m, rad]."""
        return self.displacements[self.nodes.index(node)]


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


# --------------------------------------------------------------------------------------------
# The analysis
# --------------------------------------------------------------------------------------------


def analyze_frame(
    frame: Frame,
    normal_load: float = 20e3,
    traction_force: float = 2e3,
    *,
    n_modes: int = 6,
    elements_per_member: int = DEFAULT_ELEMENTS_PER_MEMBER,
) -> FrameResult:
    """Static analysis under a test load and modal analysis of a frame.

    Parameters
    ----------
    frame : Frame
        The frame (:func:`rollerrig.frame.load_frame`).
    normal_load : float
        Air-spring force N [N] (Kayaalp 4.4.1: 20 kN, the spring's maximum).
    traction_force : float
        Traction force F_x at the contact [N] (Kayaalp 4.4.1: 2 kN), > 0 in traction.
    n_modes : int
        Natural modes to compute (fewer if the frame has fewer free DOFs).
    elements_per_member : int
        Beam elements per member.

    Returns
    -------
    FrameResult

    Raises
    ------
    FrameFileError
        The frame is a mechanism (names the node and DOF).
    ParameterError
        A test load that is not finite or beyond :data:`MAX_TEST_LOAD`, or more than
        :data:`MAX_ELEMENTS` elements in all.

    Examples
    --------
    >>> from rollerrig.frame import default_frame
    >>> r = analyze_frame(default_frame(), 20e3, 2e3, n_modes=3)
    >>> 0.0 < r.top_horizontal_deflection < 1e-3, len(r.frequencies)
    (True, 3)
    """
    for name, value in (("normal_load", normal_load), ("traction_force", traction_force)):
        if not math.isfinite(value) or abs(value) > MAX_TEST_LOAD:
            raise ParameterError(
                f"{name} must be finite and at most {MAX_TEST_LOAD:g} N in magnitude [N], "
                f"got {value!r}"
            )
    if not 1 <= elements_per_member <= 64:
        raise ParameterError(f"elements_per_member must be in [1, 64], got {elements_per_member}")
    if elements_per_member * len(frame.members) > MAX_ELEMENTS:
        raise ParameterError(
            f"{len(frame.members)} members x {elements_per_member} elements each is more than "
            f"the {MAX_ELEMENTS} elements the analysis takes (MAX_ELEMENTS); use fewer "
            "elements per member or a smaller frame"
        )
    patterns = unit_load_patterns(frame)
    mesh = build_model(frame, elements_per_member=elements_per_member, loads=patterns)
    check_stability(mesh)
    mesh.model.analyze_linear(check_stability=False, check_statics=False)
    unit = {case: _node_matrix(mesh, case) for case in CASES}
    disp = normal_load * unit["normal"] + traction_force * unit["traction"]
    gauges = unit_load_stresses(mesh, unit)
    gauge_stresses = {
        n: g.normal * normal_load + g.traction * traction_force for n, g in gauges.items()
    }
    peak, forces = _stress_survey(mesh, disp)
    top_index = [mesh.nodes.index(n) for n in frame.top_nodes]
    horizontal = np.hypot(disp[top_index, 0], disp[top_index, 1])
    k = int(np.argmax(horizontal))
    flexibility = sum(
        float(np.dot(f, unit["traction"][mesh.nodes.index(node), :3]))
        for node, f in patterns["traction"].items()
    )
    frequencies, shapes, mass = _modes(frame, elements_per_member, n_modes)
    traction_nodes = [(mesh.nodes.index(n), f) for n, f in patterns["traction"].items()]
    participation = np.array(
        [sum(float(np.dot(f, shape[i, :3])) for i, f in traction_nodes) for shape in shapes]
    )
    return FrameResult(
        frame=frame,
        normal_load=float(normal_load),
        traction_force=float(traction_force),
        nodes=mesh.nodes,
        unit_displacements=unit,
        displacements=disp,
        gauges=gauges,
        gauge_stresses=gauge_stresses,
        max_von_mises=peak,
        member_forces=forces,
        top_horizontal_deflection=float(horizontal[k]),
        top_longitudinal_deflection=float(disp[top_index[k], 0]),
        top_node=frame.top_nodes[k],
        contact_flexibility=float(flexibility),
        frequencies=frequencies,
        mode_shapes=shapes,
        contact_participation=participation,
        frame_mass=mass,
        elements_per_member=elements_per_member,
    )


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


def _modes(frame: Frame, elements_per_member: int, n_modes: int):
    """(frequencies [Hz], mass-normalised shapes (n_modes, n_nodes, 6), model mass [kg]).

    Stiffness and consistent mass matrices are PyNite's (members' own mass through a
    self-weight case with gravity 1, lumped masses as nodal loads), with one correction: PyNite
    takes the torsion constant J for the rotary inertia of a section about the member's axis,
    where the polar moment I_p = I_y + I_z belongs (HEB 200: J = 59 cm^4, I_p = 7699 cm^4); the
    missing ``ρ L (I_p - J) / 6 [[2, 1], [1, 2]]`` is added on each element's twist DOFs. The
    generalised eigenproblem of the free DOFs is solved sparse (shift-invert Lanczos,
    ``scipy.sparse.linalg.eigsh``, about a shift of -1 (rad/s)^2, below every frequency, so that
    the nearest eigenvalues are the lowest); a small one dense (``scipy.linalg.eigh``).
    """
    import scipy.linalg
    from Pynite import Analysis
    from scipy.sparse.linalg import eigsh

    sparse = scipy_sparse()
    mesh = build_model(frame, elements_per_member=elements_per_member, masses=True)
    model = mesh.model
    Analysis._prepare_model(model)
    k = model.Ke("mass", check_stability=False, sparse=True).tocsr()
    m = model.M("mass", "Z", 1.0, sparse=True).tocoo()
    rows, cols, data = [m.row], [m.col], [m.data]
    block = np.arange(3)
    for member, elements in mesh.elements.items():
        mb = frame.members[member]
        s, rho = frame.sections[mb.section], frame.materials[mb.material].density
        for el, s0, s1 in elements:
            e = model.members[el]
            extra = rho * (s1 - s0) * (s.polar_moment - s.torsion_constant) / 6.0
            axis = e.T()[0, :3]
            i, j = e.i_node.ID * 6 + 3, e.j_node.ID * 6 + 3
            for a, b, w in ((i, i, 2.0), (j, j, 2.0), (i, j, 1.0), (j, i, 1.0)):
                rows.append(np.repeat(a + block, 3))
                cols.append(np.tile(b + block, 3))
                data.append((w * extra * np.outer(axis, axis)).ravel())
    m = sparse.coo_matrix(
        (np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))), shape=m.shape
    ).tocsr()
    order = np.concatenate([np.arange(6) + model.nodes[n].ID * 6 for n in mesh.nodes])
    held = np.concatenate(
        [np.asarray(frame.supports.get(n, (False,) * 6), dtype=bool) for n in mesh.nodes]
    )
    free = order[~held]
    n = max(1, min(int(n_modes), free.size))
    kff, mff = k[free][:, free], m[free][:, free]
    if free.size < _DENSE_BELOW or n >= free.size - 1:
        values, vectors = scipy.linalg.eigh(
            kff.toarray(), mff.toarray(), subset_by_index=[0, n - 1]
        )
    else:
        values, vectors = eigsh(kff.tocsc(), k=n, M=mff.tocsc(), sigma=-1.0, which="LM")
        ranked = np.argsort(values)
        values, vectors = values[ranked], vectors[:, ranked]
        vectors = vectors / np.sqrt(np.einsum("ij,ij->j", vectors, mff @ vectors))
    shapes = []
    for v in vectors.T:
        phi = np.zeros(order.size)
        phi[~held] = v  # normalised: vᵀ M v = 1 [kg]
        big = int(np.argmax(np.abs(phi)))
        shapes.append(np.sign(phi[big]) * phi.reshape(-1, 6))  # largest component positive
    total = frame.total_mass()
    frequencies = np.sqrt(np.clip(values, 0.0, None)) / (2.0 * np.pi)
    return frequencies, np.asarray(shapes), float(total)


# --------------------------------------------------------------------------------------------
# The frame as one degree of freedom at the contact
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ContactDof:
    """The frame reduced to one longitudinal degree of freedom at the wheel-roller contact.

    The coordinate is the relative longitudinal displacement of wheel and roller at the contact
    (work-conjugate to the traction force). For the twin: a spring ``stiffness`` in series with
    the contact; to give it the dominant mode's frequency, a mass ``equivalent_mass`` on it
    (``stiffness / (2π f)²``). ``modal_mass`` and ``modal_stiffness`` are that mode's alone,
    referred to the contact coordinate (``q_r = 1``); ``participation`` is the mode's share of
    the static flexibility (1 when the mode carries all of it).

    Attributes
    ----------
    stiffness : float
        Static longitudinal stiffness at the contact, 1 / (fᵀ K⁻¹ f) [N/m].
    mode : int
        Index (0-based) of the mode that contributes most to the contact flexibility.
    frequency : float
        Its natural frequency [Hz].
    modal_mass : float
        m_r / q_r², its modal mass referred to the contact coordinate [kg].
    modal_stiffness : float
        (2π f)² × modal_mass [N/m].
    participation : float
        (q_r² / ω_r²) / (fᵀ K⁻¹ f) [1].
    equivalent_mass : float
        stiffness / (2π f)² [kg].
    """

    stiffness: float
    mode: int
    frequency: float
    modal_mass: float
    modal_stiffness: float
    participation: float
    equivalent_mass: float

    def to_dict(self) -> dict[str, float]:
        """SI values keyed with their units, for JSON."""
        return {
            "stiffness [N/m]": self.stiffness,
            "mode": self.mode + 1,
            "frequency [Hz]": self.frequency,
            "modal_mass [kg]": self.modal_mass,
            "modal_stiffness [N/m]": self.modal_stiffness,
            "participation [1]": self.participation,
            "equivalent_mass [kg]": self.equivalent_mass,
        }


def check_contact(frame: Frame) -> None:
    """Raise :class:`FrameFileError` when the load points put no force on the frame under
    traction: the contact coordinate of :func:`contact_dof` is then undefined (checked before
    an analysis that would end there)."""
    if not any(any(lp.traction) for lp in frame.load_points.values()):
        raise FrameFileError(
            frame.origin,
            [
                "load_points: every load point's traction is [0, 0, 0], so the frame has no "
                "stiffness at the contact; give the force a unit traction force puts on the "
                "frame (traction = [x, y, z]) at the load points"
            ],
        )


def contact_dof(result: FrameResult) -> ContactDof:
    """The frame's longitudinal stiffness and the dominant mode's mass at the contact.

    The mode chosen is the one with the largest share ``q_r² / ω_r²`` of the contact's static
    flexibility (the first longitudinal mode seen from the contact).

    Raises
    ------
    FrameFileError
        The frame's load points put no force on it under traction (no contact coordinate).
    ParameterError
        No mode computed moves the contact.

    Examples
    --------
    >>> from rollerrig.frame import default_frame
    >>> dof = contact_dof(analyze_frame(default_frame(), n_modes=6))
    >>> dof.stiffness > 1e7 and 0 < dof.participation <= 1.0 + 1e-9
    True
    """
    check_contact(result.frame)
    omega = 2.0 * np.pi * result.frequencies
    share = result.contact_participation**2 / omega**2
    r = int(np.argmax(share))
    q = float(result.contact_participation[r])
    if not share[r] > 0.0:
        raise ParameterError(
            f"none of the {len(omega)} modes computed moves the contact; compute more modes"
        )
    modal_mass = 1.0 / (q * q)  # shapes are mass-normalised: m_r = 1
    k = result.longitudinal_stiffness_at_contact
    return ContactDof(
        stiffness=k,
        mode=r,
        frequency=float(result.frequencies[r]),
        modal_mass=modal_mass,
        modal_stiffness=float(omega[r] ** 2 * modal_mass),
        participation=float(share[r] / result.contact_flexibility),
        equivalent_mass=float(k / omega[r] ** 2),
    )
