"""The roller drive as a dynamic machine under V/f, coupled with the rig: modes and the lag.

A python-level (scipy) model for studies, written so that its parts port into the compiled
twin: the inverse-Γ machine (:mod:`rollerrig.drives.induction_dq`) fed by the open-loop V/f
controller (:mod:`rollerrig.drives.vf`), acting between the AM rotor (body 6) and stator
(body 7) of the rig's torsional chain, with the wheel-roller contact, the PMSM and the bearings
exactly as in the twin: the right-hand side calls :func:`rollerrig.rig.model.rig_rhs` with the
roller-drive torque slot set to the machine's air-gap torque (roller mode 1 with a lag, whose
state then *is* the torque; its own derivative is discarded).

State layout of :class:`DqTwin` (27): the twin's 20 states (``roller_drive_torque_state`` and
``speed_error_integral`` unused), then the machine's fluxes
(:data:`rollerrig.drives.induction_dq.STATE_NAMES`) and the controller's filters
(:data:`rollerrig.drives.vf.STATE_NAMES`). The frequency command is ω* = p v*(t)/r_r from the
twin's speed set point table (ramped beforehand, :func:`rollerrig.drives.vf.ramp_limited_command`).

Functions:

* :func:`drive_steady_state` — machine + controller at a held rotor speed or delivering a
  torque; :func:`simulate_drive_on_inertia` — machine + controller on one rigid inertia with a
  load-torque function (the set-up motulator simulates).
* :class:`DqTwin` — the coupled twin: :meth:`~DqTwin.rhs`, :meth:`~DqTwin.steady_free_rolling`,
  :meth:`~DqTwin.linearise`, :meth:`~DqTwin.simulate`.
* :func:`dq_coupled_modes`, :func:`eigen_table`, :func:`thevenin_eigen_table` — the modes at
  steady free rolling, with and without the dq drive.
* :func:`fit_lag_at_held_speed`, :func:`fit_lag_in_rig` — the first-order lag (τ, c_lp) that
  best reproduces the dq drive's torque response, to compare with Kayaalp's c_lp = 2.75.
* :func:`drive_variants`, :func:`drive_dynamics_study` — the study of issue 13 (JSON-ready),
  :func:`format_eigen_table`.

Not integrated into the compiled twin: the fast backend's state layout
(:mod:`rollerrig.rig.model`) has no flux or controller states yet.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from rollerrig._validation import ParameterError, require_positive
from rollerrig.contact.creep import POLACH_PARAMETER_SETS
from rollerrig.drives import induction_dq as dq
from rollerrig.drives import vf
from rollerrig.drives.induction import clp_from_lag_time_constant
from rollerrig.experiment.protocol import Protocol
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble, steady_free_rolling_state
from rollerrig.rig.dq_drive import (
    N_RIG,
    N_STATES,
    SEED_LAG,
    STATE_NAMES,
    X_CTRL,
    X_PSI,
    DqDrive,
    DriveOperatingPoint,
    LagFit,
    _drive_derivatives,
    _ramped_tables,
    default_dq_drive,
    drive_steady_state,
    fit_lag_at_held_speed,
    simulate_drive_on_inertia,
)
from rollerrig.rig.drive_verdicts import band_class, band_verdict, mode_class, robustness
from rollerrig.rig.linear import (
    DEFAULT_DAMPING_THRESHOLD,
    CoupledMode,
    coupled_modes,
    modes_of,
)

__all__ = [
    "SEED_LAG",
    "STATE_NAMES",
    "VARIANTS",
    "DqDrive",
    "DqTwin",
    "DriveOperatingPoint",
    "LagFit",
    "default_dq_drive",
    "dq_coupled_modes",
    "drive_dynamics_study",
    "drive_steady_state",
    "drive_variants",
    "eigen_table",
    "fit_lag_at_held_speed",
    "fit_lag_in_rig",
    "format_eigen_table",
    "simulate_drive_on_inertia",
    "thevenin_eigen_table",
]


#: Kayaalp's fitted lag: c_lp = 2.75 at Δt = 1e-4 s -> τ = 0.3635 s (4.5.1.8).


# --------------------------------------------------------------------------------------------
# Machine + controller alone
# --------------------------------------------------------------------------------------------


# --------------------------------------------------------------------------------------------
# The coupled twin
# --------------------------------------------------------------------------------------------
def _protocol(speed: float, load: float, friction: str, torque_time=None, torque=None):
    duration = 1.0 if torque_time is None else float(torque_time[-1])
    return Protocol(
        name="dq-drive",
        description="steady free rolling / torque steps for the dq roller drive",
        source="rollerrig.rig.drive_dynamics",
        duration=duration,
        torque_time=[0.0] if torque_time is None else list(torque_time),
        torque_request=[0.0] if torque is None else list(torque),
        speed_time=[0.0],
        roller_speed=[speed],
        load_time=[0.0],
        normal_load=[load],
        friction_time=[0.0],
        friction_condition=(friction,),
    )


@dataclass
class DqTwin:
    """The rig's coupled twin with the dq V/f roller drive (python level).

    Build with :meth:`at` (an operating point or a torque protocol).

    Attributes
    ----------
    rig : RigParameters
        The rig.
    drive : DqDrive
        The roller drive.
    wheel : str
        Wheel drive, ``"pmsm"`` or ``"ideal_torque"``.
    params : ndarray
        The twin's parameter vector (roller slot carries the machine torque).
    tables : ndarray
        Input tables (speed set point ramped).
    speed, normal_load : float
        Operating point [m/s], [N].
    friction : str
        Polach set.
    """

    rig: object
    drive: DqDrive
    wheel: str
    params: np.ndarray = field(repr=False)
    tables: np.ndarray = field(repr=False)
    speed: float
    normal_load: float
    friction: str = "dry"
    _buf: np.ndarray = field(default=None, repr=False)

    @classmethod
    def at(
        cls,
        rig,
        speed: float,
        normal_load: float,
        drive: DqDrive | None = None,
        *,
        wheel: str = "pmsm",
        friction: str = "dry",
        torque_time: Sequence[float] | None = None,
        torque_request: Sequence[float] | None = None,
    ) -> DqTwin:
        """The coupled twin at a roller speed [m/s] and normal load [N].

        ``torque_time``/``torque_request`` give a wheel torque request [s], [N.m] (default
        none: free rolling). The friction set must be one of Polach's (``dry``, ``wet``).
        """
        v = float(require_positive("speed", speed, "m/s"))
        load = float(require_positive("normal_load", normal_load, "N"))
        if friction not in POLACH_PARAMETER_SETS:
            raise ParameterError(
                f"friction must be one of {sorted(POLACH_PARAMETER_SETS)}, got {friction!r}"
            )
        drive = drive or default_dq_drive(rig)
        drives = m.DriveConfig(wheel=wheel, roller="induction", roller_lag=1.0)
        inputs = assemble(rig, _protocol(v, load, friction, torque_time, torque_request), drives)
        p = inputs.segments[0].params.copy()
        p[m.P_RIPPLE_AMP] = 0.0
        p[m.P_ROLLER_MODE] = m.ROLLER_MODES["induction"]
        p[m.P_LAG_TAU] = 1.0  # the roller torque slot is a state: the machine's torque
        rr = p[m.P_RR]
        rate_v = drive.control.ramp_rate * 2.0 * np.pi * rr / drive.machine.pole_pairs
        tables = _ramped_tables(inputs.tables, rate_v)
        return cls(rig, drive, wheel, p, tables, v, load, friction, np.zeros(N_RIG))

    # --- right-hand side ---------------------------------------------------------------------
    def rhs(self, t: float, x: np.ndarray) -> np.ndarray:
        """dx/dt of the coupled model (27 states, :data:`STATE_NAMES`)."""
        p = self.params
        pm = self.drive.machine.as_array()
        pc = self.drive.control.as_array()
        psi, ctrl = x[X_PSI : X_PSI + 4], x[X_CTRL : X_CTRL + 3]
        xr = np.array(x[:N_RIG], dtype=float)
        xr[m.X_T_ROLLER] = dq.im_torque_kernel(psi[0], psi[1], psi[2], psi[3], pm[2], pm[4])
        dx = np.empty(N_STATES)
        dxr = self._buf if self._buf is not None else np.zeros(N_RIG)
        m.rig_rhs(t, xr, p, self.tables, dxr)
        dx[:N_RIG] = dxr
        dx[m.X_T_ROLLER] = 0.0
        dx[m.X_INT_SPEED] = 0.0
        v_set = m._interp(t, self.tables[m.TAB_SPEED_T], self.tables[m.TAB_SPEED])
        omega_cmd = pm[4] * v_set / p[m.P_RR]
        rotor_speed = x[m.X_OMEGA + 5] - x[m.X_OMEGA + 6]
        d_psi, d_ctrl, _, _ = _drive_derivatives(
            self.drive, psi, ctrl, omega_cmd, rotor_speed, pm, pc
        )
        dx[X_PSI : X_PSI + 4] = d_psi
        dx[X_CTRL : X_CTRL + 3] = d_ctrl
        return dx

    def torques(self, x: np.ndarray, t: float = 0.0) -> dict[str, float]:
        """Roller-drive air-gap torque, T56 and the contact force at a state (SI)."""
        pm = self.drive.machine.as_array()
        xr = np.array(x[:N_RIG], dtype=float)
        psi = x[X_PSI : X_PSI + 4]
        xr[m.X_T_ROLLER] = dq.im_torque_kernel(psi[0], psi[1], psi[2], psi[3], pm[2], pm[4])
        terms = m.rig_terms(t, xr, self.params, self.tables)
        names = m.TERM_NAMES
        return {
            "roller_drive_torque": float(xr[m.X_T_ROLLER]),
            "t56": float(terms[names.index("t56")]),
            "contact_force": float(terms[names.index("contact_force")]),
        }

    # --- steady state -------------------------------------------------------------------------
    def steady_free_rolling(self) -> np.ndarray:
        """Steady free rolling with the dq drive: the state (27) the tests start from.

        The chain's state comes from :func:`rollerrig.rig.assemble.steady_free_rolling_state`
        with the roller held at the dq drive's steady speed (an ideal speed source there); the
        drive's speed is where it delivers the bearing losses (:func:`drive_steady_state`).
        """
        p_ideal = self.params.copy()
        p_ideal[m.P_ROLLER_MODE] = m.ROLLER_MODES["ideal_speed"]
        tables = self.tables.copy()
        rr = self.params[m.P_RR]
        omega_cmd = self.drive.electrical_omega_command(self.speed, rr)
        roller_speed = self.speed / rr
        x_rig = None
        for _ in range(3):  # the losses depend on the speed only through tanh(ω/ω_reg)
            tables[m.TAB_SPEED] = roller_speed * rr
            x_rig = steady_free_rolling_state(p_ideal, tables, friction_condition=self.friction)
            needed = float(x_rig[m.X_T_ROLLER])
            op = drive_steady_state(self.drive, omega_cmd, torque=needed)
            roller_speed = op.rotor_speed
        x = np.zeros(N_STATES)
        x[:N_RIG] = x_rig
        x[m.X_T_ROLLER] = 0.0
        x[X_PSI : X_PSI + 7] = op.state
        return x

    def active_states(self, x: np.ndarray | None = None) -> np.ndarray:
        """Indices of the states that move (unused twin and controller states dropped).

        With a state ``x`` (linearisation), the current filter is dropped when only the current
        limit uses it and the limit is inactive there: it then feeds nothing (a decoupled real
        pole −α_i).
        """
        control = self.drive.control
        drop = {m.X_T_ROLLER, m.X_INT_SPEED}
        if self.params[m.P_WHEEL_MODE] == 0.0:
            drop |= {m.X_ID, m.X_IQ, m.X_INT_D, m.X_INT_Q}
        used = set(control.active_states)
        if x is not None and not (control.ir_resistance > 0.0 or control.slip_gain > 0.0):
            i_f = np.hypot(x[X_CTRL], x[X_CTRL + 1])
            if not i_f > control.current_limit:
                used -= set(vf.STATE_NAMES[:2])
        drop |= {X_CTRL + k for k, n in enumerate(vf.STATE_NAMES) if n not in used}
        return np.array([k for k in range(N_STATES) if k not in drop])

    def linearise(self, x0: np.ndarray | None = None, step: float = 1e-7):
        """Jacobian A = ∂f/∂x on the active states at steady free rolling (central differences,
        ``h_k = step · max(|x0_k|, 1)``, as :func:`rollerrig.rig.linear.linearise_rhs`).

        Returns
        -------
        jacobian : ndarray
        names : tuple of str
        x0 : ndarray
        """
        x0 = self.steady_free_rolling() if x0 is None else np.asarray(x0, dtype=float)
        active = self.active_states(x0)
        jac = np.empty((active.size, active.size))
        for col, k in enumerate(active):
            h = step * max(abs(x0[k]), 1.0)
            xp, xm = x0.copy(), x0.copy()
            xp[k] += h
            xm[k] -= h
            jac[:, col] = (self.rhs(0.0, xp)[active] - self.rhs(0.0, xm)[active]) / (2.0 * h)
        return jac, tuple(STATE_NAMES[k] for k in active), x0

    def modes(self, damping_threshold: float = 0.3) -> tuple[CoupledMode, ...]:
        """Modes at steady free rolling (:func:`rollerrig.rig.linear.modes_of`)."""
        jac, names, _ = self.linearise()
        return modes_of(jac, names, self.rig, damping_threshold)

    def simulate(
        self,
        t_end: float,
        x0: np.ndarray | None = None,
        t_eval: np.ndarray | None = None,
        rtol: float = 1e-6,
        atol: float = 1e-8,
    ):
        """Integrate the coupled model (scipy Radau, finite-difference Jacobian on the active
        states); returns the ``solve_ivp`` solution (inactive states held)."""
        x0 = self.steady_free_rolling() if x0 is None else np.asarray(x0, dtype=float)
        active = self.active_states()
        full = x0.copy()

        def f(t, z):
            full[active] = z
            return self.rhs(t, full)[active]

        sol = solve_ivp(
            f, (0.0, float(t_end)), x0[active], method="Radau", t_eval=t_eval, rtol=rtol, atol=atol
        )
        if not sol.success:
            raise ParameterError(f"the coupled simulation failed: {sol.message}")
        y = np.repeat(x0[:, None], sol.t.size, axis=1)
        y[active] = sol.y
        sol.y_full = y
        return sol


# --------------------------------------------------------------------------------------------
# Mode tables
# --------------------------------------------------------------------------------------------
def dq_coupled_modes(
    rig, speed: float, normal_load: float, drive: DqDrive | None = None, **kwargs
) -> tuple[CoupledMode, ...]:
    """Modes of the twin with the dq V/f drive at steady free rolling (speed [m/s], load [N])."""
    return DqTwin.at(rig, speed, normal_load, drive, **kwargs).modes()


def _row(modes, speed, load, label, band, threshold=DEFAULT_DAMPING_THRESHOLD):
    """One row of a mode table: the oscillatory modes below 20 Hz and the verdict for ``band``."""
    osc = [md for md in modes if md.kind == "oscillatory" and md.frequency < 20.0]
    in_band = [md for md in osc if band[0] <= md.frequency <= band[1]]
    unstable = [md for md in modes if md.kind != "rigid" and md.eigenvalue.real > 0.0]
    row = {
        "speed [km/h]": speed * 3.6,
        "normal_load [kN]": load / 1e3,
        "drive": label,
        "modes below 20 Hz": [
            {
                "frequency [Hz]": md.frequency,
                "damping_ratio [-]": md.damping_ratio,
                "class": mode_class(md.damping_ratio, threshold),
                "what_moves": md.what_moves,
                "am_rotor_share [-]": md.bodies.get("am_rotor", 0.0),
            }
            for md in osc
        ],
        f"lightly damped in {band[0]:g}-{band[1]:g} Hz": any(
            0.0 <= md.damping_ratio < threshold for md in in_band
        ),
        "least damped in band": (
            None
            if not in_band
            else min(((md.frequency, md.damping_ratio) for md in in_band), key=lambda fz: fz[1])
        ),
        "unstable": [(float(md.eigenvalue.real), md.frequency) for md in unstable],
    }
    row[f"class in {band[0]:g}-{band[1]:g} Hz"] = band_class(row, band)
    return row


def eigen_table(
    rig,
    drives: Sequence[DqDrive],
    speeds: Sequence[float] = (5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6),
    loads: Sequence[float] = (4.3e3, 10e3, 20e3),
    *,
    band: tuple[float, float] = (1.0, 1.7),
    wheel: str = "pmsm",
) -> list[dict]:
    """Modes of the twin with each dq drive at steady free rolling, one row per (drive, speed
    [m/s], load [N]): the oscillatory modes below 20 Hz with what moves, whether one in ``band``
    [Hz] is lightly damped (0 <= ζ below :data:`rollerrig.rig.linear.DEFAULT_DAMPING_THRESHOLD`;
    a growing mode, ζ < 0, is ``unstable``, never lightly damped), the class of the band
    (:func:`rollerrig.rig.drive_verdicts.band_class`) and any unstable eigenvalue."""
    rows = []
    for d in drives:
        for v in speeds:
            for n in loads:
                modes = DqTwin.at(rig, v, n, d, wheel=wheel).modes()
                rows.append(_row(modes, v, n, d.label, band))
    return rows


def thevenin_eigen_table(
    rig,
    lags: Sequence[float | None] = (None, 0.0),
    speeds: Sequence[float] = (5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6),
    loads: Sequence[float] = (4.3e3, 10e3, 20e3),
    *,
    band: tuple[float, float] = (1.0, 1.7),
) -> list[dict]:
    """The same table for the existing Thevenin drive (:func:`rollerrig.rig.linear.coupled_modes`)
    with each response lag τ [s] (None: the rig's c_lp)."""
    rows = []
    for lag in lags:
        label = "Thevenin, lag " + ("c_lp (rig)" if lag is None else f"{lag:g} s")
        for v in speeds:
            for n in loads:
                cm = coupled_modes(rig, v, n, drives=m.DriveConfig(roller_lag=lag))
                rows.append(_row(cm.modes, v, n, label, band))
    return rows


def format_eigen_table(rows: Sequence[dict]) -> str:
    """Plain text of :func:`eigen_table` rows: ``f/ζ`` of each oscillatory mode below 20 Hz.

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> rig = default_rig()
    >>> text = format_eigen_table(eigen_table(rig, [default_dq_drive(rig)], [30 / 3.6], [4.3e3]))
    >>> text.splitlines()[0].split()[:3]
    ['drive', 'speed', '[km/h]']
    """
    lines = [f"{'drive':<38} {'speed [km/h]':>12} {'N [kN]':>7}  modes below 20 Hz: f [Hz]/zeta"]
    for r in rows:
        modes = " ".join(
            f"{md['frequency [Hz]']:.2f}/{md['damping_ratio [-]']:.3f}"
            for md in r["modes below 20 Hz"]
        )
        flag = " UNSTABLE" if r["unstable"] else ""
        flag += "".join(f" [{v}]" for k, v in r.items() if k.startswith("class in "))
        lines.append(
            f"{r['drive']:<38} {r['speed [km/h]']:>12.0f} {r['normal_load [kN]']:>7.1f}  "
            f"{modes}{flag}"
        )
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------
# The lag the dq drive amounts to
# --------------------------------------------------------------------------------------------


def fit_lag_in_rig(
    rig,
    speed: float,
    normal_load: float,
    torque_step: float = 300.0,
    drive: DqDrive | None = None,
    *,
    t_step: float = 0.2,
    rise: float = 0.02,
    duration: float = 2.5,
    friction: str = "dry",
    bounds: tuple[float, float] = (1e-3, 1.0),
    signal: str = "roller_drive_torque",
) -> LagFit:
    """Fit the twin's Thevenin + lag drive to the dq drive's response to a wheel-torque step.

    Both twins (ideal-torque wheel drive, as Kayaalp 4.5.1.8 did) start from steady free rolling
    at ``speed`` [m/s] and ``normal_load`` [N]; the wheel torque request rises by
    ``torque_step`` [N.m] in ``rise`` [s] at ``t_step`` [s]. τ of the Thevenin drive
    (:data:`rollerrig.rig.model.DriveConfig` ``roller_lag``) minimises the RMS difference of
    ``signal`` (``"roller_drive_torque"`` or ``"t56"``) over the run.
    """
    drive = drive or default_dq_drive(rig)
    tt = [0.0, t_step, t_step + rise, duration]
    tq = [0.0, 0.0, torque_step, torque_step]
    t = np.linspace(0.0, duration, int(duration * 400) + 1)
    twin = DqTwin.at(
        rig,
        speed,
        normal_load,
        drive,
        wheel="ideal_torque",
        friction=friction,
        torque_time=tt,
        torque_request=tq,
    )
    sol = twin.simulate(duration, t_eval=t)
    dq_sig = np.array([twin.torques(sol.y_full[:, k], tk)[signal] for k, tk in enumerate(t)])

    proto = _protocol(speed, normal_load, friction, tt, tq)

    def lag_response(tau):
        drives = m.DriveConfig(wheel="ideal_torque", roller="induction", roller_lag=tau)
        inputs = assemble(rig, proto, drives)
        p = inputs.segments[0].params.copy()
        p[m.P_RIPPLE_AMP] = 0.0
        buf = np.zeros(m.N_STATES)
        keep = np.array(
            [
                k
                for k in range(m.N_STATES)
                if k not in (m.X_ID, m.X_IQ, m.X_INT_D, m.X_INT_Q, m.X_INT_SPEED)
            ]
        )
        full = inputs.initial_state.copy()

        def f(tk, z):
            full[keep] = z
            m.rig_rhs(tk, full, p, inputs.tables, buf)
            return buf[keep].copy()

        # max_step: without it scipy's Radau can stall in Newton failures after a long step
        # (4177 Jacobians, 28 s at τ = 0.04 s with R_s = 0.085 ohm); with it 0.5 s at every τ
        s = solve_ivp(
            f,
            (0.0, duration),
            full[keep],
            method="Radau",
            t_eval=t,
            rtol=1e-6,
            atol=1e-8,
            max_step=0.02,
        )
        y = np.repeat(inputs.initial_state[:, None], t.size, axis=1)
        y[keep] = s.y
        idx = m.TERM_NAMES.index(
            "roller_drive_torque" if signal == "roller_drive_torque" else "t56"
        )
        return np.array([m.rig_terms(tk, y[:, k], p, inputs.tables)[idx] for k, tk in enumerate(t)])

    def cost(log_tau):
        return float(np.sqrt(np.mean((lag_response(np.exp(log_tau)) - dq_sig) ** 2)))

    best = minimize_scalar(
        cost,
        bounds=(np.log(bounds[0]), np.log(bounds[1])),
        method="bounded",
        options={"xatol": 1e-3},
    )
    tau = float(np.exp(best.x))
    return LagFit(
        time_constant=tau,
        clp=float(clp_from_lag_time_constant(tau)),
        rms_error=float(best.fun),
        peak_response=float(np.max(np.abs(dq_sig - dq_sig[0]))),
        t=t,
        dq_torque=dq_sig,
        lag_torque=lag_response(tau),
    )


# --------------------------------------------------------------------------------------------
# The study
# --------------------------------------------------------------------------------------------
VARIANTS: tuple[tuple[str, dict], ...] = (
    ("dq default", {}),
    ("dq pure V/f", {"boost": 0.0}),
    ("dq slip comp 1.0, 0.1 s", {"slip_compensation": 1.0, "slip_filter_time": 0.1}),
    ("dq slip comp 1.0, 0.05 s", {"slip_compensation": 1.0, "slip_filter_time": 0.05}),
    (
        "dq slip comp 1.0, 0.1 s, R_R est. 1.5",
        {"slip_compensation": 1.0, "slip_filter_time": 0.1, "rotor_resistance_estimate": 1.5},
    ),
    ("dq slip comp 1.5, 0.1 s", {"slip_compensation": 1.5, "slip_filter_time": 0.1}),
    ("dq slip comp 1.5, 0.05 s", {"slip_compensation": 1.5, "slip_filter_time": 0.05}),
)
"""The study's V/f variants: label and settings over the rig file's ``[roller_drive_vf]``."""


def drive_variants(rig) -> list[DqDrive]:
    """The V/f settings the study compares (:data:`VARIANTS`), each built by
    :func:`default_dq_drive` over the rig file's settings.

    ``dq default`` (the rig file's settings), ``pure V/f`` (no boost: the existing twin's
    law), full slip compensation with a 0.1 s and a 0.05 s slip filter, full compensation
    with a rotor-resistance estimate 50 % high (which acts exactly as 150 % compensation), and
    150 % compensation with 0.1 s and 0.05 s filters. Only the slip filter is set; the current
    filter keeps the rig file's value (the machine's default on the bundled rig).
    """
    return [default_dq_drive(rig, label=label, **settings) for label, settings in VARIANTS]


def drive_dynamics_study(
    rig,
    speeds: Sequence[float] = (5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6),
    loads: Sequence[float] = (4.3e3, 10e3, 20e3),
    drives: Sequence[DqDrive] | None = None,
    *,
    rig_fit_points: Sequence[tuple[float, float]] = ((10 / 3.6, 4.3e3), (30 / 3.6, 4.3e3)),
    check_loads: Sequence[float] | None = None,
    band: tuple[float, float] = (1.0, 1.7),
    progress: Callable[[str], None] | None = None,
) -> dict:
    """The issue-13 study, JSON-ready: mode tables with and without the dq drive, the lag fits,
    the verdict of each drive about ``band`` [Hz] and whether it holds over its assumptions.

    ``check_loads`` [N]: the loads of the robustness checks (default ``loads``: the whole
    grid of speeds × loads); an empty sequence skips the checks. Drives not built by
    :func:`default_dq_drive` are not checked. Cost (one core): the checks linearise the twin
    at about 950 operating points, about 15 s; the rest of the study about 11 s.
    ``progress``: called as ``progress(step)`` as each step starts (a command's progress).

    Returns
    -------
    dict
        ``thevenin`` and ``dq`` (rows of :func:`thevenin_eigen_table` / :func:`eigen_table`),
        ``verdicts`` (per drive: :func:`~rollerrig.rig.drive_verdicts.band_verdict` and
        :func:`~rollerrig.rig.drive_verdicts.robustness`), ``robustness_grid`` (speeds and
        loads of the checks),
        ``lag_held_speed`` (per speed: τ [s] and c_lp [1/s] of :func:`fit_lag_at_held_speed`
        for the first drive), ``lag_in_rig`` (per point of ``rig_fit_points``:
        :func:`fit_lag_in_rig`), ``seed_lag [s]`` (τ of c_lp = 2.75) and the machine's
        parameters and assumptions.
    """
    say = progress if progress is not None else (lambda step: None)
    drives = list(drives or drive_variants(rig))
    first = drives[0]
    rr = rig.geometry.roller_radius_x
    held = []
    say(f"the dq machine's lag at held speed ({len(speeds)} speeds)")
    for v in speeds:
        fit = fit_lag_at_held_speed(first, v, rr)
        held.append(
            {
                "speed [km/h]": v * 3.6,
                "tau [s]": fit.time_constant,
                "c_lp [1/s]": fit.clp,
                "rms_error [N.m]": fit.rms_error,
                "peak_response [N.m]": fit.peak_response,
            }
        )
    in_rig = []
    say(f"the lag fitted in the rig ({len(rig_fit_points)} points)")
    for v, n in rig_fit_points:
        fit = fit_lag_in_rig(rig, v, n, drive=first)
        in_rig.append(
            {
                "speed [km/h]": v * 3.6,
                "normal_load [kN]": n / 1e3,
                "tau [s]": fit.time_constant,
                "c_lp [1/s]": fit.clp,
                "rms_error [N.m]": fit.rms_error,
                "peak_response [N.m]": fit.peak_response,
            }
        )
    say(f"modes of the twin with {len(drives)} dq drives at {len(speeds) * len(loads)} points")
    dq_rows = eigen_table(rig, drives, speeds, loads, band=band)
    if check_loads is None:
        check_loads = tuple(loads)
    cache: dict = {}

    def rows_for(r, settings):
        # the same drive on the same rig recurs across variants and assumptions: once each
        key = (r.model_dump_json(exclude={"provenance"}), tuple(sorted(settings.items())))
        if key not in cache:
            drive = default_dq_drive(r, **settings)
            cache[key] = eigen_table(r, [drive], speeds, check_loads, band=band)
        return cache[key]

    verdicts = []
    for i, d in enumerate(drives):
        if check_loads and d.settings is not None:
            say(f"verdicts over the assumptions: {d.label} ({i + 1} of {len(drives)})")
        nominal = band_verdict([r for r in dq_rows if r["drive"] == d.label], band)
        entry = {"drive": d.label, "settings": d.settings, **nominal}
        if check_loads and d.settings is not None:
            entry["robustness"] = robustness(rig, d.settings, rows_for, nominal, band=band)
        verdicts.append(entry)
    mach = first.machine
    say("modes with the Thevenin drive")
    return {
        "machine": {
            "stator_resistance_equivalent_star [ohm]": mach.stator_resistance,
            "stator_resistance_as_connected [ohm]": rig.induction_motor.stator_resistance,
            "connection": rig.induction_motor.connection,
            "stator_resistance_per_unit [-]": rig.induction_motor.stator_resistance_per_unit,
            "rotor_resistance [ohm]": mach.rotor_resistance,
            "leakage_inductance [H]": mach.leakage_inductance,
            "magnetising_inductance [H]": mach.magnetising_inductance,
            "transient_rotor_time_constant [s]": mach.transient_rotor_time_constant,
            "rotor_time_constant [s]": mach.rotor_time_constant,
            "assumptions": list(mach.assumptions),
        },
        "controls": {d.label: list(d.control.assumptions) for d in drives},
        "thevenin": thevenin_eigen_table(rig, speeds=speeds, loads=loads),
        "dq": dq_rows,
        "band [Hz]": list(band),
        "verdicts": verdicts,
        "robustness_grid": {
            "speeds [km/h]": [v * 3.6 for v in speeds],
            "normal_loads [kN]": [n / 1e3 for n in check_loads],
            "one at a time": "each assumption over its range, the others at the drive's values",
        },
        "lag_held_speed": held,
        "lag_in_rig": in_rig,
        "seed_lag [s]": SEED_LAG,
    }
