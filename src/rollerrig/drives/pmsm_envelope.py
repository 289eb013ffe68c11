"""The wheel PMSM's voltage envelope: the stator voltage its i_d = 0 control needs in steady state.

Above its base speed a PMSM under i_d = 0 control
(:func:`rollerrig.drives.pmsm.pmsm_current_reference`, no field weakening) cannot hold the
current its torque request needs: the back-EMF ω_e φ takes the inverter's voltage circle
(:func:`rollerrig.drives.pmsm.max_phase_voltage`), the current loops saturate, and the torque
collapses within a few current-loop time constants while the request goes on rising. On the
twin of a quarter-scale rig run at 30 km/h (the wheel at 73 rad/s, its back-EMF 340 V of
346 V) the wheel torque fell from 43 to 2 N.m in 40 ms; the corrected CoA, smoothed over
0.2 s, then missed the truth by up to 4 expanded uncertainties there (2026-12-03). This module
says where a test runs into that envelope: the twin's protocol (:mod:`rollerrig.rig.assemble`,
a warning) and a recording (:mod:`rollerrig.analysis`, a note).

Kept apart from :mod:`rollerrig.drives.pmsm`, whose kernels the compiled twin is built from (an
edit there recompiles it).

References
----------
Kayaalp (the seed), eqs. 4.23-4.24 (sign of eq. 4.24 corrected in
:func:`rollerrig.drives.pmsm.pmsm_current_derivatives`).
P. C. Krause, O. Wasynczuk, S. D. Sudhoff, *Analysis of Electric Machinery and Drive Systems*,
2nd ed., Wiley-IEEE Press, 2002, ch. 7 (steady-state voltage equations in the rotor frame).
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import require_finite, require_nonnegative, require_positive
from rollerrig.drives.pmsm import max_phase_voltage

__all__ = ["VOLTAGE_LIMIT_SHARE", "pmsm_steady_voltage", "pmsm_voltage_share"]

VOLTAGE_LIMIT_SHARE = 0.95
"""Share of the inverter's voltage (:func:`pmsm_voltage_share`) from which a test counts as at
the PMSM's voltage limit [-]. The steady demand is reckoned at the free-rolling speed; the
wheel's creep and speed ripple add a few per cent: on the twin of the quarter-scale rig at
30 km/h the torque collapsed at 45 N.m of request, where the steady demand at the free-rolling
speed was 0.985 of the limit (2 % creep takes it past 1)."""


def pmsm_steady_voltage(
    torque, omega_mech, pole_pairs, flux_linkage, stator_resistance, inductance_q, max_current
):
    r"""Stator voltage amplitude [V] that i_d = 0 control needs for ``torque`` at ``omega_mech``.

    Eqs. 4.23-4.24 of the seed in steady state (di/dt = 0) with i_d = 0 and the current
    reference clipped at the inverter's limit:

    .. math::

        i_q = \operatorname{clip}\!\left(\frac{T}{\tfrac32 p \varphi}, -I_{max}, I_{max}\right),
        \quad v_d = -\omega_e L_q i_q, \quad v_q = R i_q + \omega_e \varphi, \quad
        |v| = \sqrt{v_d^2 + v_q^2}, \quad \omega_e = p\,\omega_{mech}.

    Parameters
    ----------
    torque : float or array_like
        Air-gap torque [N.m] (a request: clipped at the current limit).
    omega_mech : float or array_like
        Mechanical rotor speed [rad/s].
    pole_pairs : float
        Number of pole pairs p [-].
    flux_linkage : float
        Permanent-magnet flux linkage φ [Wb].
    stator_resistance : float
        Stator phase resistance R [ohm].
    inductance_q : float
        q-axis inductance L_q [H].
    max_current : float
        Current limit of the inverter I_max [A].

    Returns
    -------
    ndarray
        |v| [V], the broadcast shape of ``torque`` and ``omega_mech``.

    Examples
    --------
    At no torque the voltage is the back-EMF p ω φ (22 pole pairs, 0.2 Wb, 68 rad/s: 299.2 V):

    >>> float(pmsm_steady_voltage(0.0, 68.0, 22, 0.2, 0.04, 5e-4, 400.0))
    299.2
    """
    torque = require_finite("torque", torque, "N.m")
    omega = require_finite("omega_mech", omega_mech, "rad/s")
    p = require_positive("pole_pairs", pole_pairs, "-", single=True)
    flux = require_positive("flux_linkage", flux_linkage, "Wb", single=True)
    resistance = require_nonnegative("stator_resistance", stator_resistance, "ohm", single=True)
    lq = require_positive("inductance_q", inductance_q, "H", single=True)
    i_max = require_positive("max_current", max_current, "A", single=True)
    i_q = np.clip(torque / (1.5 * p * flux), -i_max, i_max)
    omega_e = p * omega
    return np.hypot(-omega_e * lq * i_q, resistance * i_q + omega_e * flux)


def pmsm_voltage_share(torque, omega_mech, pmsm) -> np.ndarray:
    """|v| of :func:`pmsm_steady_voltage` over the inverter's largest, V_dc/√3 [-], for the
    rig's ``pmsm`` (:class:`rollerrig.rig.sections.PmsmParameters`): 1 or more where the drive
    cannot hold its current (the voltage limit; no field weakening).

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> pm = default_rig().pmsm
    >>> bool(pmsm_voltage_share(0.0, 0.0, pm) == 0.0)
    True
    """
    demand = pmsm_steady_voltage(
        torque,
        omega_mech,
        pmsm.pole_pairs,
        pmsm.flux_linkage,
        pmsm.stator_resistance,
        pmsm.inductance_q,
        pmsm.max_current,
    )
    return demand / float(max_phase_voltage(pmsm.dc_link_voltage))
