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
(:func:`inverse_gamma_from_thevenin`); with a finite L_M (:func:`inverse_gamma_from_nameplate`)
the rated point and the breakdown torque are kept exactly and the curve differs elsewhere by
the magnetising branch. Not modelled: magnetic saturation, iron and mechanical losses,
skin effect in the rotor bars, PWM ripple and dead time (a switching frequency of kHz against
dynamics below ~100 Hz: the average model).

Layers
------
Kernels (scalars, plain arithmetic, compile under ``numba.njit``; port them into the coupled
right-hand side): :func:`im_currents_kernel`, :func:`im_torque_kernel`,
:func:`im_flux_derivatives_kernel`, :func:`im_power_kernel`.

Public: :class:`InverseGammaMachine`, :func:`inverse_gamma_from_nameplate`,
:func:`inverse_gamma_from_rig`, :func:`inverse_gamma_from_thevenin`, :func:`state_derivative`,
:func:`torque`, :func:`currents`, :func:`magnetic_energy`, :func:`power_balance`,
:func:`steady_state`, :func:`steady_torque`, :func:`jacobian`, :func:`machine_eigenvalues`.

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

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import brentq

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
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
# Parameters
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class InverseGammaMachine:
    """Inverse-Γ parameters of an induction machine and its rated values (equivalent star).

    Attributes
    ----------
    stator_resistance : float
        R_s [ohm].
    rotor_resistance : float
        R_R, rotor resistance referred by the inverse-Γ transformation [ohm].
    leakage_inductance : float
        L_σ, total leakage inductance [H].
    magnetising_inductance : float
        L_M [H].
    pole_pairs : int
        p [-].
    rated_frequency : float
        Rated supply frequency [Hz].
    rated_voltage : float
        Rated stator voltage, peak phase value of the equivalent star, √(2/3) V_line [V].
    rated_current : float
        Rated stator current, peak, √2 I_line [A].
    rated_torque : float
        Rated torque [N.m].
    rated_speed : float
        Rated mechanical speed [rad/s].
    assumptions : tuple of str
        Each assumption the parameters rest on, stated with its reasoning.
    fit : dict
        How the parameters were found (targets and residuals), JSON-ready.

    Examples
    --------
    >>> m = inverse_gamma_from_nameplate()
    >>> round(m.leakage_inductance * 1e3, 3), round(m.magnetising_inductance * 1e3, 2)
    (1.302, 6.9)
    """

    stator_resistance: float
    rotor_resistance: float
    leakage_inductance: float
    magnetising_inductance: float
    pole_pairs: int
    rated_frequency: float
    rated_voltage: float
    rated_current: float
    rated_torque: float
    rated_speed: float
    assumptions: tuple[str, ...] = ()
    fit: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):
        require_nonnegative("stator_resistance", self.stator_resistance, "ohm")
        require_positive("rotor_resistance", self.rotor_resistance, "ohm")
        require_positive("leakage_inductance", self.leakage_inductance, "H")
        require_positive("magnetising_inductance", self.magnetising_inductance, "H")
        require_positive("pole_pairs", self.pole_pairs, "-")
        require_positive("rated_frequency", self.rated_frequency, "Hz")
        require_positive("rated_voltage", self.rated_voltage, "V")
        require_positive("rated_current", self.rated_current, "A")
        require_positive("rated_torque", self.rated_torque, "N.m")
        require_positive("rated_speed", self.rated_speed, "rad/s")

    # --- derived quantities ------------------------------------------------------------------
    @property
    def rated_angular_frequency(self) -> float:
        """Rated electrical angular frequency ω_n = 2π f_n [rad/s]."""
        return 2.0 * np.pi * self.rated_frequency

    @property
    def nominal_stator_flux(self) -> float:
        """Stator flux linkage of the V/f law, U_n/ω_n [Wb] (peak)."""
        return self.rated_voltage / self.rated_angular_frequency

    @property
    def synchronous_speed(self) -> float:
        """Mechanical synchronous speed at the rated frequency [rad/s]."""
        return self.rated_angular_frequency / self.pole_pairs

    @property
    def rated_slip(self) -> float:
        """Rated slip 1 − Ω_N/Ω_sync [-]."""
        return 1.0 - self.rated_speed / self.synchronous_speed

    @property
    def rotor_time_constant(self) -> float:
        """Open-circuit rotor time constant L_M/R_R [s] (rotor flux at imposed current)."""
        return self.magnetising_inductance / self.rotor_resistance

    @property
    def transient_rotor_time_constant(self) -> float:
        """Short-circuit rotor time constant L_σ L_M/(R_R (L_σ + L_M)) [s] (at imposed
        stator flux: the torque's response to slip under V/f, neglecting R_s)."""
        ls, lm = self.leakage_inductance, self.magnetising_inductance
        return ls * lm / (self.rotor_resistance * (ls + lm))

    def as_array(self) -> np.ndarray:
        """``[R_s, R_R, L_σ, L_M, p]``: the flat parameters the kernels take (SI)."""
        return np.array(
            [
                self.stator_resistance,
                self.rotor_resistance,
                self.leakage_inductance,
                self.magnetising_inductance,
                float(self.pole_pairs),
            ]
        )

    def gamma_parameters(self) -> dict[str, float]:
        """Γ-model parameters (Slemon 1989), as motulator's ``InductionMachinePars`` takes them.

        γ = L_M/(L_M + L_σ): R_r = R_R/γ², L_ℓ = L_σ/γ, L_s = L_M + L_σ.
        """
        g = self.magnetising_inductance / (self.magnetising_inductance + self.leakage_inductance)
        return {
            "n_p": int(self.pole_pairs),
            "R_s": self.stator_resistance,
            "R_r": self.rotor_resistance / g**2,
            "L_ell": self.leakage_inductance / g,
            "L_s": self.magnetising_inductance + self.leakage_inductance,
        }

    def with_(self, **changes) -> InverseGammaMachine:
        """A copy with some fields changed (``dataclasses.replace``, validated)."""
        return replace(self, **changes)

    def thevenin(self, supply_frequency, voltage=None):
        """Exact Thevenin equivalent seen from the rotor branch R_R/s at a supply frequency.

        Parameters
        ----------
        supply_frequency : float or array_like
            f [Hz] (> 0).
        voltage : float or array_like, optional
            Stator voltage, peak [V]; default the V/f law ``U_n f/f_n`` (no boost).

        Returns
        -------
        v_th, r_th, x_th : ndarray
            |V_Th| (peak) [V], R_Th [ohm], X_Th [ohm].
        """
        f = require_positive("supply_frequency", supply_frequency, "Hz")
        w = 2.0 * np.pi * f
        u = self.rated_voltage * f / self.rated_frequency if voltage is None else voltage
        u = require_finite("voltage", u, "V")
        zm = 1j * w * self.magnetising_inductance
        zs = self.stator_resistance + 1j * w * self.leakage_inductance
        v_th = u * zm / (zs + zm)
        z_th = zs * zm / (zs + zm)
        return np.abs(v_th), z_th.real, z_th.imag


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
    f = float(require_finite("supply_frequency", supply_frequency, "Hz"))
    u_mag = float(require_nonnegative("voltage", voltage, "V"))
    speed = float(require_finite("rotor_speed", rotor_speed, "rad/s"))
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
        ∂ψ̇/∂[u_d, u_q, ω_s, Ω] ([1], [1], [Wb], [Wb]: per mechanical rad/s).
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
        j = float(require_positive("inertia", inertia, "kg.m^2"))
        bl = float(require_finite("load_damping", load_damping, "N.m.s/rad"))
        full = np.zeros((5, 5))
        full[:4, :4] = a
        full[:4, 4] = b[:, 3]
        full[4, :4] = c / j
        full[4, 4] = -bl / j
    lam = np.linalg.eigvals(full)
    return lam[np.lexsort((lam.real, lam.imag))]


