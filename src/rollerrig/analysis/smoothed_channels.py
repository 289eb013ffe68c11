"""The smoothed channels and the corrected CoA of an adhesion test's analysis.

One step of :func:`rollerrig.analysis.adhesion.analyze_test`: the torque and the speeds smoothed
by the Savitzky-Golay filter the analysis tuned, the creep, slip velocity and rig's CoA from
them, and the CoA corrected for the roller's inertia and bearing loss
(:func:`rollerrig.measure.correction.corrected_adhesion`) with its own, shorter filter
(:data:`CORRECTION_WINDOW`).
"""

from __future__ import annotations

import numpy as np

from rollerrig.measure.correction import corrected_adhesion
from rollerrig.measure.quantities import ANALYSIS_CHANNELS
from rollerrig.recordings.recording import Recording
from rollerrig.signal.smoothing import savitzky_golay

__all__ = ["CORRECTION_WINDOW"]

CORRECTION_WINDOW = 0.2
"""Span of the dynamics correction's quartic Savitzky-Golay filter [s] (the acceleration needs
less smoothing than the noise does: a 0.2 s quartic filter keeps the transients; measured: CoA
error 0.009 against 0.019 with a 0.8 s quadratic one)."""


def _smoothed_and_corrected(rec: Recording, rig, window: int, order: int) -> Recording:
    """``rec`` with the smoothed torque, creep, slip velocity and CoA, and the corrected CoA.

    Savitzky-Golay (``window`` [samples], ``order``) smoothing of the torque and the speeds, the
    creep and the rig's CoA from them; the CoA corrected for the roller's inertia and bearing
    loss (:func:`rollerrig.measure.correction.corrected_adhesion`) and the roller acceleration.
    """
    fs = rec.sample_rate
    torque_s = savitzky_golay(rec["torque"], window, order)
    wheel_s = savitzky_golay(rec["wheel_speed"], window, order)
    roller_s = savitzky_golay(rec["roller_speed"], window, order)
    rw, rr = rig.geometry.wheel_radius_x, rig.geometry.roller_radius_x
    v_roller = roller_s * rr
    slip_s = wheel_s * rw - v_roller
    creep_s = np.divide(slip_s, v_roller, out=np.zeros_like(slip_s), where=np.abs(v_roller) > 1e-3)
    coa_s = torque_s / (rr * rec["normal_load"])
    b = rig.bearing
    coa_c, alpha = corrected_adhesion(
        rec["torque"],
        rec["roller_speed"],
        rec["normal_load"],
        fs,
        roller_radius=rr,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        regularisation_speed=b.regularisation_speed,
        window=_odd(CORRECTION_WINDOW * fs),
        order=4,
        load_transfer=rig.arm.transfer_ratio,
        dead_weight=rig.arm.dead_weight,
    )
    return rec.with_channels(
        torque_smoothed=torque_s,
        creep_smoothed=creep_s,
        slip_velocity_smoothed=slip_s,
        coa_smoothed=coa_s,
        coa_corrected=coa_c,
        roller_acceleration=alpha,
        units={name: unit for name, (unit, _) in ANALYSIS_CHANNELS.items()},
    )


def _odd(n: float) -> int:
    k = max(round(n), 7)
    return k if k % 2 else k + 1
