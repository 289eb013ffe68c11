"""Drive models of the rig: the wheel's PMSM, the roller's induction motor, the proposed servo.

- :mod:`~rollerrig.drives.pmsm` — PMSM dq model (Kayaalp eqs. 4.23-4.25, eq. 4.24 sign
  corrected), field-oriented PI current control with voltage limit.
- :mod:`~rollerrig.drives.induction` — induction motor Thevenin torque under open-loop V/f
  (eq. 4.28), circuit from the nameplate, linear torque-slip fit, response lag (eq. 4.29).
- :mod:`~rollerrig.drives.servo` — speed-controlled servo/PMSM roller drive (the seed's fix).
"""

from rollerrig.drives.induction import (
    SEED_LAG_STEP,
    TheveninCircuit,
    clp_from_lag_time_constant,
    discrete_lag_filter,
    induction_torque,
    lag_derivative,
    lag_time_constant_from_clp,
    linear_induction_torque,
    linear_slope_from_nameplate,
    thevenin_from_nameplate,
    vf_supply_frequency,
    vf_voltage,
)
from rollerrig.drives.pmsm import (
    max_phase_voltage,
    pi_gains_for_bandwidth,
    pmsm_current_derivatives,
    pmsm_current_reference,
    pmsm_foc_voltages,
    pmsm_magnetic_energy,
    pmsm_torque,
    pmsm_torque_ripple,
)
from rollerrig.drives.servo import (
    servo_gains_for_bandwidth,
    servo_speed_torque,
)

__all__ = [
    "SEED_LAG_STEP",
    "TheveninCircuit",
    "clp_from_lag_time_constant",
    "discrete_lag_filter",
    "induction_torque",
    "lag_derivative",
    "lag_time_constant_from_clp",
    "linear_induction_torque",
    "linear_slope_from_nameplate",
    "max_phase_voltage",
    "pi_gains_for_bandwidth",
    "pmsm_current_derivatives",
    "pmsm_current_reference",
    "pmsm_foc_voltages",
    "pmsm_magnetic_energy",
    "pmsm_torque",
    "pmsm_torque_ripple",
    "servo_gains_for_bandwidth",
    "servo_speed_torque",
    "thevenin_from_nameplate",
    "vf_supply_frequency",
    "vf_voltage",
]