# --------------------------------------------------------------------------------------------
# Parameters from the nameplate
# --------------------------------------------------------------------------------------------
def _star_equivalent(line_voltage, connection, stator_resistance):
    """Equivalent-star phase voltage (rms) and stator resistance of the winding as connected."""
    if connection == "delta":
        return line_voltage / np.sqrt(3.0), stator_resistance / 3.0, 3.0
    if connection == "star":
        return line_voltage / np.sqrt(3.0), stator_resistance, 1.0
    raise ParameterError(f"connection must be 'delta' or 'star', got {connection!r}")


def _thevenin_rms(v, rs, xs, xm):
    """|V_Th| (rms), R_Th, X_Th of the inverse-Γ circuit at one frequency (reactances)."""
    zm = 1j * xm
    zs = rs + 1j * xs
    return abs(v * zm / (zs + zm)), (zs * zm / (zs + zm)).real, (zs * zm / (zs + zm)).imag


def _fit_leakage_and_rotor(v, rs, xm, omega_sync, slip, t_rated, t_max):
    """X_σ from the breakdown torque, R_R from the rated point, for a given X_M (rms, star)."""

    def breakdown(xs):
        vt, rt, xt = _thevenin_rms(v, rs, xs, xm)
        return 3.0 * vt * vt / (2.0 * omega_sync * (rt + np.hypot(rt, xt))) - t_max

    hi = 1.0
    while breakdown(hi) > 0.0:
        hi *= 10.0
        if hi > 1e9:
            raise ParameterError("no leakage reactance gives the breakdown torque")
    if breakdown(1e-12 * hi) < 0.0:
        raise ParameterError(
            f"the breakdown torque {t_max:g} N.m cannot be reached with this stator resistance "
            f"({rs:g} ohm, equivalent star) and magnetising reactance ({xm:g} ohm): lower "
            "stator_resistance or breakdown_torque_ratio"
        )
    xs = brentq(breakdown, 1e-12 * hi, hi, xtol=1e-15, rtol=1e-14)
    vt, rt, xt = _thevenin_rms(v, rs, xs, xm)
    z = np.hypot(rt, xt)
    # Eq. 4.28 at the rated slip as a quadratic in R_R (thevenin_from_nameplate, same algebra).
    a = t_rated * omega_sync
    b = (2.0 * a * rt - 3.0 * vt * vt) * slip
    c = a * (slip * z) ** 2
    disc = b * b - 4.0 * a * c
    if not disc > 0.0:
        raise ParameterError(
            f"the rated torque {t_rated:g} N.m at slip {slip:.4g} is not reachable with "
            f"X_M = {xm:g} ohm (equivalent star): the breakdown torque is too small"
        )
    rr = (-b + np.sqrt(disc)) / (2.0 * a)
    return xs, rr


