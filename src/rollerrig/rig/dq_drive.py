"""The dq induction machine under open-loop V/f as the rig's roller drive, on its own: its
state layout beside the twin's, the drive at a held speed or torque
(:func:`drive_steady_state`), on one rigid inertia (:func:`simulate_drive_on_inertia`), the
first-order lag that best reproduces it (:func:`fit_lag_at_held_speed`), and the ramped speed
tables the twin's assembly uses.

The coupled twin with this drive, its modes and the drive study:
:mod:`rollerrig.rig.drive_dynamics`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar, root

from rollerrig._validation import ParameterError, require_positive
from rollerrig.drives import induction_dq as dq
from rollerrig.drives import vf
from rollerrig.drives.induction import clp_from_lag_time_constant, lag_time_constant_from_clp
from rollerrig.rig import model as m

__all__ = [
    "N_RIG",
    "N_STATES",
    "SEED_LAG",
    "STATE_NAMES",
    "X_CTRL",
    "X_PSI",
    "DqDrive",
    "DriveOperatingPoint",
    "LagFit",
    "default_dq_drive",
    "drive_steady_state",
    "fit_lag_at_held_speed",
    "simulate_drive_on_inertia",
]


N_RIG = m.N_STATES


X_PSI = N_RIG  # 4 fluxes


X_CTRL = N_RIG + 4  # 3 controller states


N_STATES = N_RIG + 7


STATE_NAMES = (*m.STATE_NAMES, *dq.STATE_NAMES, *vf.STATE_NAMES)


SEED_LAG = lag_time_constant_from_clp(2.75)


@dataclass(frozen=True)
class DqDrive:
    """The roller drive: the machine and its V/f controller.

    Attributes
    ----------
    machine : InverseGammaMachine
        The machine.
    control : VfControl
        The controller.
    label : str
        Short name for tables.
    settings : dict or None
        Keyword arguments of :func:`default_dq_drive` it was built with (None: built
        otherwise).
    """

    machine: dq.InverseGammaMachine
    control: vf.VfControl
    label: str = "dq V/f"
    settings: dict | None = field(default=None, compare=False)
    """The V/f settings it was built with over the rig file's (:func:`default_dq_drive`);
    None: built otherwise."""

    def electrical_omega_command(self, roller_speed_setpoint, roller_radius):
        """ω* [rad/s] for a roller surface speed set point [m/s]."""
        return vf.frequency_command(roller_speed_setpoint, roller_radius, self.machine.pole_pairs)


def default_dq_drive(rig, *, label: str = "dq V/f", **vf_options) -> DqDrive:
    """The rig's AM as a dq machine (:func:`~rollerrig.drives.induction_dq.inverse_gamma_from_rig`)
    with the rig file's V/f settings (``[roller_drive_vf]``; keyword arguments replace them,
    see :func:`~rollerrig.drives.vf.vf_control_for`).

    The one way from V/f settings to a dq drive: the rig file's drive, the study's variants
    (:func:`drive_variants`) and the checks of their verdicts over the assumptions
    (:mod:`rollerrig.rig.drive_verdicts`) are all built here, so that the same settings
    give the same drive (e.g. a slip filter set alone leaves the current filter at the
    machine's default, whether set in the rig file or in a variant).
    """
    machine = dq.inverse_gamma_from_rig(rig.induction_motor)
    options = {**rig.roller_drive_vf.options(), **vf_options}  # the rig file's, then these
    return DqDrive(machine, vf.vf_control_for(machine, **options), label, dict(vf_options))


def _drive_derivatives(drive: DqDrive, psi, ctrl, omega_cmd, rotor_speed, pm, pc):
    """Machine and controller derivatives and outputs (scalars; the ported core)."""
    i_s_d = (psi[0] - psi[2]) / pm[2]
    i_s_q = (psi[1] - psi[3]) / pm[2]
    u_d, u_q, omega_s, d_if_d, d_if_q, d_slip = vf.vf_control_kernel(
        omega_cmd, i_s_d, i_s_q, ctrl[0], ctrl[1], ctrl[2], *pc
    )
    d_psi = dq.im_flux_derivatives_kernel(
        psi[0], psi[1], psi[2], psi[3], u_d, u_q, omega_s, pm[4] * rotor_speed, *pm[:4]
    )
    t_em = dq.im_torque_kernel(psi[0], psi[1], psi[2], psi[3], pm[2], pm[4])
    return d_psi, (d_if_d, d_if_q, d_slip), t_em, (u_d, u_q, omega_s, i_s_d, i_s_q)


@dataclass(frozen=True)
class DriveOperatingPoint:
    """Steady state of machine + controller.

    Attributes
    ----------
    state : ndarray, shape (7,)
        Fluxes [Wb] and controller states.
    rotor_speed : float
        Ω [rad/s].
    torque : float
        [N.m].
    omega_s : float
        Output frequency [rad/s] (electrical).
    voltage : complex
        u_s in the controller frame [V].
    stator_current : complex
        [A].
    """

    state: np.ndarray
    rotor_speed: float
    torque: float
    omega_s: float
    voltage: complex
    stator_current: complex


def drive_steady_state(
    drive: DqDrive,
    omega_cmd: float,
    *,
    rotor_speed: float | None = None,
    torque: float | None = None,
) -> DriveOperatingPoint:
    """Steady state of the machine and its controller at a frequency command.

    Give either the rotor speed (held) or the torque the machine must deliver (the speed is
    then found on the stable branch, starting from the linear slip estimate).

    Parameters
    ----------
    drive : DqDrive
        Machine and controller.
    omega_cmd : float
        Frequency command ω* [rad/s] (electrical), > 0.
    rotor_speed : float, optional
        Ω [rad/s].
    torque : float, optional
        Air-gap torque [N.m] (motoring positive).

    Returns
    -------
    DriveOperatingPoint

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> d = default_dq_drive(default_rig(), boost=0.0)
    >>> op = drive_steady_state(d, 2 * np.pi * 50.0, torque=891.0)
    >>> round(op.rotor_speed, 6)  # the nameplate's rated speed P/T
    61.728395
    """
    if (rotor_speed is None) == (torque is None):
        raise ParameterError("give exactly one of rotor_speed [rad/s] and torque [N.m]")
    w_cmd = require_positive("omega_cmd", omega_cmd, "rad/s", single=True)
    machine, control = drive.machine, drive.control
    pm, pc = machine.as_array(), control.as_array()
    n_p = machine.pole_pairs
    slope = (
        3.0
        * (machine.rated_voltage / np.sqrt(2.0)) ** 2
        / (machine.rotor_resistance * machine.synchronous_speed**2)
    )  # small-slip slope, to start
    # Starting guess: the linear slip estimate, the slip compensation's frequency shift, and
    # the machine's steady state there with the plain V/f voltage.
    slip_e = 0.0 if torque is None else n_p * float(torque) / slope  # electrical slip
    omega_s0 = w_cmd + control.slip_gain * slip_e
    speed0 = (omega_s0 - slip_e) / n_p if rotor_speed is None else float(rotor_speed)
    u0 = abs(vf.vf_voltage_kernel(omega_s0, pc[0], pc[1], pc[2]))
    op0 = dq.steady_state(machine, omega_s0 / (2 * np.pi), u0, speed0)
    i0 = op0.stator_current
    slip0 = (omega_s0 - n_p * speed0) if control.uses_slip_filter else 0.0
    z0 = np.concatenate([op0.state, [i0.real, i0.imag, slip0]])
    # Residuals scaled by their sizes: dψ/dt by U_n, filter rates by α I_n and α ω_n,
    # the torque by T_n; unknowns likewise (ψ_n, I_n, ω_n, Ω_n).
    r_scale = np.array(
        [machine.rated_voltage] * 4
        + [control.current_bandwidth * machine.rated_current] * 2
        + [control.slip_bandwidth * machine.rated_angular_frequency, machine.rated_torque]
    )
    x_scale = np.array(
        [machine.nominal_stator_flux] * 4
        + [machine.rated_current] * 2
        + [machine.rated_angular_frequency, machine.synchronous_speed]
    )
    held = rotor_speed is not None
    n_eq = 7 if held else 8

    def residual(y):
        z = y * x_scale[:n_eq]
        speed = float(rotor_speed) if held else z[7]
        d_psi, d_ctrl, t_em, _ = _drive_derivatives(drive, z[:4], z[4:7], w_cmd, speed, pm, pc)
        r = [*d_psi, *d_ctrl] if held else [*d_psi, *d_ctrl, t_em - float(torque)]
        return np.array(r, dtype=float) / r_scale[:n_eq]

    y0 = (z0 if held else np.append(z0, speed0)) / x_scale[:n_eq]
    sol = root(residual, y0, method="hybr", options={"xtol": 1e-14})
    if np.max(np.abs(residual(sol.x))) > 1e-11:
        sol = root(residual, sol.x, method="lm", options={"xtol": 1e-15, "ftol": 1e-15})
    if np.max(np.abs(residual(sol.x))) > 1e-11:
        at = f"Ω = {rotor_speed:g} rad/s" if held else f"T = {torque:g} N.m"
        raise ParameterError(
            f"no steady state of the V/f drive at ω* = {w_cmd:g} rad/s ({at}): {sol.message}"
            + (
                " (with full slip compensation a held speed off ω*/p has none)"
                if held and control.slip_gain > 0.0
                else ""
            )
        )
    z = sol.x * x_scale[:n_eq]
    speed = float(rotor_speed) if held else float(z[7])
    _, _, t_em, (u_d, u_q, omega_s, i_d, i_q) = _drive_derivatives(
        drive, z[:4], z[4:7], w_cmd, speed, pm, pc
    )
    return DriveOperatingPoint(
        state=z[:7].copy(),
        rotor_speed=speed,
        torque=float(t_em),
        omega_s=float(omega_s),
        voltage=complex(u_d, u_q),
        stator_current=complex(i_d, i_q),
    )


def simulate_drive_on_inertia(
    drive: DqDrive,
    t_end: float,
    speed_command: Callable[[float], float],
    *,
    inertia: float | None = None,
    load_torque: Callable[[float], float] | None = None,
    rotor_speed: Callable[[float], float] | None = None,
    initial: np.ndarray | None = None,
    t_eval: np.ndarray | None = None,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    method: str = "LSODA",
) -> dict[str, np.ndarray]:
    """Simulate the V/f drive on one rigid inertia (or at an imposed speed).

    States: fluxes (4), controller (3), then Ω (with ``inertia``) and the frame angle θ_s
    (to give stator-frame quantities). ``J dΩ/dt = T − T_L(t)``.

    Parameters
    ----------
    drive : DqDrive
        Machine and controller.
    t_end : float
        Duration [s].
    speed_command : callable
        Mechanical speed command Ω*(t) [rad/s] (ramped by the caller if wanted).
    inertia : float, optional
        J [kg.m^2]; None: the speed is imposed by ``rotor_speed``.
    load_torque : callable, optional
        T_L(t) [N.m] (default 0).
    rotor_speed : callable, optional
        Imposed Ω(t) [rad/s] when ``inertia`` is None.
    initial : ndarray, optional
        Initial ``[ψ (4), controller (3), Ω]`` (Ω omitted without inertia); default all zero
        (a start from rest, de-energised).
    t_eval : ndarray, optional
        Output times [s].
    rtol, atol : float
        Solver tolerances.
    method : str
        solve_ivp method.

    Returns
    -------
    dict
        ``t`` [s], ``psi`` (4, n) [Wb], ``ctrl`` (3, n), ``speed`` [rad/s], ``theta_s`` [rad],
        ``torque`` [N.m], ``i_s`` complex controller-frame current [A], ``i_ss`` stator-frame
        current [A], ``u_s`` controller-frame voltage [V], ``omega_s`` [rad/s].
    """
    machine, control = drive.machine, drive.control
    pm, pc = machine.as_array(), control.as_array()
    n_p = machine.pole_pairs
    load = load_torque or (lambda t: 0.0)
    if inertia is None and rotor_speed is None:
        raise ParameterError("give inertia [kg.m^2] or an imposed rotor_speed(t) [rad/s]")
    mech = inertia is not None
    j = require_positive("inertia", inertia, "kg.m^2", single=True) if mech else 1.0
    n = 9 if mech else 8

    def rhs(t, x):
        speed = x[7] if mech else rotor_speed(t)
        d_psi, d_ctrl, t_em, (_, _, omega_s, _, _) = _drive_derivatives(
            drive, x[:4], x[4:7], n_p * speed_command(t), speed, pm, pc
        )
        dx = np.empty(n)
        dx[:4] = d_psi
        dx[4:7] = d_ctrl
        if mech:
            dx[7] = (t_em - load(t)) / j
        dx[-1] = omega_s
        return dx

    x0 = np.zeros(n)
    if initial is not None:
        x0[: n - 1] = np.asarray(initial, dtype=float)[: n - 1]
    sol = solve_ivp(
        rhs, (0.0, float(t_end)), x0, method=method, t_eval=t_eval, rtol=rtol, atol=atol
    )
    if not sol.success:
        raise ParameterError(f"the drive simulation failed: {sol.message}")
    t, y = sol.t, sol.y
    speed = y[7] if mech else np.array([rotor_speed(tt) for tt in t])
    out = {"t": t, "psi": y[:4], "ctrl": y[4:7], "speed": speed, "theta_s": y[-1]}
    i_d = (y[0] - y[2]) / pm[2]
    i_q = (y[1] - y[3]) / pm[2]
    u = [
        vf.vf_control_kernel(n_p * speed_command(tt), a, b, c, d, e, *pc)[:3]
        for tt, a, b, c, d, e in zip(t, i_d, i_q, y[4], y[5], y[6], strict=True)
    ]
    u = np.array(u, dtype=float).T
    out["torque"] = dq.im_torque_kernel(y[0], y[1], y[2], y[3], pm[2], pm[4])
    out["i_s"] = i_d + 1j * i_q
    out["i_ss"] = out["i_s"] * np.exp(1j * y[-1])
    out["u_s"] = u[0] + 1j * u[1]
    out["omega_s"] = u[2]
    return out


def _ramped_tables(tables: np.ndarray, rate_speed: float) -> np.ndarray:
    """The input tables with the speed set point through the drive's ramp (exact)."""
    if not np.isfinite(rate_speed):
        return tables
    t, v = vf.ramp_limited_command(tables[m.TAB_SPEED_T], tables[m.TAB_SPEED], rate_speed)
    rows = [tables[i] for i in range(m.N_TABLE_ROWS)]
    rows[m.TAB_SPEED_T], rows[m.TAB_SPEED] = t, v
    return m.stack_table_rows(rows)


@dataclass(frozen=True)
class LagFit:
    """A first-order lag fitted to a torque response.

    Attributes
    ----------
    time_constant : float
        τ [s].
    clp : float
        Kayaalp's c_lp at his step 1e-4 s, 1/(τ + Δt) [1/s].
    rms_error : float
        RMS of the fitted minus the dq response, over the fit window [N.m].
    peak_response : float
        Largest |ΔT| of the dq response [N.m] (the scale of ``rms_error``).
    t : ndarray
        Times [s].
    dq_torque, lag_torque : ndarray
        The dq drive's torque and the fitted lag model's [N.m].
    """

    time_constant: float
    clp: float
    rms_error: float
    peak_response: float
    t: np.ndarray = field(repr=False)
    dq_torque: np.ndarray = field(repr=False)
    lag_torque: np.ndarray = field(repr=False)


def fit_lag_at_held_speed(
    drive: DqDrive,
    roller_speed: float,
    roller_radius: float,
    slip_step: float = 0.3,
    duration: float = 1.0,
    n: int = 2001,
) -> LagFit:
    """τ of the lag ``τ dT/dt = T_ss − T`` that best fits the dq drive's torque after a step.

    The machine runs at steady state at the set speed (ω* from ``roller_speed`` [m/s]), at no
    load; at t = 0 the rotor speed steps by ``slip_step`` [rad/s] (mechanical, above the set
    speed: braking, as the AM on the rig in traction) and is held. The Thevenin + lag model
    answers with ``T_ss (1 − e^{−t/τ})``, T_ss the new steady torque of the dq drive (they
    agree in steady state); τ minimises the RMS difference.
    """
    w_cmd = float(drive.electrical_omega_command(roller_speed, roller_radius))
    speed0 = w_cmd / drive.machine.pole_pairs
    op0 = drive_steady_state(drive, w_cmd, rotor_speed=speed0)
    t = np.linspace(0.0, duration, n)
    out = simulate_drive_on_inertia(
        drive,
        duration,
        lambda tt: speed0,
        rotor_speed=lambda tt: speed0 + slip_step,
        initial=op0.state,
        t_eval=t,
    )
    t_dq = out["torque"]
    op1 = drive_steady_state(drive, w_cmd, rotor_speed=speed0 + slip_step)
    t0, t1 = op0.torque, op1.torque

    def lag(tau):
        return t1 + (t0 - t1) * np.exp(-t / tau)

    def cost(log_tau):
        return float(np.sqrt(np.mean((lag(np.exp(log_tau)) - t_dq) ** 2)))

    best = minimize_scalar(cost, bounds=(np.log(1e-4), np.log(10.0)), method="bounded")
    tau = float(np.exp(best.x))
    return LagFit(
        time_constant=tau,
        clp=float(clp_from_lag_time_constant(tau)),
        rms_error=float(best.fun),
        peak_response=float(np.max(np.abs(t_dq - t0))),
        t=t,
        dq_torque=t_dq,
        lag_torque=lag(tau),
    )
