"""Static and modal analysis of a rig frame on PyNiteFEA, and its reduction to the contact.

:func:`analyze_frame` builds the frame's FE model and its two unit load cases
(:mod:`rollerrig.frame.femodel`: 1 N of normal load, 1 N of traction force; the analysis is
linear, so any test load is ``N u_normal + F u_traction``), refuses a mechanism
(:mod:`rollerrig.frame.modes`), solves the static cases, and gathers the stresses at the gauges,
the largest von Mises stress and the members' end forces (:mod:`rollerrig.frame.stresses`), the
top deflection, the natural modes and the contact's flexibility and participations into a
:class:`~rollerrig.frame.results.FrameResult`. :func:`~rollerrig.frame.reduction.contact_dof`
reduces that to one degree of freedom at the wheel-roller contact
(:mod:`rollerrig.frame.reduction`).

The names of those modules that this module exported before them are re-exported here.
"""

from __future__ import annotations

import numbers

import numpy as np

from rollerrig._validation import ParameterError, require_finite, require_whole
from rollerrig.frame.femodel import (
    CASES,
    DEFAULT_ELEMENTS_PER_MEMBER,
    _node_matrix,
    build_model,
    unit_load_patterns,
)
from rollerrig.frame.limits import MAX_MEMBERS
from rollerrig.frame.modes import _modes, check_stability
from rollerrig.frame.reduction import (
    ContactDof,
    check_contact,
    contact_dof,
    contact_shares,
    dominant_is_established,
)
from rollerrig.frame.results import FrameResult
from rollerrig.frame.stresses import (
    GaugeStress,
    MemberEnds,
    StressPeak,
    _stress_survey,
    unit_load_stresses,
)
from rollerrig.frame.structure import Frame

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

MAX_ELEMENTS = MAX_MEMBERS * DEFAULT_ELEMENTS_PER_MEMBER
"""Most beam elements of a model (members x elements per member) [-]: the size
:data:`rollerrig.frame.limits.MAX_MEMBERS` is chosen for (about a minute on two cores)."""

MAX_CONTACT_MODES = 200
"""Most natural modes computed in search of the mode that dominates the contact [-] (the
bundled frame needs 4; each search doubles the count, so at worst twice what it needs). Beyond,
:func:`~rollerrig.frame.reduction.contact_dof` says that the dominant mode is not established
rather than name one."""

MAX_TEST_LOAD = 1e7
"""Largest test load, normal or traction, in magnitude [N] (10 MN; the rig's air spring gives
20 kN): far beyond any rig, a linear model means nothing there."""


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
        Natural modes to compute at least (fewer if the frame has fewer free DOFs). More are
        computed, and returned, while those computed do not establish which mode dominates
        the contact's flexibility (:func:`~rollerrig.frame.reduction.contact_dof`): the count
        doubles until they do, up to :data:`MAX_CONTACT_MODES`.
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
    >>> 0.0 < r.top_horizontal_deflection < 1e-3
    True

    The contact's dominant mode is the 4th, so 3 modes were not enough to establish it:

    >>> len(r.frequencies), contact_dof(r).mode + 1
    (6, 4)
    """
    if not isinstance(frame, Frame):
        raise ParameterError(
            f"frame must be a Frame (load_frame, default_frame), got {type(frame).__name__}"
        )
    for name, value in (("normal_load", normal_load), ("traction_force", traction_force)):
        if isinstance(value, str | bytes | bool) or np.ndim(value) != 0:
            raise ParameterError(f"{name} must be a single number [N], got {value!r}")
        value = require_finite(name, value, "N", single=True)
        if abs(value) > MAX_TEST_LOAD:
            raise ParameterError(
                f"{name} must be finite and at most {MAX_TEST_LOAD:g} N in magnitude [N], "
                f"got {value!r}"
            )
    # Counts: 2.5 elements or modes, True or "3" were taken (n_modes 0 or -3 silently as 1).
    epm = elements_per_member
    if isinstance(epm, bool | np.bool_) or not isinstance(epm, numbers.Real) or not 1 <= epm <= 64:
        raise ParameterError(f"elements_per_member must be in [1, 64], got {epm!r}")
    elements_per_member = require_whole("elements_per_member", epm, 1, 64)
    n_modes = require_whole("n_modes", n_modes, 1)
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
    traction_nodes = [(mesh.nodes.index(n), f) for n, f in patterns["traction"].items()]
    count = n_modes
    while True:
        frequencies, shapes, mass = _modes(frame, elements_per_member, count)
        participation = np.array(
            [sum(float(np.dot(f, shape[i, :3])) for i, f in traction_nodes) for shape in shapes]
        )
        # The contact's dominant mode may lie above the modes asked for (the bundled frame's is
        # the 4th): with too few, contact_dof would name a mode that carries none of it.
        if not flexibility > 0.0:  # no traction pattern: no contact to find a mode for
            break
        shares = contact_shares(frequencies, participation, flexibility)
        every = len(frequencies) < count  # the frame has no more modes
        if every or count >= MAX_CONTACT_MODES or dominant_is_established(shares):
            break
        count = min(2 * count, MAX_CONTACT_MODES)
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