def _stator_current_rms(v, rs, xs, xm, rr, slip):
    zr = rr / slip
    zm = 1j * xm
    return abs(v / (rs + 1j * xs + zm * zr / (zm + zr)))


def inverse_gamma_from_nameplate(
    rated_power=55e3,
    rated_frequency=50.0,
    rated_torque=891.0,
    rated_current=133.0,
    rated_line_voltage=380.0,
    connection="delta",
    pole_pairs=5,
    breakdown_torque_ratio=2.5,
    stator_resistance=0.085,
    *,
    magnetising_inductance=None,
    no_load_current_ratio=None,
) -> InverseGammaMachine:
    r"""Inverse-Γ parameters from the nameplate, consistent with the rig's Thevenin circuit.

    Defaults: the roller AM of Kayaalp Table 2 with the bundled rig's stator resistance and
    breakdown ratio (R_s = 0.085 Ω per delta phase, 1.7 % per unit). Result with them
    (equivalent star): R_s = 28.3 mΩ, L_σ = 1.302 mH, L_M = 6.90 mH, R_R = 30.1 mΩ;
    L_σ/R_R = 43 ms, L_M/R_R = 0.229 s; no-load current 0.64 of rated.

    Three targets at the rated frequency and voltage, three unknowns (L_σ, R_R, L_M); R_s is
    given. The targets are the rig's, so this is the Thevenin fit of
    :func:`~rollerrig.drives.induction.thevenin_from_nameplate` with a finite magnetising
    branch:

    1. the rated torque at the rated slip (from P = T Ω),
    2. the breakdown torque ``breakdown_torque_ratio × rated_torque``,
    3. the rated current at the rated point (fixes L_M; the nameplate current 133 A against
       the 88 A of the Thevenin rotor branch implies a large magnetising current, as in a
       10-pole machine: power factor √(1 − (I_0/I_N)²) ≈ 0.66 at P/(√3 U I) = 0.63).

    For a given L_M the exact Thevenin equivalent seen from the rotor branch is
    :math:`V_{Th} = V jX_M/(R_s + j(X_\sigma + X_M))`,
    :math:`Z_{Th} = jX_M(R_s + jX_\sigma)/(R_s + j(X_\sigma + X_M))`; X_σ follows from the
    breakdown torque (Chapman 2012, eq. 6-54, with V_Th, R_Th, X_Th) by root finding, R_R from
    the rated point (the quadratic of thevenin_from_nameplate); an outer root finding on X_M
    meets the rated current.

    Assumptions (stated in :attr:`InverseGammaMachine.assumptions`):

    * ``stator_resistance`` is per phase of the winding *as connected* (delta: the delta
      phase), exactly as :meth:`~rollerrig.rig.sections.InductionMotorParameters.circuit`
      passes it to the Thevenin fit; the equivalent star has a third of it.
    * The rated current is the current at the rated point of the equivalent circuit (no iron
      losses, no mechanical losses: the nameplate's efficiency is not used).
    * Constant parameters: no saturation, no rotor skin effect (the rig runs at 2-15 Hz supply
      and small slip: the rotor frequency is below 1 Hz, so the skin effect is negligible).

    Parameters
    ----------
    rated_power, rated_frequency, rated_torque, rated_current, rated_line_voltage : float
        Nameplate [W], [Hz], [N.m], line current rms [A], line voltage rms [V].
    connection : {"delta", "star"}
        Winding connection.
    pole_pairs : int
        p [-].
    breakdown_torque_ratio : float
        Breakdown over rated torque [-], > 1.
    stator_resistance : float
        Per phase of the winding as connected [ohm].
    magnetising_inductance : float, optional, keyword-only
        L_M of the equivalent star [H]: replaces target 3 (the rated current is then not met).
    no_load_current_ratio : float, optional, keyword-only
        I_0/I_N in (0, 1): L_M from the no-load current, U/(ω (L_σ + L_M)) = I_0 (replaces
        target 3).

    Returns
    -------
    InverseGammaMachine

    Raises
    ------
    rollerrig._validation.ParameterError
        On non-physical values or when the targets cannot be met together (the message says
        which).
    """
    p_r = float(require_positive("rated_power", rated_power, "W"))
    f_r = float(require_positive("rated_frequency", rated_frequency, "Hz"))
    t_r = float(require_positive("rated_torque", rated_torque, "N.m"))
    i_r = float(require_positive("rated_current", rated_current, "A"))
    v_line = float(require_positive("rated_line_voltage", rated_line_voltage, "V"))
    n_p = float(require_positive("pole_pairs", pole_pairs, "-"))
    ratio = float(
        require_in_range("breakdown_torque_ratio", breakdown_torque_ratio, 1.0, np.inf, "-")
    )
    r_conn = float(require_nonnegative("stator_resistance", stator_resistance, "ohm"))
    if magnetising_inductance is not None and no_load_current_ratio is not None:
        raise ParameterError(
            "give at most one of magnetising_inductance [H] and no_load_current_ratio [-]"
        )
    v, rs, _ = _star_equivalent(v_line, connection, r_conn)
    w1 = 2.0 * np.pi * f_r
    omega_sync = w1 / n_p
    omega_rated = p_r / t_r
    if not omega_rated < omega_sync:
        raise ParameterError(
            f"rated_power / rated_torque = {omega_rated:g} rad/s must be below the synchronous "
            f"speed 2π·rated_frequency/pole_pairs = {omega_sync:g} rad/s"
        )
    slip = 1.0 - omega_rated / omega_sync
    t_max = ratio * t_r

    def current_error(xm):
        xs, rr = _fit_leakage_and_rotor(v, rs, xm, omega_sync, slip, t_r, t_max)
        return _stator_current_rms(v, rs, xs, xm, rr, slip) - i_r

    assumptions = [
        "stator_resistance is per phase of the winding as connected (as the rig's Thevenin "
        "circuit uses it); the equivalent star has R/3 for delta.",
        "inverse-Γ circuit: exact for any split of the leakage between stator and rotor, so no "
        "X1:X2 split is assumed; constant parameters (no saturation, no skin effect: rotor "
        "frequency < 1 Hz on the rig).",
        "L_σ and R_R reproduce the rig's rated point (rated torque at the rated slip) and "
        "breakdown torque with the magnetising branch included (exact Thevenin of the "
        "inverse-Γ circuit).",
    ]
    if magnetising_inductance is not None:
        xm = float(require_positive("magnetising_inductance", magnetising_inductance, "H")) * w1
        how = "magnetising_inductance given"
        assumptions.append(f"L_M = {xm / w1:.4g} H given by the caller.")
    elif no_load_current_ratio is not None:
        i0 = i_r * float(
            require_in_range("no_load_current_ratio", no_load_current_ratio, 0.0, 1.0, "-")
        )

        def no_load_error(xm):
            xs, _ = _fit_leakage_and_rotor(v, rs, xm, omega_sync, slip, t_r, t_max)
            return v / abs(rs + 1j * (xs + xm)) - i0

        xm = _bracketed_root(no_load_error, v, i0, "no_load_current_ratio")
        how = f"no-load current {no_load_current_ratio:g} x rated"
        assumptions.append(
            f"L_M from the no-load current I_0 = {no_load_current_ratio:g} I_N (given by the "
            "caller), U/(ω(L_σ + L_M)) = I_0."
        )
    else:
        limit = current_error(1e6 * v / i_r) + i_r
        if not i_r > limit:
            raise ParameterError(
                f"rated_current = {i_r:g} A is below the current of the rotor branch alone at "
                f"the rated point ({limit:.4g} A): no magnetising inductance meets it; check "
                "rated_current (line current) and the connection, or give "
                "magnetising_inductance"
            )
        xm = _bracketed_root(current_error, v, i_r, "rated_current")
        how = "rated current at the rated point"
        assumptions.append(
            "L_M from the nameplate's rated current: the stator current at the rated point "
            f"equals {i_r:g} A (no iron or mechanical losses in the circuit)."
        )
    xs, rr = _fit_leakage_and_rotor(v, rs, xm, omega_sync, slip, t_r, t_max)
    i_at_rated = _stator_current_rms(v, rs, xs, xm, rr, slip)
    fit = {
        "magnetising_from": how,
        "rated_slip [-]": slip,
        "breakdown_torque [N.m]": t_max,
        "stator_current_at_rated_point [A rms]": float(i_at_rated),
        "no_load_current [A rms]": float(v / abs(rs + 1j * (xs + xm))),
        "equivalent_star_phase_voltage [V rms]": float(v),
    }
    return InverseGammaMachine(
        stator_resistance=rs,
        rotor_resistance=float(rr),
        leakage_inductance=float(xs / w1),
        magnetising_inductance=float(xm / w1),
        pole_pairs=int(n_p) if float(n_p).is_integer() else n_p,
        rated_frequency=f_r,
        rated_voltage=float(np.sqrt(2.0) * v),
        rated_current=float(np.sqrt(2.0) * i_r),
        rated_torque=t_r,
        rated_speed=omega_rated,
        assumptions=tuple(assumptions),
        fit=fit,
    )


