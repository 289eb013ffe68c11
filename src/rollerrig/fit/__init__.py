"""rollerrig.fit: parameter identification from measured (or synthetic) tests."""

from rollerrig.fit.polach import (
    PARAMETER_NAMES,
    PolachFit,
    PolachFitWarning,
    creep_stiffness_for_rig,
    fit_polach,
    polach_coa,
)

__all__ = [
    "PARAMETER_NAMES",
    "PolachFit",
    "PolachFitWarning",
    "creep_stiffness_for_rig",
    "fit_polach",
    "polach_coa",
]
