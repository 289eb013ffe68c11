"""Drive models of the rig: the wheel's PMSM, the roller's induction motor, the proposed servo.

- :mod:`~rollerrig.drives.pmsm` — PMSM dq model (Kayaalp eqs. 4.23-4.25, eq. 4.24 sign
  corrected), field-oriented PI current control with voltage limit.
- :mod:`~rollerrig.drives.pmsm_envelope` — the stator voltage the PMSM needs in steady state:
  where a test runs into its voltage limit.
- :mod:`~rollerrig.drives.induction` — induction motor Thevenin torque under open-loop V/f
  (eq. 4.28), circuit from the nameplate, linear torque-slip fit, response lag (eq. 4.29).
- :mod:`~rollerrig.drives.servo` — speed-controlled servo/PMSM roller drive (the seed's fix).
- :mod:`~rollerrig.drives.induction_dq` — the induction motor's dynamics (inverse-Γ dq model:
  kernels, steady state, linearisation), its parameters in :mod:`~rollerrig.drives.inverse_gamma`
  and from the nameplate in :mod:`~rollerrig.drives.inverse_gamma_nameplate`.
"""

from rollerrig.drives import induction, pmsm, pmsm_envelope, servo
from rollerrig.drives.induction import *  # noqa: F403
from rollerrig.drives.pmsm import *  # noqa: F403
from rollerrig.drives.pmsm_envelope import *  # noqa: F403
from rollerrig.drives.servo import *  # noqa: F403

# The public names of the four modules, each list kept once, in its module.
__all__ = [*induction.__all__, *pmsm.__all__, *pmsm_envelope.__all__, *servo.__all__]