def _bracketed_root(fun, v, current, name):
    """Root in X_M of a function that decreases with X_M, bracketed geometrically.

    Below some X_M the breakdown torque cannot be met at all (``fun`` raises); the lower end
    of the bracket is raised until it can.
    """
    lo = 1e-3 * v / current
    hi = 1e6 * v / current
    f_lo = None
    while lo < hi:
        try:
            f_lo = fun(lo)
            break
        except ParameterError:
            lo *= 1.5
    try:
        if f_lo is None or f_lo < 0.0 or fun(hi) > 0.0:
            raise ValueError
        return brentq(fun, lo, hi, xtol=1e-14, rtol=1e-13)
    except (ValueError, ParameterError) as exc:
        raise ParameterError(
            f"no magnetising inductance meets {name}: check it against the rated point and "
            "the breakdown torque, or give magnetising_inductance"
        ) from exc


def inverse_gamma_from_rig(section, **kwargs) -> InverseGammaMachine:
    """:func:`inverse_gamma_from_nameplate` on a rig's ``[induction_motor]`` section.

    Parameters
    ----------
    section : rollerrig.rig.sections.InductionMotorParameters
        The section (``rig.induction_motor``).
    **kwargs
        ``magnetising_inductance`` or ``no_load_current_ratio`` (see there).

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> m = inverse_gamma_from_rig(default_rig().induction_motor)
    >>> round(m.rated_slip, 5)
    0.01756
    """
    return inverse_gamma_from_nameplate(
        section.rated_power,
        section.rated_frequency,
        section.rated_torque,
        section.rated_current,
        section.rated_line_voltage,
        section.connection,
        section.pole_pairs,
        section.breakdown_torque_ratio,
        section.stator_resistance,
        **kwargs,
    )


