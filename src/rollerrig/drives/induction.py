"""Asynchronous (induction) motor of the roller drive under open-loop V/f control.

Kayaalp models the roller's squirrel-cage motor (AM) by its Thevenin equivalent circuit
(eq. 4.28), fed by an open-loop volts-per-hertz inverter, and adds a response lag (eq. 4.29). In
section 4.5.1.8 he also replaces the Thevenin curve by a linear torque-slip fit (Fig. 45).

Layers
------
Kernels (pure arithmetic and numpy ufuncs, compile under ``numba.njit``, no validation; called
from the coupled right-hand side; the names are a contract with the coupled model, so they carry
no ``_kernel`` suffix):

* :func:`induction_torque` -- eq. 4.28 under V/f, free of the 1/s singularity.
* :func:`vf_voltage`, :func:`vf_supply_frequency` -- the open-loop V/f controller.
* :func:`linear_induction_torque` -- the linear torque-slip fit of Fig. 45.
* :func:`lag_derivative` -- the continuous first-order lag that replaces eq. 4.29.

Validated public functions: :class:`TheveninCircuit`, :func:`thevenin_from_nameplate`,
:func:`linear_slope_from_nameplate`, :func:`lag_time_constant_from_clp`,
:func:`clp_from_lag_time_constant`, :func:`discrete_lag_filter`.

Sign convention: the torque is the air-gap torque on the rotor, motoring positive (it drives the
roller in its rolling direction). On the rig in traction the wheel drives the roller faster than
synchronous speed, the slip is negative and the torque is negative: the AM brakes the roller.

References
----------
Kayaalp (dissertation, the seed), section 4.5.1.4.2 (eq. 4.28), section 4.5.1.8 (eq. 4.29,
Figs. 45-46), Table 2.
S. J. Chapman, *Electric Machinery Fundamentals*, 5th ed., McGraw-Hill, 2012, sections 6.5
(Thevenin torque, eqs. 6-50 to 6-54: slip and value of the pull-out torque) and 6.9 (V/f
speed control).
A. E. Fitzgerald, C. Kingsley, S. D. Umans, *Electric Machinery*, 6th ed., McGraw-Hill, 2003,
section 6.6 (Thevenin simplification, X_m >> X_1).
IEEE Std 112-2017, *Test Procedure for Polyphase Induction Motors and Generators*, Table 2
(split of the leakage reactance X_1 : X_2 by design class).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
    require_whole,
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
    "thevenin_from_nameplate",
    "vf_supply_frequency",
    "vf_voltage",
]

#: Step of Kayaalp's simulation, to which c_lp of eq. 4.29 refers [s] (section 4.5.1.8).
SEED_LAG_STEP = 1e-4

# Relative guard in the torque denominator: (1e-12 · R2' · ω_syn,rated)². It only matters when
# both the slip speed and the synchronous speed are below ~1e-12 of the rated synchronous speed.
_DENOMINATOR_GUARD = 1e-24


# --------------------------------------------------------------------------------------------
# Kernels
# --------------------------------------------------------------------------------------------
def induction_torque(
    omega_rotor,
    supply_frequency,
    voltage,
    resistance_th,
    reactance_th_rated,
    rotor_resistance,
    reactance_rotor_rated,
    rated_frequency,
    pole_pairs,
):
    r"""Air-gap torque of the induction motor from its Thevenin circuit (Kayaalp, eq. 4.28).

    Eq. 4.28 with slip :math:`s = (\omega_{syn} - \omega_r)/\omega_{syn}`,
    :math:`\omega_{syn} = 2\pi f/p`, and reactances proportional to the supply frequency,
    :math:`X = (X_{Th} + X_2')\,f/f_{rated}` (V/f operation; the caller supplies the voltage,
    e.g. from :func:`vf_voltage`):

    .. math::

        T = \frac{3}{\omega_{syn}}\,
            \frac{V_{Th}^2\,R_2'/s}{(R_{Th} + R_2'/s)^2 + X^2}
          = \frac{3 V_{Th}^2 R_2'\,\Delta\omega}
                 {(R_{Th}\,\Delta\omega + R_2'\,\omega_{syn})^2 + X^2 \Delta\omega^2},
        \qquad \Delta\omega = \omega_{syn} - \omega_r .

    The second form follows by multiplying numerator and denominator by :math:`s^2\omega_{syn}^2`
    (Chapman 2012, eq. 6-50). It has no 1/s singularity: it is smooth through s = 0 (T = 0),
    valid for negative slip (generating/braking: rotor faster than synchronous, T < 0, the
    normal case on the rig in traction) and for s >= 1 (plugging), and odd under reversal of
    all speeds. At f -> 0 with V -> 0 the torque goes to zero; a tiny guard
    :math:`(10^{-12} R_2' \omega_{syn,rated})^2` added to the denominator keeps the 0/0 at
    :math:`\Delta\omega = \omega_{syn} = 0` finite (it returns 0) and changes nothing elsewhere.

    Parameters
    ----------
    omega_rotor : float or array_like
        Mechanical rotor speed ω_r [rad/s].
    supply_frequency : float or array_like
        Inverter output (stator) frequency f [Hz].
    voltage : float or array_like
        Thevenin voltage at that frequency, rms per phase [V].
    resistance_th : float
        Thevenin resistance R_Th, per phase [ohm].
    reactance_th_rated : float
        Thevenin reactance X_Th at the rated frequency, per phase [ohm].
    rotor_resistance : float
        Rotor resistance referred to the stator R2', per phase [ohm].
    reactance_rotor_rated : float
        Rotor leakage reactance referred to the stator X2' at the rated frequency [ohm].
    rated_frequency : float
        Frequency at which the reactances are given [Hz].
    pole_pairs : float
        Number of pole pairs p [-].

    Returns
    -------
    torque : float or ndarray
        Air-gap torque on the rotor, motoring positive [N.m].

    Examples
    --------
    >>> t = induction_torque(61.0, 50.0, 380.0, 0.1, 0.72, 0.05, 0.72, 50.0, 5)
    >>> t > 0.0
    True
    >>> float(induction_torque(62.0, 0.0, 0.0, 0.1, 0.72, 0.05, 0.72, 50.0, 5)) == 0.0
    True
    """
    omega_sync = 2.0 * np.pi * supply_frequency / pole_pairs
    omega_sync_rated = 2.0 * np.pi * rated_frequency / pole_pairs
    slip_speed = omega_sync - omega_rotor
    reactance = (reactance_th_rated + reactance_rotor_rated) * (supply_frequency / rated_frequency)
    resistive = resistance_th * slip_speed + rotor_resistance * omega_sync
    reactive = reactance * slip_speed
    guard = _DENOMINATOR_GUARD * (rotor_resistance * omega_sync_rated) ** 2
    denominator = resistive * resistive + reactive * reactive + guard
    return 3.0 * voltage * voltage * rotor_resistance * slip_speed / denominator


def vf_voltage(supply_frequency, rated_voltage, rated_frequency, boost_voltage=0.0):
    r"""Open-loop V/f law: voltage proportional to frequency, with optional low-speed boost.

    .. math::

        V(f) = \min\!\left(V_{rated},\;
               V_0 + (V_{rated} - V_0)\,\frac{|f|}{f_{rated}}\right)

    Keeping V/f constant keeps the air-gap flux about constant (Chapman 2012, sec. 6.9); the
    boost V_0 compensates the stator resistance drop at low frequency. Above the rated frequency
    the voltage stays at its rated value (field weakening).

    Parameters
    ----------
    supply_frequency : float or array_like
        Supply frequency f [Hz] (its sign, the direction of rotation, is ignored).
    rated_voltage : float
        Voltage at the rated frequency [V] (rms per phase, or the Thevenin voltage).
    rated_frequency : float
        Rated frequency [Hz].
    boost_voltage : float, optional
        Voltage at zero frequency V_0 [V]; 0 gives the pure V ∝ f law.

    Returns
    -------
    voltage : float or ndarray
        Voltage at the supply frequency [V], same kind as ``rated_voltage``.

    Examples
    --------
    >>> float(vf_voltage(25.0, 380.0, 50.0)), float(vf_voltage(60.0, 380.0, 50.0))
    (190.0, 380.0)
    """
    linear = boost_voltage + (rated_voltage - boost_voltage) * (
        np.abs(supply_frequency) / rated_frequency
    )
    return np.minimum(rated_voltage, linear)


def vf_supply_frequency(target_speed, pole_pairs):
    r"""Supply frequency of the open-loop V/f controller for a target roller speed.

    .. math:: f = \frac{p\,\omega^*}{2\pi}

    The controller sets the synchronous speed equal to the target speed, without slip
    compensation and without speed feedback (Kayaalp, section 4.5.1.4.2): the actual speed
    droops with load (below the target when motoring, above it when braking).

    Parameters
    ----------
    target_speed : float or array_like
        Target mechanical speed of the rotor ω* [rad/s].
    pole_pairs : float
        Number of pole pairs p [-].

    Returns
    -------
    frequency : float or ndarray
        Supply frequency [Hz].

    Examples
    --------
    >>> round(float(vf_supply_frequency(2.0 * 3.141592653589793 * 10.0, 5)), 9)
    50.0
    """
    return pole_pairs * target_speed / (2.0 * np.pi)


def linear_induction_torque(omega_rotor, omega_sync, slope):
    r"""Linear torque-slip characteristic (Kayaalp, section 4.5.1.8, Fig. 45).

    .. math:: T = k\,(\omega_{syn} - \omega_r)

    The small-slip limit of eq. 4.28; Kayaalp fits it between synchronous speed and the maximum
    torque. Motoring positive, braking (negative) above synchronous speed.

    Parameters
    ----------
    omega_rotor : float or array_like
        Mechanical rotor speed [rad/s].
    omega_sync : float or array_like
        Synchronous speed [rad/s].
    slope : float
        Torque per slip speed k [N.m.s/rad] (:func:`linear_slope_from_nameplate`).

    Returns
    -------
    torque : float or ndarray
        Torque on the rotor, motoring positive [N.m].

    Examples
    --------
    >>> float(linear_induction_torque(61.0, 62.0, 800.0))
    800.0
    """
    return slope * (omega_sync - omega_rotor)


def lag_derivative(torque_target, torque_lagged, time_constant):
    r"""Right-hand side of the first-order response lag of the AM torque.

    .. math:: \frac{dT_a}{dt} = \frac{T_{th} - T_a}{\tau}

    The continuous replacement of Kayaalp's discrete filter, eq. 4.29; map its parameter c_lp
    with :func:`lag_time_constant_from_clp`. Semantics: ``time_constant`` is τ [s] and must be
    > 0. τ = 0 (c_lp·Δt = 1, Kayaalp's "no delay") is **not** handled here: the caller then
    uses the algebraic relation T_a = T_th and carries no lag state.

    Parameters
    ----------
    torque_target : float or array_like
        Undelayed torque T_th [N.m] (e.g. :func:`induction_torque`).
    torque_lagged : float or array_like
        Lagged torque state T_a [N.m].
    time_constant : float
        Lag time constant τ > 0 [s].

    Returns
    -------
    float or ndarray
        dT_a/dt [N.m/s].

    Examples
    --------
    >>> float(lag_derivative(100.0, 0.0, 0.5))
    200.0
    """
    return (torque_target - torque_lagged) / time_constant


# --------------------------------------------------------------------------------------------
# Thevenin circuit from the nameplate
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class TheveninCircuit:
    """Per-phase Thevenin equivalent of an induction motor at its rated supply frequency.

    Attributes
    ----------
    voltage : float
        Thevenin voltage V_Th at the rated frequency, rms per phase [V].
    resistance : float
        Thevenin resistance R_Th [ohm].
    reactance_th : float
        Thevenin reactance X_Th at the rated frequency [ohm].
    rotor_resistance : float
        Rotor resistance referred to the stator R2' [ohm].
    rotor_reactance : float
        Rotor leakage reactance referred to the stator X2' at the rated frequency [ohm].
    rated_frequency : float
        Rated supply frequency [Hz].
    pole_pairs : int
        Number of pole pairs [-].

    Examples
    --------
    >>> am = thevenin_from_nameplate()
    >>> round(float(am.torque(55e3 / 891.0, 50.0)), 6)
    891.0
    """

    voltage: float
    resistance: float
    reactance_th: float
    rotor_resistance: float
    rotor_reactance: float
    rated_frequency: float
    pole_pairs: int

    def __post_init__(self):
        for name, check, unit in (
            ("voltage", require_positive, "V"),
            ("resistance", require_nonnegative, "ohm"),
            ("reactance_th", require_nonnegative, "ohm"),
            ("rotor_resistance", require_positive, "ohm"),
            ("rotor_reactance", require_nonnegative, "ohm"),
            ("rated_frequency", require_positive, "Hz"),
        ):
            value = getattr(self, name)
            if isinstance(value, str | bytes | bool):  # "380" would stay text, True one volt
                raise ParameterError(f"{name} must be a number [{unit}], got {value!r}")
            arr = check(name, value, unit)
            if arr.ndim != 0:
                raise ParameterError(
                    f"{name} must be a single number [{unit}], got shape {arr.shape}"
                )
            object.__setattr__(self, name, float(arr))
        # A count: 2.5 pole pairs, True or "5" would give a wrong synchronous speed.
        object.__setattr__(self, "pole_pairs", require_whole("pole_pairs", self.pole_pairs, 1))

    @property
    def reactance(self) -> float:
        """Total leakage reactance X = X_Th + X2' at the rated frequency [ohm]."""
        return self.reactance_th + self.rotor_reactance

    def synchronous_speed(self, supply_frequency=None):
        """Synchronous speed 2πf/p [rad/s] (rated frequency if ``supply_frequency`` is None)."""
        f = self.rated_frequency if supply_frequency is None else supply_frequency
        return 2.0 * np.pi * require_finite("supply_frequency", f, "Hz") / self.pole_pairs

    def torque(self, omega_rotor, supply_frequency=None, boost_voltage=0.0):
        """Air-gap torque [N.m] under the V/f law (:func:`vf_voltage`, :func:`induction_torque`).

        Parameters
        ----------
        omega_rotor : float or array_like
            Rotor speed [rad/s].
        supply_frequency : float or array_like, optional
            Supply frequency [Hz]; the rated frequency if None.
        boost_voltage : float, optional
            Low-speed voltage boost of the V/f law [V].
        """
        f = self.rated_frequency if supply_frequency is None else supply_frequency
        f = require_finite("supply_frequency", f, "Hz")
        omega_rotor = require_finite("omega_rotor", omega_rotor, "rad/s")
        if f.ndim and omega_rotor.ndim and f.shape != omega_rotor.shape:
            omega_rotor, f = require_broadcastable(omega_rotor=omega_rotor, supply_frequency=f)
        boost = require_nonnegative("boost_voltage", boost_voltage, "V", single=True)
        v = vf_voltage(f, self.voltage, self.rated_frequency, boost)
        return induction_torque(
            omega_rotor,
            f,
            v,
            self.resistance,
            self.reactance_th,
            self.rotor_resistance,
            self.rotor_reactance,
            self.rated_frequency,
            self.pole_pairs,
        )

    def breakdown_slip(self) -> float:
        """Slip of maximum motoring torque s_max = R2'/sqrt(R_Th² + X²) [-] (Chapman eq. 6-51)."""
        return self.rotor_resistance / np.hypot(self.resistance, self.reactance)

    def breakdown_torque(self) -> float:
        """Maximum motoring torque at the rated frequency [N.m] (Chapman 2012, eq. 6-54).

        T_max = 3 V² / (2 ω_syn (R_Th + sqrt(R_Th² + X²))).
        """
        return (
            3.0
            * self.voltage**2
            / (
                2.0
                * self.synchronous_speed()
                * (self.resistance + np.hypot(self.resistance, self.reactance))
            )
        )

    def small_slip_slope(self) -> float:
        """Slope dT/d(ω_syn − ω_r) at zero slip, rated frequency: 3 V²/(R2' ω_syn²) [N.m.s/rad]."""
        return 3.0 * self.voltage**2 / (self.rotor_resistance * self.synchronous_speed() ** 2)


def _rated_point(rated_power, rated_torque, rated_frequency, pole_pairs):
    omega_sync = 2.0 * np.pi * rated_frequency / pole_pairs
    omega_rated = rated_power / rated_torque
    if not omega_rated < omega_sync:
        raise ParameterError(
            f"rated_power / rated_torque = {omega_rated:g} rad/s must be below the synchronous "
            f"speed 2π·rated_frequency/pole_pairs = {omega_sync:g} rad/s"
        )
    return omega_sync, omega_rated


def thevenin_from_nameplate(
    rated_power=55e3,
    rated_frequency=50.0,
    rated_torque=891.0,
    rated_line_voltage=380.0,
    connection="delta",
    pole_pairs=5,
    breakdown_torque_ratio=2.5,
    stator_resistance=0.1,
    *,
    stator_reactance_fraction=0.5,
) -> TheveninCircuit:
    r"""Thevenin circuit that reproduces the nameplate's rated point and a breakdown torque.

    Defaults: the roller AM of Kayaalp, Table 2 (55 kW, 50 Hz, 891 N.m, 3×380 V delta,
    10 poles). The rated speed follows from P = T ω (61.73 rad/s = 589.5 rpm against a
    synchronous 62.83 rad/s = 600 rpm: rated slip 1.756 %). Result with the defaults:
    V_Th = 380 V, R_Th = 0.1 ohm, X_Th = X2' = 0.7221 ohm, R2' = 0.1273 ohm; breakdown slip
    8.79 %, rotor current at the rated point 50.7 A per delta phase.

    Assumptions (the seed gives no circuit parameters; it cites Onat [98]):

    1. V_Th equals the phase voltage (delta: the line voltage; star: line/sqrt(3)). This neglects
       the voltage divider of the magnetising branch, V_Th = V_1 X_m/|R_1 + j(X_1 + X_m)|,
       i.e. assumes X_m >> X_1, R_1 (Fitzgerald et al. 2003, sec. 6.6); the error is a few
       percent for machines of this size and is absorbed in the fitted R2' and X.
    2. R_Th equals the stator phase resistance (same approximation, R_Th = R_1 (X_m/(X_1+X_m))²).
       Default 0.1 ohm per delta phase ≈ 0.02 per unit (base 380 V / 76.8 A = 4.95 ohm), a
       typical value for a 55 kW machine, not a measurement.
    3. Breakdown torque = ``breakdown_torque_ratio`` × rated torque; 2.5 is typical of
       standard cage motors (NEMA design A/B pull-out torque 2-3 p.u.).
    4. The total leakage X = X_Th + X2' is split by ``stator_reactance_fraction`` (default 0.5,
       IEEE Std 112 for design A/D); only the sum enters the torque.

    Solution: from the breakdown torque (Chapman 2012, eq. 6-54),
    :math:`Z = \sqrt{R_{Th}^2 + X^2} = 3V^2/(2\omega_{syn}T_{max}) - R_{Th}`, so
    :math:`X = \sqrt{Z^2 - R_{Th}^2}`. Then eq. 4.28 at the rated slip s_r is a quadratic in R2':

    .. math::

        T_r\omega_{syn} R_2'^2 + (2T_r\omega_{syn}R_{Th} - 3V^2) s_r R_2'
        + T_r\omega_{syn} s_r^2 Z^2 = 0 .

    Its roots multiply to (s_r Z)²; the larger root has s_max = R2'/Z > s_r, the rated point on
    the stable side of the characteristic, and is taken.

    Parameters
    ----------
    rated_power : float
        Rated mechanical output power [W].
    rated_frequency : float
        Rated supply frequency [Hz].
    rated_torque : float
        Rated torque [N.m].
    rated_line_voltage : float
        Rated line-to-line voltage, rms [V].
    connection : {"delta", "star"}
        Stator winding connection.
    pole_pairs : int
        Number of pole pairs [-].
    breakdown_torque_ratio : float
        Breakdown (pull-out) torque over rated torque [-], > 1.
    stator_resistance : float
        Stator resistance per phase of the winding as connected [ohm].
    stator_reactance_fraction : float, keyword-only
        Share of X_Th in the total leakage reactance [-], in [0, 1].

    Returns
    -------
    TheveninCircuit

    Raises
    ------
    rollerrig._validation.ParameterError
        If a value is non-physical, the rated speed is not below synchronous speed, or the
        stator resistance is too large for the requested breakdown torque.

    Examples
    --------
    >>> am = thevenin_from_nameplate()
    >>> round(am.rotor_resistance, 4), round(am.reactance, 4)
    (0.1273, 1.4441)
    """
    rated_power = require_positive("rated_power", rated_power, "W", single=True)
    rated_frequency = require_positive("rated_frequency", rated_frequency, "Hz", single=True)
    rated_torque = require_positive("rated_torque", rated_torque, "N.m", single=True)
    line_voltage = require_positive("rated_line_voltage", rated_line_voltage, "V", single=True)
    pole_pairs = require_whole("pole_pairs", pole_pairs, 1)
    ratio = require_in_range(
        "breakdown_torque_ratio", breakdown_torque_ratio, 1.0, np.inf, "-", single=True
    )
    r_th = require_nonnegative("stator_resistance", stator_resistance, "ohm", single=True)
    fraction = require_in_range(
        "stator_reactance_fraction",
        stator_reactance_fraction,
        0.0,
        1.0,
        "-",
        low_inclusive=True,
        high_inclusive=True,
        single=True,
    )
    if connection == "delta":
        v_th = line_voltage
    elif connection == "star":
        v_th = line_voltage / np.sqrt(3.0)
    else:
        raise ParameterError(f"connection must be 'delta' or 'star', got {connection!r}")

    omega_sync, omega_rated = _rated_point(rated_power, rated_torque, rated_frequency, pole_pairs)
    slip = (omega_sync - omega_rated) / omega_sync
    t_max = ratio * rated_torque
    z = 3.0 * (v_th * v_th) / (2.0 * omega_sync * t_max) - r_th  # v_th**2 raises on overflow
    if not math.isfinite(z):
        raise ParameterError(
            f"rated_line_voltage = {line_voltage:g} V with rated_torque = {rated_torque:g} N.m "
            "gives a leakage impedance beyond the float range; check the units of the nameplate"
        )
    if not z > r_th:
        raise ParameterError(
            f"stator_resistance = {r_th:g} ohm is too large for a breakdown torque of {t_max:g} "
            f"N.m at {v_th:g} V: it must be below {1.5 * v_th**2 / (2 * omega_sync * t_max):g} ohm"
        )
    x_total = np.sqrt(z * z - r_th * r_th)

    a = rated_torque * omega_sync
    b = (2.0 * a * r_th - 3.0 * v_th**2) * slip
    c = a * (slip * z) ** 2
    disc = b * b - 4.0 * a * c  # > 0 because rated torque < breakdown torque
    r2 = (-b + np.sqrt(disc)) / (2.0 * a)
    return TheveninCircuit(
        voltage=float(v_th),
        resistance=r_th,
        reactance_th=float(fraction * x_total),
        rotor_resistance=float(r2),
        rotor_reactance=float((1.0 - fraction) * x_total),
        rated_frequency=rated_frequency,
        pole_pairs=pole_pairs,
    )


def linear_slope_from_nameplate(
    rated_power=55e3, rated_frequency=50.0, rated_torque=891.0, pole_pairs=5
):
    r"""Slope of the linear torque-slip characteristic through the nameplate's rated point.

    .. math:: k = \frac{T_r}{\omega_{syn} - \omega_r}, \qquad \omega_r = P_r/T_r

    The secant from synchronous speed to the rated point (Kayaalp, Fig. 45, fits a line between
    synchronous speed and maximum torque from measurements; with no data the nameplate gives the
    secant). For Table 2: 891 / (62.832 − 61.728) = 807.5 N.m.s/rad. It is smaller than the
    Thevenin tangent at s = 0 by the factor [(R_Th s_r + R2')² + X² s_r²]/R2'².

    Parameters
    ----------
    rated_power : float
        Rated power [W].
    rated_frequency : float
        Rated frequency [Hz].
    rated_torque : float
        Rated torque [N.m].
    pole_pairs : int
        Number of pole pairs [-].

    Returns
    -------
    float
        Slope k [N.m.s/rad].

    Examples
    --------
    >>> round(linear_slope_from_nameplate(), 1)
    807.5
    """
    rated_power = require_positive("rated_power", rated_power, "W", single=True)
    rated_frequency = require_positive("rated_frequency", rated_frequency, "Hz", single=True)
    rated_torque = require_positive("rated_torque", rated_torque, "N.m", single=True)
    pole_pairs = require_whole("pole_pairs", pole_pairs, 1)
    omega_sync, omega_rated = _rated_point(rated_power, rated_torque, rated_frequency, pole_pairs)
    return rated_torque / (omega_sync - omega_rated)


# --------------------------------------------------------------------------------------------
# Response lag (eq. 4.29)
# --------------------------------------------------------------------------------------------
def lag_time_constant_from_clp(c_lp, step=SEED_LAG_STEP):
    r"""Time constant of the continuous lag equivalent to Kayaalp's discrete filter, eq. 4.29.

    Kayaalp's filter, with the step Δt that the printed eq. 4.29 omits (section 4.5.1.8:
    c_lp = 1e4 at Δt = 1e-4 s gives "zero response delay", so the weight is w = c_lp·Δt):

    .. math:: T_{a,n} = c_{lp}\Delta t\, T_{th,n} + (1 - c_{lp}\Delta t)\, T_{a,n-1}

    is exactly the backward-Euler discretisation at step Δt of
    :math:`\tau\,\dot T_a = T_{th} - T_a` when :math:`w = \Delta t/(\tau + \Delta t)`, i.e.

    .. math:: \tau = \frac{1 - c_{lp}\Delta t}{c_{lp}} = \frac{1}{c_{lp}} - \Delta t .

    c_lp = 1e4 -> τ = 0 (no lag; handle algebraically, see :func:`lag_derivative`);
    c_lp = 2.75 (Kayaalp's fitted value) -> τ = 0.363536 s.

    Parameters
    ----------
    c_lp : float or array_like
        Filter parameter [1/s], with 0 < c_lp·Δt <= 1.
    step : float, optional
        Step Δt of the discrete filter [s]; Kayaalp's 1e-4 s by default.

    Returns
    -------
    float or ndarray
        Time constant τ >= 0 [s].

    Examples
    --------
    >>> round(lag_time_constant_from_clp(2.75), 6), lag_time_constant_from_clp(1e4)
    (0.363536, 0.0)
    """
    step = require_positive("step", step, "s", single=True)
    c = require_positive("c_lp", c_lp, "1/s")
    require_in_range(
        "c_lp * step", c * step, 0.0, 1.0, "-", low_inclusive=False, high_inclusive=True
    )
    tau = np.maximum((1.0 - c * step) / c, 0.0)
    return float(tau) if tau.ndim == 0 else tau


def clp_from_lag_time_constant(time_constant, step=SEED_LAG_STEP):
    r"""Inverse of :func:`lag_time_constant_from_clp`: c_lp = 1/(τ + Δt) [1/s].

    Parameters
    ----------
    time_constant : float or array_like
        Lag time constant τ >= 0 [s].
    step : float, optional
        Step Δt of the discrete filter [s].

    Returns
    -------
    float or ndarray
        Filter parameter c_lp [1/s].

    Examples
    --------
    >>> round(clp_from_lag_time_constant(1.0 / 2.75 - 1e-4), 9), clp_from_lag_time_constant(0.0)
    (2.75, 10000.0)
    """
    step = require_positive("step", step, "s", single=True)
    tau = require_nonnegative("time_constant", time_constant, "s")
    c = 1.0 / (tau + step)
    return float(c) if c.ndim == 0 else c


def discrete_lag_filter(torque_target, c_lp, step=SEED_LAG_STEP, initial=0.0):
    r"""Kayaalp's discrete low-pass filter, eq. 4.29 (with the step made explicit).

    .. math:: T_{a,n} = w\,T_{th,n} + (1 - w)\,T_{a,n-1}, \qquad w = c_{lp}\Delta t

    Provided to reproduce the seed and to check the continuous replacement
    (:func:`lag_time_constant_from_clp`); the coupled model uses :func:`lag_derivative`.

    Parameters
    ----------
    torque_target : array_like
        Samples T_th,n, n = 1..N, spaced by ``step`` [N.m].
    c_lp : float
        Filter parameter [1/s], 0 < c_lp·Δt <= 1.
    step : float, optional
        Sample step Δt [s].
    initial : float, optional
        T_a,0 [N.m].

    Returns
    -------
    ndarray
        Filtered samples T_a,n, n = 1..N [N.m].

    Examples
    --------
    >>> discrete_lag_filter([1.0, 1.0], 5000.0).tolist()
    [0.5, 0.75]
    """
    u = require_finite("torque_target", torque_target, "N.m")
    if u.ndim > 1:  # raveling would run the rows on as one series
        raise ParameterError(
            f"torque_target must be a 1-D series of samples [N.m], got shape {u.shape}"
        )
    u = u.ravel()
    step = require_positive("step", step, "s", single=True)
    c = require_positive("c_lp", c_lp, "1/s", single=True)
    w = require_in_range("c_lp * step", c * step, 0.0, 1.0, "-", high_inclusive=True, single=True)
    y = require_finite("initial", initial, "N.m", single=True)
    out = np.empty_like(u)
    for n, un in enumerate(u):
        y = w * un + (1.0 - w) * y
        out[n] = y
    return out
