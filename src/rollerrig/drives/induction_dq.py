"""Dynamic induction machine: the inverse-Γ model with stator and rotor flux linkages as states.

The roller's AM in the twin is a quasi-static Thevenin torque-slip curve (Kayaalp eq. 4.28,
:mod:`rollerrig.drives.induction`) followed by a hand-fitted first-order lag (eq. 4.29). This
module is the machine that curve is the steady state of: the inverse-Γ equivalent circuit
(Slemon 1989), whose electromagnetic dynamics (the stator transient, the rotor's short-circuit
time constant L_σ/R_R and open-circuit one L_M/R_R) the lag stands in for.

Model (space vectors, peak-value scaled, of the equivalent star; Slemon 1989; Hinkkanen et al.
2022, eqs. 1-3):

.. math::

    \\frac{d\\psi_s}{dt} &= u_s - R_s i_s - j\\omega_s \\psi_s \\\\
    \\frac{d\\psi_R}{dt} &= -R_R i_R - j(\\omega_s - \\omega_m)\\psi_R \\\\
    i_s &= (\\psi_s - \\psi_R)/L_\\sigma, \\qquad i_R = \\psi_R/L_M - i_s \\\\
    T &= \\tfrac{3}{2} p\\,\\mathrm{Im}\\{\\psi_s^* i_s\\}
       = \\tfrac{3}{2}\\frac{p}{L_\\sigma}\\,\\mathrm{Im}\\{\\psi_R^*\\psi_s\\}

with ω_m = p Ω the electrical rotor speed (Ω the mechanical speed of the rotor relative to the
stator) and ω_s the angular speed of the reference frame.

Frame: **synchronous with the inverter's voltage** (angle θ_s with dθ_s/dt = ω_s, the V/f
controller's output frequency; :mod:`rollerrig.drives.vf`). Why: under V/f the voltage is
constant in this frame, so steady operation at a set speed is an *equilibrium* (constant
fluxes) that can be linearised and whose eigenvalues are the small-signal modes; in the stator
frame the same operation is a sinusoid. The kernels take ω_s as an input, so the same code runs
in the stator frame (ω_s = 0; used to compare with motulator's stator-frame model).

Equivalent circuit: the inverse-Γ circuit (R_s, total leakage L_σ, magnetising L_M, rotor
R_R) is exactly equivalent to the T circuit for *any* split of the leakage between stator and
rotor (Slemon 1989), so unlike the Thevenin fit no X1:X2 split is assumed. The Thevenin curve
of :func:`~rollerrig.drives.induction.thevenin_from_nameplate` is its limit L_M → ∞
(:func:`~rollerrig.drives.inverse_gamma_nameplate.inverse_gamma_from_thevenin`); with a finite
L_M (:func:`~rollerrig.drives.inverse_gamma_nameplate.inverse_gamma_from_nameplate`)
the rated point and the breakdown torque are kept exactly and the curve differs elsewhere by
the magnetising branch. Not modelled: magnetic saturation, iron and mechanical losses,
skin effect in the rotor bars, PWM ripple and dead time (a switching frequency of kHz against
dynamics below ~100 Hz: the average model).

Layers
------
Kernels (scalars, plain arithmetic, compile under ``numba.njit``; port them into the coupled
right-hand side): :func:`im_currents_kernel`, :func:`im_torque_kernel`,
:func:`im_flux_derivatives_kernel`, :func:`im_power_kernel`.

Public: :func:`state_derivative`, :func:`torque`, :func:`currents`, :func:`magnetic_energy`,
:func:`power_balance`, :func:`steady_state`, :func:`steady_torque`, :func:`jacobian`,
:func:`machine_eigenvalues`. The parameters are
:class:`~rollerrig.drives.inverse_gamma.InverseGammaMachine`
(:mod:`rollerrig.drives.inverse_gamma`), found from the nameplate by
:func:`~rollerrig.drives.inverse_gamma_nameplate.inverse_gamma_from_nameplate`,
:func:`~rollerrig.drives.inverse_gamma_nameplate.inverse_gamma_from_rig` and
:func:`~rollerrig.drives.inverse_gamma_nameplate.inverse_gamma_from_thevenin`
(:mod:`rollerrig.drives.inverse_gamma_nameplate`); all four are importable from here too.
The kernels stay in this file: the fast backend's compile cache is keyed on its content
(``rollerrig.solve._cache.SOURCES``), and whatever calls them stays with them so that
this module imports its parameter modules and not the other way round.

Units: SI; voltages and currents are peak values of the equivalent-star phase (a space vector of
magnitude U is a phase voltage of U/√2 rms), flux linkages [Wb] = [V.s].

References
----------
G. R. Slemon, "Modelling of induction machines for electric drives", IEEE Trans. Ind. Appl.
25 (1989) 1126-1131 (the inverse-Γ and Γ circuits, equivalent to the T circuit).
M. Hinkkanen, L. Tiitinen, E. Mölsä, L. Harnefors, "On the stability of volts-per-hertz control
for induction motors", IEEE J. Emerg. Sel. Topics Power Electron. 10 (2022) 1609-1618.
P. C. Krause, O. Wasynczuk, S. D. Sudhoff, S. Pekarek, *Analysis of Electric Machinery and
Drive Systems*, 3rd ed., Wiley-IEEE, 2013, ch. 6 (induction machine; eigenvalues at constant
speed depend on the reference frame).
S. J. Chapman, *Electric Machinery Fundamentals*, 5th ed., 2012, sec. 6.5 (Thevenin torque).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_nonnegative,
    require_positive,
)
from rollerrig.drives.inverse_gamma import InverseGammaMachine
from rollerrig.drives.inverse_gamma_nameplate import (
    inverse_gamma_from_nameplate,
    inverse_gamma_from_rig,
    inverse_gamma_from_thevenin,
)

__all__ = [
    "STATE_NAMES",
    "InverseGammaMachine",
    "MachineOperatingPoint",
    "currents",
    "im_currents_kernel",
    "im_flux_derivatives_kernel",
    "im_power_kernel",
    "im_torque_kernel",
    "inverse_gamma_from_nameplate",
    "inverse_gamma_from_rig",
    "inverse_gamma_from_thevenin",
    "jacobian",
    "machine_eigenvalues",
    "magnetic_energy",
    "power_balance",
    "state_derivative",
    "steady_state",
    "steady_torque",
    "torque",
]

#: Names of the four machine states, in order [Wb].
STATE_NAMES = ("am_psi_s_d", "am_psi_s_q", "am_psi_r_d", "am_psi_r_q")


# --------------------------------------------------------------------------------------------
# Kernels
# --------------------------------------------------------------------------------------------
def im_currents_kernel(
    psi_s_d, psi_s_q, psi_r_d, psi_r_q, leakage_inductance, magnetising_inductance
):
    r"""Stator and rotor currents from the flux linkages (inverse-Γ model).

    .. math:: i_s = (\psi_s - \psi_R)/L_\sigma, \qquad i_R = \psi_R/L_M - i_s

    Parameters
    ----------
    psi_s_d, psi_s_q : float
        Stator flux linkage, d and q components [Wb].
    psi_r_d, psi_r_q : float
        Rotor flux linkage ψ_R (inverse-Γ), d and q [Wb].
    leakage_inductance : float
        Total leakage inductance L_σ [H].
    magnetising_inductance : float
        Magnetising inductance L_M [H].

    Returns
    -------
    i_s_d, i_s_q, i_r_d, i_r_q : float
        Stator and rotor currents [A] (peak, equivalent star).

    Examples
    --------
    >>> [round(i, 9) for i in im_currents_kernel(1.0, 0.0, 0.9, 0.0, 0.01, 0.1)]
    [10.0, 0.0, -1.0, 0.0]
    """
    i_s_d = (psi_s_d - psi_r_d) / leakage_inductance
    i_s_q = (psi_s_q - psi_r_q) / leakage_inductance
    i_r_d = psi_r_d / magnetising_inductance - i_s_d
    i_r_q = psi_r_q / magnetising_inductance - i_s_q
    return i_s_d, i_s_q, i_r_d, i_r_q


def im_torque_kernel(psi_s_d, psi_s_q, psi_r_d, psi_r_q, leakage_inductance, pole_pairs):
    r"""Electromagnetic (air-gap) torque on the rotor, motoring positive.

    .. math::

        T = \tfrac{3}{2} p\,\mathrm{Im}\{\psi_s^* i_s\}
          = \tfrac{3}{2}\frac{p}{L_\sigma}(\psi_{R,d}\psi_{s,q} - \psi_{R,q}\psi_{s,d})

    Parameters
    ----------
    psi_s_d, psi_s_q, psi_r_d, psi_r_q : float
        Stator and rotor flux linkages [Wb].
    leakage_inductance : float
        L_σ [H].
    pole_pairs : float
        p [-].

    Returns
    -------
    float
        Torque [N.m].

    Examples
    --------
    >>> round(im_torque_kernel(0.0, 1.0, 1.0, 0.0, 0.01, 2), 6)
    300.0
    """
    return 1.5 * pole_pairs / leakage_inductance * (psi_r_d * psi_s_q - psi_r_q * psi_s_d)


def im_flux_derivatives_kernel(
    psi_s_d,
    psi_s_q,
    psi_r_d,
    psi_r_q,
    u_d,
    u_q,
    omega_s,
    omega_m,
    stator_resistance,
    rotor_resistance,
    leakage_inductance,
    magnetising_inductance,
):
    r"""Time derivatives of the stator and rotor flux linkages in a frame rotating at ω_s.

    .. math::

        \dot\psi_s = u_s - R_s i_s - j\omega_s\psi_s, \qquad
        \dot\psi_R = -R_R i_R - j(\omega_s - \omega_m)\psi_R

    Parameters
    ----------
    psi_s_d, psi_s_q, psi_r_d, psi_r_q : float
        Flux linkages in the frame [Wb].
    u_d, u_q : float
        Stator voltage in the frame [V] (peak, equivalent star).
    omega_s : float
        Angular speed of the frame [rad/s] (electrical; 0 gives the stator frame).
    omega_m : float
        Electrical rotor speed p Ω [rad/s].
    stator_resistance, rotor_resistance : float
        R_s, R_R [ohm].
    leakage_inductance, magnetising_inductance : float
        L_σ, L_M [H].

    Returns
    -------
    d_psi_s_d, d_psi_s_q, d_psi_r_d, d_psi_r_q : float
        [V].

    Examples
    --------
    >>> d = im_flux_derivatives_kernel(0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.1, 0.1, 0.01, 0.1)
    >>> [abs(float(v)) for v in d]  # at zero flux only the voltage drives dψ_s/dt
    [1.0, 0.0, 0.0, 0.0]
    """
    i_s_d = (psi_s_d - psi_r_d) / leakage_inductance
    i_s_q = (psi_s_q - psi_r_q) / leakage_inductance
    i_r_d = psi_r_d / magnetising_inductance - i_s_d
    i_r_q = psi_r_q / magnetising_inductance - i_s_q
    omega_r = omega_s - omega_m
    d_psi_s_d = u_d - stator_resistance * i_s_d + omega_s * psi_s_q
    d_psi_s_q = u_q - stator_resistance * i_s_q - omega_s * psi_s_d
    d_psi_r_d = -rotor_resistance * i_r_d + omega_r * psi_r_q
    d_psi_r_q = -rotor_resistance * i_r_q - omega_r * psi_r_d
    return d_psi_s_d, d_psi_s_q, d_psi_r_d, d_psi_r_q


def im_power_kernel(
    psi_s_d,
    psi_s_q,
    psi_r_d,
    psi_r_q,
    u_d,
    u_q,
    rotor_speed,
    stator_resistance,
    rotor_resistance,
    leakage_inductance,
    magnetising_inductance,
    pole_pairs,
):
    r"""The terms of the machine's power balance at one instant.

    .. math::

        p_{in} = \tfrac32\mathrm{Re}\{u_s i_s^*\}, \quad
        p_{Cu} = \tfrac32(R_s|i_s|^2 + R_R|i_R|^2), \quad
        p_{mech} = T\,\Omega, \quad
        W = \tfrac32\left(\tfrac12 L_\sigma|i_s|^2 + \tfrac{|\psi_R|^2}{2L_M}\right)

    and :math:`p_{in} = p_{Cu} + p_{mech} + dW/dt` in any frame (the rotation terms cancel
    because :math:`i_s^*\psi_s + i_R^*\psi_R = L_\sigma|i_s|^2 + |\psi_R|^2/L_M` is real).

    Parameters
    ----------
    psi_s_d, psi_s_q, psi_r_d, psi_r_q : float
        Flux linkages [Wb].
    u_d, u_q : float
        Stator voltage in the same frame [V].
    rotor_speed : float
        Mechanical rotor speed Ω relative to the stator [rad/s].
    stator_resistance, rotor_resistance, leakage_inductance, magnetising_inductance : float
        R_s, R_R [ohm], L_σ, L_M [H].
    pole_pairs : float
        p [-].

    Returns
    -------
    p_in, p_copper, p_mech, energy : float
        Electrical input [W], copper losses [W], mechanical output [W], magnetic energy [J].

    Examples
    --------
    >>> p = im_power_kernel(1.0, 0.0, 0.9, 0.0, 0.0, 0.0, 0.0, 0.1, 0.1, 0.01, 0.1, 2)
    >>> round(p[1], 6), round(p[3], 6)  # 1.5 (0.1·10² + 0.1·1²), 1.5 (0.01·10²/2 + 0.81/0.2)
    (15.15, 6.825)
    """
    i_s_d = (psi_s_d - psi_r_d) / leakage_inductance
    i_s_q = (psi_s_q - psi_r_q) / leakage_inductance
    i_r_d = psi_r_d / magnetising_inductance - i_s_d
    i_r_q = psi_r_q / magnetising_inductance - i_s_q
    p_in = 1.5 * (u_d * i_s_d + u_q * i_s_q)
    p_copper = 1.5 * (
        stator_resistance * (i_s_d * i_s_d + i_s_q * i_s_q)
        + rotor_resistance * (i_r_d * i_r_d + i_r_q * i_r_q)
    )
    t_em = 1.5 * pole_pairs / leakage_inductance * (psi_r_d * psi_s_q - psi_r_q * psi_s_d)
    p_mech = t_em * rotor_speed
    energy = 1.5 * (
        0.5 * leakage_inductance * (i_s_d * i_s_d + i_s_q * i_s_q)
        + 0.5 * (psi_r_d * psi_r_d + psi_r_q * psi_r_q) / magnetising_inductance
    )
    return p_in, p_copper, p_mech, energy


# --------------------------------------------------------------------------------------------
# Steady state (phasors: the fluxes are constant in the synchronous frame)
# --------------------------------------------------------------------------------------------
def _steady_fluxes(machine: InverseGammaMachine, omega_s, u, omega_m):
    """Steady fluxes (complex arrays) in the frame rotating at ω_s for a voltage u (complex)."""
    rs, rr = machine.stator_resistance, machine.rotor_resistance
    ls, lm = machine.leakage_inductance, machine.magnetising_inductance
    omega_r = omega_s - omega_m
    # (R_s/L_σ + jω_s) ψ_s − (R_s/L_σ) ψ_R = u
    # −(R_R/L_σ) ψ_s + (R_R/L_σ + R_R/L_M + jω_r) ψ_R = 0
    a11 = rs / ls + 1j * omega_s
    a12 = -rs / ls
    a21 = -rr / ls
    a22 = rr / ls + rr / lm + 1j * omega_r
    det = a11 * a22 - a12 * a21
    psi_s = u * a22 / det
    psi_r = -u * a21 / det
    return psi_s, psi_r


@dataclass(frozen=True)
class MachineOperatingPoint:
    """Steady operation of the machine at a supply frequency, voltage and rotor speed.

    Attributes
    ----------
    state : ndarray, shape (4,)
        ``[ψ_s,d, ψ_s,q, ψ_R,d, ψ_R,q]`` in the voltage frame [Wb].
    supply_frequency : float
        f [Hz].
    voltage : complex
        Stator voltage u_s in the frame [V] (peak).
    rotor_speed : float
        Mechanical speed Ω [rad/s].
    stator_current, rotor_current : complex
        i_s, i_R [A] (peak).
    torque : float
        [N.m].
    slip : float
        (ω_s − pΩ)/ω_s [-].
    input_power, copper_loss, mechanical_power : float
        [W].
    """

    state: np.ndarray
    supply_frequency: float
    voltage: complex
    rotor_speed: float
    stator_current: complex
    rotor_current: complex
    torque: float
    slip: float
    input_power: float
    copper_loss: float
    mechanical_power: float


def steady_state(
    machine: InverseGammaMachine,
    supply_frequency: float,
    voltage: float,
    rotor_speed: float,
    *,
    voltage_angle: float = 0.5 * np.pi,
) -> MachineOperatingPoint:
    """Steady state of the machine fed with a constant voltage at a constant rotor speed.

    In the frame of the voltage the fluxes are constant; they solve the linear equations
    obtained by setting the derivatives of :func:`im_flux_derivatives_kernel` to zero.

    Parameters
    ----------
    machine : InverseGammaMachine
        Parameters.
    supply_frequency : float
        f [Hz]; its sign is the direction of the rotating field.
    voltage : float
        Magnitude of the stator voltage, peak [V], >= 0.
    rotor_speed : float
        Mechanical rotor speed Ω [rad/s].
    voltage_angle : float, optional
        Angle of u_s in the frame [rad]; π/2 (the q axis, so that ψ_s lies near the d axis) as
        in :mod:`rollerrig.drives.vf`.

    Returns
    -------
    MachineOperatingPoint

    Examples
    --------
    >>> m = inverse_gamma_from_nameplate()
    >>> op = steady_state(m, 50.0, m.rated_voltage, m.rated_speed)
    >>> round(op.torque, 6), round(abs(op.stator_current) / m.rated_current, 9)
    (891.0, 1.0)
    """
    f = require_finite("supply_frequency", supply_frequency, "Hz", single=True)
    u_mag = require_nonnegative("voltage", voltage, "V", single=True)
    speed = require_finite("rotor_speed", rotor_speed, "rad/s", single=True)
    omega_s = 2.0 * np.pi * f
    omega_m = machine.pole_pairs * speed
    u = u_mag * np.exp(1j * float(voltage_angle))
    psi_s, psi_r = _steady_fluxes(machine, omega_s, u, omega_m)
    state = np.array([psi_s.real, psi_s.imag, psi_r.real, psi_r.imag])
    i_s = (psi_s - psi_r) / machine.leakage_inductance
    i_r = psi_r / machine.magnetising_inductance - i_s
    p = machine.as_array()
    p_in, p_cu, p_mech, _ = im_power_kernel(*state, u.real, u.imag, speed, *p)
    t_em = im_torque_kernel(*state, machine.leakage_inductance, machine.pole_pairs)
    return MachineOperatingPoint(
        state=state,
        supply_frequency=f,
        voltage=complex(u),
        rotor_speed=speed,
        stator_current=complex(i_s),
        rotor_current=complex(i_r),
        torque=float(t_em),
        slip=float((omega_s - omega_m) / omega_s) if omega_s != 0.0 else float("nan"),
        input_power=float(p_in),
        copper_loss=float(p_cu),
        mechanical_power=float(p_mech),
    )


def steady_torque(machine: InverseGammaMachine, rotor_speed, supply_frequency, voltage=None):
    """Steady air-gap torque [N.m] over arrays of speed, frequency and voltage (vectorised).

    Parameters
    ----------
    machine : InverseGammaMachine
        Parameters.
    rotor_speed : array_like
        Mechanical rotor speed Ω [rad/s].
    supply_frequency : array_like
        f [Hz].
    voltage : array_like, optional
        Voltage magnitude, peak [V]; default the V/f law ``U_n |f|/f_n`` (no boost).

    Returns
    -------
    ndarray
        Torque, motoring positive [N.m].

    Examples
    --------
    >>> m = inverse_gamma_from_nameplate()
    >>> round(float(steady_torque(m, m.rated_speed, 50.0)), 6)
    891.0
    """
    speed = require_finite("rotor_speed", rotor_speed, "rad/s")
    f = require_finite("supply_frequency", supply_frequency, "Hz")
    u = machine.rated_voltage * np.abs(f) / machine.rated_frequency if voltage is None else voltage
    u = require_nonnegative("voltage", u, "V")
    psi_s, psi_r = _steady_fluxes(
        machine, 2.0 * np.pi * f, 1j * u + 0.0j, machine.pole_pairs * speed
    )
    t = (
        1.5
        * machine.pole_pairs
        / machine.leakage_inductance
        * (psi_r.real * psi_s.imag - psi_r.imag * psi_s.real)
    )
    return t


# --------------------------------------------------------------------------------------------
# Public wrappers of the kernels
# --------------------------------------------------------------------------------------------
def _state4(state) -> np.ndarray:
    x = require_finite("state", state, "Wb")
    if x.shape[0] != 4:
        raise ParameterError(
            f"state must hold the 4 fluxes [psi_s_d, psi_s_q, psi_r_d, psi_r_q] [Wb] along its "
            f"first axis, got shape {x.shape}"
        )
    return x


def state_derivative(
    machine: InverseGammaMachine, state, u_d, u_q, omega_s, rotor_speed
) -> np.ndarray:
    """dψ/dt of the machine [V] (:func:`im_flux_derivatives_kernel`), vectorised.

    Parameters
    ----------
    machine : InverseGammaMachine
        Parameters.
    state : array_like, shape (4, ...)
        ``[ψ_s,d, ψ_s,q, ψ_R,d, ψ_R,q]`` [Wb].
    u_d, u_q : float or array_like
        Stator voltage in the frame [V] (peak).
    omega_s : float or array_like
        Frame speed [rad/s] (electrical).
    rotor_speed : float or array_like
        Mechanical rotor speed Ω [rad/s].

    Returns
    -------
    ndarray, shape (4, ...)
        [V].
    """
    x = _state4(state)
    p = machine.as_array()
    d = im_flux_derivatives_kernel(
        x[0], x[1], x[2], x[3], u_d, u_q, omega_s, p[4] * np.asarray(rotor_speed), *p[:4]
    )
    return np.array(d, dtype=float)


def torque(machine: InverseGammaMachine, state):
    """Air-gap torque [N.m] of the machine at a state (:func:`im_torque_kernel`)."""
    x = _state4(state)
    return im_torque_kernel(x[0], x[1], x[2], x[3], machine.leakage_inductance, machine.pole_pairs)


def currents(machine: InverseGammaMachine, state) -> np.ndarray:
    """``[i_s,d, i_s,q, i_R,d, i_R,q]`` [A] at a state (:func:`im_currents_kernel`)."""
    x = _state4(state)
    return np.array(
        im_currents_kernel(
            x[0], x[1], x[2], x[3], machine.leakage_inductance, machine.magnetising_inductance
        ),
        dtype=float,
    )


def magnetic_energy(machine: InverseGammaMachine, state):
    """Magnetic energy W = 3/2 (L_σ|i_s|²/2 + |ψ_R|²/(2 L_M)) [J]."""
    x = _state4(state)
    return im_power_kernel(*x, 0.0, 0.0, 0.0, *machine.as_array())[3]


def power_balance(machine: InverseGammaMachine, state, u_d, u_q, omega_s, rotor_speed) -> dict:
    """The power balance at an instant: p_in = p_Cu + p_mech + dW/dt, each term [W].

    dW/dt is the exact derivative of :func:`magnetic_energy` along :func:`state_derivative`
    (the chain rule, no finite difference); ``residual`` is p_in − p_Cu − p_mech − dW/dt.

    Returns
    -------
    dict
        ``input``, ``copper``, ``mechanical``, ``energy_rate``, ``residual`` [W].
    """
    x = _state4(state)
    p = machine.as_array()
    p_in, p_cu, p_mech, _ = im_power_kernel(*x, u_d, u_q, rotor_speed, *p)
    dx = state_derivative(machine, x, u_d, u_q, omega_s, rotor_speed)
    i_s_d, i_s_q, _, _ = currents(machine, x)
    lm = machine.magnetising_inductance
    # W = 3/2 [ (ψs−ψR)²/(2Lσ) + ψR²/(2LM) ]  ->  dW = 3/2 [ i_s·dψs + (ψR/LM − i_s)·dψR ]
    i_r_d = x[2] / lm - i_s_d
    i_r_q = x[3] / lm - i_s_q
    rate = 1.5 * (i_s_d * dx[0] + i_s_q * dx[1] + i_r_d * dx[2] + i_r_q * dx[3])
    return {
        "input": p_in,
        "copper": p_cu,
        "mechanical": p_mech,
        "energy_rate": rate,
        "residual": p_in - p_cu - p_mech - rate,
    }


# --------------------------------------------------------------------------------------------
# Linearisation
# --------------------------------------------------------------------------------------------
def jacobian(machine: InverseGammaMachine, state, omega_s: float, rotor_speed: float):
    """Analytic linearisation of the machine about a state.

    Returns
    -------
    a : ndarray, shape (4, 4)
        ∂ψ̇/∂ψ [1/s].
    b : ndarray, shape (4, 4)
        ∂ψ̇/∂[u_d, u_q, ω_s, Ω] ([-], [-], [Wb], [Wb]: per mechanical rad/s).
    c : ndarray, shape (4,)
        ∂T/∂ψ [N.m/Wb].

    Examples
    --------
    >>> m = inverse_gamma_from_nameplate()
    >>> op = steady_state(m, 50.0, m.rated_voltage, m.rated_speed)
    >>> a, b, c = jacobian(m, op.state, 2 * np.pi * 50.0, m.rated_speed)
    >>> a.shape, b.shape, c.shape
    ((4, 4), (4, 4), (4,))
    """
    x = _state4(state)
    rs, rr = machine.stator_resistance, machine.rotor_resistance
    ls, lm = machine.leakage_inductance, machine.magnetising_inductance
    n_p = machine.pole_pairs
    ws = float(omega_s)
    wr = ws - n_p * float(rotor_speed)
    g = rr * (1.0 / lm + 1.0 / ls)
    a = np.array(
        [
            [-rs / ls, ws, rs / ls, 0.0],
            [-ws, -rs / ls, 0.0, rs / ls],
            [rr / ls, 0.0, -g, wr],
            [0.0, rr / ls, -wr, -g],
        ]
    )
    psd, psq, prd, prq = x
    b = np.array(
        [
            [1.0, 0.0, psq, 0.0],
            [0.0, 1.0, -psd, 0.0],
            [0.0, 0.0, prq, -n_p * prq],
            [0.0, 0.0, -prd, n_p * prd],
        ]
    )
    k = 1.5 * n_p / ls
    c = k * np.array([-prq, prd, psq, -psd])
    return a, b, c


def machine_eigenvalues(
    machine: InverseGammaMachine,
    supply_frequency: float,
    voltage: float,
    rotor_speed: float,
    *,
    inertia: float | None = None,
    load_damping: float = 0.0,
) -> np.ndarray:
    """Small-signal eigenvalues of the machine fed by a constant voltage at an operating point.

    Without ``inertia`` the speed is held (4 electrical eigenvalues, in the frame of the
    voltage); with it the rotor is one rigid inertia J, ``J dΩ/dt = T − T_L − b δΩ`` (5
    eigenvalues). The voltage and frequency are held constant (open-loop V/f at a fixed
    command).

    Parameters
    ----------
    machine : InverseGammaMachine
        Parameters.
    supply_frequency : float
        f [Hz].
    voltage : float
        Voltage magnitude, peak [V].
    rotor_speed : float
        Ω at the operating point [rad/s].
    inertia : float, optional
        J [kg.m^2].
    load_damping : float, optional
        b = dT_L/dΩ of the load [N.m.s/rad].

    Returns
    -------
    ndarray of complex
        Eigenvalues [1/s], sorted by imaginary then real part.
    """
    op = steady_state(machine, supply_frequency, voltage, rotor_speed)
    a, b, c = jacobian(machine, op.state, 2.0 * np.pi * op.supply_frequency, op.rotor_speed)
    if inertia is None:
        full = a
    else:
        j = require_positive("inertia", inertia, "kg.m^2", single=True)
        bl = require_finite("load_damping", load_damping, "N.m.s/rad", single=True)
        full = np.zeros((5, 5))
        full[:4, :4] = a
        full[:4, 4] = b[:, 3]
        full[4, :4] = c / j
        full[4, 4] = -bl / j
    lam = np.linalg.eigvals(full)
    return lam[np.lexsort((lam.real, lam.imag))]