def inverse_gamma_from_thevenin(
    circuit,
    connection: str = "delta",
    magnetising_inductance: float = 1e3,
    *,
    rated_current: float = 133.0,
    rated_torque: float = 891.0,
) -> InverseGammaMachine:
    """The inverse-Γ machine whose limit L_M → ∞ is a given Thevenin circuit.

    With R_s = R_Th, L_σ = (X_Th + X2')/ω_n, R_R = R2' (each referred to the equivalent star)
    and L_M → ∞ the exact Thevenin of the inverse-Γ circuit is V_Th = V, Z_Th = R_s + jω L_σ:
    the curve of :func:`~rollerrig.drives.induction.induction_torque` at every frequency of the
    V/f law. A large finite ``magnetising_inductance`` approaches it with a relative error of
    order L_σ/L_M.

    Parameters
    ----------
    circuit : rollerrig.drives.induction.TheveninCircuit
        The circuit (``rig.induction_motor.circuit()``).
    connection : {"delta", "star"}
        How its per-phase values are meant (the rig: delta, V_Th = line voltage).
    magnetising_inductance : float
        L_M [H] of the equivalent star (large).
    rated_current : float, keyword-only
        Line current [A] for the rated values (not used by the dynamics).
    rated_torque : float, keyword-only
        [N.m]; the rated speed is where the circuit gives it on its stable branch.

    Returns
    -------
    InverseGammaMachine
    """
    k = 3.0 if connection == "delta" else 1.0
    if connection not in ("delta", "star"):
        raise ParameterError(f"connection must be 'delta' or 'star', got {connection!r}")
    v_phase = circuit.voltage / np.sqrt(3.0) if connection == "delta" else circuit.voltage
    w1 = 2.0 * np.pi * circuit.rated_frequency
    omega_sync = w1 / circuit.pole_pairs
    # Rated speed: where the circuit gives the rated torque on its stable branch.
    speed = brentq(
        lambda w: float(circuit.torque(w)) - rated_torque,
        omega_sync * (1.0 - circuit.breakdown_slip()),
        omega_sync,
        xtol=1e-13,
    )
    return InverseGammaMachine(
        stator_resistance=circuit.resistance / k,
        rotor_resistance=circuit.rotor_resistance / k,
        leakage_inductance=circuit.reactance / k / w1,
        magnetising_inductance=float(magnetising_inductance),
        pole_pairs=circuit.pole_pairs,
        rated_frequency=circuit.rated_frequency,
        rated_voltage=float(np.sqrt(2.0) * v_phase),
        rated_current=float(np.sqrt(2.0) * rated_current),
        rated_torque=float(rated_torque),
        rated_speed=float(speed),
        assumptions=(
            "the Thevenin circuit's limit: V_Th = V and R_Th = R_s (X_M >> X_σ); L_M chosen "
            f"large ({magnetising_inductance:g} H) so that the magnetising branch is negligible.",
        ),
        fit={"from": "thevenin circuit"},
    )
