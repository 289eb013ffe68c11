"""Contact mechanics of the wheel-roller pair.

- :mod:`~rollerrig.contact.hertz` — exact Hertz elliptical contact (complete elliptic integrals).
- :mod:`~rollerrig.contact.kalker` — Kalker's creepage coefficients (Kalker 1990, Table E.3).
- :mod:`~rollerrig.contact.creep` — Polach's creep law with slip-velocity-dependent friction,
  Kalker's linear theory, named parameter sets.
- :mod:`~rollerrig.contact.kinematics` — creep and slip velocity from wheel and roller speeds.
- :mod:`~rollerrig.contact.roller` — roller versus tangent rail (contact size).
- :mod:`~rollerrig.contact.curves` — creep-adhesion curves for a geometry.
- :mod:`~rollerrig.contact.fastsim` — Kalker's FASTSIM and the modified FASTSIM (k0, α∞, β).
- :mod:`~rollerrig.contact.flexibilities` — the simplified theory's flexibilities (Kalker's,
  CONTACT's blend).
- :mod:`~rollerrig.contact.slope_reduction` — the modified FASTSIM's slope reduction k.
- :mod:`~rollerrig.contact.ellipse_grid` — FASTSIM's grids of the contact ellipse.
- :mod:`~rollerrig.contact.tangential_result` — forces and traction fields of a creep law.
- :mod:`~rollerrig.contact.strip` — FaStrip (Sichani, Enblom & Berg 2016).
- :mod:`~rollerrig.contact.laws` — creep laws and friction parameter sets by name.
- :mod:`~rollerrig.contact.cntc` — optional backend: Kalker's exact theory through CONTACT.
"""

from rollerrig.contact.creep import (
    POLACH_DRY,
    POLACH_PARAMETER_SETS,
    POLACH_WET,
    PolachParameters,
    adhesion_gradient,
    friction_coefficient,
    kalker_linear_force,
    polach_creep_force,
)
from rollerrig.contact.curves import CreepCurve, polach_creep_curve
from rollerrig.contact.fastsim import (
    FastsimGrid,
    TangentialResult,
    TractionField,
    fastsim,
    fastsim_grid,
    kalker_flexibilities,
)
from rollerrig.contact.hertz import (
    CombinedElasticConstants,
    HertzContact,
    combined_elastic_constants,
    hertz_contact,
)
from rollerrig.contact.kalker import (
    KALKER_TABLE,
    KalkerCoefficients,
    KalkerTable,
    kalker_coefficients,
)
from rollerrig.contact.kinematics import DEFAULT_REGULARISATION_SPEED, creep_and_slip_velocity
from rollerrig.contact.laws import (
    CREEP_LAWS,
    FRICTION_PARAMETER_SETS,
    FastsimParameters,
    creep_force,
    law_creep_curve,
    parameter_set,
)
from rollerrig.contact.roller import (
    RollerRailComparison,
    area_ratio_to_tangent_rail,
    contact_versus_roller_radius,
)
from rollerrig.contact.strip import fastrip

__all__ = [
    "CREEP_LAWS",
    "DEFAULT_REGULARISATION_SPEED",
    "FRICTION_PARAMETER_SETS",
    "KALKER_TABLE",
    "POLACH_DRY",
    "POLACH_PARAMETER_SETS",
    "POLACH_WET",
    "CombinedElasticConstants",
    "CreepCurve",
    "FastsimGrid",
    "FastsimParameters",
    "HertzContact",
    "KalkerCoefficients",
    "KalkerTable",
    "PolachParameters",
    "RollerRailComparison",
    "TangentialResult",
    "TractionField",
    "adhesion_gradient",
    "area_ratio_to_tangent_rail",
    "combined_elastic_constants",
    "contact_versus_roller_radius",
    "creep_and_slip_velocity",
    "creep_force",
    "fastrip",
    "fastsim",
    "fastsim_grid",
    "friction_coefficient",
    "hertz_contact",
    "kalker_coefficients",
    "kalker_flexibilities",
    "kalker_linear_force",
    "law_creep_curve",
    "parameter_set",
    "polach_creep_curve",
    "polach_creep_force",
]
