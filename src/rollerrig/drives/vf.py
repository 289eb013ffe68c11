"""Open-loop V/f (scalar) control of the roller's induction motor, as inverters implement it.

The frequency command comes from the roller speed set point (the rig runs the roller at a
commanded speed: f* = p Ω*/2π, no speed feedback); the inverter shapes it and the voltage:

* **frequency ramp**: the command passes a rate limiter (acceleration/deceleration time).
  The set point is an input, so the ramp is applied to the input table before the run
  (:func:`ramp_limited_command`, exact for piecewise-linear set points); it is not a state.
* **V/f law with low-speed boost**: |u| = U_0 + (U_n − U_0)|f|/f_n below the rated frequency,
  U_n above it (field weakening); the voltage lies on the q axis of the controller's frame, so
  that the stator flux lies near its d axis (:func:`vf_voltage_kernel`).
* **IR compensation** (optional, automatic): adds R̂_s (i_0 + j i_q,f): the drop of the
  nominal magnetising current on the d axis and of the filtered torque-producing current on
  the q axis (the form of Hinkkanen et al. 2022, eq. 13, as in motulator's ``VHzControl``).
* **slip compensation** (optional): raises the frequency by k_sc ω̂_r, the slip estimated from
  the measured current, ω̂_r = R̂_R Im{i_s ψ̂_R*}/|ψ̂_R|² with ψ̂_R = ψ_nom − L̂_σ i_s,f,
  low-pass filtered (Hinkkanen et al. 2022, eq. 14).
* **current limit** (optional): a proportional frequency correction on the filtered current
  magnitude above the limit, in the direction that unloads the machine (lowers the frequency
  when motoring, raises it when braking): −K (|i_f| − I_lim)⁺ sgn(i_q,f).

Frame: the controller's voltage frame, rotating at the output frequency ω_s; the machine model
(:mod:`rollerrig.drives.induction_dq`) uses the same frame, so the measured current enters the
controller in dq without a transformation. Controller states: the filtered current i_f (d, q)
[A] and the filtered slip estimate [rad/s] (3 states; :data:`STATE_NAMES`).

Not modelled: the inverter's sampling, PWM and computational delay (one sample of e.g. 250 µs
is a phase lag of 1.3° at 14.7 Hz), dead-time voltage error, DC-link dynamics and the DC-link
voltage limit (the rig runs at 5-30 % of the rated voltage).

Layers
------
Kernels (plain arithmetic; port them into the coupled right-hand side):
:func:`vf_voltage_kernel`, :func:`vf_control_kernel`. Public: :class:`VfControl`,
:func:`vf_control_for`, :func:`ramp_limited_command`, :func:`frequency_command`,
:meth:`VfControl.outputs`.

References
----------
M. Hinkkanen, L. Tiitinen, E. Mölsä, L. Harnefors, "On the stability of volts-per-hertz control
for induction motors", IEEE J. Emerg. Sel. Topics Power Electron. 10 (2022) 1609-1618.
Siemens, *SINAMICS V20 Inverter, Operating Instructions*, 07/2012, A5E03728167, parameter list:
continuous boost P1310 in % of R_s·I_N (the form used for :attr:`VfControl.boost_voltage`),
slip compensation P1335 in % of the rated slip, ramp-up/down times P1120/P1121.
B. K. Bose, *Modern Power Electronics and AC Drives*, Prentice Hall, 2002, sec. 8.3 (open-loop
volts/Hz control with boost and slip compensation).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
)

__all__ = [
    "STATE_NAMES",
    "VF_SETTING_RANGES",
    "VfControl",
    "frequency_command",
    "ramp_limited_command",
    "vf_control_for",
    "vf_control_kernel",
    "vf_voltage_kernel",
]

#: Names of the controller states: filtered stator current (d, q) [A], filtered slip [rad/s].
STATE_NAMES = ("vf_i_f_d", "vf_i_f_q", "vf_slip_f")

VF_SETTING_RANGES: dict[str, tuple[float, float]] = {
    "boost": (0.0, 2.5),
    "slip_compensation": (0.0, 1.5),
    "current_limit": (1.0, 4.0),
    "ramp_time": (0.01, 650.0),
    "current_filter_time": (1e-3, 10.0),
    "slip_filter_time": (1e-3, 10.0),
    "rotor_resistance_estimate": (0.5, 2.0),
    "filter_time": (1e-3, 10.0),
}
"""Plausible range (inclusive) of each setting of :func:`vf_control_for` and of the rig file's
``[roller_drive_vf]`` table, in the units of those settings:

