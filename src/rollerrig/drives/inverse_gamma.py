"""The inverse-Γ parameters of an induction machine and its rated values (equivalent star).

:class:`InverseGammaMachine` holds R_s, R_R, L_σ, L_M and p with the rated values they were
found for, and what follows from them alone: time constants, the V/f law's flux, the Γ-model
parameters, the exact Thevenin equivalent seen from the rotor branch. The machine's dynamics are
:mod:`rollerrig.drives.induction_dq`; its parameters from a nameplate or a Thevenin circuit,
:mod:`rollerrig.drives.inverse_gamma_nameplate`.

Units: SI; voltages and currents are peak values of the equivalent-star phase.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from rollerrig._validation import require_finite, require_nonnegative, require_positive

__all__ = ["InverseGammaMachine"]


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
    >>> from rollerrig.drives.inverse_gamma_nameplate import inverse_gamma_from_nameplate
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
