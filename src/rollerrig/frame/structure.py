"""The frame in memory: a validated :class:`Frame` and its parts, in SI units.

Nodes are points [m] in the global axes of the frame file (x longitudinal, y lateral, z
vertical, up); members are straight beams between two nodes, each with a section
(:mod:`rollerrig.frame.sections`) and a material; a support holds some of a node's six degrees
of freedom (:data:`DOF_NAMES`); load points, lumped masses and strain gauges sit on nodes and
members. Nothing here reads or checks a file: :mod:`rollerrig.frame.framefile` builds a
:class:`Frame` from one.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rollerrig.frame.sections import SectionProperties

__all__ = ["DOF_NAMES", "Frame", "LoadPoint", "Material", "Member", "PointMass", "StrainGauge"]

DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
"""The six degrees of freedom of a node: translations along and rotations about x, y, z."""


@dataclass(frozen=True)
class Material:
    """An isotropic elastic material.

    Attributes
    ----------
    name : str
    youngs_modulus : float
        E [Pa].
    poisson : float
        ν [-].
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

    Build one with :func:`~rollerrig.frame.framefile.load_frame`,
    :func:`~rollerrig.frame.framefile.frame_from_dict` or
    :func:`~rollerrig.frame.framefile.default_frame`.
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
