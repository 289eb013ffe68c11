"""Permanent magnet synchronous motor (PMSM) of the wheel drive with field-oriented control.

The model is written in the rotor (dq) reference frame with the amplitude-invariant Park
transform (dq quantities have the amplitude of the phase quantities, hence the factor 3/2 in
power and torque). It follows Kayaalp, eqs. 4.23-4.25, with the sign of the speed voltage in
eq. 4.24 corrected (see :func:`pmsm_current_derivatives`).

Layers
------
Kernels (pure arithmetic and numpy ufuncs, compile under ``numba.njit``, no validation; called
from the coupled right-hand side):

* :func:`pmsm_current_derivatives` -- stator current ODE, eqs. 4.23-4.24 (corrected).
* :func:`pmsm_torque` -- air-gap torque, eq. 4.25.
* :func:`pmsm_current_reference` -- i_d* = 0 control, i_q* from the torque request.
* :func:`pmsm_foc_voltages` -- PI current control with decoupling, voltage circle limit and
  back-calculation anti-windup.
* :func:`pmsm_magnetic_energy` -- stored magnetic energy of the dq inductances.
* :func:`pmsm_torque_ripple` -- optional sinusoidal inverter ripple on the torque.

Their names are a contract with the coupled model, so they do not carry the ``_kernel`` suffix.

Validated public helpers: :func:`max_phase_voltage`, :func:`pi_gains_for_bandwidth`. The
machine's parameters (Kayaalp Table 1 plus documented assumptions) live in the rig parameter
set, ``RigParameters.pmsm``.

References
----------
Kayaalp (dissertation, the seed), section 4.5.1.4.1, eqs. 4.23-4.25, Table 1.
P. C. Krause, O. Wasynczuk, S. D. Sudhoff, *Analysis of Electric Machinery and Drive Systems*,
2nd ed., Wiley-IEEE Press, 2002, ch. 7 (permanent-magnet ac machines in the rotor frame).
P. Pillay, R. Krishnan, "Modeling, simulation, and analysis of permanent-magnet motor drives,
Part I", IEEE Trans. Industry Applications 25(2), 1989, 265-273.
L. Harnefors, H.-P. Nee, "Model-based current control of AC machines using the internal model
control method", IEEE Trans. Industry Applications 34(1), 1998, 133-141 (PI gains by
pole-zero cancellation).
K. J. Åström, T. Hägglund, *Advanced PID Control*, ISA, 2006, section 3.5 (anti-windup by
back-calculation).
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig._validation import ParameterError, require_nonnegative, require_positive

__all__ = [
    "max_phase_voltage",
    "pi_gains_for_bandwidth",
    "pmsm_current_derivatives",
    "pmsm_current_reference",
    "pmsm_foc_voltages",
    "pmsm_magnetic_energy",
    "pmsm_torque",
    "pmsm_torque_ripple",
]

# Smallest voltage magnitude used as a divisor in the voltage-circle limit [V]; far below any
# physical voltage, it only keeps 0/0 away when the PI output is exactly zero.
_TINY_VOLTAGE = 1e-300


# --------------------------------------------------------------------------------------------
# Kernels
# --------------------------------------------------------------------------------------------
def pmsm_current_derivatives(
    i_d,
    i_q,
    v_d,
    v_q,
    omega_mech,
    pole_pairs,
    stator_resistance,
    inductance_d,
    inductance_q,
    flux_linkage,
):
    r"""Time derivatives of the dq stator currents (Kayaalp, eqs. 4.23-4.24, corrected).

    .. math::

        \frac{di_d}{dt} = \frac{v_d - R i_d + \omega_e L_q i_q}{L_d}, \qquad
        \frac{di_q}{dt} = \frac{v_q - R i_q - \omega_e L_d i_d - \omega_e \varphi}{L_q},

    with the electrical speed :math:`\omega_e = p\,\omega_{mech}`.

    **Correction of the seed.** Kayaalp's eq. 4.24 prints the speed voltage of the d-axis flux as
    :math:`+\frac{L_d}{L_q} p \omega i_d`. The standard rotor-frame model has a minus sign: the
    q-axis speed voltage is :math:`+\omega_e \psi_d = \omega_e (L_d i_d + \varphi)`, so both the
    :math:`L_d i_d` and the :math:`\varphi` terms enter with the same sign (Krause et al. 2002,
    ch. 7; Pillay & Krishnan 1989, eq. 2). With the printed sign the model would not conserve
    energy (see :func:`pmsm_magnetic_energy`), and flux weakening (i_d < 0) would increase the
    back-EMF instead of reducing it.

    Parameters
    ----------
    i_d, i_q : float or array_like
        d- and q-axis stator currents [A] (amplitude-invariant Park transform).
    v_d, v_q : float or array_like
        d- and q-axis stator voltages [V].
    omega_mech : float or array_like
        Mechanical rotor speed [rad/s].
    pole_pairs : float
        Number of pole pairs p [-].
    stator_resistance : float
        Stator phase resistance R_s [ohm].
    inductance_d, inductance_q : float
        d- and q-axis inductances L_d, L_q [H].
    flux_linkage : float
        Permanent-magnet flux linkage amplitude φ [Wb].

    Returns
    -------
    di_d_dt, di_q_dt : float or ndarray
        Current derivatives [A/s].

    Examples
    --------
    >>> did, diq = pmsm_current_derivatives(0.0, 10.0, 0.0, 300.0, 68.0, 22, 0.04, 5e-4, 5e-4, 0.2)
    >>> round(float(diq), 6)
    800.0
    """
    omega_e = pole_pairs * omega_mech
    di_d_dt = (v_d - stator_resistance * i_d + omega_e * inductance_q * i_q) / inductance_d
    di_q_dt = (
        v_q - stator_resistance * i_q - omega_e * inductance_d * i_d - omega_e * flux_linkage
    ) / inductance_q
    return di_d_dt, di_q_dt


def pmsm_torque(i_d, i_q, pole_pairs, flux_linkage, inductance_d, inductance_q):
    r"""Air-gap torque of the PMSM (Kayaalp, eq. 4.25).

    .. math:: T = \tfrac{3}{2}\, p \left[\varphi i_q + (L_d - L_q) i_d i_q\right]

    The factor 3/2 belongs to the amplitude-invariant Park transform (Krause et al. 2002, ch. 7).

    Parameters
    ----------
    i_d, i_q : float or array_like
        d- and q-axis stator currents [A].
    pole_pairs : float
        Number of pole pairs p [-].
    flux_linkage : float
        Permanent-magnet flux linkage amplitude φ [Wb].
    inductance_d, inductance_q : float
        d- and q-axis inductances [H].

    Returns
    -------
    torque : float or ndarray
        Air-gap torque on the rotor, motoring positive [N.m].

    Examples
    --------
    >>> round(float(pmsm_torque(0.0, 100.0, 22, 0.2, 5e-4, 5e-4)), 6)
    660.0
    """
    return 1.5 * pole_pairs * (flux_linkage * i_q + (inductance_d - inductance_q) * i_d * i_q)


def pmsm_current_reference(torque_request, pole_pairs, flux_linkage, max_current):
    r"""Current references of i_d = 0 field-oriented control below base speed.

    .. math::

        i_d^* = 0, \qquad
        i_q^* = \operatorname{clip}\!\left(\frac{T^*}{\tfrac{3}{2} p \varphi},
                -I_{max}, I_{max}\right)

    With i_d = 0 the reluctance term of eq. 4.25 vanishes, so i_q* yields the requested torque
    exactly for salient machines too, as long as the current limit is not reached.

    Parameters
    ----------
    torque_request : float or array_like
        Torque request T* [N.m].
    pole_pairs : float
        Number of pole pairs p [-].
    flux_linkage : float
        Permanent-magnet flux linkage amplitude φ [Wb].
    max_current : float
        Current limit on i_q (amplitude) [A].

    Returns
    -------
    i_d_ref, i_q_ref : float or ndarray
        Current references [A].

    Examples
    --------
    >>> i_d_ref, i_q_ref = pmsm_current_reference(660.0, 22, 0.2, 500.0)
    >>> float(i_d_ref), round(float(i_q_ref), 9)
    (0.0, 100.0)
    """
    i_q_ref = torque_request / (1.5 * pole_pairs * flux_linkage)
    i_q_ref = np.minimum(np.maximum(i_q_ref, -max_current), max_current)
    i_d_ref = 0.0 * i_q_ref
    return i_d_ref, i_q_ref


def pmsm_foc_voltages(
    i_d,
    i_q,
    i_d_ref,
    i_q_ref,
    integral_d,
    integral_q,
    omega_mech,
    pole_pairs,
    inductance_d,
    inductance_q,
    flux_linkage,
    kp,
    ki,
    max_voltage,
):
    r"""Field-oriented PI current control: dq voltages and integrator derivatives.

    Unsaturated voltages (PI plus decoupling and back-EMF feed-forward, Krause et al. 2002):

    .. math::

        u_d = k_p e_d + k_i I_d - \omega_e L_q i_q, \qquad
        u_q = k_p e_q + k_i I_q + \omega_e (L_d i_d + \varphi),

    with :math:`e_x = i_x^* - i_x` and :math:`I_x = \int e_x\,dt`. The voltage vector is limited
    to the circle :math:`|v| \le V_{max}` by scaling it (direction kept):
    :math:`v = u \min(1, V_{max}/|u|)`. Anti-windup by back-calculation (Åström & Hägglund 2006,
    sec. 3.5) with tracking time constant :math:`T_t = k_p/k_i` (the integral time):

    .. math:: \frac{dI_x}{dt} = e_x + \frac{v_x - u_x}{k_p}.

    Without saturation :math:`v = u` and the integrator is a plain integral of the error. Under
    saturation the integrator settles at :math:`k_i I_x = v_x - u_{x,ff}` instead of winding up.
    With the feed-forward matching the machine (same L_d, L_q, φ) and gains from
    :func:`pi_gains_for_bandwidth`, the unsaturated closed loop from i* to i is the first-order
    lag :math:`\omega_c/(s + \omega_c)`.

    Parameters
    ----------
    i_d, i_q : float or array_like
        Measured dq currents [A].
    i_d_ref, i_q_ref : float or array_like
        Current references [A].
    integral_d, integral_q : float or array_like
        Integrator states, the integrals of the current errors [A.s].
    omega_mech : float or array_like
        Mechanical rotor speed [rad/s].
    pole_pairs : float
        Number of pole pairs p [-].
    inductance_d, inductance_q : float
        d- and q-axis inductances used by the feed-forward [H].
    flux_linkage : float
        Permanent-magnet flux linkage used by the feed-forward [Wb].
    kp : float
        Proportional gain [ohm] (= V/A); must be > 0 (back-calculation divides by it).
    ki : float
        Integral gain [ohm/s].
    max_voltage : float
        Radius of the voltage circle, the largest dq voltage amplitude [V]; V_dc/sqrt(3) for
        space-vector PWM (:func:`max_phase_voltage`).

    Returns
    -------
    v_d, v_q : float or ndarray
        Applied (limited) dq voltages [V].
    dintegral_d_dt, dintegral_q_dt : float or ndarray
        Derivatives of the integrator states [A].

    Examples
    --------
    >>> v_d, v_q, _, _ = pmsm_foc_voltages(
    ...     0.0, 100.0, 0.0, 100.0, 0.0, 0.08, 68.0, 22, 5e-4, 5e-4, 0.2, 0.6, 50.0, 346.0)
    >>> round(float(v_q), 2)
    303.2
    """
    omega_e = pole_pairs * omega_mech
    e_d = i_d_ref - i_d
    e_q = i_q_ref - i_q
    u_d = kp * e_d + ki * integral_d - omega_e * inductance_q * i_q
    u_q = kp * e_q + ki * integral_q + omega_e * (inductance_d * i_d + flux_linkage)
    magnitude = np.sqrt(u_d * u_d + u_q * u_q)
    scale = np.minimum(1.0, max_voltage / np.maximum(magnitude, _TINY_VOLTAGE))
    v_d = scale * u_d
    v_q = scale * u_q
    dintegral_d_dt = e_d + (v_d - u_d) / kp
    dintegral_q_dt = e_q + (v_q - u_q) / kp
    return v_d, v_q, dintegral_d_dt, dintegral_q_dt


def pmsm_magnetic_energy(i_d, i_q, inductance_d, inductance_q):
    r"""Magnetic energy stored in the dq inductances (amplitude-invariant transform).

    .. math:: W = \tfrac{3}{4}\left(L_d i_d^2 + L_q i_q^2\right)

    With it the model of :func:`pmsm_current_derivatives` satisfies the power balance
    :math:`\tfrac{3}{2}(v_d i_d + v_q i_q) = \tfrac{3}{2} R (i_d^2 + i_q^2) + T\omega_{mech} +
    dW/dt` exactly (Krause et al. 2002, ch. 7); the magnet flux stores no energy change at
    constant flux.

    Parameters
    ----------
    i_d, i_q : float or array_like
        dq currents [A].
    inductance_d, inductance_q : float
        dq inductances [H].

    Returns
    -------
    energy : float or ndarray
        Stored magnetic energy [J].

    Examples
    --------
    >>> round(float(pmsm_magnetic_energy(0.0, 100.0, 5e-4, 5e-4)), 6)
    3.75
    """
    return 0.75 * (inductance_d * i_d * i_d + inductance_q * i_q * i_q)


def pmsm_torque_ripple(time, amplitude, frequency):
    r"""Sinusoidal torque ripple of the inverter, to add to the air-gap torque.

    .. math:: \Delta T(t) = A \sin(2\pi f t)

    A phenomenological stand-in for the switching oscillation Kayaalp sees on the simulated PMSM
    torque (section 4.5.1.6, Fig. 40a); the seed gives neither amplitude nor frequency.

    Parameters
    ----------
    time : float or array_like
        Time [s].
    amplitude : float
        Ripple amplitude [N.m].
    frequency : float
        Ripple frequency [Hz].

    Returns
    -------
    ripple : float or ndarray
        Torque ripple [N.m].

    Examples
    --------
    >>> round(float(pmsm_torque_ripple(0.25, 10.0, 1.0)), 12)
    10.0
    """
    return amplitude * np.sin(2.0 * np.pi * frequency * time)


# --------------------------------------------------------------------------------------------
# Validated public helpers
# --------------------------------------------------------------------------------------------
def max_phase_voltage(dc_link_voltage):
    r"""Largest dq voltage amplitude of a space-vector-modulated inverter (linear range).

    .. math:: V_{max} = V_{dc} / \sqrt{3}

    Space-vector PWM reaches the circle inscribed in the voltage hexagon, whose radius is
    V_dc/sqrt(3) in phase-voltage amplitude, i.e. in amplitude-invariant dq units (Holmes &
    Lipo, *Pulse Width Modulation for Power Converters*, Wiley 2003, ch. 6).

    Parameters
    ----------
    dc_link_voltage : float or array_like
        DC-link voltage V_dc [V].

    Returns
    -------
    float or ndarray
        Voltage-circle radius [V].

    Examples
    --------
    >>> round(max_phase_voltage(600.0), 3)
    346.41
    """
    v_dc = require_positive("dc_link_voltage", dc_link_voltage, "V")
    result = v_dc / np.sqrt(3.0)
    return float(result) if result.ndim == 0 else result


def pi_gains_for_bandwidth(inductance, resistance, bandwidth):
    r"""PI current-controller gains by pole-zero cancellation.

    .. math:: k_p = L\,\omega_c, \qquad k_i = R\,\omega_c

    The PI zero :math:`-k_i/k_p = -R/L` cancels the electrical pole of the (decoupled) winding
    :math:`1/(Ls + R)`, so the closed loop is the first-order lag :math:`\omega_c/(s+\omega_c)`
    with time constant :math:`1/\omega_c` (Harnefors & Nee 1998).

    Parameters
    ----------
    inductance : float
        Winding inductance L [H].
    resistance : float
        Winding resistance R [ohm].
    bandwidth : float
        Closed-loop bandwidth ω_c [rad/s].

    Returns
    -------
    kp : float
        Proportional gain [ohm].
    ki : float
        Integral gain [ohm/s].

    Examples
    --------
    >>> pi_gains_for_bandwidth(5e-4, 0.04, 1000.0)
    (0.5, 40.0)
    """
    inductance = require_positive("inductance", inductance, "H", single=True)
    resistance = require_nonnegative("resistance", resistance, "ohm", single=True)
    bandwidth = require_positive("bandwidth", bandwidth, "rad/s", single=True)
    kp, ki = inductance * bandwidth, resistance * bandwidth
    if not (math.isfinite(kp) and math.isfinite(ki)):
        raise ParameterError(
            f"inductance = {inductance:g} H and resistance = {resistance:g} ohm at bandwidth = "
            f"{bandwidth:g} rad/s give gains beyond the float range; check their units"
        )
    return kp, ki
