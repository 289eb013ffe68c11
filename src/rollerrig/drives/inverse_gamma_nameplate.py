"""Inverse-Γ parameters of an induction machine from its nameplate, from a rig's
``[induction_motor]`` section, or from the Thevenin circuit of the same motor.

:func:`inverse_gamma_from_nameplate` meets three targets at the rated frequency and voltage
(the rated torque at the rated slip, the breakdown torque, the rated current) with three
unknowns (L_σ, R_R, L_M), R_s given: the rig's Thevenin fit
(:func:`~rollerrig.drives.induction.thevenin_from_nameplate`) with a finite magnetising
branch. :func:`inverse_gamma_from_thevenin` is the other way round: the machine whose limit
L_M → ∞ is a given Thevenin circuit. Each states its assumptions in
:attr:`~rollerrig.drives.inverse_gamma.InverseGammaMachine.assumptions`.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from scipy.optimize import brentq

from rollerrig._validation import (
    ParameterError,
    require_in_range,
    require_nonnegative,
    require_positive,
)
from rollerrig.drives.inverse_gamma import InverseGammaMachine

__all__ = [
    "inverse_gamma_from_nameplate",
    "inverse_gamma_from_rig",
    "inverse_gamma_from_thevenin",
]


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


def _remembered(fit):
    """``fit`` with its results kept for the nameplates last asked for (a pure function of
    numbers and names, about 5 ms a call: every twin of a dq calibration or drive study
    built it again, about 1 000 times for one comparison). Each caller gets its own copy of
    the result's ``fit`` dict."""
    cached = functools.lru_cache(maxsize=32)(fit)

    @functools.wraps(fit)
    def remembered(*args, **kwargs):
        try:
            hash((args, tuple(kwargs.items())))
        except TypeError:  # e.g. an array: not remembered, validated and refused as usual
            return fit(*args, **kwargs)
        machine = cached(*args, **kwargs)
        return dataclasses.replace(machine, fit=dict(machine.fit))

    remembered.cache_clear = cached.cache_clear  # type: ignore[attr-defined]
    remembered.cache_info = cached.cache_info  # type: ignore[attr-defined]
    return remembered


@_remembered
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
    p_r = require_positive("rated_power", rated_power, "W", single=True)
    f_r = require_positive("rated_frequency", rated_frequency, "Hz", single=True)
    t_r = require_positive("rated_torque", rated_torque, "N.m", single=True)
    i_r = require_positive("rated_current", rated_current, "A", single=True)
    v_line = require_positive("rated_line_voltage", rated_line_voltage, "V", single=True)
    n_p = require_positive("pole_pairs", pole_pairs, "-", single=True)
    ratio = require_in_range(
        "breakdown_torque_ratio", breakdown_torque_ratio, 1.0, np.inf, "-", single=True
    )
    r_conn = require_nonnegative("stator_resistance", stator_resistance, "ohm", single=True)
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
        xm = (
            require_positive("magnetising_inductance", magnetising_inductance, "H", single=True)
            * w1
        )
        how = "magnetising_inductance given"
        assumptions.append(f"L_M = {xm / w1:.4g} H given by the caller.")
    elif no_load_current_ratio is not None:
        i0 = i_r * require_in_range(
            "no_load_current_ratio", no_load_current_ratio, 0.0, 1.0, "-", single=True
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
