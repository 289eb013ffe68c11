"""rollerrig.fit: parameter identification from measured (or synthetic) tests.

- :mod:`rollerrig.fit.model`: the model fitted, Polach's CoA, and the creep stiffness of the
  rig's contact;
- :mod:`rollerrig.fit.polach`: the bounded least-squares fit and its covariance;
- :mod:`rollerrig.fit.diagnostics`: what the data constrain (slip-velocity coverage, A/B
  identifiability), residual structure, distance from a known truth.
"""

from rollerrig.fit.model import PARAMETER_NAMES, creep_stiffness_for_rig, polach_coa
from rollerrig.fit.polach import PolachFit, PolachFitWarning, fit_polach

__all__ = [
    "PARAMETER_NAMES",
    "PolachFit",
    "PolachFitWarning",
    "creep_stiffness_for_rig",
    "fit_polach",
    "polach_coa",
]
