"""What a frame file may hold: the plausible range of each kind of number, the most entries of
each table, and the distance within which two points are one.

Every number is checked against its range as it is read (:data:`PLAUSIBLE`), and the size of
each table before any entry is read (:data:`MAX_NODES`, :data:`MAX_MEMBERS`,
:data:`MAX_ENTRIES`), so that nothing absurd or too large reaches the FE analysis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["MAX_ENTRIES", "MAX_MEMBERS", "MAX_NODES", "NODE_TOLERANCE", "PLAUSIBLE", "Plausible"]

NODE_TOLERANCE = 1e-6
"""Two nodes closer than this are one point [m]; a load point given by coordinates must lie
within it of a node."""

MAX_MEMBERS = 200
"""Most members a frame file may hold [-]. The analysis divides each member into four beam
elements and builds the model three times in PyNite's pure Python (stability check, static,
modal), whose meshing looks at every node for each element: the cost grows faster than the
size. Measured on two cores: a ladder frame of 199 members in 9 s (36 s with the cores shared
by four other processes), one of 499 members in over 10 minutes. The bundled rig frame has 28.
Checked before any entry is read."""

MAX_NODES = 2 * MAX_MEMBERS
"""Most nodes a frame file may hold [-]: every node is the end of a member, so a frame of
:data:`MAX_MEMBERS` members has at most twice as many. Checked before any entry is read."""

MAX_ENTRIES = MAX_NODES
"""Most entries in each of the other tables (materials, sections, supports, load points,
masses, strain gauges) [-]: none can usefully hold more than one per node."""


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
