"""The results of a frame analysis: displacements, stresses, deflections and modes, in SI."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError, did_you_mean
from rollerrig.frame.femodel import DEFAULT_ELEMENTS_PER_MEMBER
from rollerrig.frame.stresses import GaugeStress, MemberEnds, StressPeak
from rollerrig.frame.structure import Frame

__all__ = ["FrameResult"]


@dataclass
class FrameResult:
    """Static and modal results of :func:`~rollerrig.frame.analysis.analyze_frame` (SI units).

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
        Gauge -> :class:`~rollerrig.frame.stresses.GaugeStress` (per newton).
    gauge_stresses : dict
        Gauge -> axial stress under the test loads [Pa] (> 0 tension).
    max_von_mises : StressPeak
    member_forces : dict
        Member -> :class:`~rollerrig.frame.stresses.MemberEnds` under the test loads.
    top_horizontal_deflection : float
        Largest horizontal displacement sqrt(u_x² + u_y²) of the top nodes [m].
    top_longitudinal_deflection : float
        u_x at that node [m].
    top_node : str
    contact_flexibility : float
        Relative longitudinal displacement of wheel and roller at the contact per newton of
        traction [m/N].
    frequencies : ndarray
        Natural frequencies [Hz], ascending: the ``n_modes`` asked of
        :func:`~rollerrig.frame.analysis.analyze_frame`, and more when it took more to establish
        the contact's dominant mode.
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
        try:
            return self.displacements[self.nodes.index(node)]
        except ValueError:  # list.index: "'nope' is not in list"
            frame_nodes = list(self.frame.nodes)  # not the mesh's inner nodes (name~k)
            raise ParameterError(
                f"node {node!r} is not a node of the frame{did_you_mean(str(node), frame_nodes)}; "
                f"its nodes: {', '.join(map(str, frame_nodes[:20]))}"
                + (" ..." if len(frame_nodes) > 20 else "")
            ) from None
