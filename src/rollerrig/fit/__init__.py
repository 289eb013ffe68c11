"""rollerrig.fit: parameter identification from measured (or synthetic) tests.

- :mod:`rollerrig.fit.model`: the model fitted, Polach's CoA, and the creep stiffness of the
  rig's contact;
- :mod:`rollerrig.fit.polach`: the bounded least-squares fit and its covariance;
- :mod:`rollerrig.fit.diagnostics`: what the data constrain (slip-velocity coverage, A/B
  identifiability), residual structure, distance from a known truth;
- :mod:`rollerrig.fit.modified_fastsim`: the same fit for the modified FASTSIM; its law (the
  parameters, their bounds, the CoA at many loads) in :mod:`rollerrig.fit.modified_fastsim_model`,
  its result in :mod:`rollerrig.fit.modified_fastsim_result`, its A/B coverage in
  :mod:`rollerrig.fit.modified_fastsim_coverage`.
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