* ``boost``: U_0 / (R_s I_N) [-], 0 to 2.5 (Siemens SINAMICS V20 P1310: 0-250 %);
* ``slip_compensation``: k_sc [-], 0 to 1.5 (beyond full compensation the drive speeds up with
  load; the controller's own bound);
* ``current_limit``: I_lim / I_N [-], 1 to 4: below the rated current the limit throttles the
  machine in its own normal running (its magnetising current alone is 0.64 I_N on the bundled
  rig, and a limit of 0.65 I_N cannot hold 800 N.m at 30 km/h: the drive stalls and has no
  steady state), above 4 I_N no inverter of the class delivers (V20 P0640: at most 400 %);
* ``ramp_time``: 0 to f_n [s], 10 ms to 650 s (V20 P1120: up to 650 s);
* ``current_filter_time``, ``slip_filter_time``: the time constants of the current filter
  (IR compensation, slip estimate's flux, current limit) and of the slip-estimate filter [s],
  1 ms to 10 s; ``0`` in the rig file means the machine's default;
* ``rotor_resistance_estimate``: R̂_R / R_R [-], the inverter's rotor resistance over the
  machine's, 0.5 to 2 (a cage between 20 °C and a hot 150 °C changes its resistance by
  +50 % (aluminium, α = 0.0039/K), and a commissioning estimate can be off either way);
* ``filter_time`` [s]: the former single key of both filters (deprecated; read as both).
"""


# --------------------------------------------------------------------------------------------
# Kernels
# --------------------------------------------------------------------------------------------
def vf_voltage_kernel(omega_s, rated_voltage, rated_omega, boost_voltage):
    r"""Signed voltage magnitude of the V/f law with boost (on the q axis of the frame).

    .. math::

        u_q = \mathrm{sgn}(\omega_s)\,\min\!\left(U_n,\; U_0 + (U_n - U_0)
              \frac{|\omega_s|}{\omega_n}\right)

    with a smooth sign ``tanh(ω_s/(10⁻³ ω_n))`` so that the law is continuous through zero
    frequency (the boost reverses with the field).

    Parameters
    ----------
    omega_s : float
        Output angular frequency ω_s [rad/s] (electrical).
    rated_voltage : float
        U_n, peak phase voltage at the rated frequency [V].
    rated_omega : float
        ω_n = 2π f_n [rad/s].
    boost_voltage : float
        U_0, voltage at zero frequency [V] (peak).

    Returns
    -------
    float
        u_q [V].

    Examples
    --------
    >>> round(float(vf_voltage_kernel(157.08, 310.0, 314.16, 0.0)), 3)
    155.0
    """
    magnitude = np.minimum(
        rated_voltage,
        boost_voltage + (rated_voltage - boost_voltage) * np.abs(omega_s) / rated_omega,
    )
    return magnitude * np.tanh(omega_s / (1e-3 * rated_omega))


def vf_control_kernel(
    omega_cmd,
    i_s_d,
    i_s_q,
    i_f_d,
    i_f_q,
    slip_f,
    rated_voltage,
    rated_omega,
    boost_voltage,
    ir_resistance,
    magnetising_current,
    slip_gain,
    rotor_resistance,
    leakage_inductance,
    nominal_flux,
    current_bandwidth,
    slip_bandwidth,
    current_limit,
    limit_gain,
):
    r"""The V/f controller at one instant: voltage, output frequency and its state derivatives.

    .. math::

        \omega_s &= \omega^* + k_{sc}\,\hat\omega_{r,f}
                    - K_{lim}\,(|i_f| - I_{lim})^+\,\mathrm{sgn}(i_{f,q}) \\
        u_s &= j\,u_q^{V/f}(\omega_s) + \hat R_s\,(i_0 + j\,i_{f,q}) \\
        \dot i_f &= \alpha_i (i_s - i_f), \qquad
        \dot{\hat\omega}_{r,f} = \alpha_f\left(
            \frac{\hat R_R\,\mathrm{Im}\{i_s\hat\psi_R^*\}}{|\hat\psi_R|^2}
            - \hat\omega_{r,f}\right), \quad \hat\psi_R = \psi_{nom} - \hat L_\sigma i_f

    Switches: ``ir_resistance = 0`` (no IR compensation), ``slip_gain = 0`` (no slip
    compensation), ``limit_gain = 0`` (no current limit); ``boost_voltage = 0`` the pure V ∝ f
    law.

    Parameters
    ----------
    omega_cmd : float
        Frequency command ω* (after the ramp) [rad/s] (electrical).
    i_s_d, i_s_q : float
        Measured stator current in the controller frame [A].
    i_f_d, i_f_q : float
        Filtered current (state) [A].
    slip_f : float
        Filtered slip estimate (state) [rad/s].
    rated_voltage, rated_omega, boost_voltage : float
        V/f law (:func:`vf_voltage_kernel`) [V], [rad/s], [V].
    ir_resistance : float
        R̂_s of the IR compensation [ohm] (0: off).
    magnetising_current : float
        i_0, nominal magnetising current [A].
    slip_gain : float
        k_sc [-] (0: off, 1: full compensation).
    rotor_resistance, leakage_inductance, nominal_flux : float
        R̂_R [ohm], L̂_σ [H], ψ_nom [Wb] of the slip estimate.
    current_bandwidth, slip_bandwidth : float
        α_i, α_f [rad/s].
    current_limit : float
        I_lim, peak [A].
    limit_gain : float
        K_lim [rad/s per A] (0: off).

    Returns
    -------
    u_d, u_q, omega_s, d_i_f_d, d_i_f_q, d_slip_f : float
        [V], [V], [rad/s], [A/s], [A/s], [rad/s²].
    """
    excess = np.maximum(np.sqrt(i_f_d * i_f_d + i_f_q * i_f_q) - current_limit, 0.0)
    limit_sign = np.tanh(i_f_q / (1e-3 * current_limit))
    omega_s = omega_cmd + slip_gain * slip_f - limit_gain * excess * limit_sign
    u_d = ir_resistance * magnetising_current
    u_q = vf_voltage_kernel(omega_s, rated_voltage, rated_omega, boost_voltage) + (
        ir_resistance * i_f_q
    )
    psi_r_d = nominal_flux - leakage_inductance * i_f_d
    psi_r_q = -leakage_inductance * i_f_q
    slip_meas = (
        rotor_resistance
        * (i_s_q * psi_r_d - i_s_d * psi_r_q)
        / (psi_r_d * psi_r_d + psi_r_q * psi_r_q)
    )
    d_i_f_d = current_bandwidth * (i_s_d - i_f_d)
    d_i_f_q = current_bandwidth * (i_s_q - i_f_q)
    d_slip_f = slip_bandwidth * (slip_meas - slip_f)
    return u_d, u_q, omega_s, d_i_f_d, d_i_f_q, d_slip_f


# --------------------------------------------------------------------------------------------
# Settings
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class VfControl:
    """Settings of the open-loop V/f controller (SI; voltages and currents peak, star).

    Attributes
    ----------
    rated_voltage : float
        U_n at the rated frequency [V].
    rated_frequency : float
        f_n [Hz].
    pole_pairs : int
        p [-] (frequency command from the mechanical speed set point).
    boost_voltage : float
        U_0, V/f law at zero frequency [V]; 0: pure V ∝ f.
    ir_resistance : float
        R̂_s of the automatic IR compensation [ohm]; 0: off.
    magnetising_current : float
        i_0 of the IR compensation [A].
    slip_gain : float
        Slip compensation k_sc [-] in [0, 1.5]; 0: off.
    rotor_resistance, leakage_inductance, nominal_flux : float
        R̂_R [ohm], L̂_σ [H], ψ_nom [Wb] (the controller's model of the machine).
    current_bandwidth : float
        α_i of the current filter [rad/s].
    slip_bandwidth : float
        α_f of the slip-estimate filter [rad/s].
    current_limit : float
        I_lim [A] (peak).
    limit_gain : float
        K_lim [rad/s per A]; 0: no current limit.
    ramp_rate : float
        Frequency ramp [Hz/s] (inf: none); applied to the input (:func:`ramp_limited_command`).
    assumptions : tuple of str
        Why each default is what it is.
    """

    rated_voltage: float
    rated_frequency: float
    pole_pairs: int
    boost_voltage: float = 0.0
    ir_resistance: float = 0.0
    magnetising_current: float = 0.0
    slip_gain: float = 0.0
    rotor_resistance: float = 0.0
    leakage_inductance: float = 0.0
    nominal_flux: float = 1.0
    current_bandwidth: float = 10.0
    slip_bandwidth: float = 10.0
    current_limit: float = np.inf
    limit_gain: float = 0.0
    ramp_rate: float = np.inf
    assumptions: tuple[str, ...] = ()

    def __post_init__(self):
        require_positive("rated_voltage", self.rated_voltage, "V")
        require_positive("rated_frequency", self.rated_frequency, "Hz")
        require_positive("pole_pairs", self.pole_pairs, "-")
        require_in_range(
            "boost_voltage", self.boost_voltage, 0.0, self.rated_voltage, "V", low_inclusive=True
        )
        require_nonnegative("ir_resistance", self.ir_resistance, "ohm")
        require_nonnegative("magnetising_current", self.magnetising_current, "A")
        require_in_range(
            "slip_gain",
            self.slip_gain,
            0.0,
            1.5,
            "-",
            low_inclusive=True,
            high_inclusive=True,
        )
        require_nonnegative("rotor_resistance", self.rotor_resistance, "ohm")
        require_nonnegative("leakage_inductance", self.leakage_inductance, "H")
        require_positive("nominal_flux", self.nominal_flux, "Wb")
        require_positive("current_bandwidth", self.current_bandwidth, "rad/s")
        require_positive("slip_bandwidth", self.slip_bandwidth, "rad/s")
        if not self.current_limit > 0.0:
            raise ParameterError(f"current_limit must be > 0 [A], got {self.current_limit!r}")
        require_nonnegative("limit_gain", self.limit_gain, "rad/(s.A)")
        if not self.ramp_rate > 0.0:
            raise ParameterError(f"ramp_rate must be > 0 [Hz/s] (inf: none), got {self.ramp_rate}")
        if self.slip_gain > 0.0 and not self.rotor_resistance > 0.0:
            raise ParameterError(
                "slip compensation (slip_gain > 0) needs rotor_resistance > 0 [ohm]"
            )
        if self.limit_gain > 0.0 and not np.isfinite(self.current_limit):
            raise ParameterError(
                "a current limit (limit_gain > 0) needs a finite current_limit [A]"
            )

    @property
    def rated_omega(self) -> float:
        """ω_n = 2π f_n [rad/s]."""
        return 2.0 * np.pi * self.rated_frequency

    @property
    def uses_current_filter(self) -> bool:
        """Whether the filtered current is used (IR compensation, slip compensation, limit)."""
        return self.ir_resistance > 0.0 or self.slip_gain > 0.0 or self.limit_gain > 0.0

    @property
    def uses_slip_filter(self) -> bool:
        """Whether the slip estimate is used (slip compensation)."""
        return self.slip_gain > 0.0

    @property
    def active_states(self) -> tuple[str, ...]:
        """The controller states in use (the others are constant and need not be carried)."""
        names = STATE_NAMES[:2] if self.uses_current_filter else ()
        return names + (STATE_NAMES[2:] if self.uses_slip_filter else ())

    def with_(self, **changes) -> VfControl:
        """A copy with some settings changed (validated)."""
        return replace(self, **changes)

    def as_array(self) -> np.ndarray:
        """The 13 flat settings :func:`vf_control_kernel` takes after its 6 signals (SI)."""
        limit = self.current_limit if np.isfinite(self.current_limit) else 1e30
        return np.array(
            [
                self.rated_voltage,
                self.rated_omega,
                self.boost_voltage,
                self.ir_resistance,
                self.magnetising_current,
                self.slip_gain,
                max(self.rotor_resistance, 0.0),
                self.leakage_inductance,
                self.nominal_flux,
                self.current_bandwidth,
                self.slip_bandwidth,
                limit,
                self.limit_gain,
            ]
        )

    def outputs(self, omega_cmd, i_s_d, i_s_q, state=(0.0, 0.0, 0.0)):
        """:func:`vf_control_kernel` with these settings.

        Parameters
        ----------
        omega_cmd : float
            Frequency command [rad/s] (electrical).
        i_s_d, i_s_q : float
            Stator current in the controller frame [A].
        state : sequence of 3 floats
            ``[i_f_d, i_f_q, slip_f]``.

        Returns
        -------
        tuple
            ``(u_d, u_q, omega_s, d_i_f_d, d_i_f_q, d_slip_f)``.

        Examples
        --------
        >>> c = VfControl(rated_voltage=310.0, rated_frequency=50.0, pole_pairs=5)
        >>> u_d, u_q, w_s = c.outputs(2 * np.pi * 25.0, 0.0, 0.0)[:3]
        >>> float(u_d), round(float(u_q), 6), round(float(w_s / (2 * np.pi)), 6)
        (0.0, 155.0, 25.0)
        """
        return vf_control_kernel(omega_cmd, i_s_d, i_s_q, *state, *self.as_array())


def vf_control_for(
    machine,
    *,
    boost: float = 0.5,
    ir_compensation: bool = False,
    slip_compensation: float = 0.0,
    current_limit: float | None = 1.5,
    ramp_time: float | None = 10.0,
    current_filter_time: float | None = None,
    slip_filter_time: float | None = None,
    limit_gain: float | None = None,
    rotor_resistance_estimate: float = 1.0,
) -> VfControl:
    """V/f settings for a machine, with each default stated as an assumption.

    Defaults (the rig's inverter is not documented; Kayaalp 4.5.1.4.2 says only "open-loop
    volts per Hertz"): a general-purpose inverter in its linear V/f mode as shipped.

    * ``boost = 0.5``: continuous boost U_0 = 0.5 R_s I_N (the form of Siemens' P1310, in % of
      R_s I_N; 50 % assumed as the factory value). With the rig's R_s (0.0283 Ω equivalent
      star) it is 1.9 V rms of 219 V, 15 % of the voltage at 5 km/h (2.4 Hz). 0 gives the
      pure V ∝ f law of the existing twin.
    * ``ir_compensation = False``: no automatic IR compensation (a separate option in drives).
    * ``slip_compensation = 0``: none (Siemens P1335 ships at 0 %; Kayaalp's model has the
      speed droop with load, i.e. no slip compensation).
    * ``current_limit = 1.5``: current limit at 1.5 I_N (a typical overload factor), a
      proportional frequency correction of gain ω_n/I_N per A·... (see ``limit_gain``);
      inactive in the rig's tests (the AM stays below its rated current).
    * ``ramp_time = 10`` s from 0 to f_n (5 Hz/s): a usual factory ramp; it shapes only
      changes of the speed set point.
    * filters: the motulator/Hinkkanen default bandwidth 0.1 (R_R/L_σ + R_R/L_M) for both
      the current and the slip filter when the features using them are on.
    * ``rotor_resistance_estimate = 1``: the inverter knows the machine's R_R. Its slip
      estimate is proportional to R̂_R (ω̂_r = R̂_R Im{i_s ψ̂_R*}/|ψ̂_R|²) and enters the
      frequency only as k_sc ω̂_r, so an estimate e × R_R acts exactly like the gain e k_sc
      with an exact estimate (an estimate 50 % high with k_sc = 1 is k_sc = 1.5).

    Parameters
    ----------
    machine : rollerrig.drives.induction_dq.InverseGammaMachine
        The machine (its rated values, R_s and the controller's model R̂_R, L̂_σ = the true ones).
    boost : float
        U_0 / (R_s I_N) [-] (I_N peak, star) in [0, 2.5]: 0 for none.
    ir_compensation : bool
        Automatic IR compensation with R̂_s = R_s.
    slip_compensation : float
        k_sc [-] in [0, 1.5].
    current_limit : float or None
        I_lim / I_N [-] in [1, 4]; None: no limit.
    ramp_time : float or None
        Time from 0 to f_n [s] in [0.01, 650]; None: no ramp.
    current_filter_time, slip_filter_time : float, optional
        1/α_i, 1/α_f [s] in [0.001, 10].
    limit_gain : float, optional
        K_lim [rad/s per A]; default ω_n/I_N (the frequency drops by ω_n when the current
        exceeds the limit by I_N).
    rotor_resistance_estimate : float
        R̂_R / R_R [-] in [0.5, 2]: the rotor resistance of the inverter's slip estimate over
        the machine's (a cold machine with a hot estimate: > 1).

    Returns
    -------
    VfControl

    Raises
    ------
    ParameterError
        A setting outside its plausible range (:data:`VF_SETTING_RANGES`), naming it, its unit
        and the range.
    """
    b = _in_range("boost", boost, "-")
    k_sc = _in_range("slip_compensation", slip_compensation, "-")
    r_est = _in_range("rotor_resistance_estimate", rotor_resistance_estimate, "-")
    rs, rr = machine.stator_resistance, machine.rotor_resistance
    ls, lm = machine.leakage_inductance, machine.magnetising_inductance
    psi_nom = machine.nominal_stator_flux
    w_rb = rr * (ls + lm) / (ls * lm)
    alpha_i = (
        0.1 * w_rb
        if current_filter_time is None
        else 1.0 / _in_range("current_filter_time", current_filter_time, "s")
    )
    alpha_f = (
        0.1 * w_rb
        if slip_filter_time is None
        else 1.0 / _in_range("slip_filter_time", slip_filter_time, "s")
    )
    if current_limit is None:
        i_lim, k_lim = np.inf, 0.0
    else:
        i_lim = _in_range("current_limit", current_limit, "-") * machine.rated_current
        k_lim = (
            machine.rated_angular_frequency / machine.rated_current
            if limit_gain is None
            else require_nonnegative("limit_gain", limit_gain, "rad/(s.A)", single=True)
        )
    rate = (
        np.inf
        if ramp_time is None
        else machine.rated_frequency / _in_range("ramp_time", ramp_time, "s")
    )
    assumptions = (
        f"boost U_0 = {b:g} R_s I_N = {b * rs * machine.rated_current:.4g} V peak (continuous "
        "boost in % of R_s I_N as Siemens P1310; 50 % assumed as the factory value).",
        "IR compensation " + ("on (R̂_s = R_s)." if ir_compensation else "off (assumed)."),
        f"slip compensation k_sc = {k_sc:g} (0: none, as Kayaalp's open-loop model; Siemens "
        "P1335 ships at 0 %).",
        "current limit "
        + (
            f"{current_limit:g} I_N, proportional frequency correction."
            if current_limit
            else "off."
        ),
        "frequency ramp "
        + (f"0 -> f_n in {ramp_time:g} s (a usual factory ramp)." if ramp_time else "none."),
        "current filter "
        + (
            "0.1 (R_R/L_σ + R_R/L_M) (Hinkkanen et al. 2022; motulator's default)"
            if current_filter_time is None
            else f"{current_filter_time:g} s"
        )
        + ", slip filter "
        + ("0.1 (R_R/L_σ + R_R/L_M)." if slip_filter_time is None else f"{slip_filter_time:g} s."),
        "controller model of the machine = the machine (R̂_s, L̂_σ exact), R̂_R = "
        + (
            "R_R."
            if r_est == 1.0
            else f"{r_est:g} R_R (the slip compensation acts as k_sc = {r_est * k_sc:g})."
        ),
    )
    return VfControl(
        rated_voltage=machine.rated_voltage,
        rated_frequency=machine.rated_frequency,
        pole_pairs=machine.pole_pairs,
        boost_voltage=b * rs * machine.rated_current,
        ir_resistance=rs if ir_compensation else 0.0,
        magnetising_current=psi_nom / (lm + ls),
        slip_gain=k_sc,
        rotor_resistance=r_est * rr,
        leakage_inductance=ls,
        nominal_flux=psi_nom,
        current_bandwidth=alpha_i,
        slip_bandwidth=alpha_f,
        current_limit=i_lim,
        limit_gain=k_lim,
        ramp_rate=rate,
        assumptions=assumptions,
    )


def _in_range(name: str, value, unit: str, setting: str | None = None) -> float:
    """``value`` as a float, raising :class:`ParameterError` outside its plausible range
    (:data:`VF_SETTING_RANGES` of ``setting``, default ``name``)."""
    low, high = VF_SETTING_RANGES[setting or name]
    return require_in_range(
        name, value, low, high, unit, low_inclusive=True, high_inclusive=True, single=True
    )


# --------------------------------------------------------------------------------------------
# The frequency command and its ramp
# --------------------------------------------------------------------------------------------
def frequency_command(roller_speed_setpoint, roller_radius, pole_pairs):
    """Electrical angular frequency command ω* = p v*/r_r [rad/s] from the roller set point.

    Parameters
    ----------
    roller_speed_setpoint : float or array_like
        Roller surface speed set point v* [m/s].
    roller_radius : float
        r_r [m] (direct drive: the AM turns with the roller).
    pole_pairs : float
        p [-].

    Examples
    --------
    >>> round(float(frequency_command(30 / 3.6, 0.452, 5) / (2 * np.pi)), 3)  # Hz at 30 km/h
    14.671
    """
    return pole_pairs * np.asarray(roller_speed_setpoint, dtype=float) / roller_radius


def ramp_limited_command(times, values, rate):
    """A piecewise-linear command through a rate limiter, exactly (a piecewise-linear result).

    The output follows the input where its slope is within ±rate and ramps at ±rate towards it
    otherwise, catching it up at the intersection (the ramp-function generator of a drive).

    Parameters
    ----------
    times : array_like
        Breakpoints of the input, non-decreasing [s].
    values : array_like
        Input at the breakpoints (any unit u).
    rate : float
        Largest slope [u/s], > 0 (inf: the input itself).

    Returns
    -------
    times, values : ndarray
        Breakpoints of the output; it starts at ``values[0]``; after the input's last
        breakpoint (where the input holds its value) it ramps on until it has caught up.

    Examples
    --------
    >>> t, v = ramp_limited_command([0.0, 1.0, 1.0, 3.0], [0.0, 0.0, 10.0, 10.0], 5.0)
    >>> t.tolist(), v.tolist()
    ([0.0, 1.0, 3.0], [0.0, 0.0, 10.0])
    """
    t_in = require_finite("times", times, "s").ravel()
    u_in = require_finite("values", values).ravel()
    if t_in.size != u_in.size or t_in.size == 0:
        raise ParameterError("times and values must have the same, nonzero length")
    if np.any(np.diff(t_in) < 0.0):
        raise ParameterError("times must be non-decreasing [s]")
    r = float(rate)
    if not r > 0.0:
        raise ParameterError(f"rate must be > 0, got {rate!r}")
    if not np.isfinite(r):
        return t_in.copy(), u_in.copy()
    out_t, out_v = [float(t_in[0])], [float(u_in[0])]
    y, t = float(u_in[0]), float(t_in[0])
    for k in range(t_in.size - 1):
        t0, t1 = float(t_in[k]), float(t_in[k + 1])
        if t1 <= t0:  # a jump of the input at t0: nothing to integrate
            continue
        m = (float(u_in[k + 1]) - float(u_in[k])) / (t1 - t0)

        def u(tt, k=k, m=m, t0=t0):
            return float(u_in[k]) + m * (tt - t0)

        while t < t1:
            gap = u(t) - y
            tracking = abs(gap) <= 1e-12 * max(1.0, abs(y))
            if tracking and abs(m) <= r:
                t, y = t1, u(t1)
            else:
                d = np.sign(gap) if not tracking else np.sign(m)
                # catch-up time: y + d r (τ − t) = u(τ)
                slope = d * r - m
                tau = t + gap / slope if slope != 0.0 else np.inf
                if not tracking and t < tau <= t1:
                    y, t = u(tau), tau
                else:
                    y, t = y + d * r * (t1 - t), t1
            out_t.append(t)
            out_v.append(y)
    gap = float(u_in[-1]) - y
    if abs(gap) > 1e-12 * max(1.0, abs(y)):  # the input holds its last value: ramp on to it
        out_t.append(t + abs(gap) / r)
        out_v.append(float(u_in[-1]))
    t_out, v_out = np.array(out_t), np.array(out_v)
    keep = np.concatenate([[True], np.diff(t_out) > 0.0])  # the output is continuous
    t_out, v_out = t_out[keep], v_out[keep]
    if t_out.size > 2:  # drop interior points where the slope does not change
        slopes = np.diff(v_out) / np.diff(t_out)
        bend = ~np.isclose(slopes[1:], slopes[:-1], rtol=1e-12, atol=1e-9 * r)
        mask = np.concatenate([[True], bend, [True]])
        t_out, v_out = t_out[mask], v_out[mask]
    return t_out, v_out
